"""Cutter offset with LinuxCNC's rules, checked against LinuxCNC's own rs274."""

from __future__ import annotations

import math

import numpy as np
import pytest
import shapely
from shapely.geometry import LineString, Polygon

from millpath.model import Tool
from millpath.part.curve.offset import (CompensationError, chords_on_offset, compensate,
                                        reachable_contour, sample_elements)


def _program(start, pts, side="left", feed=500.0):
    code = "G41" if side == "left" else "G42"
    lines = ["G21 G17 G90 G94 G40 G49", "T1 M6", "G43 H1",
             f"G0 X{start[0]:.4f} Y{start[1]:.4f} Z0", f"{code} D1"]
    lines += [f"G1 X{p[0]:.4f} Y{p[1]:.4f} F{feed}" for p in pts]
    lines += ["G40", f"G1 X{start[0]:.4f} Y{start[1]:.4f}", "M2", ""]
    return "\n".join(lines)


def _elements_to_points(start, elements):
    return np.array([e.end for e in elements])


def _wavy(n=40, seed=0):
    rng = np.random.default_rng(seed)
    a = np.linspace(0, 2 * np.pi, n, endpoint=False)
    rad = 50 + 6 * np.sin(3 * a) + rng.uniform(-0.5, 0.5, n)
    return np.round(np.stack([rad * np.cos(a), rad * np.sin(a)], 1), 4)


def test_square_convex_corner_gets_an_arc_and_concave_corner_is_trimmed():
    # a cavity (tool inside, counter-clockwise, G41): its corners are concave
    sq = [(0, 0), (40, 0), (40, 40), (0, 40), (0, 0), (40, 0)]
    el = compensate((20, 20), [(20, 0)] + sq[1:], 5.0, "left")
    ends = np.array([e.end for e in el])
    assert all(e.kind == "line" for e in el)
    assert np.allclose(ends[1], (35, 5)) and np.allclose(ends[2], (35, 35))
    # the tool outside a square boss, clockwise with G41: corners get arcs
    boss = [(0, 0), (0, 40), (40, 40), (40, 0), (0, 0)]
    el = compensate((-20, -20), boss, 5.0, "left")
    arcs = [e for e in el if e.kind == "arc"]
    assert len(arcs) == 3 and all(e.clockwise for e in arcs)     # (0,40) (40,40) (40,0)
    assert np.allclose(arcs[0].center, (0, 40)) and np.allclose(arcs[0].end, (0, 45))


def test_entry_move_not_longer_than_the_radius_is_refused():
    with pytest.raises(CompensationError, match="entry move"):
        compensate((0, 0), [(3, 0), (10, 0)], 5.0)


def test_reversing_move_in_a_tight_concave_corner_is_a_gouge():
    # a 2 mm long step inside a V: the 5 mm tool cannot follow it
    pts = [(0, 0), (20, 0), (21, 1), (21, 3), (0, 20)]
    with pytest.raises(CompensationError, match="gouging"):
        compensate((10, 8), pts, 5.0, "left")


@pytest.mark.parametrize("side", ["left", "right"])
@pytest.mark.parametrize("seed", [0, 1])
@pytest.mark.parametrize("where", ["inside", "outside"])
def test_compensation_matches_linuxcnc_rs274(rs274, side, seed, where):
    from support.rs274 import run_rs274
    poly = _wavy(seed=seed)
    if (side == "right") == (where == "inside"):
        poly = poly[::-1]
    pts = list(poly) + [poly[0], poly[1]]
    start = (0.0, 0.0) if where == "inside" else (100.0, 0.0)
    el = compensate(start, pts, 4.0, side)
    res = run_rs274(_program(start, pts, side), {1: Tool(1, "flat", 8.0)})
    assert res.ok, res.error
    moves = [m for m in res.motions if m.kind in ("feed", "arc")][:-1]   # drop lead-out
    assert [m.kind == "arc" for m in moves] == [e.kind == "arc" for e in el]
    if where == "outside":
        assert sum(e.kind == "arc" for e in el) >= 20      # convex corners get arcs
    got = np.array([m.end[:2] for m in moves])
    assert np.abs(got - _elements_to_points(start, el)).max() <= 1.5e-4
    for m, e in zip(moves, el):
        if e.kind == "arc":
            assert np.abs(np.array(m.center[:2]) - e.center).max() <= 1.5e-4
            assert (m.rotation < 0) == e.clockwise


