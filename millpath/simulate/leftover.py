"""Material left, measured along the design's normal at points on its surface.

At each sample point ``s`` of a design triangle (outward unit normal ``n``) the material
left is the length of the segment ``s + t n`` (``t >= 0``) that is still stock: it ends
where the segment first enters the solid swept by any cutting chord (found exactly with
GJK tests and bisection to ``accuracy / 20``), leaves the stock box, or meets the design
again (the other side of a slot). A point already inside a swept solid (cut to or
below the design) has none left. Exact at the sample points; between them the figure
is interpolated by the sampling (``spacing``, reported). Program units.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numba import njit

from millpath.geometry.convex import may_meet, meets, shape_rings, underside
from millpath.geometry.cutter import BALL
from millpath.geometry.distance import (ball_core, core_point_dist2, core_segment_dist2,
                                        point_triangle_dist2, ray_triangle,
                                        segment_segment_dist2)
from millpath.geometry.index import BoxIndex, box_candidates
from millpath.threads import over_range


def sample_triangles(tri: np.ndarray, spacing: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Points on each triangle at most ``spacing`` apart, their triangle's unit normal
    (right-hand winding) and the triangle number. Rows parallel to the longest edge,
    ``spacing`` apart across it, points ``spacing`` apart along each row: about area /
    spacing^2 + length / spacing points a triangle, slivers (a wall's tall thin
    triangles) included."""
    tri = np.asarray(tri, float).reshape(-1, 3, 3)
    nrm = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    ln = np.linalg.norm(nrm, axis=1)
    ok = ln > 0
    nrm[ok] /= ln[ok, None]
    # put the longest edge first: A -> B, C opposite
    el = np.stack([np.linalg.norm(tri[:, 1] - tri[:, 0], axis=1),
                   np.linalg.norm(tri[:, 2] - tri[:, 1], axis=1),
                   np.linalg.norm(tri[:, 0] - tri[:, 2], axis=1)], axis=1)
    k = np.argmax(el, axis=1)
    idx = np.stack([k, (k + 1) % 3, (k + 2) % 3], axis=1)
    T = np.take_along_axis(tri, idx[:, :, None], axis=1)
    L = el[np.arange(len(tri)), k]
    h = np.where(L > 0, ln / np.where(L > 0, L, 1.0), 0.0)
    ns = np.maximum(1, np.ceil(L / spacing - 1e-9)).astype(np.int64)
    nt = np.maximum(1, np.ceil(h / spacing - 1e-9)).astype(np.int64)
    pts, nor, own = [], [], []
    key = ns * (int(nt.max(initial=1)) + 1) + nt
    for kk in np.unique(key[ok]):
        sel = np.flatnonzero(ok & (key == kk))
        a, c = int(ns[sel[0]]), int(nt[sel[0]])
        us, vs = [], []
        for j in range(c + 1):
            v = j / c
            m = int(math.ceil((1.0 - v) * a - 1e-9))
            if m <= 0:
                us.append(0.0)
                vs.append(v)
                continue
            us.extend(((1.0 - v) * np.arange(m + 1) / m).tolist())
            vs.extend([v] * (m + 1))
        u = np.asarray(us)[None, :, None]
        v = np.asarray(vs)[None, :, None]
        Ts = T[sel]
        p = Ts[:, None, 0] + u * (Ts[:, None, 1] - Ts[:, None, 0]) + v * (Ts[:, None, 2] - Ts[:, None, 0])
        pts.append(p.reshape(-1, 3))
        nor.append(np.repeat(nrm[sel], u.shape[1], axis=0))
        own.append(np.repeat(sel, u.shape[1]))
    if not pts:
        z = np.zeros((0, 3))
        return z, z.copy(), np.zeros(0, np.int64)
    return np.vstack(pts), np.vstack(nor), np.concatenate(own)


_KEY = np.dtype((np.void, 48))       # one row of six int64


