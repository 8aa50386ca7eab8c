"""A sharp tool's rim (flat end, drill point and cone rim, holder cylinder) searched
where its depth in the design can be largest, for the exact gouge check
(:mod:`millpath.simulate.gouge`): the two rim points abeam of a level chord all along
it, and the whole ring at each end, each line or ring cut where it crosses the design's
triangles and each piece in the material searched by golden section for its distance
from the surface; with the small triangle kernels it needs (barycentrics, the distance
of a point from the design's surface). Lengths are program units.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from millpath.geometry.distance import point_triangle_dist2, ray_triangle
from millpath.geometry.index import box_candidates
from millpath.geometry.inside import in_material

@njit(cache=True, error_model="numpy")
def barycentric(T, q):
    """(u, v) of point ``q`` (in the plane of ``T``): q = T0 + u (T1 - T0) + v (T2 - T0);
    (nan, nan) for a degenerate triangle."""
    e1 = T[1] - T[0]
    e2 = T[2] - T[0]
    w = q - T[0]
    d11 = np.dot(e1, e1)
    d12 = np.dot(e1, e2)
    d22 = np.dot(e2, e2)
    den = d11 * d22 - d12 * d12
    if den <= 0.0:
        return np.nan, np.nan
    w1 = np.dot(w, e1)
    w2 = np.dot(w, e2)
    return (d22 * w1 - d12 * w2) / den, (d11 * w2 - d12 * w1) / den


@njit(cache=True, error_model="numpy")
def in_triangle(T, q):
    """True when point ``q`` (in the plane of ``T``) lies in triangle ``T``."""
    u, v = barycentric(T, q)
    eps = 1e-9
    return u >= -eps and v >= -eps and u + v <= 1.0 + eps


@njit(cache=True, error_model="numpy")
def surface_dist2(X, r, tri, ix, buf):
    """Squared distance from point X to the nearest triangle, at most ``r**2``
    (``buf``: a scratch int64 array, see :func:`box_candidates`)."""
    best = r * r
    nc, buf = box_candidates(ix,
                             X[0] - r, X[1] - r, X[2] - r, X[0] + r, X[1] + r, X[2] + r, buf)
    for p in range(nc):
        d = point_triangle_dist2(X[0], X[1], X[2], tri[buf[p]])
        if d < best:
            best = d
    return best


@njit(cache=True, error_model="numpy")
def depth_at(q, cap, tri, ix, sbuf):
    """Distance of tool point ``q`` from the design's surface, at most ``cap``, when it
    is in the material; else -1."""
    if not in_material(q, tri, ix[2], ix[3], ix[8], ix[9], ix[10], ix[11], ix[12]):
        return -1.0
    return math.sqrt(surface_dist2(q, cap, tri, ix, sbuf))


@njit(cache=True, error_model="numpy")
def line_point(A, D, u, h, q):
    q[0] = A[0] + u * D[0]
    q[1] = A[1] + u * D[1]
    q[2] = A[2] + u * D[2] + h


@njit(cache=True, error_model="numpy")
def ring_point(E, r, h, ph, q):
    q[0] = E[0] + r * math.cos(ph)
    q[1] = E[1] + r * math.sin(ph)
    q[2] = E[2] + h


@njit(cache=True, error_model="numpy")
def golden(ring, A, D, r, h, a, b, cap, tri, ix, sbuf, q):
    """(depth, parameter) of the deepest point in [a, b] (golden-section search, 30
    steps) of the line ``A + u D`` raised by ``h`` (``ring`` False) or of the ring of
    radius ``r`` at height ``h`` about ``A`` at angle u (``ring`` True)."""
    gr = 0.5 * (math.sqrt(5.0) - 1.0)
    m1 = b - gr * (b - a)
    m2 = a + gr * (b - a)
    if ring:
        ring_point(A, r, h, m1, q)
    else:
        line_point(A, D, m1, h, q)
    d1 = depth_at(q, cap, tri, ix, sbuf)
    if ring:
        ring_point(A, r, h, m2, q)
    else:
        line_point(A, D, m2, h, q)
    d2 = depth_at(q, cap, tri, ix, sbuf)
    bd, bu = (d1, m1) if d1 >= d2 else (d2, m2)
    for _ in range(30):
        if d1 >= d2:
            b = m2
            m2 = m1
            d2 = d1
            m1 = b - gr * (b - a)
            if ring:
                ring_point(A, r, h, m1, q)
            else:
                line_point(A, D, m1, h, q)
            d1 = depth_at(q, cap, tri, ix, sbuf)
            if d1 > bd:
                bd, bu = d1, m1
        else:
            a = m1
            m1 = m2
            d1 = d2
            m2 = a + gr * (b - a)
            if ring:
                ring_point(A, r, h, m2, q)
            else:
                line_point(A, D, m2, h, q)
            d2 = depth_at(q, cap, tri, ix, sbuf)
            if d2 > bd:
                bd, bu = d2, m2
    return bd, bu


@njit(cache=True, error_model="numpy")
def search_cuts(ring, A, D, r, h, cuts, nk, lo, hi, cap, tri, ix, sbuf, q):
    """Best (depth, parameter) over [lo, hi] cut at ``cuts[:nk]`` (where the line or
    ring crosses the design: in between it is wholly in or out of the material): each
    piece whose middle is in the material searched by :func:`golden`."""
    cs = np.sort(cuts[:nk])
    bd = -1.0
    bu = lo
    prev = lo
    for k in range(nk + 1):
        nxt = hi if k == nk else cs[k]
        if nxt <= prev:
            continue
        mid = 0.5 * (prev + nxt)
        if ring:
            ring_point(A, r, h, mid, q)
        else:
            line_point(A, D, mid, h, q)
        if depth_at(q, cap, tri, ix, sbuf) >= 0.0:
            d, u = golden(ring, A, D, r, h, prev, nxt, cap, tri, ix, sbuf, q)
            if d > bd:
                bd = d
                bu = u
        prev = nxt
    return bd, bu


@njit(cache=True, error_model="numpy")
def rim_search(P0, P1, nr, rr, rh, best, tri, tn, ix, cand, nc, sbuf, out, q):
    """The deepest point in the material (distance from the design's surface) of the
    rings ``rr``/``rh`` (all but the top one) of a sharp tool swept along P0 -> P1
    where it can be deepest: with the chord's direction horizontal, the two ring
    points abeam of it (a depth largest inside the chord has its surface normal
    across the chord), all along the chord; and every ring point at the chord's ends.
    Each line or ring is cut where it crosses a triangle of ``cand[:nc]`` and each of
    its pieces in the material searched (the distance from the surface is unimodal
    there near a convex contact). Returns the depth (-1: none found) with its point
    in ``out``; ``q``: scratch (3,)."""
    D = P1 - P0
    dh = math.sqrt(D[0] * D[0] + D[1] * D[1])
    cap = 4.0 * best + 1e-9
    cuts = np.empty(2 * nc + 2)
    A = np.empty(3)
    top = -1.0
    for i in range(nr - 1):
        r = rr[i]
        # along the chord, abeam (either side; a point on the axis: once)
        nside = 0 if dh == 0.0 else (2 if r > 0.0 else 1)
        for side in range(nside):
            sg = 1.0 if side == 0 else -1.0
            A[0] = P0[0] - sg * D[1] / dh * r
            A[1] = P0[1] + sg * D[0] / dh * r
            A[2] = P0[2]
            nk = np.int64(0)     # (not a literal 0: one compiled signature per call)
            for p in range(nc):
                t = cand[p]
                u = ray_triangle(A[0], A[1], A[2] + rh[i], D[0], D[1], D[2], tri[t], 1e-300,
                                 1e-9)
                if 0.0 < u < 1.0:
                    cuts[nk] = u
                    nk += 1
            d, u = search_cuts(False, A, D, 0.0, rh[i], cuts, nk, 0.0, 1.0, cap, tri, ix,
                                sbuf, q)
            if d > top:
                top = d
                line_point(A, D, u, rh[i], out)
        if r == 0.0:
            continue
        # round the ring at each end: cut where it crosses the triangles' planes
        # within them
        for e in range(2):
            E = P0 if e == 0 else P1
            nk = np.int64(0)
            for p in range(nc):
                t = cand[p]
                nx, ny, nz = tn[t, 0], tn[t, 1], tn[t, 2]
                ab = r * math.sqrt(nx * nx + ny * ny)
                if ab == 0.0:
                    continue
                cc = (nx * tri[t, 0, 0] + ny * tri[t, 0, 1] + nz * tri[t, 0, 2]
                      - (nx * E[0] + ny * E[1] + nz * (E[2] + rh[i])))
                if abs(cc) > ab:
                    continue
                base = math.atan2(ny, nx)
                off = math.acos(min(max(cc / ab, -1.0), 1.0))
                for sg in (-1.0, 1.0):
                    ph = base + sg * off
                    ring_point(E, r, rh[i], ph, q)
                    if in_triangle(tri[t], q):
                        cuts[nk] = ph
                        nk += 1
            # the ring from its first cut round (any start will do)
            start = cuts[0] if nk > 0 else 0.0
            for k in range(nk):
                cuts[k] = start + (cuts[k] - start) % (2.0 * math.pi)
            d, u = search_cuts(True, E, D, r, rh[i], cuts, nk, start,
                                start + 2.0 * math.pi, cap, tri, ix, sbuf, q)
            if d > top:
                top = d
                ring_point(E, r, rh[i], u, out)
    return top


