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

from millpath.geometry.cutter import BALL, BULL, CYL, DRILL, height
from millpath.geometry.distance import segment_segment_dist2


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
def _closest_seg(W, i, j, v):
    """Point of segment W[i] W[j] nearest the origin into ``v``; returns the kept
    vertices as a bit mask (1 << index)."""
    abx = W[j, 0] - W[i, 0]
    aby = W[j, 1] - W[i, 1]
    abz = W[j, 2] - W[i, 2]
    ll = abx * abx + aby * aby + abz * abz
    t = 0.0
    if ll > 0.0:
        t = -(W[i, 0] * abx + W[i, 1] * aby + W[i, 2] * abz) / ll
    if t <= 0.0:
        v[:] = W[i]
        return 1 << i
    if t >= 1.0:
        v[:] = W[j]
        return 1 << j
    v[0] = W[i, 0] + t * abx
    v[1] = W[i, 1] + t * aby
    v[2] = W[i, 2] + t * abz
    return (1 << i) | (1 << j)


@njit(cache=True, error_model="numpy")
def _closest_tri(W, i, j, k, v):
    """Point of triangle W[i] W[j] W[k] nearest the origin into ``v`` (Voronoi
    regions of its vertices, edges and face); returns the kept vertices' mask.
    A degenerate (flat) triangle is taken as its three edges."""
    a = W[i]
    b = W[j]
    c = W[k]
    ab = b - a
    ac = c - a
    d1 = -_dot(ab, a)
    d2 = -_dot(ac, a)
    if d1 <= 0.0 and d2 <= 0.0:
        v[:] = a
        return 1 << i
    d3 = -_dot(ab, b)
    d4 = -_dot(ac, b)
    if d3 >= 0.0 and d4 <= d3:
        v[:] = b
        return 1 << j
    d5 = -_dot(ab, c)
    d6 = -_dot(ac, c)
    if d6 >= 0.0 and d5 <= d6:
        v[:] = c
        return 1 << k
    vc = d1 * d4 - d3 * d2
    vb = d5 * d2 - d1 * d6
    va = d3 * d6 - d5 * d4
    den = va + vb + vc
    n = np.empty(3)
    _cross(ab, ac, n)
    if den <= 1e-14 * _dot(ab, ab) * _dot(ac, ac) or _dot(n, n) == 0.0:
        best = np.inf
        m = 0
        t = np.empty(3)
        for (p, q) in ((i, j), (j, k), (i, k)):
            mm = _closest_seg(W, p, q, t)
            if _dot(t, t) < best:
                best = _dot(t, t)
                m = mm
                v[:] = t
        return m
    if vc <= 0.0 and d1 >= 0.0 and d3 <= 0.0:
        t = d1 / (d1 - d3)
        v[:] = a + t * ab
        return (1 << i) | (1 << j)
    if vb <= 0.0 and d2 >= 0.0 and d6 <= 0.0:
        t = d2 / (d2 - d6)
        v[:] = a + t * ac
        return (1 << i) | (1 << k)
    if va <= 0.0 and d4 - d3 >= 0.0 and d5 - d6 >= 0.0:
        t = (d4 - d3) / ((d4 - d3) + (d5 - d6))
        v[:] = b + t * (c - b)
        return (1 << j) | (1 << k)
    vb /= den
    vc /= den
    v[:] = a + ab * vb + ac * vc
    return (1 << i) | (1 << j) | (1 << k)


