"""Exact gouge check: how deep each motion's cutter goes into a triangle-mesh design.

For every chord of the interpreted motion and every design triangle near it, the gouge
is the larger of (a) the deepest penetration of the triangle into the cutter solid
swept along the chord: the largest ``e`` such that some point of the triangle is at
least ``e`` inside the swept cutter, i.e. measured along the normal of the design
surface, walls and slopes alike (see :mod:`millpath.geometry.convex`); and (b) for
sharp edges (a flat rim, a drill point, a bull's, a holder cylinder's), the distance
from the design's surface of the tool's deepest point along the triangle's normal,
taken at the deepest position along the chord whose foot on the plane lies in the
triangle, when that point is in the material. The cutter (flat, ball, bull, drill
point, up to its flute length) and the shank and holder cylinders
(``Tool.holder_cylinders``) are all checked. A penetration is found exactly by GJK
tests and bisection on ``e`` to ``accuracy / 10000`` (the bracket's top is taken);
penetrations below ``accuracy / 2`` count as none. A chord standing for a curve has a
bound on how far the curve strays from it (:func:`millpath.simulate.path.cover_points`):
it is added to the chord's penetration, so the figure is never under the curve's.
Lengths in program units; coordinates are tool tips in the design's frame.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numba import njit

from millpath.geometry.convex import depth, may_meet, meets, shape_rings, support_swept, underside
from millpath.geometry.cutter import BALL, CYL, Cutter
from millpath.geometry.distance import (ball_core, core_point_dist2, core_triangle_dist2,
                                        segment_segment_dist2)
from millpath.geometry.index import (BoxIndex, box_candidates, bucket_range, first_bucket,
                                     push)
from millpath.geometry.inside import in_material
from millpath.model.tool import Tool
from millpath.simulate.rims import barycentric, rim_search, surface_dist2
from millpath.threads import over_range



@dataclass
class ToolShapes:
    """Solids of each tool slot: kind, radius, corner radius, cone slope, bottom and top
    above the tip, arrays (nslots, maxshapes); shape 0 is the cutter."""

    kind: np.ndarray
    R: np.ndarray
    rc: np.ndarray
    k: np.ndarray
    zb: np.ndarray
    L: np.ndarray
    n: np.ndarray

    @classmethod
    def of(cls, tools: list[Tool]) -> "ToolShapes":
        rows = []
        for t in tools:
            top = min(t.flute_length, t.stickout) if t.stickout > 0 else t.flute_length
            c = Cutter.of(t)
            top = max(top, c.tip_height + 1e-6)
            shp = [(*c.row, 0.0, top)]
            for r, zb, zt in t.holder_cylinders():
                shp.append((CYL, r, 0.0, 0.0, zb, zt))
            rows.append(shp)
        m = max([len(r) for r in rows] + [1])
        n = len(rows)
        a = np.zeros((6, max(n, 1), m))
        cnt = np.zeros(max(n, 1), np.int64)
        for s, shp in enumerate(rows):
            cnt[s] = len(shp)
            for j, v in enumerate(shp):
                a[:, s, j] = v
        return cls(a[0].astype(np.int64), a[1], a[2], a[3], a[4], a[5], cnt)

    def arrays(self):
        return self.kind, self.R, self.rc, self.k, self.zb, self.L, self.n


def _xy_boxes(index: BoxIndex) -> np.ndarray:
    """(n, 4): each item's XY box (x0, y0, x1, y1), for :func:`underside`."""
    return np.ascontiguousarray(np.concatenate([index.lo[:, :2], index.hi[:, :2]], axis=1))


@njit(cache=True, error_model="numpy")
def over_triangle(T, nrm, pd, A, B, fa, fb):
    """The part [ua, ub] of [0, 1] where the foot of ``A + u (B - A)`` on the plane of
    ``T`` (unit normal ``nrm``, offset ``pd``) lies in ``T`` (to 1e-9 in barycentrics);
    ua > ub when it never does. The foot moves along a line, so its barycentrics are
    affine in u. ``fa``, ``fb``: scratch (3,)."""
    da = pd - (A[0] * nrm[0] + A[1] * nrm[1] + A[2] * nrm[2])
    db = pd - (B[0] * nrm[0] + B[1] * nrm[1] + B[2] * nrm[2])
    for a in range(3):
        fa[a] = A[a] + da * nrm[a]
        fb[a] = B[a] + db * nrm[a]
    ua0, va0 = barycentric(T, fa)
    ub0, vb0 = barycentric(T, fb)
    lo = 0.0
    hi = 1.0
    if ua0 != ua0:
        return 1.0, 0.0
    eps = 1e-9
    for i in range(3):
        if i == 0:
            a, b = ua0, ub0
        elif i == 1:
            a, b = va0, vb0
        else:
            a, b = 1.0 - ua0 - va0, 1.0 - ub0 - vb0
        # a + u (b - a) >= -eps
        d = b - a
        if d == 0.0:
            if a < -eps:
                return 1.0, 0.0
        elif d > 0.0:
            lo = max(lo, (-eps - a) / d)
        else:
            hi = min(hi, (-eps - a) / d)
    return lo, hi


