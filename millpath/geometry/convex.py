"""Exact intersection tests between a triangle (or segment) and a swept cutter solid.

Shapes are convex sets given by their support functions and tested with GJK
(Gilbert-Johnson-Keerthi) on the Minkowski difference. Lengths are in any consistent
unit; positions are tool tips.

A cutter solid, and each of its inner parallel bodies ``C_e = {q in C : dist(q, dC) >= e}``
(the points at least ``e`` deep inside it), is described in the tool frame (tip at the
origin, axis +Z) as the convex hull of up to three horizontal *rings* (radius ``r_i`` at
height ``h_i``; radius 0 is a point on the axis) grown by a ball of radius ``rho``:

- flat, radius R, top L:   rings (R-e, e), (R-e, L-e);            rho 0
- ball, radius R:          rings (0, R), (0, L-e);                rho R-e   (e <= R)
- bull, corner rc, a=R-rc: rings (a, rc), (a, L-e); rho rc-e  (e <= rc), else as flat
- drill, cone slope k:     rings (0, c), (R-e, c + k (R-e)), (R-e, L-e), c = e sqrt(1+k^2)
- cylinder (shank, holder) from zb to zt: rings (r-e, zb+e), (r-e, zt-e)

Swept along a straight chord P0 -> P1 the solid is that hull plus the chord (Minkowski
sum), still convex, so "the triangle meets the swept C_e" is exact, and the deepest
penetration of a triangle into the swept cutter (the largest ``e`` for which it meets
``C_e``) is found by bisection on ``e``.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

FLAT, BALL, BULL, DRILL, CYL = 0, 1, 2, 3, 4


@njit(cache=True, error_model="numpy")
def shape_rings(kind, R, rc, k, zb, L, e, rr, rh):
    """Fill ``rr``/``rh`` (length >= 3) with the rings of ``C_e``; return
    (number of rings, rho), or (0, 0) when ``C_e`` is empty. ``zb`` is the bottom of a
    cylinder (CYL), ``L`` the top of the solid above the tip."""
    if kind == BALL:
        if e >= R or L - e < R:
            return 0, 0.0
        rr[0] = 0.0
        rh[0] = R
        rr[1] = 0.0
        rh[1] = L - e
        return 2, R - e
    if kind == BULL and e < rc:
        a = R - rc
        rr[0] = a
        rh[0] = rc
        rr[1] = a
        rh[1] = L - e
        return 2, rc - e
    if kind == DRILL:
        c = e * math.sqrt(1.0 + k * k)
        r = R - e
        hc = c + k * r
        if r < 0.0 or hc > L - e:
            return 0, 0.0
        rr[0] = 0.0
        rh[0] = c
        rr[1] = r
        rh[1] = hc
        rr[2] = r
        rh[2] = L - e
        return 3, 0.0
    # FLAT, BULL beyond its corner radius, CYL
    b = zb if kind == CYL else 0.0
    r = R - e
    if r < 0.0 or b + e > L - e:
        return 0, 0.0
    rr[0] = r
    rh[0] = b + e
    rr[1] = r
    rh[1] = L - e
    return 2, 0.0


@njit(cache=True, error_model="numpy", inline="always")
def _sup_cut(P0, P1, nr, rr, rh, rho, dx, dy, dz, out):
    """Support point of (hull of rings + ball rho) swept along P0 -> P1 in (dx, dy, dz)."""
    if dx * P0[0] + dy * P0[1] + dz * P0[2] >= dx * P1[0] + dy * P1[1] + dz * P1[2]:
        bx, by, bz = P0[0], P0[1], P0[2]
    else:
        bx, by, bz = P1[0], P1[1], P1[2]
    n = math.sqrt(dx * dx + dy * dy)
    best = -np.inf
    bi = 0
    for i in range(nr):
        v = rr[i] * n + rh[i] * dz
        if v > best:
            best = v
            bi = i
    if n > 0.0:
        bx += rr[bi] * dx / n
        by += rr[bi] * dy / n
    bz += rh[bi]
    if rho > 0.0:
        dn = math.sqrt(dx * dx + dy * dy + dz * dz)
        if dn > 0.0:
            bx += rho * dx / dn
            by += rho * dy / dn
            bz += rho * dz / dn
    out[0] = bx
    out[1] = by
    out[2] = bz


@njit(cache=True, error_model="numpy")
def support_swept(P0, P1, nr, rr, rh, rho, dx, dy, dz, out):
    """Support point of a swept solid (rings, rho along P0 -> P1) in (dx, dy, dz)."""
    _sup_cut(P0, P1, nr, rr, rh, rho, dx, dy, dz, out)


@njit(cache=True, error_model="numpy", inline="always")
def _sup_tri(T, dx, dy, dz, out):
    b = 0
    bv = T[0, 0] * dx + T[0, 1] * dy + T[0, 2] * dz
    for i in range(1, 3):
        v = T[i, 0] * dx + T[i, 1] * dy + T[i, 2] * dz
        if v > bv:
            bv = v
            b = i
    out[0] = T[b, 0]
    out[1] = T[b, 1]
    out[2] = T[b, 2]


@njit(cache=True, error_model="numpy", inline="always")
def _dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


@njit(cache=True, error_model="numpy", inline="always")
def _cross(a, b, out):
    x = a[1] * b[2] - a[2] * b[1]
    y = a[2] * b[0] - a[0] * b[2]
    z = a[0] * b[1] - a[1] * b[0]
    out[0] = x
    out[1] = y
    out[2] = z


@njit(cache=True, error_model="numpy", inline="always")
def _edge_or_vertex(s, a, b, ab, ao, d, tmp):
    """The origin's nearest feature of segment a-b (a the newest point, ``ab = b - a``,
    ``ao = -a``): the edge (simplex [b, a], direction ``(ab x ao) x ab``) when the origin
    lies beyond a along ab, else the vertex a. Returns the simplex size."""
    if _dot(ab, ao) > 0.0:
        s[0] = b
        s[1] = a
        _cross(ab, ao, tmp)
        _cross(tmp, ab, d)
        return 2
    s[0] = a
    d[0] = ao[0]
    d[1] = ao[1]
    d[2] = ao[2]
    return 1


@njit(cache=True, error_model="numpy", inline="always")
def _face(s, p, q, a, nrm, sign, d):
    """The origin's nearest feature is triangle (p, q, a) (a the newest point): that
    simplex, direction ``sign * nrm``. Returns the simplex size."""
    s[0] = p
    s[1] = q
    s[2] = a
    d[0] = sign * nrm[0]
    d[1] = sign * nrm[1]
    d[2] = sign * nrm[2]
    return 3


@njit(cache=True, error_model="numpy")
def meets(T, P0, P1, nr, rr, rh, rho, tol):
    """True when triangle ``T`` (3, 3) meets the swept solid (rings, rho along
    P0 -> P1) or comes within ``tol`` of it (GJK on the Minkowski difference; within
    ``tol`` of the solid is in the solid grown by a ball of radius ``tol``)."""
    rho = rho + tol
    s = np.empty((4, 3))           # simplex, newest last
    ns = 0
    pa = np.empty(3)
    pb = np.empty(3)
    w = np.empty(3)
    d = np.empty(3)
    t1 = np.empty(3)
    t2 = np.empty(3)
    # initial direction: from the swept solid's rough centre to the triangle's centroid
    for i in range(3):
        d[i] = (T[0, i] + T[1, i] + T[2, i]) / 3.0 - 0.5 * (P0[i] + P1[i])
    d[2] -= 0.5 * (rh[0] + rh[nr - 1])
    if d[0] == 0.0 and d[1] == 0.0 and d[2] == 0.0:
        d[0] = 1.0
    for it in range(96):
        _sup_tri(T, d[0], d[1], d[2], pa)
        _sup_cut(P0, P1, nr, rr, rh, rho, -d[0], -d[1], -d[2], pb)
        for i in range(3):
            w[i] = pa[i] - pb[i]
        dn = math.sqrt(_dot(d, d))
        if ns > 0 and _dot(w, d) < 0.0:
            return False               # a separating plane
        if ns == 0 and _dot(w, d) < 0.0 and it > 0:
            return False
        s[ns, 0] = w[0]
        s[ns, 1] = w[1]
        s[ns, 2] = w[2]
        ns += 1
        # nearest feature of the simplex to the origin: new direction d
        a = s[ns - 1]
        if ns == 1:
            d[0] = -a[0]
            d[1] = -a[1]
            d[2] = -a[2]
        elif ns == 2:
            b = s[0]
            ab = b - a
            ao = -a
            ns = _edge_or_vertex(s, a, b, ab, ao, d, t1)
        elif ns == 3:
            b = s[1].copy()
            c = s[0].copy()
            ab = b - a
            ac = c - a
            ao = -a
            abc = np.empty(3)
            _cross(ab, ac, abc)
            _cross(abc, ac, t1)
            if _dot(t1, ao) > 0.0:
                if _dot(ac, ao) > 0.0:
                    ns = _edge_or_vertex(s, a, c, ac, ao, d, t2)
                else:
                    ns = _edge_or_vertex(s, a, b, ab, ao, d, t2)
            else:
                _cross(ab, abc, t1)
                if _dot(t1, ao) > 0.0:
                    ns = _edge_or_vertex(s, a, b, ab, ao, d, t2)
                else:
                    v = _dot(abc, ao)
                    if v > 0.0:
                        ns = _face(s, c, b, a, abc, 1.0, d)
                    elif v < 0.0:
                        ns = _face(s, b, c, a, abc, -1.0, d)
                    else:
                        return True            # origin on the triangle
        else:
            b = s[2].copy()
            c = s[1].copy()
            dd = s[0].copy()
            ab = b - a
            ac = c - a
            ad = dd - a
            ao = -a
            abc = np.empty(3)
            acd = np.empty(3)
            adb = np.empty(3)
            _cross(ab, ac, abc)
            _cross(ac, ad, acd)
            _cross(ad, ab, adb)
            # orient the face normals outward (away from the opposite vertex)
            if _dot(abc, ad) > 0.0:
                abc = -abc
            if _dot(acd, ab) > 0.0:
                acd = -acd
            if _dot(adb, ac) > 0.0:
                adb = -adb
            if _dot(abc, ao) > 0.0:
                ns = _face(s, c, b, a, abc, 1.0, d)
            elif _dot(acd, ao) > 0.0:
                ns = _face(s, dd, c, a, acd, 1.0, d)
            elif _dot(adb, ao) > 0.0:
                ns = _face(s, b, dd, a, adb, 1.0, d)
            else:
                return True                    # origin inside the tetrahedron
        if d[0] * d[0] + d[1] * d[1] + d[2] * d[2] < 1e-30:
            return True                        # origin on the simplex
    return True


@njit(cache=True, error_model="numpy")
def depth(T, P0, P1, kind, R, rc, k, zb, L, e0, tol, rr, rh):
    """Deepest penetration of triangle ``T`` into the solid swept along P0 -> P1:
    the largest ``e`` in [e0, R] with ``T`` meeting ``C_e``, to ``tol``; -1 when ``T``
    does not meet ``C_e0``."""
    nr, rho = shape_rings(kind, R, rc, k, zb, L, e0, rr, rh)
    if nr == 0 or not meets(T, P0, P1, nr, rr, rh, rho, 0.0):
        return -1.0
    lo = e0
    hi = R
    nr, rho = shape_rings(kind, R, rc, k, zb, L, hi, rr, rh)
    if nr > 0 and meets(T, P0, P1, nr, rr, rh, rho, 0.0):
        return hi
    while hi - lo > tol:
        m = 0.5 * (lo + hi)
        nr, rho = shape_rings(kind, R, rc, k, zb, L, m, rr, rh)
        if nr > 0 and meets(T, P0, P1, nr, rr, rh, rho, 0.0):
            lo = m
        else:
            hi = m
    return lo


@njit(cache=True, error_model="numpy")
def underside(P0, P1, kind, R, rc, k, zb, box, grow):
    """A height below every point of the tool (grown by ``grow``) swept along P0 -> P1
    over the XY rectangle ``box`` (x0, y0, x1, y1) (+inf when the tool cannot reach
    it): the lowest tip height plus the cutter's profile at a lower bound of the
    horizontal distance between the chord and the rectangle."""
    cx = 0.5 * (box[0] + box[2])
    cy = 0.5 * (box[1] + box[3])
    half = 0.5 * math.sqrt((box[2] - box[0]) ** 2 + (box[3] - box[1]) ** 2) * (1 + 1e-12)
    dx = P1[0] - P0[0]
    dy = P1[1] - P0[1]
    ll = dx * dx + dy * dy
    u = 0.0
    if ll > 0.0:
        u = min(max(((cx - P0[0]) * dx + (cy - P0[1]) * dy) / ll, 0.0), 1.0)
    ex = P0[0] + u * dx - cx
    ey = P0[1] + u * dy - cy
    h = math.sqrt(ex * ex + ey * ey) - half - grow
    z = min(P0[2], P1[2]) - grow
    if h > R:
        return np.inf
    if h <= 0.0:
        return z + (zb if kind == CYL else 0.0)
    if kind == BALL:
        return z + R - math.sqrt(R * R - h * h)
    if kind == BULL and h > R - rc:
        w = h - (R - rc)
        return z + rc - math.sqrt(max(rc * rc - w * w, 0.0))
    if kind == DRILL:
        return z + min(h * k, k * R)
    if kind == CYL:
        return z + zb
    return z
