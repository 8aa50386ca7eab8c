"""Grid-free gouge and material left against analytic truths.

Designs are triangles built here from planes (a vertical wall, 30 and 80 degree slopes);
tool positions are placed so that the cutter reaches a known distance past (gouge) or
short of (material left) the design, measured along the design's normal. Every figure
must equal that truth within 0.002 mm at the default accuracy (0.001 mm).
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
from click.testing import CliRunner

from millpath.cli.main import cli
from millpath.interpret import interpret
from millpath.model import Stock, Tool
from millpath.model.motion import Motion
from millpath.simulate.exact import Reference, verify_exact
from millpath.simulate.approach import approach_from_above

TOL = 0.002
TOOLS = {"flat": Tool(1, "flat", 6.0, flute_length=20, stickout=30),
         "ball": Tool(1, "ball", 6.0, flute_length=20, stickout=30),
         "bull": Tool(1, "bull", 6.0, corner_radius=1.0, flute_length=20, stickout=30)}


def _quad(a, b, c, d):
    return [[a, b, c], [a, c, d]]


def _wall() -> np.ndarray:
    """The plane x = 0 (part at x < 0), y in [-20, 20], z in [-10, 0]; normal +X."""
    return np.array(_quad((0, -20, -10), (0, 20, -10), (0, 20, 0), (0, -20, 0)), float)


def _passes(xs, z, y0=-30.0, y1=30.0):
    """Feed motions: one pass along Y per X, at tip height z, from above the stock."""
    out, pos = [], (xs[0], y0, 20.0)
    for x in xs:
        for p in ((x, y0, 20.0), (x, y0, z), (x, y1, z), (x, y1, 20.0)):
            if p != pos:
                out.append(Motion("feed", len(out) + 1, pos, p, feed=500, tool=1))
            pos = p
    return out


@pytest.mark.parametrize("kind", ["flat", "ball", "bull"])
@pytest.mark.parametrize("offset", [-0.02, 0.05])
def test_vertical_wall(kind, offset):
    # tool axis R + offset from the wall, tip below the stock: the side of the cutter
    # sweeps the whole wall; further passes clear the rest of the stock
    stock = Stock(-20, -20, -10, 20, 20, 0)
    xs = [3.0 + offset + 4.0 * i for i in range(6)]
    r = verify_exact(_passes(xs, -14.0), {1: TOOLS[kind]}, stock, [Reference(_wall(), "wall")])
    if offset < 0:
        assert r.max_gouge == pytest.approx(-offset, abs=TOL)
        assert r.gouging_moves == 1
        assert r.gouge_at["x"] == pytest.approx(0.0, abs=1e-6)
        assert r.gouge_at["line"] == 2           # the first pass along the wall
        assert r.max_left == pytest.approx(0.0, abs=TOL)
    else:
        assert r.max_gouge == 0.0 and r.gouging_moves == 0
        assert r.max_left == pytest.approx(offset, abs=TOL)
        assert r.left_at["x"] == pytest.approx(0.0, abs=1e-6)


def _slope(alpha_deg: float, half: float = 1.0):
    """A patch of the plane through the origin with normal (sin a, 0, cos a): 2*half
    wide down the slope, y in [-5, 5]. Returns (triangles, normal, downhill unit)."""
    a = math.radians(alpha_deg)
    n = np.array([math.sin(a), 0.0, math.cos(a)])
    t = np.array([math.cos(a), 0.0, -math.sin(a)])
    ey = np.array([0.0, 1.0, 0.0])
    c = [(-half * t - 5 * ey), (half * t - 5 * ey), (half * t + 5 * ey), (-half * t + 5 * ey)]
    return np.array(_quad(*c), float), n, t


def _tip_for(kind: str, n: np.ndarray, contact: np.ndarray, off: float) -> np.ndarray:
    """Tool tip whose cutter surface comes nearest the plane (normal ``n``) above
    ``contact``, ``off`` from it (negative: into it). The nearest point of the tube-centre
    circle (radius a = R - rc, height rc above the tip; a ball is a = 0, rc = R) lies on
    the normal through ``contact`` at rc + off; the axis is a further a uphill."""
    tool = TOOLS[kind]
    R, rc = tool.radius, tool.corner_radius
    a = R - rc
    uphill = np.array([n[0], n[1], 0.0]) / math.hypot(n[0], n[1])
    return contact + n * (rc + off) + a * uphill - np.array([0.0, 0.0, rc])


@pytest.mark.parametrize("kind", ["ball", "bull"])
@pytest.mark.parametrize("alpha", [30.0, 80.0])
def test_slope_gouge(kind, alpha):
    tri, n, t = _slope(alpha)
    tip = _tip_for(kind, n, np.zeros(3), -0.02)
    mo = [Motion("feed", 7, tuple(tip + [0, -8, 0]), tuple(tip + [0, 8, 0]), 500, tool=1)]
    stock = Stock(-10, -10, -10, 10, 10, 10)
    r = verify_exact(mo, {1: TOOLS[kind]}, stock, [Reference(tri, "slope")])
    assert r.max_gouge == pytest.approx(0.02, abs=TOL)
    assert r.gouge_at["line"] == 7
    # the deepest point is where the cutter touches the plane, on the patch's midline
    assert abs(float(np.dot([r.gouge_at[k] for k in "xyz"], t))) < 0.05


@pytest.mark.parametrize("kind", ["ball", "bull"])
@pytest.mark.parametrize("alpha", [30.0, 80.0])
def test_slope_material_left(kind, alpha):
    # passes 0.1 apart down the slope, each 0.05 off the plane: the scallops add at most
    # 0.1^2 / (8 rc) <= 0.0013 on the bull's corner, 0.0004 on the ball
    tri, n, t = _slope(alpha)
    mo, pos = [], None
    for i, s in enumerate(np.arange(-4.0, 4.0001, 0.1)):
        tip = _tip_for(kind, n, s * t, 0.05)
        a, b = tip + [0, -8, 0], tip + [0, 8, 0]
        if i % 2:
            a, b = b, a
        if pos is not None:
            mo.append(Motion("feed", len(mo) + 1, tuple(pos), tuple(a), 500, tool=1))
        mo.append(Motion("feed", len(mo) + 1, tuple(a), tuple(b), 500, tool=1))
        pos = b
    lo = tri.reshape(-1, 3).min(axis=0) - 0.5
    hi = tri.reshape(-1, 3).max(axis=0) + 0.5
    stock = Stock(lo[0], lo[1], lo[2], hi[0], hi[1], hi[2])
    r = verify_exact(mo, {1: TOOLS[kind]}, stock, [Reference(tri, "slope")])
    assert r.max_gouge == 0.0
    scallop = 0.1 ** 2 / (8 * TOOLS[kind].corner_radius)
    assert 0.05 - TOL <= r.max_left <= 0.05 + scallop + TOL


def _comp_program(code: str, xw: float) -> str:
    """A contour along the wall x = xw under G41 (travel -Y) or G42 (travel +Y): the
    tool stays on the +X side, its side R from the programmed path."""
    if code == "G42":
        a, b, c, d = (10, -30), (xw, -25), (xw, 25), (10, 30)
    else:
        a, b, c, d = (10, 30), (xw, 25), (xw, -25), (10, -30)
    return "\n".join([
        "G21 G90 G17 G40 G49 G80", "T1 M6 G43 H1", f"G0 X{a[0]} Y{a[1]} Z5", "G1 Z-12 F500",
        f"{code} G1 X{b[0]:.4f} Y{b[1]}", f"G1 X{c[0]:.4f} Y{c[1]}", f"G40 G1 X{d[0]} Y{d[1]}",
        "G0 Z5", "M2", ""])


@pytest.mark.parametrize("code", ["G41", "G42"])
@pytest.mark.parametrize("offset", [-0.02, 0.05])
def test_compensated_contour(code, offset):
    tool = TOOLS["flat"]
    motions = interpret(_comp_program(code, offset), {1: tool}, machine_units="mm")
    stock = Stock(-20, -20, -10, 5, 20, 0)
    motions = approach_from_above(list(motions), stock.zmax)
    r = verify_exact(motions, {1: tool}, stock, [Reference(_wall(), "wall")])
    if offset < 0:
        assert r.max_gouge == pytest.approx(0.02, abs=TOL)
        assert r.gouge_at["line"] == 6          # the contour block
    else:
        assert r.max_gouge == 0.0
        assert r.max_left == pytest.approx(0.05, abs=TOL)


def _write_stl(path, tri):
    from stl import mesh
    m = mesh.Mesh(np.zeros(len(tri), dtype=mesh.Mesh.dtype))
    m.vectors[:] = tri
    m.save(str(path))


def test_cli_design_is_used_and_reported(tmp_path):
    _write_stl(tmp_path / "part.stl", _wall())
    (tmp_path / "p.ngc").write_text(_comp_program("G42", -0.02))
    (tmp_path / "t.tbl").write_text("T1 P1 D6 Z50\n")
    res = CliRunner().invoke(cli, ["simulate", str(tmp_path / "p.ngc"), "--tools",
                                   str(tmp_path / "t.tbl"), "--stock", "-20,-20,-10,5,20,0",
                                   "--design", str(tmp_path / "part.stl"), "--json",
                                   "--machine-units", "mm"])
    assert res.exit_code == 0, res.output
    j = json.loads(res.output)
    assert j["max_gouge"] == pytest.approx(0.02, abs=TOL)
    assert j["reference"] == "part.stl"
    assert j["accuracy"] == 0.001
    assert j["gouging_moves"] == 1
    assert set(j["max_gouge_at"]) == {"x", "y", "z", "line", "operation"}
    assert j["by_operation"][0]["max_gouge"] == pytest.approx(0.02, abs=TOL)


@pytest.mark.parametrize("case", ["nan", "empty", "outside", "garbage"])
def test_cli_bad_design(tmp_path, case):
    p = tmp_path / "part.stl"
    tri = _wall()
    if case == "nan":
        tri[0, 0, 0] = np.nan
        _write_stl(p, tri)
    elif case == "empty":
        _write_stl(p, tri[:0])
    elif case == "outside":
        _write_stl(p, tri * 25.4 + 1000.0)        # inches read as mm, far away
    else:
        p.write_bytes(b"solid x\nfacet normal 0 0 1\n outer loop\n vertex 1 2\n")
    (tmp_path / "p.ngc").write_text(_comp_program("G42", 0.05))
    (tmp_path / "t.tbl").write_text("T1 P1 D6 Z50\n")
    res = CliRunner().invoke(cli, ["simulate", str(tmp_path / "p.ngc"), "--tools",
                                   str(tmp_path / "t.tbl"), "--stock", "-20,-20,-10,5,20,0",
                                   "--design", str(p), "--json",
                                   "--machine-units", "mm"])
    assert res.exit_code == 1
    out = res.output.strip()
    assert "Traceback" not in out and len(out.splitlines()) == 1, out
    assert out.startswith("millpath: error: ") and "part.stl" in out


@pytest.mark.parametrize("kind,alpha", [("flat", 30.0), ("flat", 80.0), ("drill", 30.0)])
def test_sharp_edge_on_slope(kind, alpha):
    """A flat end mill's rim, or a drill's point, 0.02 below a slope along its normal:
    the gouge is 0.02 (not the depth of the largest ball inside the tool, which is
    smaller by the factor sin a + cos a at a rim)."""
    tri, n, t = _slope(alpha)
    tool = TOOLS[kind] if kind in TOOLS else Tool(1, "drill", 6.0, flute_length=20,
                                                  stickout=30, point_angle=118.0)
    deepest = -0.02 * n                        # the rim / point, 0.02 inside the part
    # a flat mill's lowest point along n is the rim point downhill of its axis
    tip = deepest + (np.array([tool.radius, 0.0, 0.0]) if kind == "flat" else 0.0)
    mo = [Motion("feed", 5, tuple(tip + [0, -3, 0]), tuple(tip + [0, 3, 0]), 500, tool=1)]
    stock = Stock(-10, -10, -10, 10, 10, 10)
    r = verify_exact(mo, {1: tool}, stock, [Reference(tri, "slope")])
    assert r.max_gouge == pytest.approx(0.02, abs=TOL)
    assert r.gouge_at["line"] == 5
    assert np.allclose([r.gouge_at[k] for k in "xz"], [0.0, 0.0], atol=1e-6)