@njit(cache=True, error_model="numpy")
def xy_dist2(T, P0, P1):
    """Squared distance, seen from above, between triangle ``T`` and segment P0 -> P1
    (0 when they overlap). Every point of a tool of radius R swept along P0 -> P1 is
    within R of the segment seen from above, so a triangle that far or farther has no
    point inside it."""
    ax, ay = T[0, 0], T[0, 1]
    bx, by = T[1, 0] - ax, T[1, 1] - ay
    cx, cy = T[2, 0] - ax, T[2, 1] - ay
    det = bx * cy - by * cx
    if det != 0.0:
        rx, ry = P0[0] - ax, P0[1] - ay
        u = (rx * cy - ry * cx) / det
        v = (bx * ry - by * rx) / det
        if u >= 0.0 and v >= 0.0 and u + v <= 1.0:
            return 0.0
    best = np.inf
    for e in range(3):
        f = (e + 1) % 3
        d = segment_segment_dist2(T[e, 0], T[e, 1], 0.0, T[f, 0], T[f, 1], 0.0,
                                  P0[0], P0[1], 0.0, P1[0], P1[1], 0.0)
        if d < best:
            best = d
    return best


@njit(cache=True, error_model="numpy")
def under_candidates(ix, txy, ctop, tnz, P0, P1, kind, R, rc, k, zb, L, grow, lift, rim, buf,
                     bb):
    """Items of ``ix`` (triangles; ``txy`` their XY boxes, ``tnz`` their normals' Z) in
    the box of the tool shape swept along P0 -> P1 and grown by ``grow``, less those
    wholly below its :func:`underside` raised by ``lift``: give ``lift = e`` to keep
    only what may come within ``grow`` of the part ``e`` deep in the tool (``C_e``: the
    points of ``C_e`` grown by ``grow``, lowered by ``e``, lie in the tool grown by
    ``grow``, so they are at least ``e`` above its underside), tested for whole buckets
    first (a bucket whose highest item is below the tool over the bucket's XY box is
    passed over), and for blocks of ``COARSE`` x ``COARSE`` buckets before that
    (``ctop``: their highest tops, see :func:`coarse_tops`: a holder's wide box over a
    low part is passed over at once). ``rim``: also keep an upward-facing triangle
    (normal Z ``nz`` >= 0) whose top is ``lift * nz`` above the underside: the foot on
    it of a tool point ``e`` deep along its normal is ``e nz`` above that point, and
    (the point being the tool's deepest along the normal) inward of it, over the
    tool at most as high. ``bb``: scratch (4,). Returns (count, buffer) as
    :func:`box_candidates`."""
    lo, hi, start, items, bi0, bj0, blo, bhi, x0, y0, bs, nbx, nby = ix
    lb = 0.0 if rim else lift       # the lift that whole buckets are tested with
    qx0 = min(P0[0], P1[0]) - R - grow
    qx1 = max(P0[0], P1[0]) + R + grow
    qy0 = min(P0[1], P1[1]) - R - grow
    qy1 = max(P0[1], P1[1]) + R + grow
    qz0 = min(P0[2], P1[2]) + zb - grow + lb - 1e-9
    qz1 = max(P0[2], P1[2]) + L + grow + 1e-9
    ia, ib, ja, jb = bucket_range(x0, y0, bs, nbx, nby, qx0, qy0, qx1, qy1)
    n = 0
    for cj in range(ja // COARSE, jb // COARSE + 1):
        for ci in range(ia // COARSE, ib // COARSE + 1):
            if ctop[cj, ci] < qz0:
                continue
            for bj in range(max(ja, cj * COARSE), min(jb, cj * COARSE + COARSE - 1) + 1):
                for bi in range(max(ia, ci * COARSE), min(ib, ci * COARSE + COARSE - 1) + 1):
                    b = bj * nbx + bi
                    if (bhi[b, 0] < qx0 or blo[b, 0] > qx1 or bhi[b, 1] < qy0
                            or blo[b, 1] > qy1 or bhi[b, 2] < qz0 or blo[b, 2] > qz1):
                        continue
                    bb[0] = blo[b, 0]
                    bb[1] = blo[b, 1]
                    bb[2] = bhi[b, 0]
                    bb[3] = bhi[b, 1]
                    if bhi[b, 2] < underside(P0, P1, kind, R, rc, k, zb, bb, grow) + lb:
                        continue
                    for p in range(start[b], start[b + 1]):
                        t = items[p]
                        if not first_bucket(bi, bj, bi0[t], bj0[t], ia, ja):
                            continue
                        if (hi[t, 0] < qx0 or lo[t, 0] > qx1 or hi[t, 1] < qy0
                                or lo[t, 1] > qy1 or hi[t, 2] < qz0 or lo[t, 2] > qz1):
                            continue
                        lt = lift * tnz[t] if rim and tnz[t] >= 0.0 else lift
                        if hi[t, 2] < underside(P0, P1, kind, R, rc, k, zb, txy[t],
                                                grow) + lt:
                            continue
                        n, buf = push(buf, n, t)
    return n, buf


COARSE = 8          # buckets a side of the blocks :func:`under_candidates` looks at first


def coarse_tops(index: BoxIndex) -> np.ndarray:
    """(ceil(nby / COARSE), ceil(nbx / COARSE)): the highest item top of each block of
    ``COARSE`` x ``COARSE`` buckets of ``index`` (-inf: empty)."""
    top = index.bhi[:, 2].reshape(index.nby, index.nbx)
    ny, nx = -(-index.nby // COARSE), -(-index.nbx // COARSE)
    pad = np.full((ny * COARSE, nx * COARSE), -np.inf)
    pad[:index.nby, :index.nbx] = top
    return np.ascontiguousarray(pad.reshape(ny, COARSE, nx, COARSE).max(axis=(1, 3)))


@njit(cache=True, nogil=True, error_model="numpy")
def _gouge_groups(lo, hi, S, E, slot, cdev, gs, gS, gE, gdev, kind, R, rc, k, zb, L, nshape, tri, tn,
                  tc, tr, txy, ctop, ix, e0, tol, out_g, out_t, out_s, out_r, out_x):
    """Chords ``gs[g]:gs[g+1]`` form group g (coarse chord gS -> gE within ``gdev`` of
    each of them, see :mod:`millpath.simulate.groups`): its triangles are gathered once
    for the coarse sweep grown by the deviation, and, for a ball, those farther from
    the coarse core than R - e + deviation dropped (no chord of the group comes e deep
    into them); then each chord is checked against what is left. Chord c's depths are
    looked for from ``e0 - cdev[c]`` (its bound is added to them afterwards), the
    group's from ``e`` = the least of these."""
    ng = gs.shape[0] - 1
    for g in range(lo, hi):
        buf = np.empty(256, np.int64)
        gd = np.empty(256)
        bb = np.empty(4)
        sbuf = np.empty(64, np.int64)
        rr = np.empty(3)
        rh = np.empty(3)
        sp = np.empty(3)
        Q1 = np.empty((3, 3))
        Q2 = np.empty((3, 3))
        rrf = np.empty(3)
        rhf = np.empty(3)
        rrd = np.empty(3)
        rhd = np.empty(3)
        wa = np.empty(3)
        wb = np.empty(3)
        fa = np.empty(3)
        fb = np.empty(3)
        a0 = gs[g]
        a1 = gs[g + 1]
        s = slot[a0]
        dv = gdev[g]
        eg = e0
        for c in range(a0, a1):
            eg = min(eg, e0 - cdev[c])
            out_g[c] = -1.0
            out_t[c] = -1
            out_s[c] = -1
            out_r[c] = 0
            for a in range(3):
                out_x[c, a] = 0.0
        for j in range(nshape[s]):
            Rj = R[s, j]
            is_ball = kind[s, j] == BALL
            nr0, rho0 = shape_rings(kind[s, j], Rj, rc[s, j], k[s, j], zb[s, j], L[s, j], eg,
                                    rr, rh)
            if nr0 == 0:
                continue
            nrf, rhof = shape_rings(kind[s, j], Rj, rc[s, j], k[s, j], zb[s, j], L[s, j], 0.0,
                                    rrf, rhf)
            # not wholly below the (grown) tool over their own XY box
            # (a sharp edge: flat rim, drill point, cylinder; a bull's is rounded, its
            # depth (a) is that of its deepest point until past its corner radius)
            rim = not is_ball and nrf > 0 and rhof == 0.0
            nc, buf = under_candidates(ix, txy, ctop, tn[:, 2], gS[g], gE[g], kind[s, j], Rj,
                                       rc[s, j], k[s, j], zb[s, j], L[s, j], dv, eg, rim, buf,
                                       bb)
            if gd.shape[0] < nc:
                gd = np.empty(nc)
            if is_ball and a1 - a0 > 1:
                fc = ball_core(gS[g], gE[g], Rj, L[s, j], Q1, Q2)
                m = 0
                for p in range(nc):
                    t = buf[p]
                    far = Rj - eg + tr[t] + dv
                    if core_point_dist2(tc[t, 0], tc[t, 1], tc[t, 2], fc, Q1, Q2) > far * far:
                        continue
                    d = math.sqrt(core_triangle_dist2(tri[t], fc, Q1, Q2))
                    if Rj - d + dv < eg:
                        continue
                    buf[m] = t
                    gd[m] = d
                    m += 1
                nc = m
            else:
                for p in range(nc):
                    gd[p] = -np.inf
            for c in range(a0, a1):
                _chord_gouge(c, j, S[c], E[c], s, kind, R, rc, k, zb, L, tri, tn, tc, tr,
                             txy, ix, e0 - cdev[c], tol, buf, gd, nc, dv, nr0, rho0, nrf, rhof, rr, rh,
                             rrf, rhf, rrd, rhd, sp, wa, wb, fa, fb, Q1, Q2, sbuf, out_g,
                             out_t, out_s, out_r, out_x)


@njit(cache=True, error_model="numpy")
def _chord_gouge(c, j, P0, P1, s, kind, R, rc, k, zb, L, tri, tn, tc, tr, txy, ix, e0, tol,
                 cand, gd, nc, dv, nr0, rho0, nrf, rhof, rr, rh, rrf, rhf, rrd, rhd, sp,
                 wa, wb, fa, fb, Q1, Q2, sbuf, out_g, out_t, out_s, out_r, out_x):
    """Chord c's penetration by shape j of slot s into the triangles ``cand[:nc]`` (at
    ``gd`` from the group's coarse core, -inf unknown), raising ``out_*[c]``."""
    Rj = R[s, j]
    is_ball = kind[s, j] == BALL
    flat_core = False
    if is_ball:
        flat_core = ball_core(P0, P1, Rj, L[s, j], Q1, Q2)
    best = out_g[c]
    for p in range(nc):
        t = cand[p]
        lo = e0 if e0 > best else best
        if is_ball:
            # the chord's core is within the deviation of the group's
            if Rj - gd[p] + dv < lo:
                continue
            # a bound first: the core is at least (distance from the triangle's
            # centre) - (its radius) from the triangle
            far = Rj - lo + tr[t]
            if core_point_dist2(tc[t, 0], tc[t, 1], tc[t, 2], flat_core, Q1,
                                Q2) > far * far:
                continue
        low = False
        nx, ny, nz = tn[t, 0], tn[t, 1], tn[t, 2]
        if not is_ball and dv > 0.0:
            # (checked for the group's coarse chord when the chord is its own group)
            us = underside(P0, P1, kind[s, j], Rj, rc[s, j], k[s, j], zb[s, j], txy[t], 0.0)
            top = ix[1][t, 2]
            # wholly below the tool's underside raised by lo: no point of t is lo deep
            # in the tool; nor, when it faces up, lower than lo nz, is the foot of a
            # sharp edge's point lo deep along its normal (see under_candidates)
            low = top < us + lo
            if low and (nrf == 0 or rhof > 0.0 or nz < 0.0 or top < us + lo * nz):
                continue
        xy2 = 0.0
        if not is_ball:
            # a triangle more than R from the chord seen from above has no point in
            # the tool, nor is the foot of the rim's deepest point on it (that foot is
            # within R of the chord unless the rim goes a tool diameter into the part)
            xy2 = xy_dist2(tri[t], P0, P1)
            if xy2 > Rj * Rj:
                continue
        pd = nx * tri[t, 0, 0] + ny * tri[t, 0, 1] + nz * tri[t, 0, 2]
        if not is_ball and nrf > 0:
            # the tool's deepest point along the design's normal: a sharp rim or
            # point goes deeper into the part than any ball inside the tool reaches
            # out of it. Its place on the tool is the same all along the chord; of
            # the positions whose foot on the plane lies in t, the deepest (an end of
            # that stretch: the depth is affine along the chord; the middle when
            # level with the plane)
            support_swept(P0, P1, nrf, rrf, rhf, rhof, -nx, -ny, -nz, sp)
            dp = pd - (sp[0] * nx + sp[1] * ny + sp[2] * nz)
            if dp > lo and dp > best:
                if -(nx * P0[0] + ny * P0[1] + nz * P0[2]) >= -(nx * P1[0] + ny * P1[1]
                                                                + nz * P1[2]):
                    Pe = P0
                else:
                    Pe = P1
                for a in range(3):
                    wa[a] = P0[a] + sp[a] - Pe[a]
                    wb[a] = P1[a] + sp[a] - Pe[a]
                ua, ub = over_triangle(tri[t], tn[t], pd, wa, wb, fa, fb)
                da = pd - (wa[0] * nx + wa[1] * ny + wa[2] * nz)
                db = pd - (wb[0] * nx + wb[1] * ny + wb[2] * nz)
                u = ub if db > da else (ua if da > db else 0.5 * (ua + ub))
                dp = da + u * (db - da)
                for a in range(3):
                    sp[a] = wa[a] + u * (wb[a] - wa[a])
                # and that point in the material (not outside, behind another face
                # or beyond the design's edge): its depth is its distance from the
                # design's surface
                if ua <= ub and dp > lo and dp > best and in_material(
                        sp, tri, ix[2], ix[3], ix[8], ix[9], ix[10], ix[11], ix[12]):
                    ds = math.sqrt(surface_dist2(sp, dp, tri, ix, sbuf))
                    if ds >= lo and ds > best:
                        best = ds
                        out_t[c] = t
                        out_s[c] = j
                        out_r[c] = 1
                        for a in range(3):
                            out_x[c, a] = sp[a]
        if low:
            continue
        # the plane of t must cut the solid's C_e0, else no point of t can be e0 deep
        # in it (one support point each way)
        support_swept(P0, P1, nr0, rr, rh, rho0, nx, ny, nz, sp)
        if sp[0] * nx + sp[1] * ny + sp[2] * nz < pd:
            continue
        support_swept(P0, P1, nr0, rr, rh, rho0, -nx, -ny, -nz, sp)
        if sp[0] * nx + sp[1] * ny + sp[2] * nz > pd:
            continue
        if is_ball:     # exact: R - distance to the swept core
            d = Rj - math.sqrt(core_triangle_dist2(tri[t], flat_core, Q1, Q2))
            if d < lo:
                continue
        else:
            # no point of t within lo of the tool's side, seen from above, is lo deep
            # in it
            if Rj - lo < 0.0 or xy2 > (Rj - lo) ** 2:
                continue
            # (its own ring arrays: rr / rh hold C_e0's for the next triangles)
            d = depth(tri[t], P0, P1, kind[s, j], Rj, rc[s, j], k[s, j], zb[s, j], L[s, j],
                      lo, tol, rrd, rhd)
            if d >= 0.0:
                d += tol        # the top of the bisection's bracket: never under
        if d > best:
            best = d
            out_t[c] = t
            out_s[c] = j
            out_r[c] = 0
    if not is_ball and nrf > 0 and rhof == 0.0 and best >= e0:
        # a sharp rim or point found near the design: its depth where two faces meet
        # (a ridge of a faceted surface) lies between their deepest points, looked for
        # at the points where the depth is largest on a straight chord
        g = rim_search(P0, P1, nrf, rrf, rhf, best, tri, tn, ix, cand, nc, sbuf, sp, wa)
        if g > best:
            best = g
            out_s[c] = j
            out_r[c] = 1
            for a in range(3):
                out_x[c, a] = sp[a]
    out_g[c] = best


@njit(cache=True, nogil=True, error_model="numpy")
def _near_chords(lo, hi, S, E, slot, kind, R, rc, k, zb, L, nshape, tri, tn, txy, ctop, ix, e0,
                 grow, out):
    """out[c] = 1 when some triangle may come within ``grow`` of the part of chord c's
    swept tool that is ``e0`` deep (one test per triangle, no bisection: a ball's core
    distance, else :func:`may_meet`)."""
    n = S.shape[0]
    for c in range(lo, hi):
        buf = np.empty(256, np.int64)
        bb = np.empty(4)
        rr = np.empty(3)
        rh = np.empty(3)
        sp = np.empty(3)
        Q1 = np.empty((3, 3))
        Q2 = np.empty((3, 3))
        s = slot[c]
        P0 = S[c]
        P1 = E[c]
        hit = 0
        for j in range(nshape[s]):
            if hit:
                break
            Rj = R[s, j]
            is_ball = kind[s, j] == BALL
            flat_core = False
            if is_ball:
                flat_core = ball_core(P0, P1, Rj, L[s, j], Q1, Q2)
            nr, rho = shape_rings(kind[s, j], Rj, rc[s, j], k[s, j], zb[s, j], L[s, j], e0,
                                  rr, rh)
            if nr == 0:
                continue
            g = grow[c]
            # (np.bool_: a bool, not a literal, so under_candidates has one signature)
            nc, buf = under_candidates(ix, txy, ctop, tn[:, 2], P0, P1, kind[s, j], Rj,
                                       rc[s, j], k[s, j], zb[s, j], L[s, j], g, e0, np.bool_(False), buf,
                                       bb)
            for p in range(nc):
                t = buf[p]
                nx, ny, nz = tn[t, 0], tn[t, 1], tn[t, 2]
                pd = nx * tri[t, 0, 0] + ny * tri[t, 0, 1] + nz * tri[t, 0, 2]
                support_swept(P0, P1, nr, rr, rh, rho + g, nx, ny, nz, sp)
                if sp[0] * nx + sp[1] * ny + sp[2] * nz < pd:
                    continue
                support_swept(P0, P1, nr, rr, rh, rho + g, -nx, -ny, -nz, sp)
                if sp[0] * nx + sp[1] * ny + sp[2] * nz > pd:
                    continue
                # (C_e0 lies within Rj - e0 of the chord seen from above)
                if xy_dist2(tri[t], P0, P1) > (Rj - e0 + g) ** 2:
                    continue
                if is_ball:
                    # C_e0 lies within Rj - e0 of the core (the full core: its top
                    # is not lowered by e0, which only adds to the hits)
                    if core_triangle_dist2(tri[t], flat_core, Q1, Q2) <= (Rj - e0 + g) ** 2:
                        hit = 1
                        break
                elif may_meet(tri[t], P0, P1, nr, rr, rh, rho, g):
                    hit = 1
                    break
        out[c] = hit


@njit(cache=True, error_model="numpy")
def _locate(T, P0, P1, kind, R, rc, k, zb, L, e, tol):
    """Tool tip on the chord and the point of ``T`` deepest in the tool swept along
    P0 -> P1 (``T`` meeting its ``C_e``, ``e`` just under the gouge): the first
    position along the chord where ``T`` meets ``C_e``, by bisection; and the point by
    halving the triangle 42 times (four parts: three corners and the middle), each
    time into the part that goes deepest (:func:`depth` to ``tol``). The depth is
    concave over the triangle (the swept solid is convex): the deepest part holds a
    deepest point."""
    rr = np.empty(3)
    rh = np.empty(3)
    nr, rho = shape_rings(kind, R, rc, k, zb, L, e, rr, rh)
    a = 0.0
    b = 1.0
    for _ in range(50):
        m = 0.5 * (a + b)
        M = P0 + (P1 - P0) * m
        A = P0 + (P1 - P0) * a
        if nr > 0 and meets(T, A, M, nr, rr, rh, rho, 0.0):
            b = m
        else:
            a = m
    P = P0 + (P1 - P0) * (0.5 * (a + b))
    V = T.copy()
    C = np.empty((3, 3))
    B = np.empty((3, 3))
    mid = np.empty((3, 3))         # mid[i]: the middle of the edge opposite corner i
    for _ in range(42):
        for q in range(3):
            mid[0, q] = 0.5 * (V[1, q] + V[2, q])
            mid[1, q] = 0.5 * (V[0, q] + V[2, q])
            mid[2, q] = 0.5 * (V[0, q] + V[1, q])
        bd = -np.inf
        for part in range(4):
            for i in range(3):
                for q in range(3):
                    # corner parts: corner ``part`` and the middles of its two edges
                    C[i, q] = V[i, q] if i == part else mid[i, q]
            d = depth(C, P0, P1, kind, R, rc, k, zb, L, 0.0, tol, rr, rh)
            if d > bd:
                bd = d
                B[:, :] = C
        V[:, :] = B
    X = (V[0] + V[1] + V[2]) / 3.0
    return P, X


@njit(cache=True, error_model="numpy")
def closest_on_triangle(p, T):
    """The point of triangle ``T`` (3, 3) nearest point ``p`` (closest-point regions;
    a degenerate triangle: its nearest corner or edge point)."""
    a = T[0]
    ab = T[1] - a
    ac = T[2] - a
    ap = p - a
    d1 = np.dot(ab, ap)
    d2 = np.dot(ac, ap)
    if d1 <= 0.0 and d2 <= 0.0:
        return a.copy()
    bp = p - T[1]
    d3 = np.dot(ab, bp)
    d4 = np.dot(ac, bp)
    if d3 >= 0.0 and d4 <= d3:
        return T[1].copy()
    vc = d1 * d4 - d3 * d2
    if vc <= 0.0 and d1 >= 0.0 and d3 <= 0.0 and d1 - d3 > 0.0:
        return a + ab * (d1 / (d1 - d3))
    cp = p - T[2]
    d5 = np.dot(ab, cp)
    d6 = np.dot(ac, cp)
    if d6 >= 0.0 and d5 <= d6:
        return T[2].copy()
    vb = d5 * d2 - d1 * d6
    if vb <= 0.0 and d2 >= 0.0 and d6 <= 0.0 and d2 - d6 > 0.0:
        return a + ac * (d2 / (d2 - d6))
    va = d3 * d6 - d5 * d4
    if va <= 0.0 and d4 - d3 >= 0.0 and d5 - d6 >= 0.0 and (d4 - d3) + (d5 - d6) > 0.0:
        return T[1] + (T[2] - T[1]) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)))
    den = va + vb + vc
    if den <= 0.0:
        # degenerate: the nearest of its edges' points
        best = T[0].copy()
        bd = np.inf
        for i in range(3):
            e = T[(i + 1) % 3] - T[i]
            ll = np.dot(e, e)
            u = 0.0 if ll <= 0.0 else min(max(np.dot(p - T[i], e) / ll, 0.0), 1.0)
            q = T[i] + e * u
            d = np.dot(p - q, p - q)
            if d < bd:
                bd = d
                best = q
        return best
    return a + ab * (vb / den) + ac * (vc / den)