def sample_keys(points: np.ndarray, normals: np.ndarray, cell: float, lo, hi) -> np.ndarray:
    """One sortable key per sample: its ``cell``-sized voxel and its normal's direction
    (rounded to quarters, -4 .. 4). An int64 (the voxel numbered within the box ``lo``
    .. ``hi``, the mesh's, grown by a voxel) when that numbering fits, else the six
    numbers as a 48-byte record."""
    vox = np.floor(points / cell).astype(np.int64)
    d = np.round(normals * 4).astype(np.int64)
    v0 = np.floor(np.asarray(lo, float) / cell).astype(np.int64) - 1
    size = np.floor(np.asarray(hi, float) / cell).astype(np.int64) + 2 - v0
    if float(np.prod(size.astype(float))) * 729 >= 2.0 ** 62:
        return np.ascontiguousarray(np.concatenate([vox, d], axis=1)).view(_KEY).ravel()
    v = np.clip(vox - v0, 0, size - 1)      # (inside by a voxel: a clip never bites)
    return ((v[:, 0] * size[1] + v[:, 1]) * size[2] + v[:, 2]) * 729 \
        + (d[:, 0] + 4) * 81 + (d[:, 1] + 4) * 9 + (d[:, 2] + 4)


def first_of_each(keys: np.ndarray) -> np.ndarray:
    """Indices of the first occurrence of each key, in order."""
    _, first = np.unique(keys, return_index=True)
    first.sort()
    return first


SLACK = 1.0 - 1e-9          # "nearer" in _medial: by more than rounding (relative, squared)


@njit(cache=True)
def _box_exit(p, n, lo, hi):
    """Distance along n from p to where the ray leaves the box (0 if p is outside)."""
    t = np.inf
    for a in range(3):
        if p[a] < lo[a] - 1e-9 or p[a] > hi[a] + 1e-9:
            return 0.0
        if n[a] > 1e-15:
            t = min(t, (hi[a] - p[a]) / n[a])
        elif n[a] < -1e-15:
            t = min(t, (lo[a] - p[a]) / n[a])
    return max(t, 0.0)


@njit(cache=True, inline="always")
def _ray_box(p, n, U, ex):
    """Fill ``ex`` with the end ``p + U n`` of a ray; return the segment's box
    (x0, y0, z0, x1, y1, z1)."""
    for a in range(3):
        ex[a] = p[a] + n[a] * U
    return (min(p[0], ex[0]), min(p[1], ex[1]), min(p[2], ex[2]),
            max(p[0], ex[0]), max(p[1], ex[1]), max(p[2], ex[2]))


@njit(cache=True, inline="always")
def _point_dist2(p, n, t, T):
    """Squared distance from the ray's point ``p + t n`` to triangle T."""
    return point_triangle_dist2(p[0] + n[0] * t, p[1] + n[1] * t, p[2] + n[2] * t, T)


@njit(cache=True, nogil=True)
def _caps(lo, hi, P, N, own, blo, bhi, tri, ix, reach, out):
    """Segment length before the ray leaves the stock box or meets another triangle."""
    m = P.shape[0]
    for q in range(lo, hi):
        p = P[q]
        n = N[q]
        U = min(_box_exit(p, n, blo, bhi), reach)
        if U > 0.0:
            buf = np.empty(64, np.int64)
            ex = np.empty(3)
            qx0, qy0, qz0, qx1, qy1, qz1 = _ray_box(p, n, U, ex)
            # (a triangle the segment crosses overlaps its box: floors and tops
            # under or over a level ray are passed over whole)
            nc, buf = box_candidates(ix, qx0 - 1e-9, qy0 - 1e-9, qz0 - 1e-9, qx1 + 1e-9,
                                     qy1 + 1e-9, qz1 + 1e-9, buf)
            for k in range(nc):
                t = buf[k]
                if t == own[q]:
                    continue
                tt = ray_triangle(p[0], p[1], p[2], n[0], n[1], n[2], tri[t], 1e-14, 1e-12)
                if 1e-7 < tt < U:
                    U = tt
        out[q] = U


