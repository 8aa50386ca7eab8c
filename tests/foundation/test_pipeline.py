"""`millpath run` end to end on a small job: files, report keys, verification, and
atomic output when something fails while writing."""

import json

import pytest

from millpath.errors import MillpathError
from millpath.io.tooltable import read_tool_table
from millpath.pipeline import run_job
from support.rs274 import run_rs274


def test_run_writes_program_tools_report_and_pictures(tmp_path, job_file):
    out = tmp_path / "out"
    res = run_job(job_file, out)
    names = sorted(f.name for f in out.iterdir() if not f.name.startswith("."))
    assert names == ["deviation.png", "preview.png", "program.ngc", "report.json",
                     "stock.png", "tools.tbl", "view.html"]
    rep = json.loads((out / "report.json").read_text())
    assert rep["units"] == "mm" and rep["program"] == "program.ngc"
    assert rep["lines"] == (out / "program.ngc").read_text().count("\n")
    assert rep["moves"]["rapid"] == 2 and rep["moves"]["line"] == 5 and rep["moves"]["arc"] == 1
    assert rep["operations"][0]["type"] == "test-square"
    assert rep["operations"][0]["cycle_time_s"] > 0
    assert rep["cycle_time_s"] == pytest.approx(rep["operations"][0]["cycle_time_s"])
    assert rep["plans"] == [{"operation": 0, "type": "test-square", "test": {"planned": 8}}]
    v = rep["verification"]
    for key in ("removed_volume", "max_gouge", "max_left", "left_volume",
                "rapids_through_material", "holder_contacts", "cycle_time_s", "resolution"):
        assert key in v
    # the outline cut 2 mm deep with a 6 mm cutter never goes below its design
    assert v["max_gouge"] <= v["resolution"]
    assert v["removed_volume"] > 0
    (entry,) = read_tool_table(out / "tools.tbl")
    assert entry.number == 1 and entry.diameter == 6 and entry.z == pytest.approx(70)
    assert res.report == rep | {"seconds": rep["seconds"]}


def test_written_program_is_accepted_by_rs274(tmp_path, job_file, rs274):
    run_job(job_file, tmp_path / "out")
    r = run_rs274((tmp_path / "out" / "program.ngc").read_text(),
                  read_tool_table(tmp_path / "out" / "tools.tbl"), table_units="mm")
    assert r.ok, r.error


def test_failure_while_writing_leaves_the_output_folder_unchanged(tmp_path, job_file,
                                                                  monkeypatch):
    out = tmp_path / "out"
    out.mkdir()
    (out / "report.json").write_text("{}")

    def broken(*a, **k):
        raise MillpathError("disk full (simulated)")

    import millpath.report.preview as preview
    monkeypatch.setattr(preview, "render_preview", broken)
    with pytest.raises(MillpathError, match="disk full"):
        run_job(job_file, out)
    assert [f.name for f in out.iterdir()] == ["report.json"]
    assert not list(tmp_path.glob(".out.staging*"))
