"""Exact Euclidean distances between points, segments and triangles in 3D, for numba.

A ball end mill of radius ``R`` swept along a straight chord ``S -> E`` is the set of
points within ``R`` of its *core*: the parallelogram ``conv{S + R z, E + R z, E + L z,
S + L z}`` (``L`` the top of the flutes above the tip, ``z`` the tool axis), or the axis
segment when the chord is vertical. So a design triangle goes ``R - dist(triangle,
core)`` deep into the swept ball cutter, exactly, without the GJK bisection of
:mod:`millpath.geometry.convex`. Squared distances throughout; any consistent unit.
"""

from __future__ import annotations

import numpy as np
from numba import njit


@njit(cache=True, error_model="numpy", inline="always")
def _d3(ax, ay, az, bx, by, bz):
    return ax * bx + ay * by + az * bz


@njit(cache=True, error_model="numpy", inline="always")
def _to_edge2(px, py, pz, ax, ay, az, ex, ey, ez, t):
    """Squared distance from p to the point ``a + t e`` of an edge."""
    qx, qy, qz = ax + t * ex, ay + t * ey, az + t * ez
    return (px - qx) ** 2 + (py - qy) ** 2 + (pz - qz) ** 2


@njit(cache=True, error_model="numpy", inline="always")
def _from_vertex(px, py, pz, T, i, abx, aby, abz, acx, acy, acz):
    """(ab . w, ac . w, |w|^2) of ``w = p - T[i]``: the closest-point region tests."""
    wx, wy, wz = px - T[i, 0], py - T[i, 1], pz - T[i, 2]
    return (_d3(abx, aby, abz, wx, wy, wz), _d3(acx, acy, acz, wx, wy, wz),
            wx * wx + wy * wy + wz * wz)


@njit(cache=True, error_model="numpy", inline="always")
def _corner(px, py, pz, ax, ay, az, ex, ey, ez, ae, af, xe, xf, x2):
    """The regions of vertex X = A + e and of edge A-X (B or C, the other edge f; ``ae``,
    ``af``: A's dots with e and f, ``xe``, ``xf``: X's, ``x2``: |p - X|^2): (squared
    distance, or -1 when p is in neither; the edge's barycentric test value)."""
    if xe >= 0.0 and xf <= xe:
        return x2, 0.0
    v = ae * xf - xe * af
    if v <= 0.0 and ae >= 0.0 and xe <= 0.0:
        return _to_edge2(px, py, pz, ax, ay, az, ex, ey, ez, ae / (ae - xe)), v
    return -1.0, v


@njit(cache=True, error_model="numpy")
def point_triangle_dist2(px, py, pz, T):
    """Squared distance from a point to triangle ``T`` (3, 3) (closest-point regions;
    a degenerate triangle is handled as its edges)."""
    ax, ay, az = T[0, 0], T[0, 1], T[0, 2]
    abx, aby, abz = T[1, 0] - ax, T[1, 1] - ay, T[1, 2] - az
    acx, acy, acz = T[2, 0] - ax, T[2, 1] - ay, T[2, 2] - az
    d1, d2, a2 = _from_vertex(px, py, pz, T, 0, abx, aby, abz, acx, acy, acz)
    if d1 <= 0.0 and d2 <= 0.0:
        return a2
    d3, d4, b2 = _from_vertex(px, py, pz, T, 1, abx, aby, abz, acx, acy, acz)
    r, vc = _corner(px, py, pz, ax, ay, az, abx, aby, abz, d1, d2, d3, d4, b2)
    if r >= 0.0:
        return r
    d5, d6, c2 = _from_vertex(px, py, pz, T, 2, abx, aby, abz, acx, acy, acz)
    r, vb = _corner(px, py, pz, ax, ay, az, acx, acy, acz, d2, d1, d6, d5, c2)
    if r >= 0.0:
        return r
    va = d3 * d6 - d5 * d4
    if va <= 0.0 and (d4 - d3) >= 0.0 and (d5 - d6) >= 0.0:
        return _to_edge2(px, py, pz, T[1, 0], T[1, 1], T[1, 2], T[2, 0] - T[1, 0],
                         T[2, 1] - T[1, 1], T[2, 2] - T[1, 2],
                         (d4 - d3) / ((d4 - d3) + (d5 - d6)))
    s = va + vb + vc
    if s <= 0.0:                    # degenerate triangle: nearest of its edges
        best = np.inf
        for i in range(3):
            j = (i + 1) % 3
            d = segment_segment_dist2(px, py, pz, px, py, pz, T[i, 0], T[i, 1], T[i, 2],
                                      T[j, 0], T[j, 1], T[j, 2])
            best = min(best, d)
        return best
    den = 1.0 / s
    v = vb * den
    w = vc * den
    qx, qy, qz = ax + abx * v + acx * w, ay + aby * v + acy * w, az + abz * v + acz * w
    return (px - qx) ** 2 + (py - qy) ** 2 + (pz - qz) ** 2