@njit(cache=True, nogil=True)
def _medial(lo, hi, P, N, own, tri, ix, margin, out):
    """Shorten each ``out[q]`` to where another triangle becomes nearer to
    ``P[q] + t N[q]`` than ``t`` (beyond it the point is no longer ``t`` from the design:
    concave corners, the far side of a slot). Triangles more than ``margin`` beside the
    ray are not looked at (a wall that far off bounds only uncut stock)."""
    m = P.shape[0]
    for q in range(lo, hi):
        buf = np.empty(64, np.int64)
        ex = np.empty(3)
        p = P[q]
        n = N[q]
        U = out[q]
        if U <= 0.0:
            continue
        w = min(U, margin)
        qx0, qy0, qz0, qx1, qy1, qz1 = _ray_box(p, n, U, ex)
        # a triangle nearer than t to the ray's point at t <= U is nearer than U to its
        # end ``ex``: only the box U around ``ex`` (within the ray's box grown by w)
        nc, buf = box_candidates(ix, max(qx0 - w, ex[0] - U), max(qy0 - w, ex[1] - U),
                                 max(qz0 - w, ex[2] - U), min(qx1 + w, ex[0] + U),
                                 min(qy1 + w, ex[1] + U), min(qz1 + w, ex[2] + U), buf)
        for k in range(nc):
            t = buf[k]
            if t == own[q]:
                continue
            # strictly nearer (a neighbour across a convex edge is exactly as
            # near as the design point: rounding must not cap the ray there)
            if _point_dist2(p, n, U, tri[t]) >= U * U * SLACK:
                continue
            lo = 0.0
            hi = U
            for _ in range(40):
                mid = 0.5 * (lo + hi)
                if _point_dist2(p, n, mid, tri[t]) < mid * mid * SLACK:
                    hi = mid
                else:
                    lo = mid
                if hi - lo < 1e-7:
                    break
            U = lo
        out[q] = U


@njit(cache=True, inline="always")
def _cutter_and_ray(kind, R, rc, k, L, p, ex, rr, rh, T):
    """The cutter's rings (``rr``/``rh``; returns (count, rho), see ``shape_rings``) and
    the ray p -> ex as a degenerate triangle in ``T``, for ``meets``."""
    for a in range(3):
        T[0, a] = p[a]
        T[1, a] = ex[a]
        T[2, a] = ex[a]
    return shape_rings(kind, R, rc, k, 0.0, L, 0.0, rr, rh)


@njit(cache=True, inline="always")
def _xy_seg_dist2(ax, ay, bx, by, cx, cy, dx, dy):
    """Squared distance between 2D segments a-b and c-d."""
    return segment_segment_dist2(ax, ay, 0.0, bx, by, 0.0, cx, cy, 0.0, dx, dy, 0.0)


