"""Numba kernels: lower the Z-map under a tool swept along straight chords.

For a tool moving along a straight chord from P0 to P1 with a profile ``f(r)`` (height
of the cutter surface above the tip at radius ``r <= R``), the lowest point of the
swept tool above a cell centre at perpendicular distance ``h`` from the chord's XY line
is ``min over u of  z* + m u + f(sqrt(h^2 + u^2))`` where ``u`` is the distance along the
line from the foot of the perpendicular, ``z*`` the chord's Z at the foot and ``m`` the
chord's slope (dZ per unit XY length). The function is convex in ``u`` (the profiles
are convex and increasing), so its minimum on the feasible interval (the cell within
``R`` of the tool axis, the tool between P0 and P1) is the unconstrained minimiser
clamped to the interval. The minimiser is closed-form for flat (interval end), ball
(``u = -m sqrt((R^2 - h^2) / (1 + m^2))``) and drill cones (``u = -m h / sqrt(k^2 - m^2)``
when the cone is steeper than the chord); for bull-nose cutters it is found by
Newton's method on the derivative inside a bracket. The sweep of a chord is therefore
exact at every cell centre (to rounding); the only approximation is the chord
tolerance of arcs and cubics. Flat, ball and drill rows run branch-free so LLVM
vectorises them; vertical chords and bull-nose cutters take a scalar path.

Tool type codes and the profile ``f`` are :mod:`millpath.geometry.cutter`'s. Heights never go below the stock
bottom ``zfloor``. The grid is processed in bands of ``B`` rows; each thread owns whole
bands and visits the chords in program order, so every cell sees the cuts in order
(needed to tell rapids through material and holder contacts) without locks.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from millpath.geometry.cutter import BALL, BULL, DRILL, FLAT, height


@njit(cache=True)
def _bull_slope(R, rc, h2, m, u):
    """g'(u) and g''(u) of g(u) = m u + f(sqrt(h2 + u^2)) for a bull-nose profile."""
    a = R - rc
    d = math.sqrt(h2 + u * u)
    if d <= a or d == 0.0:
        return m, 0.0
    e = d - a
    q = rc * rc - e * e
    if q <= 1e-300:
        return (1e300 if u > 0.0 else -1e300), 1e300     # vertical tangent at d = R
    sq = math.sqrt(q)
    fp = e / sq
    fpp = rc * rc / (q * sq)
    c = u / d
    return m + fp * c, fpp * c * c + fp * h2 / (d * d * d)


@njit(cache=True)
def _bull_u(R, rc, h2, m, ulo, uhi):
    """Minimiser of z* + m u + f(sqrt(h2 + u^2)) on [ulo, uhi] for a bull-nose profile
    (convex: Newton's method on the derivative, kept inside a shrinking bracket)."""
    g1, _ = _bull_slope(R, rc, h2, m, ulo)
    if g1 >= 0.0:
        return ulo
    g1, _ = _bull_slope(R, rc, h2, m, uhi)
    if g1 <= 0.0:
        return uhi
    lo, hi = ulo, uhi
    u = 0.5 * (lo + hi)
    tol = 1e-12 * (1.0 + abs(ulo) + abs(uhi))
    for _ in range(100):
        g1, g2 = _bull_slope(R, rc, h2, m, u)
        if g1 > 0.0:
            hi = u
        else:
            lo = u
        if hi - lo < tol or g1 == 0.0:
            break
        un = u - g1 / g2 if g2 > 0.0 else 0.5 * (lo + hi)
        if not (lo < un < hi):
            un = 0.5 * (lo + hi)
        if abs(un - u) < tol:
            u = un
            break
        u = un
    return u


