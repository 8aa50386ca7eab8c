"""``millpath check``: summary, JSON output and exit status."""

from __future__ import annotations

import json

import pytest
from click.testing import CliRunner

from millpath.cli.main import cli

GOOD = "G21 F100\nG0 X0 Y0 Z5\nG1 Z-1\nG2 X10 Y0 R5\nG4 P2\nM2\n"


def test_summary_counts_moves_bbox_length_and_time(tmp_path):
    p = tmp_path / "p.ngc"
    p.write_text(GOOD)
    r = CliRunner().invoke(cli, ["check", str(p)])
    assert r.exit_code == 0, r.output
    assert "traverse 1, feed 1, arc 1, dwell 1" in r.output
    assert "Y -0.0000 .. 5.0000" in r.output or "Y 0.0000 .. 5.0000" in r.output
    # feed length: 6 (plunge) + pi * 5 (half circle)
    assert f"feed length {6 + 3.141592653589793 * 5:.3f} mm" in r.output


def test_json_has_units_moves_and_null_error(tmp_path):
    p = tmp_path / "p.ngc"
    p.write_text(GOOD)
    r = CliRunner().invoke(cli, ["check", str(p), "--json"])
    assert r.exit_code == 0
    d = json.loads(r.output)
    assert d["units"] == "mm" and d["error"] is None
    arc = [m for m in d["moves"] if m["kind"] == "arc"][0]
    assert arc["plane"] == "XY" and arc["rotation"] == -1
    assert arc["center"] == pytest.approx([5.0, 0.0, -1.0])
    assert set(d["moves"][0]) >= {"kind", "line", "start", "end", "feed", "tool_offset"}


def test_error_exits_1_with_motion_before_the_block(tmp_path):
    p = tmp_path / "bad.ngc"
    p.write_text("G21\nG0 X1\nG1 X2\nM2\n")
    r = CliRunner().invoke(cli, ["check", str(p), "--json"])
    assert r.exit_code == 1
    d = json.loads(r.output)
    assert d["error"] == {"line": 3, "message": "Cannot do g1 with zero feed rate"}
    assert len(d["moves"]) == 1
    r = CliRunner().invoke(cli, ["check", str(p)])
    assert r.exit_code == 1
    assert f"{p}:3: Cannot do g1 with zero feed rate" in r.output


def test_tool_table_and_machine_units(tmp_path):
    p = tmp_path / "t.ngc"
    p.write_text("G21\nT1 M6 G43\nG0 Z0\nM2\n")
    t = tmp_path / "tools.tbl"
    t.write_text("T1 P1 D6 Z50 ;mill\n")
    r = CliRunner().invoke(cli, ["check", str(p), "--tools", str(t), "--machine-units", "mm",
                                 "--json"])
    d = json.loads(r.output)
    assert d["moves"][0]["tool_offset"] == [0.0, 0.0, 50.0]
    r = CliRunner().invoke(cli, ["check", str(p), "--tools", str(t), "--json"])
    d = json.loads(r.output)
    assert d["moves"][0]["tool_offset"][2] == 50.0 * 25.4


def test_bounding_box_is_the_motion_without_the_start_point(tmp_path):
    """The machine starts at X0 Y0 Z0; the box covers only where the program moves the
    tool: the ends of the moves (the quarter arc about X20 Y15 adds no extreme point)."""
    p = tmp_path / "p.ngc"
    p.write_text("G21 F100\nG0 X10 Y10 Z5\nG1 X20\nG3 X25 Y15 R5\nG1 Z2\nM2\n")
    r = CliRunner().invoke(cli, ["check", str(p)])
    assert r.exit_code == 0, r.output
    assert "X 10.0000 .. 25.0000  Y 10.0000 .. 15.0000  Z 2.0000 .. 5.0000" in r.output