@njit(cache=True, inline="always")
def _point_cut(X, cand, nc, S, E, slot, clo, chi, gstart, gS, gE, gdev, glo, ghi, kind, R,
               rc, k, L, rr, rh, T, Q1, Q2, box):
    """A chord of the candidate groups ``cand[:nc]`` whose swept cutter holds the
    point ``X`` (-1: none); one containment test a chord, no bisection."""
    for a in range(3):
        T[0, a] = X[a]
        T[1, a] = X[a]
        T[2, a] = X[a]
    box[0] = X[0]
    box[1] = X[1]
    box[2] = X[0]
    box[3] = X[1]
    for it in range(nc):
        gi = cand[it]
        if (ghi[gi, 0] < X[0] or glo[gi, 0] > X[0] or ghi[gi, 1] < X[1]
                or glo[gi, 1] > X[1] or ghi[gi, 2] < X[2] or glo[gi, 2] > X[2]):
            continue
        s = slot[gstart[gi]]
        if gstart[gi + 1] - gstart[gi] > 1:
            dv = gdev[gi]
            Rg = R[s, 0] + dv
            if _xy_seg_dist2(X[0], X[1], X[0], X[1], gS[gi, 0], gS[gi, 1], gE[gi, 0],
                             gE[gi, 1]) > Rg * Rg:
                continue
            if kind[s, 0] == BALL:
                fc = ball_core(gS[gi], gE[gi], R[s, 0], L[s, 0], Q1, Q2)
                if core_point_dist2(X[0], X[1], X[2], fc, Q1, Q2) > Rg * Rg:
                    continue
            else:
                nr, rho = shape_rings(kind[s, 0], R[s, 0], rc[s, 0], k[s, 0], 0.0, L[s, 0],
                                      0.0, rr, rh)
                if nr == 0 or not may_meet(T, gS[gi], gE[gi], nr, rr, rh, rho, dv):
                    continue
        for c in range(gstart[gi], gstart[gi + 1]):
            if (chi[c, 0] < X[0] or clo[c, 0] > X[0] or chi[c, 1] < X[1]
                    or clo[c, 1] > X[1] or chi[c, 2] < X[2] or clo[c, 2] > X[2]):
                continue
            s = slot[c]
            if X[2] < underside(S[c], E[c], kind[s, 0], R[s, 0], rc[s, 0], k[s, 0], 0.0,
                                box, 0.0):
                continue
            if _xy_seg_dist2(X[0], X[1], X[0], X[1], S[c, 0], S[c, 1], E[c, 0],
                             E[c, 1]) > R[s, 0] * R[s, 0]:
                continue
            if kind[s, 0] == BALL:
                fc = ball_core(S[c], E[c], R[s, 0], L[s, 0], Q1, Q2)
                if core_point_dist2(X[0], X[1], X[2], fc, Q1, Q2) <= R[s, 0] * R[s, 0]:
                    return c
                continue
            nr, rho = shape_rings(kind[s, 0], R[s, 0], rc[s, 0], k[s, 0], 0.0, L[s, 0], 0.0,
                                  rr, rh)
            if nr > 0 and meets(T, S[c], E[c], nr, rr, rh, rho, 0.0):
                return c
    return -1


