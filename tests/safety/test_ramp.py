"""AP224 in the RAMP conventions (issue 14 item 2 and 3): a bore written from its
bottom with the axis +Z and a hole at its bottom written from the bore floor with the
axis -Z are read, planned and machined where the file puts them; with tools too short
the run is refused with the reach message and writes no program."""

import json
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner

from millpath.cli.main import cli
from millpath.part.step.ap224 import read_part
from millpath.part.step.shapes import feature_shapes

FIXTURE = Path(__file__).resolve().parent / "fixtures" / "ramp_bore.stp"

LONG_TOOLS = """
[[tools]]
number = 1
type = "flat"
diameter = 10.0
flutes = 3
flute_length = 90.0
stickout = 100.0
holder = [[40.0, 60.0]]
"""
SHORT_TOOLS = """
[[tools]]
number = 1
type = "flat"
diameter = 10.0
flutes = 3
flute_length = 30.0
stickout = 45.0
holder = [[32.0, 50.0]]
"""


def _job(tmp_path, tools):
    (tmp_path / "part.stp").write_bytes(FIXTURE.read_bytes())
    p = tmp_path / "job.toml"
    p.write_text('units = "mm"\n[simulation]\nresolution = 0.5\n' + tools
                 + '[[operations]]\ntype = "features"\nstep = "part.stp"\n')
    return p


def test_bore_from_its_bottom_and_hole_below_it_are_read_as_the_file_places_them():
    shapes = {s.id: s for s in feature_shapes(read_part(FIXTURE)).shapes}
    bore, hole = sorted(shapes.values(), key=lambda s: -s.diameter)
    # bore: origin z 7, axis +Z, 78 deep -> from its floor at 7 up to the bar top 85
    assert (bore.diameter, bore.z_top, bore.z_top - bore.depth) == (26.75, 85.0, 7.0)
    assert bore.bottom == "flat"
    # hole: origin z 7 on the bore floor, axis -Z, 7 long -> z 7 .. 0, out of the bar
    assert (hole.diameter, hole.z_top, hole.z_top - hole.depth) == (17.25, 7.0, 0.0)
    assert hole.bottom == "through"


def test_long_tools_machine_the_bore_then_the_hole_from_the_bore_floor(tmp_path):
    out = tmp_path / "out"
    r = CliRunner().invoke(cli, ["run", str(_job(tmp_path, LONG_TOOLS)), "-o", str(out),
                                 "--quiet"])
    assert r.exit_code == 0, r.stderr
    rep = json.loads((out / "report.json").read_text())
    planned = {p["id"]: p for p in rep["features"]["planned"]}
    hole = next(p for p in planned.values() if p["z"] < 0)
    assert hole["z_start"] == pytest.approx(7.0)        # never from the stock top at 85
    v = rep["verification"]
    assert v["holder_contacts"] == 0 and v["rapids_through_material"] == 0
    assert v["max_gouge"] <= v["resolution"] and rep["safety"]["status"] == "ok"
    assert (out / "program.ngc").exists()


def test_tools_too_short_refuse_with_the_reach_message(tmp_path):
    out = tmp_path / "out"
    job = _job(tmp_path, SHORT_TOOLS)
    r = CliRunner().invoke(cli, ["run", str(job), "-o", str(out), "--quiet"])
    assert r.exit_code == 1
    (line,) = r.stderr.strip().splitlines()
    assert line.startswith("millpath: error: ")
    assert "HOLE #34: needs 78 mm of reach, the longest tool reaches 45" in line
    assert not (out / "program.ngc").exists()