@njit(cache=True, error_model="numpy")
def segment_segment_dist2(p1x, p1y, p1z, q1x, q1y, q1z, p2x, p2y, p2z, q2x, q2y, q2z):
    """Squared distance between segments p1-q1 and p2-q2 (either may be a point)."""
    d1x, d1y, d1z = q1x - p1x, q1y - p1y, q1z - p1z
    d2x, d2y, d2z = q2x - p2x, q2y - p2y, q2z - p2z
    rx, ry, rz = p1x - p2x, p1y - p2y, p1z - p2z
    a = _d3(d1x, d1y, d1z, d1x, d1y, d1z)
    e = _d3(d2x, d2y, d2z, d2x, d2y, d2z)
    f = _d3(d2x, d2y, d2z, rx, ry, rz)
    eps = 1e-30
    if a <= eps and e <= eps:
        return rx * rx + ry * ry + rz * rz
    if a <= eps:
        s = 0.0
        t = min(max(f / e, 0.0), 1.0)
    else:
        c = _d3(d1x, d1y, d1z, rx, ry, rz)
        if e <= eps:
            t = 0.0
            s = min(max(-c / a, 0.0), 1.0)
        else:
            b = _d3(d1x, d1y, d1z, d2x, d2y, d2z)
            den = a * e - b * b
            s = min(max((b * f - c * e) / den, 0.0), 1.0) if den > 1e-14 * a * e else 0.0
            t = (b * s + f) / e
            if t < 0.0:
                t = 0.0
                s = min(max(-c / a, 0.0), 1.0)
            elif t > 1.0:
                t = 1.0
                s = min(max((b - c) / a, 0.0), 1.0)
    cx = p1x + d1x * s - (p2x + d2x * t)
    cy = p1y + d1y * s - (p2y + d2y * t)
    cz = p1z + d1z * s - (p2z + d2z * t)
    return cx * cx + cy * cy + cz * cz


@njit(cache=True, error_model="numpy")
def ray_triangle(px, py, pz, dx, dy, dz, T, tiny, slack):
    """Parameter ``t`` where the line ``p + t d`` meets triangle ``T`` (Moller-Trumbore,
    in scalars; barycentrics allowed ``slack`` outside [0, 1]), or -1.0 when it misses
    or lies in the triangle's plane (``|det| < tiny``)."""
    e1x, e1y, e1z = T[1, 0] - T[0, 0], T[1, 1] - T[0, 1], T[1, 2] - T[0, 2]
    e2x, e2y, e2z = T[2, 0] - T[0, 0], T[2, 1] - T[0, 1], T[2, 2] - T[0, 2]
    hx, hy, hz = dy * e2z - dz * e2y, dz * e2x - dx * e2z, dx * e2y - dy * e2x
    det = _d3(e1x, e1y, e1z, hx, hy, hz)
    if abs(det) < tiny:
        return -1.0
    f = 1.0 / det
    sx, sy, sz = px - T[0, 0], py - T[0, 1], pz - T[0, 2]
    u = f * _d3(sx, sy, sz, hx, hy, hz)
    if u < -slack or u > 1.0 + slack:
        return -1.0
    cx, cy, cz = sy * e1z - sz * e1y, sz * e1x - sx * e1z, sx * e1y - sy * e1x
    v = f * _d3(dx, dy, dz, cx, cy, cz)
    if v < -slack or u + v > 1.0 + slack:
        return -1.0
    return f * _d3(e2x, e2y, e2z, cx, cy, cz)


@njit(cache=True, error_model="numpy")
def _segment_crosses(px, py, pz, qx, qy, qz, T):
    """True when segment p-q passes through triangle T."""
    t = ray_triangle(px, py, pz, qx - px, qy - py, qz - pz, T, 1e-300, 0.0)
    return 0.0 <= t <= 1.0


@njit(cache=True, error_model="numpy")
def segment_triangle_dist2(px, py, pz, qx, qy, qz, T):
    """Squared distance between segment p-q and triangle T (0 when they cross)."""
    if _segment_crosses(px, py, pz, qx, qy, qz, T):
        return 0.0
    best = min(point_triangle_dist2(px, py, pz, T), point_triangle_dist2(qx, qy, qz, T))
    for i in range(3):
        j = (i + 1) % 3
        d = segment_segment_dist2(px, py, pz, qx, qy, qz, T[i, 0], T[i, 1], T[i, 2],
                                  T[j, 0], T[j, 1], T[j, 2])
        if d < best:
            best = d
    return best