@njit(cache=True, error_model="numpy")
def _closest_tet(W, v):
    """Point of tetrahedron W[0..3] nearest the origin into ``v``; returns the kept
    vertices' mask, 15 when the origin is inside (then ``v`` is 0)."""
    best = np.inf
    m = 0
    t = np.empty(3)
    e1 = W[1] - W[0]
    e2 = W[2] - W[0]
    e3 = W[3] - W[0]
    n = np.empty(3)
    _cross(e2, e3, n)
    vol = _dot(e1, n)
    scale = math.sqrt(_dot(e1, e1) * _dot(e2, e2) * _dot(e3, e3))
    flat = abs(vol) <= 1e-12 * scale
    inside = not flat
    for f in range(4):                  # face f leaves out vertex f
        i, j, k = (f + 1) % 4, (f + 2) % 4, (f + 3) % 4
        a = W[i]
        ab = W[j] - a
        ac = W[k] - a
        _cross(ab, ac, n)
        so = -_dot(n, a)                 # side of the origin
        sd = _dot(n, W[f] - a)           # side of the left-out vertex
        if flat or so * sd < 0.0 or so == 0.0:
            if not flat and so * sd < 0.0:
                inside = False
            mm = _closest_tri(W, i, j, k, t)
            if _dot(t, t) < best:
                best = _dot(t, t)
                m = mm
                v[:] = t
    if inside:
        v[:] = 0.0
        return 15
    return m


@njit(cache=True, error_model="numpy", inline="always")
def _level_cylinder(P0, P1, nr, rr, rh, rho):
    """True when the solid (rings, rho) is a cylinder and P0 -> P1 is level: swept, a
    prism (see :func:`meets_prism`)."""
    return (rho == 0.0 and nr == 2 and rr[0] == rr[1] and P0[2] == P1[2]
            and rh[1] >= rh[0])


@njit(cache=True, error_model="numpy")
def meets_prism(T, x0, y0, x1, y1, r, za, zb):
    """True when triangle ``T`` meets the prism {(x, y, z): (x, y) within ``r`` of the
    segment (x0, y0) - (x1, y1), za <= z <= zb}: a cylinder of radius r (flat end, the
    rings of a flat or a shank) swept along a level chord. Exact: the triangle is
    clipped to the slab, and the clipped polygon's distance from the segment, seen from
    above, compared with r."""
    # clip to za <= z <= zb (Sutherland-Hodgman, two planes): at most 5 corners
    A = np.empty((6, 3))
    B = np.empty((6, 3))
    for i in range(3):
        for a in range(3):
            A[i, a] = T[i, a]
    n = 3
    for side in range(2):
        m = 0
        for i in range(n):
            j = (i + 1) % n
            zi = A[i, 2] - za if side == 0 else zb - A[i, 2]
            zj = A[j, 2] - za if side == 0 else zb - A[j, 2]
            if zi >= 0.0:
                for a in range(3):
                    B[m, a] = A[i, a]
                m += 1
            if (zi >= 0.0) != (zj >= 0.0):
                t = zi / (zi - zj)
                for a in range(3):
                    B[m, a] = A[i, a] + (A[j, a] - A[i, a]) * t
                m += 1
        n = m
        if n == 0:
            return False
        for i in range(n):
            for a in range(3):
                A[i, a] = B[i, a]
    r2 = r * r
    for i in range(n):
        j = (i + 1) % n
        if segment_segment_dist2(A[i, 0], A[i, 1], 0.0, A[j, 0], A[j, 1], 0.0,
                                 x0, y0, 0.0, x1, y1, 0.0) <= r2:
            return True
    # the segment wholly inside the polygon (either winding; a polygon seen edge-on,
    # a wall's, is its edges, done above)
    area = 0.0
    for i in range(n):
        j = (i + 1) % n
        area += ((A[i, 0] - A[0, 0]) * (A[j, 1] - A[0, 1])
                 - (A[j, 0] - A[0, 0]) * (A[i, 1] - A[0, 1]))
    if n < 3 or area == 0.0:
        return False
    for i in range(n):
        j = (i + 1) % n
        c = ((A[j, 0] - A[i, 0]) * (y0 - A[i, 1]) - (A[j, 1] - A[i, 1]) * (x0 - A[i, 0]))
        if c * area < 0.0:
            return False
    return True


