"""G5.2/G5.3 NURBS blocks: the motion, the errors and the curve LinuxCNC makes of them.

Truths: LinuxCNC's rs274 (same motion and errors, block by block), LinuxCNC's own
flattening of the curve in its ``gcode`` Python module (the AXIS preview parser, full
double precision), and an exact rational quadratic quarter circle.
"""

from __future__ import annotations

import importlib.util
import math
import subprocess
import sys

import numpy as np
import pytest

from millpath.interpret import run
from support.difftest import differential
from millpath.model.nurbs import Nurbs

QUARTER = """G21 G17 G90 F300
G0 X10 Y0 Z-1
G5.2 X10 Y10 P0.7071067811865476
X0 Y10 P1
G5.3
G1 X0 Y0
M2
"""

HAND = {
    "quarter": QUARTER,
    "order4_L": "G21 F100\nG0 X0 Y0\nG5.2 X1 Y2 P1 L4\nX3 Y2 P2\nX4 Y0 P1\nX6 Y1 P1\nG5.3\n"
                "G1 Z-1\nM2\n",
    "first_weight_without_xy": "G21 F100\nG0 X1 Y1\nG5.2 P3\nX2 Y3 P1\nX4 Y1 P1\nG5.3\n"
                               "G0 Z1\nM2\n",
    "incremental": "G21 G91 F100\nG0 X1 Y1\nG5.2 X1 Y1 P1\nX2 Y0 P1\nX3 Y-1 P1\nG5.3\n"
                   "G1 X1\nM2\n",
    "g53_after_tool_change": "G21 F100\nT1 M6\nG0 X1 Y1\nG5.2 X2 Y3 P1\nX4 Y1 P1\nG5.3\n"
                             "T2 M6\nG1 Y5\nM2\n",
    "g5_then_m6_away_from_origin": "G21 F100\nT1 M6\nG0 X7 Y8 Z2\nG5 X2 Y3 I1 J0 P1 Q1\n"
                                   "G4 P1\nT2 M6\nG1 X9\nM2\n",
    "nurbs_then_move_then_m6": "G21 F100\nT1 M6\nG0 X7 Y8 Z2\nG5.2 X2 Y3 P1\nX4 Y1 P1\n"
                               "G5.3\nG0 Z3\nT2 M6\nG1 Z5\nM2\n",
    "g53_without_g52": "G21 F100\nG0 X1\nG5.3\nM2\n",
    "fewer_points_than_order": "G21 F100\nG5.2 X1 Y1 P1 L5\nX2 Y0 P1\nG5.3\nM2\n",
    "weight_missing": "G21 F100\nG5.2 X1 Y1 P1\nX2 Y0\nG5.3\nM2\n",
    "p_without_xy_later": "G21 F100\nG5.2 X1 Y1 P1\nP2\nG5.3\nM2\n",
    "x_without_y": "G21 F100\nG5.2 X1 P1\nG5.3\nM2\n",
    "zero_feed": "G21\nG5.2 X1 Y1 P1\nM2\n",
    "axis_after_g53": "G21 F100\nG5.2 X1 Y1 P1\nX2 Y0 P1\nG5.3\nX3 Y3\nM2\n",
    "interrupted_by_g1": "G21 F100\nG5.2 X1 Y1 P1\nX2 Y0 P1\nG1 X3\nG5.3\nM2\n",
}


@pytest.mark.parametrize("name", sorted(HAND))
def test_hand_written_against_rs274(rs274, name):
    from millpath.io.tooltable import ToolEntry
    tools = [ToolEntry(1, 1, 0.25, {"Z": 1.0}), ToolEntry(2, 2, 0.1, {"Z": 0.5})]
    c = differential(HAND[name], tools, machine_units="inch")
    assert c.same, str(c)


def _nurbs_programs(shared_dir):
    root = shared_dir / "linuxcnc" / "nc_files" / "nurbs"
    files = sorted(root.rglob("*.ngc"))
    if not files:
        pytest.skip("no NURBS programs under shared/linuxcnc/nc_files/nurbs")
    return files


def test_linuxcnc_nurbs_programs_against_rs274(rs274, shared_dir):
    """LinuxCNC's G5 (and G6.2, which rs274 rejects) sample programs: same motion or
    the same failing block."""
    bad = []
    for f in _nurbs_programs(shared_dir):
        c = differential(f.read_text(errors="replace"), None, machine_units="inch")
        if not c.same:
            bad.append(f"{f.name}: {c}")
    assert not bad, "\n".join(bad)


def _gcode_oracle(shared_dir):
    path = shared_dir / "tools" / "rs274_oracle.py"
    if not path.is_file():
        pytest.skip("shared/tools/rs274_oracle.py missing")
    probe = subprocess.run(["/usr/bin/python3", "-c", "import gcode"], capture_output=True)
    if probe.returncode != 0:
        pytest.skip("LinuxCNC's gcode module is not importable by /usr/bin/python3")
    spec = importlib.util.spec_from_file_location("rs274_oracle", path)
    mod = importlib.util.module_from_spec(spec)
    sys.modules["rs274_oracle"] = mod          # its dataclasses look themselves up there
    spec.loader.exec_module(mod)
    return mod


def _linuxcnc_parameters(curve: Nurbs) -> np.ndarray:
    """The parameters at which LinuxCNC's preview flattens a NURBS (15 per point)."""
    umax = curve.umax
    div = 15 * len(curve.points)
    u, out = 0.0, []
    while u + umax / div < umax:
        out.append(u + umax / div)
        u += umax / div
    return np.array(out)


