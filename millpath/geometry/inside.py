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
surface is 0). A ray that runs down a wall grazes the edges of the faces above and
below it, where rounding may count one and miss the other: when any crossing lies
within :data:`EDGE` (relative to the point's size) of its triangle's edge, the answer
is the majority of rays moved :data:`NUDGE` aside in three directions. Any consistent
unit.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

MAX_CROSSINGS = 64      # crossings kept per ray (more: the answer is "not known", False)
EDGE = 4e-9     # a crossing this near its triangle's edge (x the point's size) grazes it
NUDGE = 1e-7    # how far (x the point's size) the three rays are moved aside from one
                # that grazes: beyond the edges' rounding (1e-9 in barycentrics)


@njit(cache=True, error_model="numpy")
def ray_up_hit(px, py, pz, T):
    """Height above ``pz`` where the vertical line through (px, py) meets triangle
    ``T`` (edges and vertices included, to 1e-9 in barycentrics), or -1.0; the sign of
    the triangle's normal's Z (0: edge-on, no crossing); and the distance seen from
    above from (px, py) to the triangle's nearest edge (0 when missed)."""
    ax, ay = T[0, 0], T[0, 1]
    bx, by = T[1, 0] - ax, T[1, 1] - ay
    cx, cy = T[2, 0] - ax, T[2, 1] - ay
    det = bx * cy - by * cx          # twice the XY area, the sign of the normal's Z
    scale = (abs(bx) + abs(by)) * (abs(cx) + abs(cy))
    if scale == 0.0 or abs(det) <= 1e-12 * scale:
        return -1.0, 0, 0.0
    rx, ry = px - ax, py - ay
    u = (rx * cy - ry * cx) / det
    v = (bx * ry - by * rx) / det
    eps = 1e-9
    if u < -eps or v < -eps or u + v > 1.0 + eps:
        return -1.0, 0, 0.0
    z = T[0, 2] + u * (T[1, 2] - T[0, 2]) + v * (T[2, 2] - T[0, 2])
    if z < pz:
        return -1.0, 0, 0.0
    # barycentric w times twice the area over the opposite edge's length: the distance
    w = 1.0 - u - v
    ea = math.hypot(bx - cx, by - cy)       # opposite corner 0 (weight w)
    eb = math.hypot(cx, cy)                 # opposite corner 1 (weight u)
    ec = math.hypot(bx, by)                 # opposite corner 2 (weight v)
    near = abs(det) * min(w / max(ea, 1e-300), u / max(eb, 1e-300), v / max(ec, 1e-300))
    return z - pz, 1 if det > 0.0 else -1, max(near, 0.0)


@njit(cache=True, error_model="numpy")
def _ray_count(px, py, pz, tri, items, k0, k1, same, edge, hs, sg):
    """Crossings counted up the vertical ray from (px, py, pz) through the triangles
    ``items[k0:k1]`` (see the module doc); and whether one of them lies within ``edge``
    of its triangle's edge. A count of -2**30: more than ``MAX_CROSSINGS``."""
    m = 0
    grazes = False
    for k in range(k0, k1):
        h, sgn, near = ray_up_hit(px, py, pz, tri[items[k]])
        if sgn == 0 or h <= same:        # on a face: the boundary, not a crossing
            continue
        if near <= edge:
            grazes = True
        dup = False
        for a in range(m):
            if sg[a] == sgn and abs(hs[a] - h) <= same:
                dup = True
                break
        if dup:
            continue
        if m == MAX_CROSSINGS:
            return -(1 << 30), grazes
        hs[m] = h
        sg[m] = sgn
        m += 1
    total = 0
    for a in range(m):
        total += sg[a]
    return total, grazes


@njit(cache=True, error_model="numpy")
def in_material(p, tri, start, items, x0, y0, bs, nbx, nby):
    """True when point ``p`` is in the material of the mesh ``tri`` (see the module
    doc); ``start``/``items``/... the mesh's XY bucket index
    (:class:`millpath.geometry.index.BoxIndex`)."""
    size = max(1.0, abs(p[0]) + abs(p[1]) + abs(p[2]))
    same = 1e-9 * size
    hs = np.empty(MAX_CROSSINGS)
    sg = np.empty(MAX_CROSSINGS, np.int64)
    votes = 0
    for attempt in range(4):
        if attempt == 0:
            qx, qy = p[0], p[1]
        else:       # three directions 120 degrees apart, off the axes
            a = 0.3 + attempt * 2.0943951023931953
            qx = p[0] + NUDGE * size * math.cos(a)
            qy = p[1] + NUDGE * size * math.sin(a)
        i = int(math.floor((qx - x0) / bs))
        j = int(math.floor((qy - y0) / bs))
        if i < 0 or j < 0 or i >= nbx or j >= nby:
            inside = False
            grazes = False
        else:
            b = j * nbx + i
            total, grazes = _ray_count(qx, qy, p[2], tri, items, start[b], start[b + 1],
                                       same, EDGE * size, hs, sg)
            inside = total > 0
        if attempt == 0:
            if not grazes:
                return inside
            continue
        votes += 1 if inside else 0
    return votes >= 2
