"""Pockets and profiles from a DXF follow its arcs and circles, never into the material.

Truth: the curves the test draws with ezdxf (centres, radii, lines), measured
analytically (distance to a centre minus the radius, distance to a line); not the
reader's polygons. The bound is the one the drawing keys state: 1/20 of the tolerance
(0.01 mm by default), every wall on the air side of the drawn one."""

from __future__ import annotations

import math
from pathlib import Path

import ezdxf
import numpy as np
import pytest

from millpath.io.schema import validate
from millpath.model import Machine, Stock, Tool
from millpath.plan.base import PlanContext
from millpath.plan.pocket import operation as pocket
from millpath.plan.profile import operation as profile
from millpath.plan.twod.geometry import load_regions

TOL = 0.01                      # the drawing tolerance's default, mm
BOUND = TOL / 20                # the stated bound
EPS = 1e-9                      # floating point slack, mm
TOP, DEPTH = 0.0, 3.0

# the pocket: 0 <= x <= 100, 0 <= y <= 60, its right side a half circle bulging out
# (ARC centre (100, 30), r 30), its top with a half-round notch of material coming in
# (ARC centre (50, 60), r 20, the lower half); a round island (CIRCLE (25, 25), r 10)
BULGE = ((100.0, 30.0), 30.0)
NOTCH = ((50.0, 60.0), 20.0)
ISLAND = ((25.0, 25.0), 10.0)
LINES = [((0, 0), (100, 0)), ((100, 60), (70, 60)), ((30, 60), (0, 60)), ((0, 60), (0, 0))]


def _drawing(tmp_path: Path) -> str:
    doc = ezdxf.new("R2010")
    doc.header["$INSUNITS"] = 4
    msp = doc.modelspace()
    for a, b in LINES:
        msp.add_line(a, b)
    msp.add_arc(BULGE[0], BULGE[1], -90, 90)          # (100, 0) -> (130, 30) -> (100, 60)
    msp.add_arc(NOTCH[0], NOTCH[1], 180, 360)         # (30, 60) -> (50, 40) -> (70, 60)
    msp.add_circle(ISLAND[0], ISLAND[1])
    p = tmp_path / "part.dxf"
    doc.saveas(p)
    return str(p)


def _to_air(p: np.ndarray):
    """Signed distances (n, k) of points ``p`` (n, 2) to each drawn piece, positive on
    the pocket's (air) side; NaN where the point's foot is off the piece."""
    cols = []
    for (a, b) in LINES:
        a, b = np.asarray(a, float), np.asarray(b, float)
        d = b - a
        L = math.hypot(*d)
        t = ((p - a) @ d) / (L * L)
        left = (d[0] * (p[:, 1] - a[1]) - d[1] * (p[:, 0] - a[0])) / L   # air on the left
        cols.append(np.where((t >= -EPS) & (t <= 1 + EPS), left, np.nan))
    for (c, r), air_outside, (lo, hi) in ((BULGE, False, (-90, 90)), (NOTCH, True, (180, 360)),
                                          (ISLAND, True, (0, 360))):
        v = p - np.asarray(c)
        rho = np.hypot(v[:, 0], v[:, 1])
        ang = np.degrees(np.arctan2(v[:, 1], v[:, 0]))
        on = ((ang - lo) % 360.0 <= (hi - lo) + 1e-6) | (hi - lo >= 360)
        cols.append(np.where(on, (rho - r) if air_outside else (r - rho), np.nan))
    return np.column_stack(cols)


