"""``millpath run --no-pictures`` and ``[simulation] pictures = false``: the program,
tools.tbl, report.json and view.html are written as with pictures, the three PNGs are
not, and the proof's figures are the same."""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import pytest
from click.testing import CliRunner

from millpath.cli.main import cli

EXAMPLE = Path(__file__).resolve().parents[2] / "millpath" / "examples" / "features-holes-slot"
PNGS = {"preview.png", "stock.png", "deviation.png"}


@pytest.fixture(scope="module")
def runs(tmp_path_factory):
    d = tmp_path_factory.mktemp("pictures")
    shutil.copytree(EXAMPLE, d / "ex")
    job = d / "ex" / "job.toml"
    text = job.read_text()
    assert "[simulation]\n" in text
    (d / "ex" / "off.toml").write_text(text.replace("[simulation]\n",
                                                    "[simulation]\npictures = false\n", 1))
    out = {}
    for name, args in {"with": [job], "flag": [job, "--no-pictures"],
                       "key": [d / "ex" / "off.toml"]}.items():
        r = CliRunner().invoke(cli, ["run", *map(str, args), "-o", str(d / name), "--quiet"])
        assert r.exit_code == 0, r.output
        out[name] = d / name
    return out


def _files(folder: Path) -> set[str]:
    return {p.name for p in folder.iterdir() if not p.name.startswith(".")}


def test_pictures_drawn_by_default(runs):
    assert PNGS <= _files(runs["with"])


@pytest.mark.parametrize("how", ["flag", "key"])
def test_no_pictures_writes_everything_else_and_proves_the_same(runs, how):
    files = _files(runs[how])
    assert not files & PNGS
    assert files == _files(runs["with"]) - PNGS
    assert (runs[how] / "program.ngc").read_text() == (runs["with"] / "program.ngc").read_text()
    a = json.loads((runs[how] / "report.json").read_text())["verification"]
    b = json.loads((runs["with"] / "report.json").read_text())["verification"]
    assert a == b