@njit(cache=True, inline="always")
def _envelope(px, py, x0, y0, z0, ux, uy, L, m, sq, ci, ttype, R, rc, k, zcap):
    """Lowest Z of the tool swept along the chord above (px, py); +inf if not under it.

    (x0, y0, z0) is the chord start, (ux, uy) the XY unit direction, L the XY length
    (0 for a vertical chord, where z0 must be its lower end), m the slope; per chord
    constants ``sq = sqrt(1 + m^2)`` and ``ci = 1 / sqrt(k^2 - m^2)`` (drill, when the
    cone is steeper than the chord; else 0). Values at or above ``zcap`` (the cell's
    height) may be returned as +inf without computing them (bull-nose shortcut).
    """
    dx = px - x0
    dy = py - y0
    R2 = R * R
    if L <= 0.0:
        d2 = dx * dx + dy * dy
        if d2 > R2:
            return np.inf
        return z0 + height(ttype, R, rc, k, math.sqrt(d2))
    s = dx * ux + dy * uy
    hh = dx * uy - dy * ux
    h2 = hh * hh
    if h2 > R2:
        return np.inf
    w = math.sqrt(R2 - h2)
    ulo = -w if -w > -s else -s
    uhi = w if w < L - s else L - s
    if ulo > uhi:
        return np.inf
    if m == 0.0:
        u = 0.0
    elif ttype == FLAT:
        u = ulo if m > 0.0 else uhi
    elif ttype == BALL:
        u = -m * w / sq
        if ulo <= u <= uhi:
            # on the swept cylinder: R - sqrt(w^2 - u^2) + m u = R - w sqrt(1 + m^2)
            return z0 + m * s + R - w * sq
    elif ttype == DRILL:
        if ci > 0.0:
            u = -m * abs(hh) * ci
        else:
            u = ulo if m > 0.0 else uhi
    else:
        # lower bound: lowest Z along the interval plus the profile at the nearest
        # possible radius; if that does not reach the cell, skip the search
        zlb = z0 + m * (s + (ulo if m > 0.0 else uhi)) + height(ttype, R, rc, k, abs(hh))
        if zlb >= zcap:
            return np.inf
        u = _bull_u(R, rc, h2, m, ulo, uhi)
    if u < ulo:
        u = ulo
    elif u > uhi:
        u = uhi
    d = math.sqrt(h2 + u * u)
    if d > R:
        d = R
    return z0 + m * (s + u) + height(ttype, R, rc, k, d)


@njit(cache=True, inline="always")
def _row_span(yc, x0, y0, x1, y1, R):
    """X interval of the chord's R-neighbourhood (a capsule) on the line Y = yc:
    the union of the two end discs and the swept rectangle (empty: xa > xb)."""
    xa = np.inf
    xb = -np.inf
    for px, py in ((x0, y0), (x1, y1)):
        d = yc - py
        if d * d <= R * R:
            r = math.sqrt(R * R - d * d)
            xa = min(xa, px - r)
            xb = max(xb, px + r)
    Lx = x1 - x0
    Ly = y1 - y0
    L = math.sqrt(Lx * Lx + Ly * Ly)
    if L > 0.0:
        ux = Lx / L
        uy = Ly / L
        dy = yc - y0
        lo = -np.inf
        hi = np.inf
        # 0 <= s = dx ux + dy uy <= L
        if abs(ux) > 1e-12:
            a = (0.0 - dy * uy) / ux
            b = (L - dy * uy) / ux
            lo = max(lo, min(a, b))
            hi = min(hi, max(a, b))
        elif not (0.0 <= dy * uy <= L):
            hi = -np.inf
        # -R <= h = dx uy - dy ux <= R
        if abs(uy) > 1e-12:
            a = (-R + dy * ux) / uy
            b = (R + dy * ux) / uy
            lo = max(lo, min(a, b))
            hi = min(hi, max(a, b))
        elif abs(dy * ux) > R:
            hi = -np.inf
        if lo <= hi:
            xa = min(xa, x0 + lo)
            xb = max(xb, x0 + hi)
    return xa, xb


