"""Cubic Bezier (G5) fitting of XY polylines at constant Z, with a verified tolerance.

Points are ``(n, 3)`` arrays in job units on the post-processor's grid ``q``. A cubic
from ``P[i]`` to ``P[j]`` has control points ``P[i] + a T0`` and ``P[j] - b T1``, where
``T0``/``T1`` are unit tangents (direction of travel) chosen by the caller, so that two
cubics sharing a tangent at a smooth vertex join G1-continuously. The lengths ``a, b``
come from a least-squares fit with chord-length parameters (refined by Newton steps);
the control points are then rounded to the grid, as G5's I J P Q words will be written.

The check is two-sided: the cubic is sampled finely enough that its chords stay within
a tenth of the tolerance of the curve, and :func:`polyline_within` proves, segment by
segment, that the sampled cubic lies within the rest of the tolerance of the original
polyline and the original polyline within it of the sampled cubic.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit


@njit(cache=True)
def _d2(px, py, ax, ay, bx, by):
    """Squared distance from (px, py) to the segment (ax, ay)-(bx, by)."""
    sx, sy = bx - ax, by - ay
    s2 = sx * sx + sy * sy
    u = 0.0
    if s2 > 0.0:
        u = ((px - ax) * sx + (py - ay) * sy) / s2
        if u < 0.0:
            u = 0.0
        elif u > 1.0:
            u = 1.0
    dx = px - (ax + u * sx)
    dy = py - (ay + u * sy)
    return dx * dx + dy * dy


@njit(cache=True)
def polyline_within(X, Y, tol):
    """True if every point of polyline ``X`` (m, 2) is within ``tol`` of polyline ``Y``.

    A piece of ``X`` whose two ends are both within ``tol`` of the same segment of ``Y``
    is within ``tol`` of it everywhere (the distance to a segment is convex); otherwise
    the piece is halved, or accepted by the Lipschitz bound ``max(d_a, d_b) + len/2``.
    Fails (False) when an end is farther than ``tol`` or the subdivision gets too deep.
    """
    k = Y.shape[0]
    if k < 2:
        return False
    tol2 = tol * tol
    hint = 0
    st0 = np.empty(64)
    st1 = np.empty(64)
    std = np.empty(64, np.int64)
    for p in range(X.shape[0] - 1):
        x0, y0, x1, y1 = X[p, 0], X[p, 1], X[p + 1, 0], X[p + 1, 1]
        top = 0
        st0[0], st1[0], std[0] = 0.0, 1.0, 0
        top = 1
        while top > 0:
            top -= 1
            t0, t1, dep = st0[top], st1[top], std[top]
            ax, ay = x0 + t0 * (x1 - x0), y0 + t0 * (y1 - y0)
            bx, by = x0 + t1 * (x1 - x0), y0 + t1 * (y1 - y0)
            found = False
            lo = max(0, hint - 4)
            hi = min(k - 1, hint + 5)
            for s in range(lo, hi):
                if (_d2(ax, ay, Y[s, 0], Y[s, 1], Y[s + 1, 0], Y[s + 1, 1]) <= tol2 and
                        _d2(bx, by, Y[s, 0], Y[s, 1], Y[s + 1, 0], Y[s + 1, 1]) <= tol2):
                    found = True
                    hint = s
                    break
            if found:
                continue
            da = 1e300
            db = 1e300
            for s in range(k - 1):
                a2 = _d2(ax, ay, Y[s, 0], Y[s, 1], Y[s + 1, 0], Y[s + 1, 1])
                b2 = _d2(bx, by, Y[s, 0], Y[s, 1], Y[s + 1, 0], Y[s + 1, 1])
                if a2 <= tol2 and b2 <= tol2:
                    found = True
                    hint = s
                    break
                da = min(da, a2)
                db = min(db, b2)
            if found:
                continue
            if da > tol2 or db > tol2:
                return False
            half = 0.5 * math.hypot(bx - ax, by - ay)
            if math.sqrt(max(da, db)) + half <= tol:
                continue
            if dep >= 24 or top + 2 > 64:
                return False
            tm = 0.5 * (t0 + t1)
            st0[top], st1[top], std[top] = t0, tm, dep + 1
            st0[top + 1], st1[top + 1], std[top + 1] = tm, t1, dep + 1
            top += 2
    return True


@njit(cache=True)
def _bez(b, u):
    v = 1.0 - u
    w0, w1, w2, w3 = v * v * v, 3.0 * v * v * u, 3.0 * v * u * u, u * u * u
    return (w0 * b[0, 0] + w1 * b[1, 0] + w2 * b[2, 0] + w3 * b[3, 0],
            w0 * b[0, 1] + w1 * b[1, 1] + w2 * b[2, 1] + w3 * b[3, 1])


@njit(cache=True)
def _lengths(P, i, j, t0x, t0y, t1x, t1y, u):
    """Least-squares tangent lengths (a, b) for parameters ``u``; (-1, -1) if singular."""
    p0x, p0y, p3x, p3y = P[i, 0], P[i, 1], P[j, 0], P[j, 1]
    c00 = c01 = c11 = x0 = x1 = 0.0
    for k in range(i, j + 1):
        t = u[k - i]
        v = 1.0 - t
        b0, b1, b2, b3 = v * v * v, 3.0 * v * v * t, 3.0 * v * t * t, t * t * t
        Ax, Ay = t0x * b1, t0y * b1
        Bx, By = -t1x * b2, -t1y * b2
        rx = P[k, 0] - p0x * (b0 + b1) - p3x * (b2 + b3)
        ry = P[k, 1] - p0y * (b0 + b1) - p3y * (b2 + b3)
        c00 += Ax * Ax + Ay * Ay
        c01 += Ax * Bx + Ay * By
        c11 += Bx * Bx + By * By
        x0 += Ax * rx + Ay * ry
        x1 += Bx * rx + By * ry
    det = c00 * c11 - c01 * c01
    if abs(det) <= 1e-12 * (c00 * c11 + 1e-300):
        return -1.0, -1.0
    return (x0 * c11 - x1 * c01) / det, (c00 * x1 - c01 * x0) / det


@njit(cache=True)
def cubic_fit(P, i, j, t0x, t0y, t1x, t1y, tol, q, out):
    """Fit and check one cubic from ``P[i]`` to ``P[j]`` (XY, constant Z).

    ``t0``/``t1``: unit tangents of travel at both ends. On success returns True and
    writes the grid-rounded control points ``out = [c1x, c1y, c2x, c2y]``.
    """
    if j - i < 2:
        return False
    m = j - i + 1
    chord = math.hypot(P[j, 0] - P[i, 0], P[j, 1] - P[i, 1])
    if chord < 20.0 * q:
        return False
    u = np.empty(m)
    u[0] = 0.0
    for k in range(1, m):
        u[k] = u[k - 1] + math.hypot(P[i + k, 0] - P[i + k - 1, 0],
                                     P[i + k, 1] - P[i + k - 1, 1])
    total = u[m - 1]
    if total <= 0.0:
        return False
    for k in range(m):
        u[k] /= total
    b = np.empty((4, 2))
    a_len, b_len = 0.0, 0.0
    for it in range(3):
        a_len, b_len = _lengths(P, i, j, t0x, t0y, t1x, t1y, u)
        if not (a_len > 0.0 and b_len > 0.0) or a_len > 2.0 * total or b_len > 2.0 * total:
            a_len = b_len = total / 3.0
        b[0, 0], b[0, 1] = P[i, 0], P[i, 1]
        b[1, 0], b[1, 1] = P[i, 0] + a_len * t0x, P[i, 1] + a_len * t0y
        b[2, 0], b[2, 1] = P[j, 0] - b_len * t1x, P[j, 1] - b_len * t1y
        b[3, 0], b[3, 1] = P[j, 0], P[j, 1]
        if it == 2:
            break
        # Newton step on each parameter: closest point of the curve to the vertex
        for k in range(1, m - 1):
            t = u[k]
            v = 1.0 - t
            bx, by = _bez(b, t)
            d1x = 3.0 * (v * v * (b[1, 0] - b[0, 0]) + 2 * v * t * (b[2, 0] - b[1, 0])
                         + t * t * (b[3, 0] - b[2, 0]))
            d1y = 3.0 * (v * v * (b[1, 1] - b[0, 1]) + 2 * v * t * (b[2, 1] - b[1, 1])
                         + t * t * (b[3, 1] - b[2, 1]))
            d2x = 6.0 * (v * (b[2, 0] - 2 * b[1, 0] + b[0, 0]) + t * (b[3, 0] - 2 * b[2, 0] + b[1, 0]))
            d2y = 6.0 * (v * (b[2, 1] - 2 * b[1, 1] + b[0, 1]) + t * (b[3, 1] - 2 * b[2, 1] + b[1, 1]))
            ex, ey = bx - P[i + k, 0], by - P[i + k, 1]
            num = ex * d1x + ey * d1y
            den = d1x * d1x + d1y * d1y + ex * d2x + ey * d2y
            if den > 0.0:
                tn = t - num / den
                if 0.0 < tn < 1.0:
                    u[k] = tn
    for r in range(1, 3):
        b[r, 0] = round(b[r, 0] / q) * q
        b[r, 1] = round(b[r, 1] / q) * q
    # sample so that chords stay within tol/10 of the curve: |B''| h^2 / 8
    m2 = 0.0
    for r in range(2):
        m2 = max(m2, math.hypot(b[r, 0] - 2 * b[r + 1, 0] + b[r + 2, 0],
                                b[r, 1] - 2 * b[r + 1, 1] + b[r + 2, 1]))
    ns = int(math.ceil(math.sqrt(6.0 * m2 / (8.0 * 0.1 * tol)))) + 1
    ns = max(ns, 4)
    if ns > 20000:
        return False
    S = np.empty((ns + 1, 2))
    for s in range(ns + 1):
        S[s, 0], S[s, 1] = _bez(b, s / ns)
    S[0, 0], S[0, 1] = P[i, 0], P[i, 1]
    S[ns, 0], S[ns, 1] = P[j, 0], P[j, 1]
    Q = P[i:j + 1, :2]
    t9 = 0.9 * tol
    if not polyline_within(Q, S, t9):
        return False
    if not polyline_within(S, Q, t9):
        return False
    out[0], out[1], out[2], out[3] = b[1, 0], b[1, 1], b[2, 0], b[2, 1]
    return True
