"""Greedy segmentation of one polyline into lines, arcs and cubics.

``segment(P, ...)`` walks the run of points ``P`` (``(n, 3)``, job units, already on the
output grid ``q``) from its first vertex and, at each vertex, grows the longest line,
arc (XY, XZ, YZ, each possibly helical) and, when asked, XY cubic that still pass the
two-sided tolerance checks of :mod:`millpath.fit.arcs` and :mod:`millpath.fit.cubics`
(exponential then binary search on the end vertex). The one reaching furthest wins
(ties: line, then arc, then cubic). Result rows:

- kind 0, line to ``P[end]``;
- kind 1, arc to ``P[end]``: ``par = [plane, c1, c2, clockwise, radius]`` with plane
  0 = XY, 1 = XZ, 2 = YZ and the centre in that plane's (first, second) coordinates;
- kind 2, cubic to ``P[end]``: ``par = [c1x, c1y, c2x, c2y]``.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from millpath.fit.arcs import arc_fit, line_ok, plane_possible
from millpath.fit.cubics import cubic_fit
from millpath.model.toolpath import PLANE_AXES
from millpath.model.toolpath import PLANES as PLANE_NAMES

#: (first, second, normal) axis indices of XY, XZ, YZ (rows in the order of the plane
#: codes) for the compiled fits
PLANES = np.array([PLANE_AXES[p] for p in PLANE_NAMES], dtype=np.int64)

#: longest stretch (in vertices) a single primitive may replace
MAX_SPAN = 4096


@njit(cache=True)
def _check(kind, P, i, j, pl, tol, q, abs_lim, rmin, rmax, corner, T, out):
    if kind == 0:
        return line_ok(P, i, j, tol)
    if kind == 1:
        return arc_fit(P, i, j, PLANES[pl, 0], PLANES[pl, 1], PLANES[pl, 2], tol, q,
                       abs_lim, rmin, rmax, corner, out)
    # cubic: XY at one Z, tangents from T (row k: out-tangent at k, in-tangent at k)
    z = P[i, 2]
    for k in range(i + 1, j + 1):
        if P[k, 2] != z:
            return False
    return cubic_fit(P, i, j, T[i, 0], T[i, 1], T[j, 2], T[j, 3], tol, q, out)


@njit(cache=True)
def _grow(kind, P, i, n, pl, tol, q, abs_lim, rmin, rmax, corner, T, best_out, jmin):
    """Largest end vertex j >= jmin for which the check passes (i if none); the
    parameters of that fit are left in ``best_out``. ``jmin``: a candidate must reach
    at least this far to beat what another kind of primitive already reaches."""
    out = np.empty(8)
    last = min(n - 1, i + MAX_SPAN)
    best = i
    j = max(jmin, i + 1 if kind == 0 else i + 2)
    bad = last + 1
    # a few short candidates, then doubling
    while j <= last:
        if _check(kind, P, i, j, pl, tol, q, abs_lim, rmin, rmax, corner, T, out):
            best = j
            best_out[:] = out
            step = j - i
            j = i + 2 * step if step >= 2 else j + 1
        else:
            if best == i and kind != 0 and j == i + 2:
                j += 1          # noisy starts: give the least-squares fit a 4th point
                continue
            if best == i and j == jmin and j < last:
                j += 1          # one more point before giving up (not monotone)
                jmin = -1
                continue
            bad = j
            break
    if best == i:
        return i
    if j > last and bad == last + 1:
        if best < last and _check(kind, P, i, last, pl, tol, q, abs_lim, rmin, rmax,
                                  corner, T, out):
            best_out[:] = out
            return last
        bad = last
    lo, hi = best, bad
    while hi - lo > 1:
        mid = (lo + hi) // 2
        if _check(kind, P, i, mid, pl, tol, q, abs_lim, rmin, rmax, corner, T, out):
            lo = mid
            best_out[:] = out
        else:
            hi = mid
    return lo        # best_out holds the parameters of the last success, which is lo


@njit(cache=True)
def tangents(P, corner):
    """Per vertex: unit out-tangent (cols 0, 1) and in-tangent (cols 2, 3) in XY.

    At smooth vertices (turn below ``corner`` radians) both are the same blend of the
    neighbouring segment directions, so cubics meeting there join G1-continuously; at
    corners and at the run's ends they are the adjacent segment's direction.
    """
    n = P.shape[0]
    T = np.zeros((n, 4))
    for k in range(n):
        inx = iny = outx = outy = 0.0
        li = lo = 0.0
        if k > 0:
            inx, iny = P[k, 0] - P[k - 1, 0], P[k, 1] - P[k - 1, 1]
            li = math.hypot(inx, iny)
            if li > 0:
                inx, iny = inx / li, iny / li
        if k < n - 1:
            outx, outy = P[k + 1, 0] - P[k, 0], P[k + 1, 1] - P[k, 1]
            lo = math.hypot(outx, outy)
            if lo > 0:
                outx, outy = outx / lo, outy / lo
        if li > 0 and lo > 0:
            ang = abs(math.atan2(inx * outy - iny * outx, inx * outx + iny * outy))
            if ang < corner:
                tx, ty = lo * inx + li * outx, lo * iny + li * outy
                tl = math.hypot(tx, ty)
                inx, iny = tx / tl, ty / tl
                outx, outy = inx, iny
        if li == 0:
            inx, iny = outx, outy
        if lo == 0:
            outx, outy = inx, iny
        T[k, 0], T[k, 1], T[k, 2], T[k, 3] = outx, outy, inx, iny
    return T


@njit(cache=True)
def segment(P, tol, q, abs_lim, rmin, rmax, corner, cubics, smooth_angle):
    """Split polyline ``P`` into primitives; returns (kinds, ends, params) arrays."""
    n = P.shape[0]
    kinds = np.empty(n, np.int8)
    ends = np.empty(n, np.int64)
    par = np.zeros((n, 8))
    T = tangents(P, smooth_angle) if cubics else np.zeros((1, 4))
    tmp = np.empty(8)
    cand = np.empty(8)
    cnt = 0
    i = 0
    while i < n - 1:
        jl = _grow(0, P, i, n, 0, tol, q, abs_lim, rmin, rmax, corner, T, tmp, i + 1)
        best_kind = 0
        best_j = max(jl, i + 1)
        bestp = np.zeros(8)
        for pl in range(3):
            if not plane_possible(P, i, n, PLANES[pl, 0], PLANES[pl, 1], PLANES[pl, 2], tol):
                continue
            ja = _grow(1, P, i, n, pl, tol, q, abs_lim, rmin, rmax, corner, T, cand,
                       best_j + 1)
            if ja > best_j:
                best_kind = 1
                best_j = ja
                bestp[0] = pl
                bestp[1:6] = cand[:5]
        if cubics and i + 2 < n and P[i + 1, 2] == P[i, 2] and P[i + 2, 2] == P[i, 2]:
            jc = _grow(2, P, i, n, 0, tol, q, abs_lim, rmin, rmax, corner, T, cand,
                       best_j + 1)
            if jc > best_j:
                best_kind = 2
                best_j = jc
                bestp[0:4] = cand[:4]
        kinds[cnt] = best_kind
        ends[cnt] = best_j
        par[cnt] = bestp
        cnt += 1
        i = best_j
    return kinds[:cnt], ends[:cnt], par[:cnt]