@njit(cache=True, error_model="numpy")
def _nearest_on(X, r, tri, ix):
    """The design point nearest X among the triangles within ``r`` of it (X itself
    when there is none)."""
    buf = np.empty(64, np.int64)
    best = X.copy()
    bd = np.inf
    nc, buf = box_candidates(ix, X[0] - r, X[1] - r, X[2] - r, X[0] + r, X[1] + r,
                             X[2] + r, buf)
    for p in range(nc):
        q = closest_on_triangle(X, tri[buf[p]])
        d = np.dot(q - X, q - X)
        if d < bd:
            bd = d
            best = q
    return best


@dataclass
class GougeResult:
    """Per chord: penetration (-1 none), triangle, shape (0 cutter, >0 shank/holder)."""

    gouge: np.ndarray
    triangle: np.ndarray
    shape: np.ndarray
    rim: np.ndarray | None = None      # 1: the tool's deepest point along the normal
    point: np.ndarray | None = None    # (n, 3) that point of the tool, where rim is 1


def _normals(tri: np.ndarray) -> np.ndarray:
    n = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    ln = np.linalg.norm(n, axis=1)
    return np.ascontiguousarray(n / np.where(ln > 0, ln, 1.0)[:, None])


def _spheres(tri: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Centre (centroid) and radius of a sphere holding each triangle."""
    c = np.ascontiguousarray(tri.mean(axis=1))
    r = np.sqrt(((tri - c[:, None, :]) ** 2).sum(axis=2).max(axis=1)) * (1 + 1e-12) + 1e-12
    return c, np.ascontiguousarray(r)


@dataclass
class Faces:
    """What the checks need of each design triangle besides its corners: unit normal,
    centre and radius of a sphere holding it, XY box, and the index's
    :func:`coarse_tops` (see :func:`faces_of`)."""

    normals: np.ndarray
    centres: np.ndarray
    radii: np.ndarray
    xy: np.ndarray
    tops: np.ndarray


def faces_of(triangles: np.ndarray, index: BoxIndex) -> Faces:
    """:class:`Faces` of ``triangles`` (``index``: their :class:`BoxIndex`), made once
    for all the chords checked against them."""
    return Faces(_normals(triangles), *_spheres(triangles), _xy_boxes(index),
                 coarse_tops(index))


def gouge_chords(S: np.ndarray, E: np.ndarray, slot: np.ndarray, shapes: ToolShapes,
                 triangles: np.ndarray, index: BoxIndex, accuracy: float,
                 faces: Faces | None = None, groups=None, dev=None) -> GougeResult:
    """Penetration of the design into each chord's swept tool (see the module doc);
    ``faces``: :func:`faces_of` the triangles, when already made. ``groups``: (start,
    coarse S, coarse E, deviation) of runs of the chords (``start``: first chord of
    each, then the number of chords; see :mod:`millpath.simulate.groups`), looked at
    whole first; default each chord alone. ``dev``: per chord, a bound on how far the
    motion it stands for strays from it (see
    :func:`millpath.simulate.path.cover_points`): added to its penetration (never
    under the motion's), which is looked for from ``accuracy / 2 - dev``."""
    n = len(S)
    g = np.full(n, -1.0)
    t = np.full(n, -1, np.int64)
    s = np.full(n, -1, np.int64)
    rim = np.zeros(n, np.int8)
    pt = np.zeros((n, 3))
    if n and len(triangles):
        f = faces if faces is not None else faces_of(triangles, index)
        S = np.ascontiguousarray(S, float)
        E = np.ascontiguousarray(E, float)
        if groups is None:
            groups = (np.arange(n + 1), S, E, np.zeros(n))
        gs, gS, gE, gdev = groups
        cdev = (np.zeros(n) if dev is None else
                np.ascontiguousarray(np.broadcast_to(np.asarray(dev, float), (n,))))
        over_range(_gouge_groups, len(gs) - 1, S, E, np.ascontiguousarray(slot, np.int64), cdev,
                      np.ascontiguousarray(gs, np.int64), np.ascontiguousarray(gS, float),
                      np.ascontiguousarray(gE, float), np.ascontiguousarray(gdev, float),
                      *shapes.arrays(), triangles, f.normals, f.centres, f.radii, f.xy,
                      f.tops, index.arrays(), accuracy / 2.0, accuracy * 1e-4, g, t, s, rim,
                      pt)
        g = np.where(g >= 0.0, g + cdev, g)
    return GougeResult(g, t, s, rim, pt)


def locate(S, E, slot, shapes: ToolShapes, triangles, res: GougeResult, c: int,
           accuracy: float, index: BoxIndex | None = None,
           dev: float = 0.0) -> tuple[np.ndarray, np.ndarray]:
    """(tool tip, design point) of chord ``c``'s deepest penetration: for a rim, the
    design point nearest the tool's deepest point (``index``: the triangles'
    :class:`BoxIndex`; without it, that point's foot on the gouging triangle), else
    the deepest point of the gouging triangle in the swept tool (see
    :func:`_locate`). ``dev``: the chord's deviation bound (in ``res.gouge``)."""
    s, j = int(slot[c]), int(res.shape[c])
    if res.rim is not None and res.rim[c]:
        X = np.asarray(res.point[c], float)
        T = triangles[res.triangle[c]]
        n = np.cross(T[1] - T[0], T[2] - T[0])
        n = n / max(float(np.linalg.norm(n)), 1e-300)
        foot = X + float(np.dot(T[0] - X, n)) * n
        if index is None:
            return np.asarray(S[c], float), foot
        # (the design's surface is the depth away from the tool's point)
        r = (float(res.gouge[c]) - dev) * (1 + 1e-9) + 1e-9
        return np.asarray(S[c], float), _nearest_on(X, r, triangles, index.arrays())
    g = float(res.gouge[c]) - dev
    P, X = _locate(triangles[res.triangle[c]], np.asarray(S[c], float),
                   np.asarray(E[c], float), int(shapes.kind[s, j]), float(shapes.R[s, j]),
                   float(shapes.rc[s, j]), float(shapes.k[s, j]), float(shapes.zb[s, j]),
                   float(shapes.L[s, j]), max(g - accuracy * 2e-4, 0.0), accuracy * 1e-6)
    return P, X


def near_chords(S: np.ndarray, E: np.ndarray, slot: np.ndarray, shapes: ToolShapes,
                triangles: np.ndarray, index: BoxIndex, accuracy: float,
                grow, faces: Faces | None = None) -> np.ndarray:
    """Chords that may gouge by ``accuracy / 2`` or more with the tool anywhere within
    ``grow`` (a number, or one per chord) of them (a conservative test: a chord not
    flagged cannot; chords within ``grow`` of a flagged one need checking, see
    :mod:`millpath.simulate.groups`)."""
    out = np.zeros(len(S), np.int8)
    grow = np.ascontiguousarray(np.broadcast_to(np.asarray(grow, float), (len(S),)))
    if len(S) and len(triangles):
        f = faces if faces is not None else faces_of(triangles, index)
        over_range(_near_chords, len(S), np.ascontiguousarray(S, float), np.ascontiguousarray(E, float),
                     np.ascontiguousarray(slot, np.int64), *shapes.arrays(), triangles,
                     f.normals, f.xy, f.tops, index.arrays(), accuracy / 2.0,
                     grow, out)
    return out.astype(bool)