@njit(cache=True)
def _row_fast(row, xs0, dx, ddy, ux, uy, L, m, isq, ci, ttype, R, k, z0, zfloor, eps, write):
    """One row of cells (``row`` a view, first cell centre at ``xs0`` relative to the
    chord start, ``ddy`` the row's Y relative to it) under a non-vertical chord of a
    flat, ball or drill tool. Branch-free so LLVM vectorises it. Returns the number of
    cells that had material above the tool; lowers them when ``write``."""
    R2 = R * R
    big = 1e300
    uflat = -big if m > 0.0 else big
    hits = 0
    zf = zfloor + eps
    for i in range(row.shape[0]):
        ddx = xs0 + i * dx
        s = ddx * ux + ddy * uy
        hh = ddx * uy - ddy * ux
        h2 = hh * hh
        w2 = R2 - h2
        w2c = w2 if w2 > 0.0 else 0.0
        w = math.sqrt(w2c)
        ulo = -s if -s > -w else -w
        ls = L - s
        uhi = ls if ls < w else w
        if ttype == BALL:
            u0 = -m * w * isq
        elif ttype == DRILL:
            ah = hh if hh > 0.0 else -hh
            u0 = -m * ah * ci if ci > 0.0 else uflat
        else:
            u0 = uflat
        u = u0 if u0 > ulo else ulo
        u = u if u < uhi else uhi
        if ttype == BALL:
            q = w2c - u * u
            q = q if q > 0.0 else 0.0
            prof = R - math.sqrt(q)
        elif ttype == DRILL:
            d2 = h2 + u * u
            d2 = d2 if d2 < R2 else R2
            prof = k * math.sqrt(d2)
        else:
            prof = 0.0
        z = z0 + m * (s + u) + prof
        z = z if (w2 >= 0.0) & (ulo <= uhi) else big
        old = row[i]
        hits += (z < old - eps) & (old > zf)
        if write:
            z = z if z > zfloor else zfloor
            row[i] = z if z < old else old
    return hits


@njit(cache=True)
def _row_generic(row, xs0, dx, ddy, ux, uy, L, m, sq, ci, ttype, R, rc, k, z0, zfloor,
                 eps, write):
    """Scalar version of :func:`_row_fast` for every case (vertical chords, bull)."""
    hits = 0
    for i in range(row.shape[0]):
        old = row[i]
        if old <= zfloor:
            continue
        z = _envelope(xs0 + i * dx, ddy, 0.0, 0.0, z0, ux, uy, L, m, sq, ci, ttype, R, rc, k,
                      old)
        if z < old:
            if z < old - eps:
                hits += 1
            if write:
                row[i] = z if z > zfloor else zfloor
    return hits