@njit(cache=True, nogil=True)
def _left(lo, hi, P, N, U0, S, E, slot, clo, chi, gstart, gS, gE, gdev, kind, R, rc, k, zb, L, gix,
          tol, stop, out, out_c):
    """See :func:`shorten_rays`: the chords in groups (``gstart``), each group looked
    at whole first (its coarse chord ``gS -> gE`` grown by ``gdev``); a ray shorter
    than ``stop`` is not traced further."""
    m = P.shape[0]
    glo = gix[0]
    ghi = gix[1]
    for q in range(lo, hi):
        buf = np.empty(256, np.int64)
        rr = np.empty(3)
        rh = np.empty(3)
        T = np.empty((3, 3))
        Q1 = np.empty((3, 3))
        Q2 = np.empty((3, 3))
        box = np.empty(4)
        ex = np.empty(3)
        p = P[q]
        n = N[q]
        U = U0[q]
        who = -1
        if U > 0.0 and U >= stop:
            qx0, qy0, qz0, qx1, qy1, qz1 = _ray_box(p, n, U, ex)
            nc, buf = box_candidates(gix, qx0, qy0, qz0, qx1, qy1, qz1, buf)
            # the groups in their order (the last chords first, see ``swept_chords``):
            # the finishing passes shorten the ray before the roughing ones are looked at
            # the groups passing nearest the ray's start first (seen from above; ties:
            # the last chords first, see ``swept_chords``): they shorten the ray most,
            # and the short ray's box passes most others over at once
            buf[:nc].sort()
            if nc > 1:
                key = np.empty(nc)
                for it in range(nc):
                    gi = buf[it]
                    key[it] = _xy_seg_dist2(p[0], p[1], p[0], p[1], gS[gi, 0], gS[gi, 1],
                                            gE[gi, 0], gE[gi, 1])
                buf[:nc] = buf[:nc][np.argsort(key, kind="mergesort")]
            if stop > 2.0 * tol:
                # a surface cut to within ``stop``: one test a chord at the point
                # ``stop - 2 tol`` along the ray settles it (the bisection below would
                # end under ``stop`` too)
                t1 = stop - 2.0 * tol
                for a in range(3):
                    ex[a] = p[a] + n[a] * t1
                c1 = _point_cut(ex, buf, nc, S, E, slot, clo, chi, gstart, gS, gE, gdev,
                                glo, ghi, kind, R, rc, k, L, rr, rh, T, Q1, Q2, box)
                if c1 >= 0:
                    U = t1
                    who = c1
                qx0, qy0, qz0, qx1, qy1, qz1 = _ray_box(p, n, U, ex)
            for it in range(nc):
                gi = buf[it]
                if U <= 0.0 or U < stop:
                    break
                if (ghi[gi, 0] < qx0 or glo[gi, 0] > qx1 or ghi[gi, 1] < qy0
                        or glo[gi, 1] > qy1 or ghi[gi, 2] < qz0 or glo[gi, 2] > qz1):
                    continue
                s = slot[gstart[gi]]
                dv = gdev[gi]
                if gstart[gi + 1] - gstart[gi] > 1:
                    # the whole run: within its deviation of the coarse chord's sweep
                    Rg = R[s, 0] + dv
                    if _xy_seg_dist2(p[0], p[1], ex[0], ex[1], gS[gi, 0], gS[gi, 1],
                                     gE[gi, 0], gE[gi, 1]) > Rg * Rg:
                        continue
                    if kind[s, 0] == BALL:
                        fc = ball_core(gS[gi], gE[gi], R[s, 0], L[s, 0], Q1, Q2)
                        if core_segment_dist2(p[0], p[1], p[2], ex[0], ex[1], ex[2], fc,
                                              Q1, Q2) > Rg * Rg:
                            continue
                    else:
                        nr, rho = _cutter_and_ray(kind[s, 0], R[s, 0], rc[s, 0], k[s, 0],
                                                  L[s, 0], p, ex, rr, rh, T)
                        if nr == 0:
                            continue
                        if not may_meet(T, gS[gi], gE[gi], nr, rr, rh, rho, dv):
                            continue
                # the group's chord passing nearest the ray's start first (seen from
                # above): the others then mostly miss the ray it has shortened
                a0 = gstart[gi]
                c0 = -1
                if gstart[gi + 1] - a0 > 2:
                    dbest = np.inf
                    for c in range(a0, gstart[gi + 1]):
                        dd = _xy_seg_dist2(p[0], p[1], p[0], p[1], S[c, 0], S[c, 1],
                                           E[c, 0], E[c, 1])
                        if dd < dbest:
                            dbest = dd
                            c0 = c
                for kk in range(a0 - 1 if c0 >= 0 else a0, gstart[gi + 1]):
                    if kk == c0:
                        continue
                    c = c0 if kk < a0 else kk
                    if U <= 0.0 or U < stop:
                        break
                    if (chi[c, 0] < qx0 or clo[c, 0] > qx1 or chi[c, 1] < qy0
                            or clo[c, 1] > qy1 or chi[c, 2] < qz0 or clo[c, 2] > qz1):
                        # (the box of the ray shortened so far)
                        continue
                    s = slot[c]
                    # the tool's underside over the ray's box is above the ray
                    box[0] = qx0
                    box[1] = qy0
                    box[2] = qx1
                    box[3] = qy1
                    if qz1 < underside(S[c], E[c], kind[s, 0], R[s, 0], rc[s, 0], k[s, 0],
                                       0.0, box, 0.0):
                        continue
                    # the cutter lies within R of its axis: a chord whose XY path
                    # stays more than R from the ray's XY path cannot reach it
                    if _xy_seg_dist2(p[0], p[1], ex[0], ex[1], S[c, 0], S[c, 1],
                                     E[c, 0], E[c, 1]) > R[s, 0] * R[s, 0]:
                        continue
                    if kind[s, 0] == BALL:      # exact distances to the swept core
                        Rb = R[s, 0]
                        R2 = Rb * Rb
                        fc = ball_core(S[c], E[c], Rb, L[s, 0], Q1, Q2)
                        if core_segment_dist2(p[0], p[1], p[2], p[0] + n[0] * U,
                                              p[1] + n[1] * U, p[2] + n[2] * U,
                                              fc, Q1, Q2) > R2:
                            continue
                        who = c
                        if core_segment_dist2(p[0], p[1], p[2], p[0], p[1], p[2],
                                              fc, Q1, Q2) <= R2:
                            U = 0.0
                            break
                        lo = 0.0
                        hi = U
                        # safe steps first (the distance to the core changes no
                        # faster than t): a ray meeting the ball head-on ends in one
                        t = 0.0
                        for _ in range(8):
                            dd = math.sqrt(core_point_dist2(p[0] + n[0] * t,
                                                            p[1] + n[1] * t,
                                                            p[2] + n[2] * t, fc, Q1,
                                                            Q2)) - Rb
                            if dd <= tol:
                                break
                            t += dd
                            if t >= hi:
                                break
                        if t < hi:
                            lo = t
                            mid = min(t + tol, hi)
                            if core_segment_dist2(p[0], p[1], p[2], p[0] + n[0] * mid,
                                                  p[1] + n[1] * mid, p[2] + n[2] * mid,
                                                  fc, Q1, Q2) <= R2:
                                hi = mid
                        while hi - lo > tol:
                            mid = 0.5 * (lo + hi)
                            if core_segment_dist2(p[0], p[1], p[2], p[0] + n[0] * mid,
                                                  p[1] + n[1] * mid, p[2] + n[2] * mid,
                                                  fc, Q1, Q2) <= R2:
                                hi = mid
                            else:
                                lo = mid
                        U = hi
                        qx0, qy0, qz0, qx1, qy1, qz1 = _ray_box(p, n, U, ex)     # shorter: smaller
                        continue
                    nr, rho = _cutter_and_ray(kind[s, 0], R[s, 0], rc[s, 0], k[s, 0], L[s, 0],
                                              p, ex, rr, rh, T)
                    if nr == 0:
                        continue
                    if not meets(T, S[c], E[c], nr, rr, rh, rho, 0.0):
                        continue
                    for a in range(3):
                        T[1, a] = p[a]
                        T[2, a] = p[a]
                    who = c
                    if meets(T, S[c], E[c], nr, rr, rh, rho, 0.0):
                        U = 0.0
                        break
                    lo = 0.0
                    hi = U
                    while hi - lo > tol:
                        mid = 0.5 * (lo + hi)
                        for a in range(3):
                            T[1, a] = p[a] + n[a] * mid
                            T[2, a] = T[1, a]
                        if meets(T, S[c], E[c], nr, rr, rh, rho, 0.0):
                            hi = mid
                        else:
                            lo = mid
                    U = hi
                    qx0, qy0, qz0, qx1, qy1, qz1 = _ray_box(p, n, U, ex)     # shorter: smaller
        out[q] = U
        out_c[q] = who


