"""Fewest-chord linearization of four-point segments within a chordal tolerance.

The deviation of the chord from P(a) to P(b) is the largest distance of the curve
piece P([a, b]) from the chord's line. The signed distance f(u) = cross(P(u) - P(a), d)
/ |d| (d = P(b) - P(a)) is a cubic in u with f(a) = f(b) = 0, so its extremes are
where f'(u) = cross(P'(u), d) = 0: where the tangent is parallel to the chord (mean
value theorem). That is a quadratic in u; both of its roots in (a, b) are checked.

Chords are laid greedily from u = 0: each chord's far end is the largest b with
deviation <= T, found by Brent's method on deviation(a, b) - T and then checked. The
greedy walk gives the fewest chords when a sub-piece of a feasible piece is feasible,
which holds for the pieces a tolerance-sized chord spans. Lengths in job units.

Misprints (Mohamed 2006, seeds/001): eq. (18) prints the quadratic's coefficients as
Q = -13.5 P1 + 41.5 P2 - 41.5 P3 + 13.5 P4 and R = 18 P1 - 45 P2 + 36 P3 - 36 P4; from
the derivative of the basis they are Q = -13.5 P1 + 40.5 P2 - 40.5 P3 + 13.5 P4 and
R = 18 P1 - 45 P2 + 36 P3 - 9 P4 (the printed R does not vanish on a point curve), and
its roots read "(-R/2Q) -/+ 1/2 power of [(R^2 - 4QS)/2Q]" for (-R -/+ sqrt(R^2 - 4QS)) /
2Q. Here the quadratic is formed from the derived basis. Table 2's deviations disagree
with the paper's own curve in five of the six rows checked (segment 2's are about 8
times the chords' true deviation); tests/diecavity/test_misprints.py computes them by
dense sampling.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from millpath.part.curve.fourpoint import Curve, FourPointSegment


def _cross(a, b):
    return a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]


def _roots(A, B, C):
    """Both roots of A t^2 + B t + C (NaN where absent), stable, vectorized."""
    disc = B * B - 4.0 * A * C
    sq = np.sqrt(np.maximum(disc, 0.0))
    q = -0.5 * (B + np.copysign(sq, B))
    linear = np.abs(A) <= 1e-14 * (np.abs(B) + np.abs(C) + 1e-300)
    with np.errstate(divide="ignore", invalid="ignore"):
        r1 = np.where(linear, -C / B, C / q)
        r2 = np.where(linear, np.nan, q / A)
    bad = (disc < 0.0) & ~linear
    return np.where(bad, np.nan, r1), np.where(bad, np.nan, r2)


def chord_deviation(seg: FourPointSegment, a: np.ndarray | float,
                    b: np.ndarray | float) -> np.ndarray:
    """Largest distance of the curve piece P([a, b]) from the line of its chord.

    Vectorized over ``a`` and ``b`` (equal shapes). Evaluates the tangent-parallel
    points in coordinates relative to P(a) (Taylor form), so the result stays accurate
    far from the origin.
    """
    a = np.asarray(a, float)
    b = np.asarray(b, float)
    c3, c2, c1, _ = seg.poly()
    e1 = (3.0 * c3 * a[..., None] + 2.0 * c2) * a[..., None] + c1      # P'(a)
    e2 = 3.0 * c3 * a[..., None] + c2                                   # P''(a) / 2
    e3 = np.broadcast_to(c3, e1.shape)
    h = (b - a)[..., None]
    d = ((e3 * h + e2) * h + e1) * h                                    # P(b) - P(a)
    length = np.hypot(d[..., 0], d[..., 1])
    A = 3.0 * _cross(e3, d)
    B = 2.0 * _cross(e2, d)
    C = _cross(e1, d)
    best = np.zeros(np.shape(length))
    hh = h[..., 0]
    for t in _roots(A, B, C):
        ok = np.isfinite(t) & (t > 0.0) & (t < hh) & (length > 0.0)
        tt = np.where(ok, t, 0.0)[..., None]
        q = ((e3 * tt + e2) * tt + e1) * tt
        with np.errstate(divide="ignore", invalid="ignore"):
            dist = np.abs(_cross(q, d)) / length
        best = np.maximum(best, np.where(ok, dist, 0.0))
    return best


@dataclass
class SegmentLinearization:
    """Chords of one segment: parameters ``u`` (n + 1 values from 0 to 1) and each
    chord's deviation (n values); ``uniform_chords`` is the fewest chords with equal
    parameter steps that also meet the tolerance."""

    u: np.ndarray
    deviation: np.ndarray
    uniform_chords: int

    @property
    def chords(self) -> int:
        return len(self.u) - 1

    @property
    def steps(self) -> np.ndarray:
        return np.diff(self.u)


def _scalar_deviation(k: tuple, a: float, b: float) -> float:
    """Scalar :func:`chord_deviation` in plain float arithmetic (for the root search).

    ``k`` = (x3, x2, x1, y3, y2, y1): power-basis coefficients of P(u) - P(0)."""
    x3, x2, x1, y3, y2, y1 = k
    e1x = (3.0 * x3 * a + 2.0 * x2) * a + x1
    e1y = (3.0 * y3 * a + 2.0 * y2) * a + y1
    e2x = 3.0 * x3 * a + x2
    e2y = 3.0 * y3 * a + y2
    h = b - a
    dx = ((x3 * h + e2x) * h + e1x) * h
    dy = ((y3 * h + e2y) * h + e1y) * h
    length = math.hypot(dx, dy)
    if length == 0.0:
        return 0.0
    A = 3.0 * (x3 * dy - y3 * dx)
    B = 2.0 * (e2x * dy - e2y * dx)
    C = e1x * dy - e1y * dx
    roots = []
    if abs(A) <= 1e-14 * (abs(B) + abs(C) + 1e-300):
        if B != 0.0:
            roots.append(-C / B)
    else:
        disc = B * B - 4.0 * A * C
        if disc >= 0.0:
            q = -0.5 * (B + math.copysign(math.sqrt(disc), B))
            if q != 0.0:
                roots.append(C / q)
            roots.append(q / A)
    best = 0.0
    for t in roots:
        if 0.0 < t < h:
            px = ((x3 * t + e2x) * t + e1x) * t
            py = ((y3 * t + e2y) * t + e1y) * t
            best = max(best, abs(px * dy - py * dx) / length)
    return best


#: chords are searched against tol * (1 - SAFETY) so rounding never puts one above tol
SAFETY = 1e-7


def _far_end(seg: FourPointSegment, a: float, tol: float) -> float:
    """Largest b in (a, 1] with deviation(a, b) <= tol (Brent root of dev - tol)."""
    c = seg.poly()
    k = (c[0, 0], c[1, 0], c[2, 0], c[0, 1], c[1, 1], c[2, 1])
    target = tol * (1.0 - SAFETY)

    def g(b: float) -> float:
        return _scalar_deviation(k, a, b) - target
    if g(1.0) <= 0.0:
        return 1.0
    from scipy.optimize import brentq          # lazily: jobs without curves never load scipy
    b = brentq(g, a, 1.0, xtol=1e-15, rtol=4 * np.finfo(float).eps, maxiter=200)
    shrink = 0
    while g(b) > 0.0 and shrink < 60:
        b = a + (b - a) * (1.0 - 1e-10 * 2 ** shrink)
        shrink += 1
    if b <= a:
        raise ArithmeticError("chord search made no progress")
    return b


def uniform_chord_count(seg: FourPointSegment, tol: float, start: int = 1,
                        limit: int = 10_000_000) -> int:
    """Fewest equal parameter steps whose chords all deviate at most ``tol``.

    Doubles from ``start`` until feasible, then bisects, then walks down while the
    count below is still feasible (vectorized checks)."""
    def ok(n: int) -> bool:
        u = np.linspace(0.0, 1.0, n + 1)
        return bool(np.all(chord_deviation(seg, u[:-1], u[1:]) <= tol))
    n = max(1, start)
    if ok(n):
        while n > 1 and ok(n - 1):
            n -= 1
        return n
    lo, hi = n, n * 2
    while not ok(hi):
        lo, hi = hi, hi * 2
        if hi > limit:
            return hi
    while hi - lo > 1:
        mid = (lo + hi) // 2
        if ok(mid):
            hi = mid
        else:
            lo = mid
    return hi


def linearize_segment(seg: FourPointSegment, tol: float) -> SegmentLinearization:
    """Fewest chords of ``seg`` with chordal deviation <= ``tol`` (job units)."""
    if not (tol > 0 and math.isfinite(tol)):
        raise ValueError("tolerance must be a positive length")
    us = [0.0]
    while us[-1] < 1.0:
        us.append(_far_end(seg, us[-1], tol))
    u = np.array(us)
    dev = chord_deviation(seg, u[:-1], u[1:])
    return SegmentLinearization(u, dev, uniform_chord_count(seg, tol, start=len(u) - 1))


@dataclass
class CurveLinearization:
    """A linearized curve: one entry per segment, and the joined polyline."""

    curve: Curve
    tolerance: float
    segments: list[SegmentLinearization]

    def polyline(self) -> np.ndarray:
        """Vertices (n, 2) of the joined chords; for a closed curve the last vertex
        (equal to the first) is left out."""
        pts = []
        for seg, lin in zip(self.curve.segments, self.segments):
            pts.append(seg.at(lin.u[:-1]))
        if not self.curve.closed:
            pts.append(self.curve.segments[-1].end[None, :])
        return np.vstack(pts)

    @property
    def chords(self) -> int:
        return sum(s.chords for s in self.segments)

    @property
    def uniform_chords(self) -> int:
        return sum(s.uniform_chords for s in self.segments)

    def report(self, tables: bool = True, digits: int = 9) -> dict:
        """Per-segment chord counts, parameter steps and deviations, with the
        uniform-step comparison (JSON-ready)."""
        segs = []
        for i, (seg, lin) in enumerate(zip(self.curve.segments, self.segments)):
            d = {"index": i, "kind": seg.kind,
                 "points": [[round(float(x), digits) for x in p] for p in seg.points],
                 "chords": lin.chords, "uniform_chords": lin.uniform_chords,
                 "max_deviation": float(lin.deviation.max()),
                 "min_step": float(lin.steps.min()), "max_step": float(lin.steps.max())}
            if tables:
                d["u"] = [round(float(x), 12) for x in lin.u]
                d["steps"] = [round(float(x), 12) for x in lin.steps]
                d["deviations"] = [round(float(x), 12) for x in lin.deviation]
            segs.append(d)
        return {"tolerance": self.tolerance, "segments": segs, "chords": self.chords,
                "uniform_chords": self.uniform_chords,
                "saved_vs_uniform": self.uniform_chords - self.chords}


def linearize_curve(curve: Curve, tol: float) -> CurveLinearization:
    return CurveLinearization(curve, tol, [linearize_segment(s, tol) for s in curve.segments])