@njit(cache=True)
def _sweep_band(H, bmax, B, jlo, jhi, zfloor, gx, gy, dx, dy,
                x0, y0, z0, x1, y1, z1, ttype, R, rc, k, zoff, cut, eps):
    """Sweep one chord over rows [jlo, jhi). ``cut``: lower the cells (returns True if
    any cell had material above the tool); otherwise only test for material above the
    tool (holder check). ``zoff`` lifts the tool (holder cylinders)."""
    ny, nx = H.shape
    ymn = min(y0, y1) - R
    ymx = max(y0, y1) + R
    ja = max(jlo, int(math.ceil((ymn - gy) / dy - 0.5)))
    jb = min(jhi - 1, int(math.floor((ymx - gy) / dy - 0.5)))
    if ja > jb:
        return False
    xmn = min(x0, x1) - R
    xmx = max(x0, x1) + R
    ia = max(0, int(math.ceil((xmn - gx) / dx - 0.5)))
    ib = min(nx - 1, int(math.floor((xmx - gx) / dx - 0.5)))
    if ia > ib:
        return False
    zlow = min(z0, z1) + zoff
    top = -np.inf
    for bi in range(ia // B, ib // B + 1):
        if bmax[bi] > top:
            top = bmax[bi]
    tol = 0.0 if cut else eps            # cutting is exact; contact tests have a tolerance
    if top <= zlow + tol or top <= zfloor + tol:
        return False
    Lx = x1 - x0
    Ly = y1 - y0
    L = math.sqrt(Lx * Lx + Ly * Ly)
    # reference point of the chord (cell offsets are taken from it): its start, or
    # for a vertical chord its lower end
    rx = x0
    ry = y0
    if L <= 1e-6 * abs(z1 - z0) + 1e-12:     # vertical (or so steep that m u loses digits)
        L = 0.0
        ux = 0.0
        uy = 0.0
        m = 0.0
        zs = zlow
        if z1 < z0:
            rx = x1
            ry = y1
    else:
        ux = Lx / L
        uy = Ly / L
        m = (z1 - z0) / L
        zs = z0 + zoff
    sq = math.sqrt(1.0 + m * m)
    ci = 1.0 / math.sqrt(k * k - m * m) if (ttype == DRILL and k > abs(m)) else 0.0
    fast = L > 0.0 and ttype != BULL
    hits = 0
    for j in range(ja, jb + 1):
        yc = gy + (j + 0.5) * dy
        xa, xb = _row_span(yc, x0, y0, x1, y1, R)
        if xa > xb:
            continue
        i0 = max(ia, int(math.ceil((xa - gx) / dx - 0.5)))
        i1 = min(ib, int(math.floor((xb - gx) / dx - 0.5)))
        if i0 > i1:
            continue
        row = H[j, i0:i1 + 1]
        xs0 = gx + (i0 + 0.5) * dx - rx
        if fast:
            hits += _row_fast(row, xs0, dx, yc - ry, ux, uy, L, m, 1.0 / sq, ci, ttype, R,
                              k, zs, zfloor, eps, cut)
        else:
            hits += _row_generic(row, xs0, dx, yc - ry, ux, uy, L, m, sq, ci, ttype, R,
                                 rc, k, zs, zfloor, eps, cut)
        if hits > 0 and not cut:
            return True
    return hits > 0


@njit(cache=True, nogil=True)
def sweep_chunk(t, nthreads, H, zfloor, gx, gy, dx, dy, B, S, E, seg_tool,
                seg_motion, ttype, tR, trc, tk, hR, hZ, hN, eps, removes, holder_hit):
    """Sweep chords ``S[n] -> E[n]`` in order over the Z-map ``H`` (modified in place),
    in the bands of ``B`` rows ``t, t + nthreads, ...`` (thread ``t`` of ``nthreads``).

    Tool parameters are indexed by ``seg_tool`` (a slot, not a tool number): type code,
    radius, corner radius, cone slope ``k`` (height per unit radius); holder cylinders
    ``hR[slot, c]`` (radius) with bottoms ``hZ[slot, c]`` above the tip, ``hN[slot]`` of
    them. Sets ``removes[motion] = 1`` when a chord of the motion removes material
    (more than ``eps`` from a cell) and
    ``holder_hit[motion] = 1`` when a holder cylinder meets material (tested before the
    chord cuts).
    """
    ny, nx = H.shape
    nby = (ny + B - 1) // B
    nbx = (nx + B - 1) // B
    nseg = S.shape[0]
    bmax = np.empty(nbx)
    for bj in range(t, nby, nthreads):
        jlo = bj * B
        jhi = min(ny, jlo + B)
        for bi in range(nbx):
            ilo = bi * B
            ihi = min(nx, ilo + B)
            mx = -np.inf
            for j in range(jlo, jhi):
                for i in range(ilo, ihi):
                    if H[j, i] > mx:
                        mx = H[j, i]
            bmax[bi] = mx
        for s in range(nseg):
            slot = seg_tool[s]
            x0 = S[s, 0]
            y0 = S[s, 1]
            z0 = S[s, 2]
            x1 = E[s, 0]
            y1 = E[s, 1]
            z1 = E[s, 2]
            # the holder's cylinders (tested, flat, lifted) and then the tool (cutting);
            # one call site, so the band sweep is compiled for one signature
            for c in range(hN[slot] + 1):
                cut = c == hN[slot]
                if cut:
                    tt, rr, rc, kk, zo = ttype[slot], tR[slot], trc[slot], tk[slot], 0.0
                else:
                    tt, rr, rc, kk, zo = FLAT, hR[slot, c], 0.0, 0.0, hZ[slot, c]
                if _sweep_band(H, bmax, B, jlo, jhi, zfloor, gx, gy, dx, dy,
                               x0, y0, z0, x1, y1, z1, tt, rr, rc, kk, zo, cut, eps):
                    if not cut:
                        holder_hit[seg_motion[s]] = 1
                    else:
                        removes[seg_motion[s]] = 1