def ray_caps(points, normals, owner, stock_box, triangles, tri_index: BoxIndex,
             reach: float) -> np.ndarray:
    """Length of each ray before it leaves the stock box or meets another triangle of
    the design, at most ``reach``."""
    m = len(points)
    U0 = np.zeros(m)
    if m:
        over_range(_caps, m, np.ascontiguousarray(points, float), np.ascontiguousarray(normals, float),
              np.ascontiguousarray(owner, np.int64), np.asarray(stock_box[:3], float),
              np.asarray(stock_box[3:], float), triangles, tri_index.arrays(),
              float(reach), U0)
    return U0


@dataclass
class SweptChords:
    """Chords of the material-left pass, in the order rays meet them, in groups of
    consecutive chords (``start``, coarse chords ``gS -> gE`` within ``dev`` of every
    chord of the group, see :mod:`millpath.simulate.groups`) and a bucket index over
    the groups' boxes."""

    S: np.ndarray
    E: np.ndarray
    slot: np.ndarray
    clo: np.ndarray          # (n, 3) box of the cutter swept along each chord
    chi: np.ndarray
    start: np.ndarray
    gS: np.ndarray
    gE: np.ndarray
    dev: np.ndarray
    index: BoxIndex


def swept_chords(S, E, slot, shapes, start=None, gS=None, gE=None, dev=None) -> SweptChords:
    """:class:`SweptChords` of chords S -> E (tool slots ``slot``); without groups each
    chord is its own."""
    S = np.ascontiguousarray(S, float)
    E = np.ascontiguousarray(E, float)
    slot = np.ascontiguousarray(slot, np.int64)
    Rc = shapes.R[slot, 0]
    Lc = shapes.L[slot, 0]
    clo = np.minimum(S, E)
    chi = np.maximum(S, E)
    clo[:, :2] -= Rc[:, None]
    chi[:, :2] += Rc[:, None]
    chi[:, 2] += Lc
    if start is None:
        start = np.arange(len(S) + 1, dtype=np.int64)
        gS, gE, dev = S, E, np.zeros(len(S))
    first = start[:-1]
    glo = np.minimum.reduceat(clo, first, axis=0) if len(first) else clo
    ghi = np.maximum.reduceat(chi, first, axis=0) if len(first) else chi
    return SweptChords(S, E, slot, clo, chi, np.ascontiguousarray(start, np.int64),
                       np.ascontiguousarray(gS, float), np.ascontiguousarray(gE, float),
                       np.ascontiguousarray(dev, float), BoxIndex.build(glo, ghi))


