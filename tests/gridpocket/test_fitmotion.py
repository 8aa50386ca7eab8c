"""Line, arc (three-point with shrinking spans) and cubic fitting of point chains."""

from __future__ import annotations

import math

import numpy as np
import pytest
import shapely

from millpath.model.toolpath import Move, sample_move
from millpath.plan.gridpocket.fitmotion import Chain, Fitter, fit_cubic


def _chain(P, checks=None):
    P = np.asarray(P, float)
    pos = np.concatenate([[0.0], np.cumsum(np.hypot(*np.diff(P[:, :2], axis=0).T))])
    if checks is None:
        return Chain(P, pos)
    C = np.asarray(checks, float)
    cpos = np.hypot(C[:, 0] - P[0, 0], C[:, 1] - P[0, 1])
    o = np.argsort(cpos)
    return Chain(P, pos, C[o], cpos[o])


def _as_moves(start, segs):
    moves = []
    for s in segs:
        if s.kind == "line":
            moves.append(Move("line", tuple(s.end), 10.0))
        elif s.kind == "arc":
            moves.append(Move("arc", tuple(s.end), 10.0, center=tuple(s.center), plane=s.plane,
                              clockwise=s.clockwise))
        else:
            moves.append(Move("cubic", tuple(s.end), 10.0, c1=s.c1, c2=s.c2))
    pts = [np.asarray(start, float)[None]]
    pos = tuple(start)
    for m in moves:
        pts.append(sample_move(pos, m, 2e-5))
        pos = m.end
    return np.concatenate(pts)


def _max_dist(points, path):
    """Largest distance from the points to the sampled path (samples 2e-5 apart)."""
    return max(np.linalg.norm(path - p, axis=1).min() for p in points)


def _xz_arc(cx, cz, r, a0, a1, n, y=0.3):
    t = np.linspace(a0, a1, n)
    # XZ plane: first axis Z, second X; angle measured from +Z towards +X
    return np.column_stack([cx + r * np.sin(t), np.full(n, y), cz + r * np.cos(t)])


def test_points_on_one_xz_circle_become_one_arc_with_its_centre():
    P = _xz_arc(1.0, -2.0, 1.8, -0.3, 0.4, 9)
    segs = Fitter("arc", 1e-4, 100.0).fit(_chain(P))
    assert len(segs) == 1 and segs[0].kind == "arc" and segs[0].plane == "XZ"
    assert segs[0].center[0] == pytest.approx(1.0, abs=1e-9)
    assert segs[0].center[2] == pytest.approx(-2.0, abs=1e-9)
    # angle increases from +Z towards +X: counter-clockwise seen from +Y
    assert segs[0].clockwise is False
    assert np.allclose(segs[0].end, P[-1])


def test_xz_arc_direction_matches_the_posted_motion():
    P = _xz_arc(0.0, 0.0, 1.0, 0.4, -0.4, 7)          # the other way round
    segs = Fitter("arc", 1e-4, 100.0).fit(_chain(P))
    assert segs[0].clockwise is True
    path = _as_moves(P[0], segs)
    assert _max_dist(P, path) < 2e-5


def test_yz_points_use_g19_arcs():
    t = np.linspace(0.2, 1.0, 8)
    P = np.column_stack([np.full(8, 2.0), 0.5 * np.cos(t), -1 + 0.5 * np.sin(t)])
    segs = Fitter("arc", 1e-5, 100.0).fit(_chain(P))
    assert [s.plane for s in segs] == ["YZ"]
    assert _max_dist(P, _as_moves(P[0], segs)) < 3e-5


def test_span_shrinks_until_the_distance_error_passes():
    a = _xz_arc(0.0, -1.0, 1.0, -0.5, 0.0, 6)
    b = _xz_arc(0.0, -1.0 + 1.0 - 0.3, 0.3, 0.0, 0.8, 6)[1:]    # tighter circle, tangent
    P = np.concatenate([a, b])
    tol = 1e-4
    segs = Fitter("arc", tol, 100.0).fit(_chain(P))
    assert len(segs) >= 2 and all(s.kind == "arc" for s in segs)
    assert _max_dist(P, _as_moves(P[0], segs)) <= tol + 1e-5


def test_collinear_points_and_huge_radii_become_single_lines():
    P = np.column_stack([np.linspace(0, 1, 9), np.zeros(9), np.linspace(0, -0.5, 9)])
    assert [s.kind for s in Fitter("arc", 1e-4, 100.0).fit(_chain(P))] == ["line"]
    Q = _xz_arc(0.0, -500.0, 500.0, -0.001, 0.001, 7)
    segs = Fitter("arc", 1e-6, 100.0).fit(_chain(Q))
    assert all(s.kind == "line" for s in segs)
    # line mode merges only exactly collinear points
    assert len(Fitter("line", 1e-4, 100.0).fit(_chain(P))) == 1
    assert len(Fitter("line", 1e-4, 100.0).fit(_chain(_xz_arc(0, -2, 1.8, -0.3, 0.4, 9)))) == 8


