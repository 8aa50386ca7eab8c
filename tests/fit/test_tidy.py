"""Tidy output without fitting: collinear points merged within the
tolerance, feeds written rounded (whole mm/min, one decimal in/min).

Truth: the test's own point-to-segment distances between the original points and the
merged path, and the feed words as LinuxCNC's interpreter (millpath's) reads them."""

from __future__ import annotations

import re

import numpy as np

from millpath.fit.collinear import merge_collinear
from millpath.model import Tool
from millpath.model.toolpath import Operation, Toolpath
from millpath.post.writer import post


def _dist_to_polyline(P: np.ndarray, Q: np.ndarray) -> np.ndarray:
    """Distance of each point of P (n, 3) to the polyline Q (m, 3), computed directly."""
    best = np.full(len(P), np.inf)
    for a, b in zip(Q[:-1], Q[1:]):
        d = b - a
        l2 = float(d @ d)
        u = np.zeros(len(P)) if l2 == 0 else np.clip(((P - a) @ d) / l2, 0.0, 1.0)
        best = np.minimum(best, np.linalg.norm(P - (a + u[:, None] * d), axis=1))
    return best


def _polyline(tp: Toolpath) -> np.ndarray:
    return np.array([m.end for m in tp.moves], dtype=float)


def _raster(rng, noise: float) -> list[tuple[float, float, float]]:
    """Zigzag raster lines 0.5 mm steps, 60 mm long, Z noise of +-noise."""
    pts = []
    for row in range(6):
        xs = np.arange(0.0, 60.0001, 0.5)
        if row % 2:
            xs = xs[::-1]
        for x in xs:
            pts.append((float(x), 4.0 * row, float(-1.0 + rng.uniform(-noise, noise))))
    return pts


def _tp(points, feed=500.0, units="mm", tol=None) -> Toolpath:
    tp = Toolpath(units=units)
    tp.begin(Operation("test", "test", 1, tolerance=tol))
    tp.rapid(*points[0])
    for p in points[1:]:
        tp.line(*p, feed)
    return tp


def test_straight_raster_becomes_one_move_per_line_within_tolerance():
    rng = np.random.default_rng(23)
    pts = _raster(rng, 0.002)
    tp = _tp(pts)
    out = merge_collinear(tp, 0.005)
    P, Q = _polyline(tp), _polyline(out)
    assert _dist_to_polyline(P, Q).max() <= 0.005 + 1e-9          # every original point
    assert _dist_to_polyline(Q, P).max() <= 1e-12                 # kept points are originals
    # 6 rows of 121 points: a row's end points and the step between rows stay
    assert len(out.moves) <= 1 + 6 * 3 and len(tp.moves) == 1 + 6 * 121 - 1
    assert out.moves[0].kind == "rapid" and all(m.kind == "line" for m in out.moves[1:])


def test_noise_beyond_the_tolerance_is_kept():
    rng = np.random.default_rng(5)
    pts = _raster(rng, 0.05)
    tp = _tp(pts)
    out = merge_collinear(tp, 0.005)
    P, Q = _polyline(tp), _polyline(out)
    assert _dist_to_polyline(P, Q).max() <= 0.005 + 1e-9
    assert len(out.moves) > len(tp.moves) // 3      # most points are needed


def test_a_path_turning_back_on_itself_is_not_merged_across_the_turn():
    pts = [(0, 0, 0), (10, 0, 0), (20, 0, 0), (5, 0, 0), (0, 0, 0)]
    out = merge_collinear(_tp(pts), 0.01)
    ends = [m.end for m in out.moves]
    assert (20, 0, 0) in ends and len(ends) == 3     # rapid, to 20, back to 0


def test_an_operation_with_its_own_tolerance_is_merged_only_within_the_post_grid():
    """Its chordal budget is spent by its planner: only what rounding to 0.0001 mm moves
    anyway (half a step) may go; an exactly straight stretch still becomes one move."""
    rng = np.random.default_rng(7)
    pts = _raster(rng, 0.002)
    tp = _tp(pts, tol=0.01)
    out = merge_collinear(tp, 0.005)
    assert _dist_to_polyline(_polyline(tp), _polyline(out)).max() <= 0.00005 + 1e-12
    straight = [(0.0, 0.0, 0.0)] + [(0.5 * k, 0.25 * k, -0.1 * k) for k in range(1, 101)]
    out = merge_collinear(_tp(straight, tol=0.01), 0.005)
    assert [m.end for m in out.moves] == [straight[0], straight[-1]]


def _feeds(program: str) -> list[str]:
    return re.findall(r"F([0-9.]+)", program)


def test_feeds_are_written_rounded():
    tool = {1: Tool(number=1, type="flat", diameter=6.0)}
    pts = [(0, 0, 1), (10, 0, 0), (20, 0, 0), (30, 0, 0)]
    tp = Toolpath(units="mm")
    tp.begin(Operation("test", "test", 1, spindle=1000))
    tp.rapid(*pts[0])
    for p, f in zip(pts[1:], (666.667, 666.6, 1000.4)):
        tp.line(*p, f)
    assert _feeds(post(tp, tool)) == ["667", "1000"]          # 666.667 and 666.6 -> 667
    tpi = Toolpath(units="inch")
    tpi.begin(Operation("test", "test", 1, spindle=1000))
    tpi.rapid(*pts[0])
    for p, f in zip(pts[1:], (26.6667, 26.64, 0.02)):
        tpi.line(*p, f)
    assert _feeds(post(tpi, {1: Tool(number=1, type="flat", diameter=0.25)})) == \
        ["26.7", "26.6", "0.1"]                                # never rounded to zero