def shorten_rays(points, normals, lengths, sw: SweptChords, shapes,
                 accuracy: float, stop: float = 0.0) -> tuple[np.ndarray, np.ndarray]:
    """Each ray ``points + t normals`` (``0 <= t <= lengths``) cut back to where it first
    enters a cutter swept along a chord of ``sw`` (to ``accuracy / 20``), and that
    chord (-1: none). A ray once shorter than ``stop`` is left as it is (shorter than
    ``stop``, not necessarily as short as the chords make it: for figures below what
    is reported)."""
    m = len(points)
    out = np.zeros(m)
    who = np.full(m, -1, np.int64)
    if m == 0 or len(sw.S) == 0:
        return np.asarray(lengths, float).copy(), who
    over_range(_left, m, np.ascontiguousarray(points, float), np.ascontiguousarray(normals, float),
          np.ascontiguousarray(lengths, float), sw.S, sw.E, sw.slot, sw.clo, sw.chi,
          sw.start, sw.gS, sw.gE, sw.dev, *shapes.arrays()[:6], sw.index.arrays(),
          accuracy / 20.0, float(stop), out, who)
    return out, who


def medial_cap(points, normals, owner, triangles, tri_index: BoxIndex, margin: float,
               lengths) -> np.ndarray:
    """``lengths`` shortened to where another triangle of the design becomes nearer
    than the design point (see :func:`_medial`)."""
    out = np.array(lengths, float)
    if len(out):
        over_range(_medial, len(out), np.ascontiguousarray(points, float), np.ascontiguousarray(normals, float),
                np.ascontiguousarray(owner, np.int64), triangles, tri_index.arrays(),
                margin, out)
    return out