def _wall_points(tri: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """XY of every vertex and edge midpoint of the vertical triangles of ``tri``, and
    those triangles."""
    n = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    wall = tri[np.abs(n[:, 2]) <= 1e-12 * np.linalg.norm(n, axis=1)]
    mids = [(wall[:, i] + wall[:, j]) / 2 for i, j in ((0, 1), (1, 2), (2, 0))]
    return np.concatenate([wall.reshape(-1, 3)] + mids)[:, :2], wall


def _plan_area(tri: np.ndarray) -> float:
    """Area of triangles (n, 3, 3) seen from above."""
    n = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    return 0.5 * float(np.abs(n[:, 2]).sum())


def _ctx():
    tools = {1: Tool(1, "flat", 6.0)}
    stock = Stock(-10, -10, -10, 140, 70, TOP)
    return PlanContext("mm", stock, Machine(), tools, Path(".")), stock


def _pocket(tmp_path, strategy="offset"):
    ctx, stock = _ctx()
    keys = {"tool": 1, "dxf": _drawing(tmp_path), "depth": DEPTH, "stepdown": 3.0,
            "strategy": strategy, "feed": 1000.0}
    return pocket.plan(ctx, validate(keys, pocket.PARAMS, "op", None)), stock


def _centre_segments(tp, op=None) -> np.ndarray:
    """Feed moves below the top as (n, 2, 2) XY segments (lines; arcs by their ends
    and 64 chords' points, which only helix entries away from the walls make)."""
    segs, pos = [], None
    from millpath.model.toolpath import arc_geometry
    for m in tp.moves:
        if (pos is not None and m.kind in ("line", "arc") and min(pos[2], m.end[2]) < TOP - 1e-6
                and (op is None or m.op == op)):
            if m.kind == "line":
                segs.append((pos[:2], m.end[:2]))
            else:
                r, a0, sw, _ = arc_geometry(pos, m)
                c = np.asarray(m.center[:2])
                t = a0 + sw * np.linspace(0, 1, 65)
                q = c + r * np.column_stack([np.cos(t), np.sin(t)])
                segs += list(zip(q[:-1], q[1:]))
        if m.kind != "comp":
            pos = m.end
    return np.asarray(segs, float)


def _nearest_to(segs: np.ndarray, c) -> np.ndarray:
    """Distance of each segment (n, 2, 2) to the point ``c``."""
    a, b = segs[:, 0], segs[:, 1]
    d = b - a
    L2 = np.maximum((d * d).sum(1), 1e-300)
    t = np.clip(((np.asarray(c) - a) * d).sum(1) / L2, 0.0, 1.0)
    q = a + t[:, None] * d
    return np.hypot(*(q - c).T)


def test_design_walls_follow_the_drawn_curves_on_the_air_side(tmp_path):
    res, stock = _pocket(tmp_path)
    tri = res.design.mesh(stock.box)
    pts, wall = _wall_points(tri)
    s = _to_air(pts)
    near = np.nanargmin(np.abs(s), axis=1)
    d = s[np.arange(len(s)), near]
    # every wall point within the bound of the drawing, never in its material
    assert np.all(d >= -EPS), d.min()
    assert np.all(d <= BOUND + EPS), d.max()
    # and the curves themselves, by distance to their centres
    for (c, r), sign in ((ISLAND, 1.0), (NOTCH, 1.0), (BULGE, -1.0)):
        rho = np.hypot(*(pts - np.asarray(c)).T)
        on = np.abs(rho - r) < 0.1
        assert on.sum() > 100
        e = sign * (rho[on] - r)
        assert e.min() >= -EPS and e.max() <= BOUND + EPS, (c, e.min(), e.max())
    # walls face the air: the island's normals point away from its centre
    n = np.cross(wall[:, 1] - wall[:, 0], wall[:, 2] - wall[:, 0])[:, :2]
    m = wall[:, :, :2].mean(axis=1)
    isl = np.abs(np.hypot(*(m - ISLAND[0]).T) - ISLAND[1]) < 0.1
    assert np.all(((m[isl] - ISLAND[0]) * n[isl]).sum(1) > 0)
    # the mesh stays small: the island about pi sqrt(r / BOUND) chords, 2 triangles each
    chords = math.pi * math.sqrt(ISLAND[1] / BOUND)
    assert isl.sum() <= 2 * (1.1 * chords + 4), (isl.sum(), chords)
    # floor and top tile the stock box: areas of the horizontal triangles
    h = tri[np.abs(np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])[:, 2]) > 0]
    area = _plan_area(h)
    assert area == pytest.approx(150 * 80, rel=1e-9)
    # the height field agrees with the mesh's floor
    true_area = (100 * 60 + math.pi * 30 ** 2 / 2 - math.pi * 20 ** 2 / 2
                 - math.pi * 10 ** 2)
    fl = h[np.all(h[:, :, 2] == TOP - DEPTH, axis=1)]
    a_floor = _plan_area(fl)
    assert true_area - a_floor == pytest.approx(0.0, abs=BOUND * 500)   # perimeter about 450
    assert a_floor <= true_area


@pytest.mark.parametrize("strategy", ["offset", "adaptive"])
def test_pocket_tool_stays_out_of_the_drawn_island_and_notch(tmp_path, strategy):
    res, _ = _pocket(tmp_path, strategy)
    segs = _centre_segments(res.toolpath)
    R = 3.0
    for (c, r) in (ISLAND, NOTCH):
        gap = _nearest_to(segs, c).min() - (r + R)
        assert gap >= -1e-6, (c, gap)
        assert gap <= 0.05            # and it does go there
    # inside the bulge: no tool centre farther than 30 - R from its centre (x > 100)
    p = segs.reshape(-1, 2)
    p = p[p[:, 0] > 100]
    assert np.hypot(*(p - BULGE[0]).T).max() <= BULGE[1] - R + 1e-6


def test_outside_profile_contour_holds_the_drawn_circle(tmp_path):
    """An outside profile's contour is the circle's or outside it (its air outside)."""
    keys = {"dxf": _drawing(tmp_path), "layer": None, "join_tolerance": None,
            "polygon": None, "islands": None, "tolerance": None}
    inside = load_regions(keys, "mm")
    outside = load_regions({**keys, "side": "outside"}, "mm")
    for regs, sign in ((inside, -1.0), (outside, 1.0)):
        # the outline's bulge: pocket contour inside the arc, profile contour outside
        ring = np.asarray(regs[0].polygon.exterior.coords)[:-1]
        sel = ring[:, 0] > 100 + 1e-6
        rho = np.hypot(*(ring[sel] - BULGE[0]).T)
        e = sign * (rho - BULGE[1])
        assert e.min() >= -EPS and e.max() <= BOUND + EPS
        # edge midpoints too (the chords' worst)
        mid = (ring + np.roll(ring, -1, axis=0)) / 2
        sel = mid[:, 0] > 100 + 1e-6
        e = sign * (np.hypot(*(mid[sel] - BULGE[0]).T) - BULGE[1])
        assert e.min() >= -EPS and e.max() <= BOUND + EPS
    # a planned outside profile keeps its 6 mm tool 3 mm off the drawn arc
    ctx, _ = _ctx()
    pkeys = {"tool": 1, "dxf": keys["dxf"], "side": "outside", "depth": DEPTH,
             "stepdown": 3.0, "feed": 1000.0}
    res = profile.plan(ctx, validate(pkeys, profile.PARAMS, "op", None))
    segs = _centre_segments(res.toolpath)
    near = _nearest_to(segs, BULGE[0])
    a = (segs[:, :, 0] > 100 + 1e-6).all(axis=1)
    assert near[a].min() - (BULGE[1] + 3.0) >= -1e-6