@pytest.mark.parametrize("name", ["butterfly-xy.ngc", "leto-xy.ngc", "trident-xy.ngc",
                                  "nurbs-xy.ngc"])
def test_curve_matches_linuxcnc_flattening(shared_dir, name, tmp_path, monkeypatch):
    """Every point LinuxCNC's gcode module puts on a G5.3 curve is our curve's point at
    the same parameter (1e-6 mm), and the curve ends where LinuxCNC's does."""
    oracle = _gcode_oracle(shared_dir)
    monkeypatch.chdir(tmp_path)          # the module writes rs274ngc.var where it runs
    path = shared_dir / "linuxcnc" / "nc_files" / "nurbs" / "G5" / name
    ref = oracle.run_gcode_module(str(path))
    assert ref.error is None
    ours = run(path, None, machine_units="inch")
    assert ours.error is None
    curves = [m for m in ours.motions if m.kind == "nurbs"]
    assert curves
    feeds = [m for m in ref.motions if m.kind == "feed"]
    checked = 0
    for mo in curves:
        # the preview's feeds of this G5.3 line, in order: flattened points, then the end
        pts = [m.end for m in feeds if m.line == mo.line]
        curve = mo.controls
        want = curve.evaluate(_linuxcnc_parameters(curve))
        assert len(pts) == len(want) + 1
        got = np.array([p[:2] for p in pts])
        assert np.max(np.abs(got[:-1] - want)) <= 1e-6
        assert np.max(np.abs(got[-1] - np.array(mo.end[:2]))) <= 1e-9
        assert all(abs(p[2] - mo.start[2]) <= 1e-9 for p in pts)
        checked += 1
    assert checked == len(curves)


def test_quarter_circle_is_exact_and_sampled_within_tolerance():
    """A rational quadratic with middle weight cos 45 deg is a circular arc."""
    c = Nurbs(3, ((10.0, 0.0, 1.0), (10.0, 10.0, math.sqrt(0.5)), (0.0, 10.0, 1.0)))
    u = np.linspace(0.0, c.umax, 1001)
    p = c.evaluate(u)
    assert np.max(np.abs(np.hypot(p[:, 0], p[:, 1]) - 10.0)) <= 1e-12
    for tol in (0.1, 0.01, 0.001):
        s = c.sample(tol)
        # the sagitta of each chord of a circle of radius 10
        half = np.hypot(*np.diff(s, axis=0).T) / 2.0
        sag = 10.0 - np.sqrt(100.0 - half ** 2)
        assert sag.max() <= tol + 1e-12
        assert np.allclose(s[0], (10, 0)) and np.allclose(s[-1], (0, 10))
    assert abs(c.length() - 5 * math.pi) <= 1e-5


def test_check_summary_of_a_nurbs_quarter_circle(tmp_path):
    """``millpath check``: the NURBS move counted, its length pi R / 2, the bounding box
    holding the arc (the curve's corner control point (10, 10) is outside it)."""
    from click.testing import CliRunner
    from millpath.cli.main import cli
    ngc = tmp_path / "q.ngc"
    ngc.write_text(QUARTER)
    r = CliRunner().invoke(cli, ["check", str(ngc), "--json"])
    assert r.exit_code == 0, r.output
    import json
    moves = json.loads(r.output)["moves"]
    nurbs = [m for m in moves if m["kind"] == "nurbs"]
    assert len(nurbs) == 1 and nurbs[0]["order"] == 3 and nurbs[0]["end"] == [0, 10, -1]
    from millpath.cli.check import summary
    from millpath.interpret import interpret
    s = summary(interpret(QUARTER), "mm")
    assert s["moves"]["nurbs"] == 1
    assert abs(s["feed_length"] - (5 * math.pi + 10.0)) <= 1e-4
    lo, hi = s["bbox"]
    assert max(abs(a - b) for a, b in zip(lo, (0.0, 0.0, -1.0))) <= 1e-9
    assert max(abs(a - b) for a, b in zip(hi, (10.0, 10.0, -1.0))) <= 1e-9
    # an arc from -45 to 45 degrees: its corner control point (10 sqrt 2, 0) is not in
    # the box, its middle (10, 0) is (within the sampling tolerance, 1e-4 of its size)
    r = 10 * math.sqrt(0.5)
    arc = (f"G21 F100\nG0 X{r:.12f} Y{-r:.12f}\nG5.2 X{2 * r:.12f} Y0 P{math.sqrt(0.5):.15f}\n"
           f"X{r:.12f} Y{r:.12f} P1\nG5.3\nM2\n")
    lo, hi = summary(interpret(arc), "mm")["bbox"]
    assert 10.0 - 2e-3 <= hi[0] <= 10.0 + 1e-9
    assert abs(lo[0] - r) <= 1e-9 and abs(lo[1] + r) <= 1e-9 and abs(hi[1] - r) <= 1e-9
    # no point of the sampled arc beyond the circle: x + y <= 10 sqrt 2
    from millpath.simulate.path import motion_points
    pts = motion_points(nurbs_motion(QUARTER), 1e-3)
    assert np.max(np.hypot(pts[:, 0], pts[:, 1])) <= 10.0 + 1e-9
    assert np.min(np.hypot(pts[:, 0], pts[:, 1])) >= 10.0 - 1e-3 - 1e-9


def nurbs_motion(text):
    from millpath.interpret import interpret
    return next(m for m in interpret(text) if m.kind == "nurbs")