@njit(cache=True, error_model="numpy")
def triangle_triangle_dist2(A, B):
    """Squared distance between triangles A and B (0 when they meet): the nearest of
    each one's edges to the other."""
    best = np.inf
    for i in range(3):
        j = (i + 1) % 3
        d = segment_triangle_dist2(A[i, 0], A[i, 1], A[i, 2], A[j, 0], A[j, 1], A[j, 2], B)
        if d < best:
            best = d
            if best == 0.0:
                return 0.0
        d = segment_triangle_dist2(B[i, 0], B[i, 1], B[i, 2], B[j, 0], B[j, 1], B[j, 2], A)
        if d < best:
            best = d
            if best == 0.0:
                return 0.0
    return best


@njit(cache=True, error_model="numpy")
def ball_core(P0, P1, R, L, Q1, Q2):
    """Fill ``Q1``/``Q2`` (3, 3) with the two triangles of a ball cutter's core swept
    along P0 -> P1 (see the module doc); return False when the chord is vertical (the
    core is then the axis segment ``Q1[0] - Q1[1]``)."""
    dx = P1[0] - P0[0]
    dy = P1[1] - P0[1]
    if dx * dx + dy * dy <= 1e-24:
        Q1[0, 0] = P0[0]
        Q1[0, 1] = P0[1]
        Q1[0, 2] = min(P0[2], P1[2]) + R
        Q1[1, 0] = P0[0]
        Q1[1, 1] = P0[1]
        Q1[1, 2] = max(P0[2], P1[2]) + max(L, R)
        return False
    for a in range(3):
        Q1[0, a] = P0[a]
        Q1[1, a] = P1[a]
        Q1[2, a] = P1[a]
        Q2[0, a] = P0[a]
        Q2[1, a] = P1[a]
        Q2[2, a] = P0[a]
    Q1[0, 2] += R
    Q1[1, 2] += R
    Q1[2, 2] += max(L, R)
    Q2[0, 2] += R
    Q2[1, 2] += max(L, R)
    Q2[2, 2] += max(L, R)
    return True


@njit(cache=True, error_model="numpy", inline="always")
def _under_core(z, Q1):
    """True when height ``z`` is at or below a flat core's bottom edge (``Q1[0]`` -
    ``Q1[1]``, the ball centres): every core point lies straight above an edge point,
    farther from anything that low, so the edge alone gives the distance."""
    return z <= min(Q1[0, 2], Q1[1, 2])


@njit(cache=True, error_model="numpy")
def core_triangle_dist2(T, flat_core, Q1, Q2):
    """Squared distance between triangle T and a core from :func:`ball_core`."""
    if not flat_core or _under_core(max(T[0, 2], T[1, 2], T[2, 2]), Q1):
        return segment_triangle_dist2(Q1[0, 0], Q1[0, 1], Q1[0, 2], Q1[1, 0], Q1[1, 1],
                                      Q1[1, 2], T)
    return min(triangle_triangle_dist2(T, Q1), triangle_triangle_dist2(T, Q2))


@njit(cache=True, error_model="numpy")
def core_segment_dist2(px, py, pz, qx, qy, qz, flat_core, Q1, Q2):
    """Squared distance between segment p-q and a core from :func:`ball_core`."""
    if not flat_core or _under_core(max(pz, qz), Q1):
        return segment_segment_dist2(px, py, pz, qx, qy, qz, Q1[0, 0], Q1[0, 1], Q1[0, 2],
                                     Q1[1, 0], Q1[1, 1], Q1[1, 2])
    return min(segment_triangle_dist2(px, py, pz, qx, qy, qz, Q1),
               segment_triangle_dist2(px, py, pz, qx, qy, qz, Q2))


@njit(cache=True, error_model="numpy")
def core_point_dist2(px, py, pz, flat_core, Q1, Q2):
    """Squared distance between a point and a core from :func:`ball_core`."""
    if not flat_core or _under_core(pz, Q1):
        return segment_segment_dist2(px, py, pz, px, py, pz, Q1[0, 0], Q1[0, 1], Q1[0, 2],
                                     Q1[1, 0], Q1[1, 1], Q1[1, 2])
    return min(point_triangle_dist2(px, py, pz, Q1), point_triangle_dist2(px, py, pz, Q2))
