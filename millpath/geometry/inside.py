"""Is a point in the material of a design mesh? An upward ray test, for numba.

A design mesh is wound so its normals point out of the material (see
:func:`millpath.simulate.exact.orient_outward`): a closed solid outward, an open
surface (a height field, material below it) upward. The ray from ``p`` straight up
counts +1 where it leaves the material (a face whose normal points up) and -1 where it
enters (a face whose normal points down); crossings at the same height (an edge or a
vertex shared by faces) count once, faces edge-on (walls) not at all. ``p`` is in the
material when the count is positive: 1 for a closed solid or a height field (every
entry matched by an exit above it, and one more exit), 0 outside, beyond an open
surface's edge included. A point on a face is on the boundary (its distance to the
surface is 0). Any consistent unit.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

MAX_CROSSINGS = 64      # crossings kept per ray (more: the answer is "not known", False)


@njit(cache=True, error_model="numpy")
def ray_up_hit(px, py, pz, T):
    """Height above ``pz`` where the vertical line through (px, py) meets triangle
    ``T`` (edges and vertices included, to 1e-9 in barycentrics), or -1.0; and the
    sign of the triangle's normal's Z (0: edge-on, no crossing)."""
    ax, ay = T[0, 0], T[0, 1]
    bx, by = T[1, 0] - ax, T[1, 1] - ay
    cx, cy = T[2, 0] - ax, T[2, 1] - ay
    det = bx * cy - by * cx          # twice the XY area, the sign of the normal's Z
    scale = (abs(bx) + abs(by)) * (abs(cx) + abs(cy))
    if scale == 0.0 or abs(det) <= 1e-12 * scale:
        return -1.0, 0
    rx, ry = px - ax, py - ay
    u = (rx * cy - ry * cx) / det
    v = (bx * ry - by * rx) / det
    eps = 1e-9
    if u < -eps or v < -eps or u + v > 1.0 + eps:
        return -1.0, 0
    z = T[0, 2] + u * (T[1, 2] - T[0, 2]) + v * (T[2, 2] - T[0, 2])
    if z < pz:
        return -1.0, 0
    return z - pz, 1 if det > 0.0 else -1


@njit(cache=True, error_model="numpy")
def in_material(p, tri, start, items, x0, y0, bs, nbx, nby):
    """True when point ``p`` is in the material of the mesh ``tri`` (see the module
    doc); ``start``/``items``/... the mesh's XY bucket index
    (:class:`millpath.geometry.index.BoxIndex`)."""
    i = int(math.floor((p[0] - x0) / bs))
    j = int(math.floor((p[1] - y0) / bs))
    if i < 0 or j < 0 or i >= nbx or j >= nby:
        return False
    b = j * nbx + i
    same = 1e-9 * max(1.0, abs(p[0]) + abs(p[1]) + abs(p[2]))
    hs = np.empty(MAX_CROSSINGS)
    sg = np.empty(MAX_CROSSINGS, np.int64)
    m = 0
    for k in range(start[b], start[b + 1]):
        h, sgn = ray_up_hit(p[0], p[1], p[2], tri[items[k]])
        if sgn == 0 or h <= same:        # on a face: the boundary, not a crossing
            continue
        dup = False
        for a in range(m):
            if sg[a] == sgn and abs(hs[a] - h) <= same:
                dup = True
                break
        if dup:
            continue
        if m == MAX_CROSSINGS:
            return False
        hs[m] = h
        sg[m] = sgn
        m += 1
    total = 0
    for a in range(m):
        total += sg[a]
    return total > 0