def test_arcs_never_pass_below_check_points_by_more_than_the_tolerance():
    tol = 1e-4
    P = _xz_arc(1.0, -2.0, 1.8, -0.3, 0.4, 9)
    dense = _xz_arc(1.0, -2.0, 1.8, -0.3, 0.4, 161)
    # required Z on the circle itself: the arc through the points is fine
    segs = Fitter("arc", tol, 100.0).fit(_chain(P, dense))
    assert [s.kind for s in segs] == ["arc"]
    # required Z 2 tol above the circle between every pair of points: no span of two or
    # more segments may be drawn as one arc or line any more
    raised = _xz_arc(1.0, -2.0, 1.8 + 2 * tol, -0.3, 0.4, 17)[1::2]
    segs = Fitter("arc", tol, 100.0).fit(_chain(P, np.vstack([P, raised])))
    assert len(segs) == len(P) - 1 and all(s.kind == "line" for s in segs)


def test_fit_cubic_passes_through_second_and_second_to_last_points():
    t = np.linspace(0, 1, 7)[:, None]
    p0, c1, c2, p3 = map(np.array, ([0, 0], [1, 2], [3, 2], [4, 0]))
    Q = (1 - t) ** 3 * p0 + 3 * (1 - t) ** 2 * t * c1 + 3 * (1 - t) * t ** 2 * c2 + t ** 3 * p3
    a, b = fit_cubic(Q)
    seg = np.linalg.norm(np.diff(Q, axis=0), axis=1)
    s = np.concatenate([[0], np.cumsum(seg)]) / seg.sum()
    for k in (1, -2):
        u = s[k]
        p = (1 - u) ** 3 * Q[0] + 3 * (1 - u) ** 2 * u * a + 3 * (1 - u) * u ** 2 * b + u ** 3 * Q[-1]
        assert np.allclose(p, Q[k], atol=1e-12)


def test_bezier_mode_writes_xy_cubics_and_approximates_vertical_ones_by_arcs():
    t = np.linspace(0, math.pi / 2, 9)
    xy = np.column_stack([np.cos(t), np.sin(t), np.full(9, -0.2)])     # flat quarter circle
    tol = 2e-4
    # between the points the chords are 5e-3 inside the circle: a cubic that follows
    # the circle is allowed on a wall pass (inside the outline grown by tol) ...
    chain = _chain(xy)
    chain.region = shapely.Point(0, 0).buffer(1 + tol, quad_segs=256)
    segs = Fitter("bezier", tol, 100.0).fit(chain)
    assert segs[0].kind == "cubic" and {s.kind for s in segs} <= {"cubic", "line"}
    assert _max_dist(xy, _as_moves(xy[0], segs)) <= tol + 1e-5
    # ... but not elsewhere, where it must stay within tol of the point polyline
    segs = Fitter("bezier", tol, 100.0).fit(_chain(xy))
    assert "cubic" not in {s.kind for s in segs}
    dense = np.column_stack([np.cos(t2 := np.linspace(0, math.pi / 2, 60)), np.sin(t2),
                             np.full(60, -0.2)])
    segs = Fitter("bezier", tol, 100.0).fit(_chain(dense))
    assert "cubic" in {s.kind for s in segs}
    assert _max_dist(dense, _as_moves(dense[0], segs)) <= tol + 1e-5
    x = np.linspace(0, 1, 9)
    xz = np.column_stack([x, np.full(9, 0.5), -0.3 - 0.1 * x ** 2 + 0.05 * x ** 3])
    segs = Fitter("bezier", tol, 100.0).fit(_chain(xz))
    assert {s.kind for s in segs} <= {"arc", "line"} and any(s.kind == "arc" for s in segs)
    assert all(s.plane == "XZ" for s in segs if s.kind == "arc")
    assert _max_dist(xz, _as_moves(xz[0], segs)) <= tol + 1e-5
    assert np.allclose(segs[-1].end, xz[-1])


def test_a_corner_is_never_smoothed_into_the_wall():
    # an L of points at constant Z: a cubic through the corner would swing outside
    P = np.array([[0, 0, 0], [1, 0, 0], [2, 0, 0], [2, 1, 0], [2, 2, 0]], float)
    for mode in ("arc", "bezier"):
        path = _as_moves(P[0], Fitter(mode, 1e-3, 100.0).fit(_chain(P)))
        assert path[:, 0].max() <= 2 + 1e-3 and path[:, 1].min() >= -1e-3