@njit(cache=True, error_model="numpy")
def meets(T, P0, P1, nr, rr, rh, rho, tol):
    """True when triangle ``T`` (3, 3) meets the swept solid (rings, rho along
    P0 -> P1) or comes within ``tol`` of it: GJK distance iteration (van den Bergen)
    on the Minkowski difference ``T - solid``, which keeps the simplex's point ``v``
    nearest the origin; ``|v|`` bounds the distance from above and ``v.w / |v|``
    (``w`` the support point against ``v``) from below, so the answer is proven once
    one bound passes ``tol``, or when the bounds meet (within ``1e-10`` of the
    coordinates' size: both answers are then right to that)."""
    if tol <= 0.0 and _level_cylinder(P0, P1, nr, rr, rh, rho):
        # a cylinder swept along a level chord is a prism: exact without iterating
        return meets_prism(T, P0[0], P0[1], P1[0], P1[1], rr[0], P0[2] + rh[0],
                           P0[2] + rh[1])
    W = np.empty((4, 3))
    Wn = np.empty((4, 3))
    nw = 0
    pa = np.empty(3)
    pb = np.empty(3)
    w = np.empty(3)
    v = np.empty(3)
    nv = np.empty(3)
    scale = 1.0
    for i in range(3):
        scale = max(scale, abs(P0[i]), abs(P1[i]), abs(T[0, i]), abs(T[1, i]), abs(T[2, i]))
    gap = 1e-10 * scale
    # a first point of the difference: the triangle's centroid less a point of the solid
    for i in range(3):
        v[i] = (T[0, i] + T[1, i] + T[2, i]) / 3.0 - P0[i]
    v[0] -= rr[0]
    v[2] -= rh[0]
    lower = -np.inf
    for it in range(256):
        vv = _dot(v, v)
        if vv <= gap * gap:
            return True
        vn = math.sqrt(vv)
        if vn <= tol:
            return True
        _sup_tri(T, -v[0], -v[1], -v[2], pa)
        _sup_cut(P0, P1, nr, rr, rh, rho, v[0], v[1], v[2], pb)
        for i in range(3):
            w[i] = pa[i] - pb[i]
        lb = _dot(v, w) / vn               # the distance is at least this
        if lb > lower:
            lower = lb
        if lower > tol:
            return False
        if vn - lower <= gap:
            return True                    # bounds met: the distance is tol or less
        W[nw] = w
        nw += 1
        if nw == 1:
            m = 1
            nv[:] = w
        elif nw == 2:
            m = _closest_seg(W, 0, 1, nv)
        elif nw == 3:
            # (int64 corners, not literals: one compiled signature of _closest_tri)
            m = _closest_tri(W, np.int64(0), np.int64(1), np.int64(2), nv)
        else:
            m = _closest_tet(W, nv)
            if m == 15:
                return True                # the origin is inside: they meet
        if it > 0 and _dot(nv, nv) >= vv:      # (the first v is not the simplex's)
            return True        # no progress (rounding): within reach of tol, say they meet
        v[:] = nv
        q = 0
        for i in range(nw):
            if m & (1 << i):
                Wn[q] = W[i]
                q += 1
        for i in range(q):
            W[i] = Wn[i]
        nw = q
    return lower <= tol


@njit(cache=True, error_model="numpy")
def may_meet(T, P0, P1, nr, rr, rh, rho, g):
    """:func:`meets` ``(..., g)`` for pre-tests, which may answer True more often: a
    cylinder swept along a level chord is tested as its prism grown by ``g`` across
    and along the axis (which holds the prism grown by ``g`` in every direction)
    without iterating."""
    if g > 0.0 and _level_cylinder(P0, P1, nr, rr, rh, rho):
        return meets_prism(T, P0[0], P0[1], P1[0], P1[1], rr[0] + g, P0[2] + rh[0] - g,
                           P0[2] + rh[1] + g)
    return meets(T, P0, P1, nr, rr, rh, rho, g)


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
    if kind == CYL:
        return z + zb
    return z + height(kind, R, rc, k, h if h > 0.0 else 0.0)
