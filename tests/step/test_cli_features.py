"""``millpath features PART.stp [--json]``."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from click.testing import CliRunner

from millpath.cli.main import cli

FIXTURES = Path(__file__).parent / "fixtures"


def test_table_lists_stock_units_material_and_features():
    r = CliRunner().invoke(cli, ["features", str(FIXTURES / "slots_pockets.stp")])
    assert r.exit_code == 0, r.output
    assert "units: length mm" in r.output
    assert "material: aluminium 6082" in r.output
    assert "stock: block" in r.output and "length 160" in r.output
    for word in ("SLOT", "POCKET", "SQUARE_U_PROFILE", "RECTANGULAR_CLOSED_PROFILE",
                 "NGON_CLOSED_PROFILE", "SLOT_END 'radiused'"):
        assert word in r.output, word


def test_json_output(shared_dir):
    r = CliRunner().invoke(cli, ["features", str(shared_dir / "step" / "ap224_995277945.stp"),
                                 "--json"])
    assert r.exit_code == 0, r.output
    doc = json.loads(r.output)
    assert doc["units"]["length"] == "inch"
    assert doc["stock"]["shape"] == "cylinder"
    assert doc["material"].startswith("phosphor bronze")
    assert len(doc["features"]) == 14
    assert {u["type"] for u in doc["unmachinable"]} >= {"THREAD", "OUTER_ROUND", "ROUND_HOLE"}


@pytest.mark.parametrize("record, message", [
    ("#2=B('x);", "unterminated string"),
    ("#2=B(#9);", "dangling reference #9"),
    ("#2=B(1.5.2);", "bad number '1.5.2'"),
])
def test_malformed_file_prints_one_line_and_exits_1(tmp_path, record, message):
    bad = tmp_path / "bad.stp"
    bad.write_text("ISO-10303-21;\nHEADER;\nENDSEC;\nDATA;\n#1=A(1);\n" + record +
                   "\nENDSEC;\nEND-ISO-10303-21;\n")
    r = CliRunner().invoke(cli, ["features", str(bad)])
    assert r.exit_code == 1
    assert r.output.strip().splitlines() == [f"millpath: error: {bad}:6: #2: {message}"]


def test_truncated_file_exits_1(tmp_path):
    bad = tmp_path / "cut.stp"
    bad.write_text("ISO-10303-21;\nHEADER;\nENDSEC;\nDATA;\n#1=A(1);\n#2=B((1,2),\n")
    r = CliRunner().invoke(cli, ["features", str(bad)])
    assert r.exit_code == 1
    line = r.output.strip()
    assert line.startswith(f"millpath: error: {bad}:") and "#2: truncated file" in line


def test_names_with_brackets_are_printed_verbatim(tmp_path):
    from millpath.part.step.build import Ap224Builder
    b = Ap224Builder("[BRACKETS]", units="mm", material="steel [S235] /bold")
    b.block(10.0, 10.0, 5.0)
    b.hole((5.0, 5.0, 5.0), 3.0, 2.0, bottom="flat", name="[red]hole")
    (tmp_path / "b.stp").write_text(b.text())
    r = CliRunner().invoke(cli, ["features", str(tmp_path / "b.stp")])
    assert r.exit_code == 0, r.output
    assert "material: steel [S235] /bold" in r.output and "[red]hole" in r.output


@pytest.mark.parametrize("setup", ["inf", "-1e308", "mm", "+z "])
def test_a_setup_that_is_no_axis_is_one_line(setup):
    """A --setup that names no axis of the stock is one error line naming the file."""
    part = FIXTURES / "slots_pockets.stp"
    r = CliRunner().invoke(cli, ["features", str(part), "--setup", setup])
    assert r.exit_code == 1, r.output
    lines = r.output.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith(f"millpath: error: {part}: setup: one of")