def test_reachable_contour_cuts_a_sharp_corner_and_stays_loop_free():
    # a cavity with a sharp 20 degree spike the 6 mm tool cannot enter
    spike = [(0, 0), (60, 0), (60, 30), (100, 40), (60, 40), (0, 40)]
    dense = []
    for a, b in zip(spike, spike[1:] + spike[:1]):
        k = max(1, int(math.hypot(b[0] - a[0], b[1] - a[1]) / 0.5))
        for s in np.linspace(0, 1, k, endpoint=False):
            dense.append((a[0] + (b[0] - a[0]) * s, a[1] + (b[1] - a[1]) * s))
    v = np.array(dense)
    rc = reachable_contour(v, 3.0, "left", start=40)
    assert rc.removed, "the spike tip must be reported"
    tip = np.array([100, 40])
    removed_pts = v[[i for run in rc.removed for i in run]]
    assert np.min(np.hypot(*(removed_pts - tip).T)) < 1.0
    q = rc.points
    assert q[0][1] == 0.0                       # starts on the bottom edge
    start = q[0] + np.array([0.0, 7.0])         # straight in from above, > r long
    el = compensate(start, [q[0]] + list(q[1:]) + [q[0], q[1]], 3.0, "left")
    path = sample_elements(start, el, 0.2)
    region = Polygon(v)
    # the tool centre stays at least r from the wall (no gouge) ...
    d = shapely.distance(region.exterior, shapely.points(path[5:]))
    assert d.min() >= 3.0 - 1e-6
    # ... and one lap of it (past the entry's back-track) does not cross itself
    lap = [e for e in el if 10 <= e.index <= len(q)]
    first = [e for e in el if e.index < 10][-1].end
    assert LineString(sample_elements(first, lap, 0.2)).is_simple


def _mouth(r0=32.0, half=0.3, turn=0.0185):
    """A round cavity of chords turning ``turn`` (under LinuxCNC's 0.05 rad: each a
    near-straight join) with a wedge of material cut in to its centre: the arc meets
    the wedge's sides in corners concave for the tool inside."""
    n = int((2 * np.pi - 2 * half) / turn)
    a = np.linspace(half, 2 * np.pi - half, n + 1)
    arc = np.stack([r0 * np.cos(a), r0 * np.sin(a)], 1)
    return np.round(np.vstack([arc, [[0.0, 0.0]]]), 4)


def _from_longest(q: np.ndarray) -> np.ndarray:
    """The closed contour ``q`` rolled to start at its longest chord (entered at its
    middle: room for LinuxCNC's corners at both its ends)."""
    k = int(np.argmax(np.hypot(*(np.roll(q, -1, axis=0) - q).T)))
    return np.roll(q, -k, axis=0)


@pytest.mark.parametrize("start", [0, 1, 2, 5, 7, 60, 290, 298, 299, 300, 306, 307, 308])
def test_reachable_contour_is_compensated_from_any_start_chord(start):
    """Whatever chord it starts from (next to the wedge's corners included, or one the
    tool cannot follow), the contour kept has a length left on every move once
    LinuxCNC's corners and joins are taken, the start chord's join with the last chord
    included: compensated by the same rules, entered from inside, it raises no
    concave-corner error. The chords tried are those the die-cavity planner tries
    (their offset on the eroded cavity's boundary)."""
    v = _mouth()
    r = 4.0
    keep = chords_on_offset(v, r, "left", Polygon(v).buffer(-r, quad_segs=64), 2e-3)
    rc = reachable_contour(v, r, "left", start=start, keep=keep)
    q = _from_longest(rc.points)
    t = (q[1] - q[0]) / np.hypot(*(q[1] - q[0]))
    m = 0.5 * (q[0] + q[1])
    entry = m + 2.5 * r * np.array([-t[1], t[0]]) - 2.0 * r * t
    compensate(entry, [m] + list(q[1:]) + [q[0], m], r, "left")


def test_reachable_contour_start_next_to_a_corner_is_accepted_by_rs274(rs274):
    """The contour kept from a start chord just before the wedge's corner, written
    under G41 with LinuxCNC's own rs274: accepted, no concave-corner error."""
    from support.rs274 import run_rs274
    v = _mouth()
    r = 4.0
    keep = chords_on_offset(v, r, "left", Polygon(v).buffer(-r, quad_segs=64), 2e-3)
    rc = reachable_contour(v, r, "left", start=len(v) - 3, keep=keep)
    q = _from_longest(np.round(rc.points, 4))
    t = (q[1] - q[0]) / np.hypot(*(q[1] - q[0]))
    m = np.round(0.5 * (q[0] + q[1]), 4)
    entry = m + 2.5 * r * np.array([-t[1], t[0]])
    res = run_rs274(_program(entry, [m] + list(q[1:]) + [q[0], m]),
                    {1: Tool(1, "flat", 2 * r, flute_length=10, stickout=30)})
    assert res.ok, res.error
