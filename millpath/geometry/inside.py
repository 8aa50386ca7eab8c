"""Is a point in the material behind a design triangle? A ray test, for numba.

A design mesh is wound so its normals point out of the material (see
:func:`millpath.simulate.exact.orient_outward`). A point ``p`` lies ``d`` behind the
plane of triangle ``t`` (outward unit normal ``n``) with its foot ``q = p + d n`` in
``t``. Just behind ``q`` is material; walking from ``q`` back to ``p`` the segment may
cross other faces. Each crossing of ``p -> q`` counts +1 where the segment leaves the
material (the face's normal along ``n``) and -1 where it enters (against ``n``);
crossings at the same place (an edge or a vertex shared by faces) count once. ``p`` is
in the material when they sum to 0 (every exit matched by an entry), outside when -1.
Faces edge-on to the segment are not crossings. Any consistent unit.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from millpath.geometry.index import bucket_range, first_bucket

MAX_CROSSINGS = 64      # crossings kept per segment (more: the answer is "not known")


@njit(cache=True, error_model="numpy")
def segment_hit(px, py, pz, dx, dy, dz, T):
    """Where the segment ``p + s d`` (0 <= s <= 1) passes through triangle ``T``: ``s``
    (edges and vertices included, to 1e-9 in barycentrics), or -1.0; and the sign of
    ``d`` along the triangle's normal (0 when edge-on)."""
    e1x, e1y, e1z = T[1, 0] - T[0, 0], T[1, 1] - T[0, 1], T[1, 2] - T[0, 2]
    e2x, e2y, e2z = T[2, 0] - T[0, 0], T[2, 1] - T[0, 1], T[2, 2] - T[0, 2]
    nx, ny, nz = e1y * e2z - e1z * e2y, e1z * e2x - e1x * e2z, e1x * e2y - e1y * e2x
    nn = math.sqrt(nx * nx + ny * ny + nz * nz)
    dd = math.sqrt(dx * dx + dy * dy + dz * dz)
    dn = dx * nx + dy * ny + dz * nz
    if nn == 0.0 or dd == 0.0 or abs(dn) <= 1e-12 * nn * dd:
        return -1.0, 0
    hx, hy, hz = dy * e2z - dz * e2y, dz * e2x - dx * e2z, dx * e2y - dy * e2x
    det = e1x * hx + e1y * hy + e1z * hz
    f = 1.0 / det
    sx, sy, sz = px - T[0, 0], py - T[0, 1], pz - T[0, 2]
    u = f * (sx * hx + sy * hy + sz * hz)
    eps = 1e-9
    if u < -eps or u > 1.0 + eps:
        return -1.0, 0
    cx, cy, cz = sy * e1z - sz * e1y, sz * e1x - sx * e1z, sx * e1y - sy * e1x
    v = f * (dx * cx + dy * cy + dz * cz)
    if v < -eps or u + v > 1.0 + eps:
        return -1.0, 0
    s = f * (e2x * cx + e2y * cy + e2z * cz)
    if s < 0.0 or s > 1.0:
        return -1.0, 0
    return s, 1 if dn > 0.0 else -1


@njit(cache=True, error_model="numpy")
def in_material_behind(p, n, d, t, tri, tlo, thi, start, items, bi0, bj0, x0, y0, bs,
                       nbx, nby):
    """True when point ``p``, ``d`` behind triangle ``t`` along its outward unit normal
    ``n`` (foot in ``t``), is in the material: the segment ``p -> p + d n`` leaves
    and enters the material equally often (see the module doc). False when it enters
    once more than it leaves (``p`` outside) or when the count is not consistent."""
    qx, qy, qz = p[0] + d * n[0], p[1] + d * n[1], p[2] + d * n[2]
    dx, dy, dz = qx - p[0], qy - p[1], qz - p[2]
    lx0, lx1 = min(p[0], qx), max(p[0], qx)
    ly0, ly1 = min(p[1], qy), max(p[1], qy)
    lz0, lz1 = min(p[2], qz), max(p[2], qz)
    # the same place along the segment: 1e-9 of the model's size
    ends = 1e-9 * max(1.0, abs(p[0]) + abs(p[1]) + abs(p[2]) + d) / max(d, 1e-300)
    ss = np.empty(MAX_CROSSINGS)
    sg = np.empty(MAX_CROSSINGS, np.int64)
    m = 0
    ia, ib, ja, jb = bucket_range(x0, y0, bs, nbx, nby, lx0, ly0, lx1, ly1)
    for bj in range(ja, jb + 1):
        for bi in range(ia, ib + 1):
            b = bj * nbx + bi
            for k in range(start[b], start[b + 1]):
                u = items[k]
                if u == t or not first_bucket(bi, bj, bi0[u], bj0[u], ia, ja):
                    continue
                if (thi[u, 0] < lx0 or tlo[u, 0] > lx1 or thi[u, 1] < ly0
                        or tlo[u, 1] > ly1 or thi[u, 2] < lz0 or tlo[u, 2] > lz1):
                    continue
                s, sgn = segment_hit(p[0], p[1], p[2], dx, dy, dz, tri[u])
                if sgn == 0 or s <= ends or s >= 1.0 - ends:
                    continue
                dup = False
                for a in range(m):
                    if sg[a] == sgn and abs(ss[a] - s) <= ends:
                        dup = True
                        break
                if dup:
                    continue
                if m == MAX_CROSSINGS:
                    return False
                ss[m] = s
                sg[m] = sgn
                m += 1
    total = 0
    for a in range(m):
        total += sg[a]
    return total == 0
