"""The adaptive walker: steps of the tool centre whose engagement is measured, not assumed.

The material still to remove is a boolean raster ``M[j, i]`` (cell centres
``gx + (i + 0.5) h``, ``gy + (j + 0.5) h``); ``A[j, i]`` marks cells where the tool
centre may go. A step of length ``ds`` from ``p`` to ``q`` removes the material cells
inside the disk of radius ``R`` round ``q`` (those round ``p`` are gone already): its
area divided by ``ds`` is the width of cut, the engagement of the step times the tool
diameter. At each step the walker turns as far to the right (toward the material:
climb milling with a clockwise spindle) as the area limit ``amax`` allows, scanning
directions from hard right to hard left and refining the boundary by bisection; it
stops when no direction keeps within the limit (a corner it cannot take), when it has
cut nothing for ``idle_max`` steps, or after ``max_steps``. In a corner it cannot
enter in one bite it loops in cleared space and takes another small bite on the next
lap (trochoidal motion); an idle stretch between two steps that cut is replaced by the
straight way between them when the tool passes it in cleared space (no cell of ``M``
in its disk anywhere along it).
Lengths in job units.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit


@njit(cache=True)
def _span(yc, cy, r2):
    """Half width of a disk of squared radius ``r2`` centred at height ``cy``, on the
    row at ``yc``; -1 if the row misses it."""
    d = yc - cy
    w = r2 - d * d
    if w < 0.0:
        return -1.0
    return math.sqrt(w)


@njit(cache=True)
def crescent(M, gx, gy, h, R, px, py, qx, qy, cut):
    """Material cells inside disk(q, R) but outside disk(p, R); cleared if ``cut``.
    Returns the number of cells."""
    ny, nx = M.shape
    r2 = R * R
    j0 = max(0, int(math.floor((qy - R - gy) / h - 0.5)))
    j1 = min(ny - 1, int(math.ceil((qy + R - gy) / h - 0.5)))
    n = 0
    for j in range(j0, j1 + 1):
        yc = gy + (j + 0.5) * h
        wq = _span(yc, qy, r2)
        if wq < 0.0:
            continue
        ia = max(0, int(math.ceil((qx - wq - gx) / h - 0.5)))
        ib = min(nx - 1, int(math.floor((qx + wq - gx) / h - 0.5)))
        wp = _span(yc, py, r2)
        if wp >= 0.0:
            pa = int(math.ceil((px - wp - gx) / h - 0.5))
            pb = int(math.floor((px + wp - gx) / h - 0.5))
        else:
            pa = ib + 1
            pb = ib
        # cells of [ia, ib] left of pa and right of pb
        for i in range(ia, min(ib, pa - 1) + 1):
            if M[j, i]:
                n += 1
                if cut:
                    M[j, i] = False
        for i in range(max(ia, pb + 1), ib + 1):
            if M[j, i]:
                n += 1
                if cut:
                    M[j, i] = False
    return n


@njit(cache=True)
def cut_disk(M, gx, gy, h, R, cx, cy):
    """Clear the material inside disk((cx, cy), R); returns the cells cleared."""
    return crescent(M, gx, gy, h, R, cx + 1e9, cy, cx, cy, True)


@njit(cache=True)
def allowed(A, gx, gy, h, x, y):
    ny, nx = A.shape
    i = int(math.floor((x - gx) / h))
    j = int(math.floor((y - gy) / h))
    if i < 0 or j < 0 or i >= nx or j >= ny:
        return False
    return A[j, i]


@njit(cache=True)
def step_cells(M, A, gx, gy, h, R, x, y, ds, ang):
    """Material cells of ``M`` a step of length ``ds`` from (x, y) in direction ``ang``
    (radians) would remove, or -1 where the step ends outside ``A``."""
    qx = x + ds * math.cos(ang)
    qy = y + ds * math.sin(ang)
    if not allowed(A, gx, gy, h, qx, qy):
        return -1
    return crescent(M, gx, gy, h, R, x, y, qx, qy, False)


@njit(cache=True)
def walk(M, S, A, gx, gy, h, R, x, y, heading, ds, amax, max_steps, idle_max, out):
    """Walk from (x, y) (whose disk is already cleared) with initial ``heading``
    (radians). ``amax``: the most cells of ``M`` a step may remove; ``S`` (the
    material a next pass is looked for in) is cleared along with ``M``. Writes the positions (including
    the start) into ``out`` (k, 3: x, y, cells removed by the step into it) and
    returns k."""
    K = 25
    turn = 0.5 * math.pi
    n = 0
    out[0, 0] = x
    out[0, 1] = y
    out[0, 2] = 0.0
    n = 1
    idle = 0
    lastcut = 0
    cap = out.shape[0]
    for _ in range(max_steps):
        if n >= cap:
            break
        found = False
        best_a = 0.0
        best_c = 0
        prev_d = 0.0
        have_prev = False
        for k in range(K):
            d = -turn + k * (2.0 * turn / (K - 1))
            ang = heading + d
            c = step_cells(M, A, gx, gy, h, R, x, y, ds, ang)
            if c < 0:
                have_prev = False
                continue
            if c <= amax:
                found = True
                best_a = ang
                best_c = c
                if have_prev:           # refine toward the right (more engagement)
                    lo = d
                    hi = prev_d
                    for _it in range(5):
                        mid = 0.5 * (lo + hi)
                        cm = step_cells(M, A, gx, gy, h, R, x, y, ds, heading + mid)
                        if cm < 0:
                            hi = mid
                            continue
                        if cm <= amax:
                            lo = mid
                            best_a = heading + mid
                            best_c = cm
                        else:
                            hi = mid
                break
            prev_d = d
            have_prev = True
        if not found:
            break
        if best_c == 0:
            idle += 1
            if idle > idle_max:
                break
        else:
            if idle > 1 and segment_clear(M, A, gx, gy, h, R, out[lastcut, 0],
                                          out[lastcut, 1], x, y):
                # the idle loop since the last step that cut went through cleared
                # space only (nothing was cut on it): replace it by the straight way
                # from that step's end to here, which the full tool passes in air
                n = lastcut + 1
                out[n, 0] = x
                out[n, 1] = y
                out[n, 2] = 0.0
                n += 1
            idle = 0
        qx = x + ds * math.cos(best_a)
        qy = y + ds * math.sin(best_a)
        crescent(M, gx, gy, h, R, x, y, qx, qy, True)
        crescent(S, gx, gy, h, R, x, y, qx, qy, True)
        x = qx
        y = qy
        heading = best_a
        out[n, 0] = x
        out[n, 1] = y
        out[n, 2] = best_c
        if best_c > 0:
            lastcut = n
        n += 1
    # drop the idle tail: steps after the last one that cut
    last = n - 1
    while last > 0 and out[last, 2] == 0.0:
        last -= 1
    return last + 1


@njit(cache=True)
def segment_clear(M, A, gx, gy, h, R, x0, y0, x1, y1):
    """True if the tool can feed straight from (x0, y0) to (x1, y1) through cleared
    space: every position along it (steps of h) allowed and its disk free of material."""
    L = math.hypot(x1 - x0, y1 - y0)
    n = max(1, int(math.ceil(L / h)))
    px = x0
    py = y0
    if crescent(M, gx, gy, h, R, px + 1e9, py, px, py, False) > 0:
        return False
    for k in range(1, n + 1):
        qx = x0 + (x1 - x0) * k / n
        qy = y0 + (y1 - y0) * k / n
        if not allowed(A, gx, gy, h, qx, qy):
            return False
        if crescent(M, gx, gy, h, R, px, py, qx, qy, False) > 0:
            return False
        px = qx
        py = qy
    return True


@njit(cache=True)
def block_any(M, f):
    """(ceil(ny / f), ceil(nx / f)) blocks: True where any cell of the block is."""
    ny, nx = M.shape
    out = np.zeros(((ny + f - 1) // f, (nx + f - 1) // f), np.bool_)
    for j in range(ny):
        bj = j // f
        for i in range(nx):
            if M[j, i]:
                out[bj, i // f] = True
    return out
