"""C1 blending of four-point segments and closing a chain into a cavity outline.

A blend B joins the end E of segment A to the start S of segment C. Its outer points
are B1 = E and B4 = S; its inner points B2, B3 are chosen so that B'(0) = A'(1) and
B'(1) = C'(0) (equal first derivatives with respect to u, hence C1). With the end
derivatives of a four-point segment (see :mod:`millpath.part.curve.fourpoint`):

     9 B2 - 4.5 B3 = A'(1) + 5.5 B1 - B4
   4.5 B2 -   9 B3 = C'(0) + B1 - 5.5 B4

solved per coordinate (determinant -60.75, never singular).
"""

from __future__ import annotations

import numpy as np

from millpath.errors import GeometryError
from millpath.part.curve.fourpoint import Curve, FourPointSegment

#: gaps shorter than this (job units) are treated as a shared point (no blend)
JOIN_EPS = 1e-9


def blend_points(a: FourPointSegment, c: FourPointSegment) -> np.ndarray:
    """The four points (4, 2) of the C1 blend from the end of ``a`` to the start of ``c``."""
    b1, b4 = a.end, c.start
    rhs = np.array([a.d1(1.0) + 5.5 * b1 - b4, c.d1(0.0) + b1 - 5.5 * b4])
    m = np.array([[9.0, -4.5], [4.5, -9.0]])
    inner = np.linalg.solve(m, rhs)              # rows: B2, B3
    return np.array([b1, inner[0], inner[1], b4])


def blend(a: FourPointSegment, c: FourPointSegment) -> FourPointSegment:
    return FourPointSegment(blend_points(a, c), kind="blend")


def build_curve(points, close: bool = True, file=None) -> Curve:
    """Group ``points`` (n, 2) four at a time into given segments and blend the gaps.

    A blend is inserted wherever a segment does not end at the next one's start
    (and, with ``close``, between the last and the first). Raises GeometryError if the
    number of points is not a multiple of four or a segment is degenerate.
    """
    p = np.asarray(points, float)
    if p.ndim != 2 or p.shape[1] != 2:
        raise GeometryError("points must be [x, y] pairs", file)
    if len(p) < 4 or len(p) % 4:
        raise GeometryError(f"points: four per segment are needed, got {len(p)} points", file)
    if not np.all(np.isfinite(p)):
        raise GeometryError("points: coordinates must be finite", file)
    given = []
    for k in range(0, len(p), 4):
        q = p[k:k + 4]
        if np.min(np.hypot(*(np.diff(q, axis=0).T))) < JOIN_EPS:
            raise GeometryError(f"points {k + 1}-{k + 4}: two consecutive points of a "
                                f"segment coincide", file)
        given.append(FourPointSegment(q, "given", k))
    segs: list[FourPointSegment] = []
    n = len(given)
    for i, s in enumerate(given):
        segs.append(s)
        if i + 1 < n or close:
            nxt = given[(i + 1) % n]
            if np.hypot(*(s.end - nxt.start)) > JOIN_EPS:
                if n == 1 and not close:
                    break
                segs.append(blend(s, nxt))
            elif i + 1 == n:
                # shared closing point: make it exactly equal
                segs[-1] = FourPointSegment(np.vstack([s.points[:3], nxt.start]), s.kind,
                                            s.source)
    return Curve(segs)
