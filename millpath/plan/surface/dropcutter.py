"""Drop-cutter (inverse tool offset) against a triangle mesh, exact, batched, all cores.

For a point (x, y) the drop-cutter returns the lowest tool-tip Z at which the cutter
touches the mesh without cutting into it, i.e. the maximum over all triangles of the
contact Z, and the contact point. Units are the mesh's (job units); the tool axis is +Z.

The cutter is its profile (:class:`~millpath.geometry.cutter.Cutter`: radius R,
corner radius rc, flat part a = R - rc). The algorithm is written once for that profile:

- vertex: ``z = pz - h(d)`` for vertices at horizontal distance ``d <= R``;
- facet: the cutter touches a plane of upward unit normal ``n`` at the point whose
  outward normal is ``-n``: ``cc = (x, y, tip + rc) - a n_xy/|n_xy| - rc n``; the
  contact counts when ``cc`` projects inside the triangle;
- edge: in the vertical plane of the edge at distance ``d`` from the axis, the tip Z
  for a contact at ``v`` (along the edge from the foot of the perpendicular) is
  ``f(v) = z_line(v) - h(sqrt(d^2 + v^2))``, a concave function; the drop is its
  maximum over the part of the edge under the cutter. Flat: an interval end; ball:
  closed form ``v = m w / sqrt(1 + m^2)``; bull: the one root of a quartic in
  ``q = rho - a`` on a bracket, by safeguarded Newton to machine precision.

Speed: a uniform XY grid of triangle lists (CSR; a triangle is listed in the cells its
footprint meets, not every cell of its bounding box), each list sorted by the triangle's
top Z, so a query stops scanning a cell at the first triangle whose top is below the
best contact found (no contact can be higher than a triangle's top vertex); the cells
under the cutter are scanned highest bound first, and no further once a cell's bound
(its top lowered by the profile at its distance) cannot beat the best contact;
bounding-box rejection, then the drop onto the triangle's whole plane (an upper bound
for the triangle), before any exact test; a triangle listed in several cells is tested
once per query; each query starts from the previous point's contact and from the mesh
point under its axis (a mesh point under the cutter bounds the drop from below), so
points in pass order test few triangles;
chunks of points on several threads (:mod:`millpath.threads`).

Points where the cutter touches no triangle get ``-inf`` (or ``z_floor``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numba import njit

from millpath.model.tool import Tool
from millpath.part.surface.mesh import Mesh
from millpath.geometry.cutter import BULL, DRILL, Cutter, height
from millpath.threads import over_range


@dataclass
class MeshIndex:
    """A mesh with per-triangle data and a uniform XY grid of triangle lists.

    ``cell`` is the grid pitch (job units); ``starts[c]:starts[c+1]`` indexes
    ``items`` for cell ``c = iy * nx + ix``; each list is sorted by top Z, highest first.
    """

    mesh: Mesh
    tri: np.ndarray        # (n, 3, 3)
    box: np.ndarray        # (n, 4) xmin, xmax, ymin, ymax
    ztop: np.ndarray       # (n,)
    plane: np.ndarray      # (n, 4) unit normal (nz >= 0) and offset d = n . p
    x0: float
    y0: float
    cell: float
    nx: int
    ny: int
    starts: np.ndarray     # (nx * ny + 1,) int64
    items: np.ndarray      # (m,) int32
    seen: np.ndarray | None = None   # (n,) int64: serial queries' marks of tested triangles
    marks: int = 0                   # marks used so far in ``seen``


@njit(cache=True)
def _tri_overlaps_cell(tri, t, gx0, gx1, gy0, gy1):
    """Whether triangle ``t``'s XY footprint meets the rectangle (separating axes: the
    rectangle's two axes are already known to overlap, test the three edge normals;
    exact also for a vertical triangle, whose footprint is a segment)."""
    for i in range(3):
        j = (i + 1) % 3
        k = (i + 2) % 3
        nx_ = tri[t, i, 1] - tri[t, j, 1]
        ny_ = tri[t, j, 0] - tri[t, i, 0]
        if nx_ == 0.0 and ny_ == 0.0:
            continue
        p0 = nx_ * tri[t, i, 0] + ny_ * tri[t, i, 1]
        pk = nx_ * tri[t, k, 0] + ny_ * tri[t, k, 1]
        tmin = min(p0, pk)
        tmax = max(p0, pk)
        c0 = nx_ * gx0 + ny_ * gy0
        c1 = nx_ * gx1 + ny_ * gy0
        c2 = nx_ * gx0 + ny_ * gy1
        c3 = nx_ * gx1 + ny_ * gy1
        cmin = min(min(c0, c1), min(c2, c3))
        cmax = max(max(c0, c1), max(c2, c3))
        slack = 1e-9 * (abs(cmin) + abs(cmax) + abs(tmin) + abs(tmax))
        if cmax < tmin - slack or cmin > tmax + slack:
            return False
    return True


@njit(cache=True)
def _fill_grid(tri, box, order, x0, y0, cell, nx, ny):
    """Cell lists (CSR) of the triangles whose footprint meets each cell (a cell grown
    by a hair on every side), in the order ``order``."""
    pad = 1e-7 * cell
    counts = np.zeros(nx * ny + 1, np.int64)
    for pas in range(2):
        if pas == 1:
            starts = np.cumsum(counts)
            fill = starts[:-1].copy()
            items = np.empty(starts[-1], np.int32)
        for k in range(order.shape[0]):
            t = order[k]
            ix0 = max(0, min(nx - 1, int((box[t, 0] - x0) / cell)))
            ix1 = max(0, min(nx - 1, int((box[t, 1] - x0) / cell)))
            iy0 = max(0, min(ny - 1, int((box[t, 2] - y0) / cell)))
            iy1 = max(0, min(ny - 1, int((box[t, 3] - y0) / cell)))
            big = ix1 > ix0 + 1 or iy1 > iy0 + 1
            for iy in range(iy0, iy1 + 1):
                for ix in range(ix0, ix1 + 1):
                    if big:
                        gx0 = x0 + ix * cell - pad
                        gy0 = y0 + iy * cell - pad
                        if not _tri_overlaps_cell(tri, t, gx0, gx0 + cell + 2 * pad, gy0,
                                                  gy0 + cell + 2 * pad):
                            continue
                    c = iy * nx + ix
                    if pas == 0:
                        counts[c + 1] += 1
                    else:
                        items[fill[c]] = t
                        fill[c] += 1
    return starts, items


def build_index(mesh: Mesh, cell: float | None = None) -> MeshIndex:
    """Index a mesh for drop-cutter queries. ``cell`` defaults to about three mean
    triangle extents (job units); a cell of 0.25 to 0.5 times the cutter radius is a
    good choice for large batches."""
    tri = mesh.triangles
    lo = tri.min(axis=1)
    hi = tri.max(axis=1)
    box = np.ascontiguousarray(np.stack([lo[:, 0], hi[:, 0], lo[:, 1], hi[:, 1]], axis=1))
    ztop = np.ascontiguousarray(hi[:, 2])
    n = mesh.normals()
    d = np.einsum("ij,ij->i", n, tri[:, 0])
    plane = np.ascontiguousarray(np.concatenate([n, d[:, None]], axis=1))
    (x0, y0, _), (x1, y1, _) = mesh.bounds
    span = max(x1 - x0, y1 - y0, 1e-9)
    if cell is None:
        # three typical (median) triangle extents: a few long triangles (a flat floor,
        # a vertical wall) are listed only in the cells their footprint meets
        ext = np.maximum(hi[:, 0] - lo[:, 0], hi[:, 1] - lo[:, 1])
        cell = 3.0 * float(np.median(ext)) if len(ext) else 1.0
        cell = max(cell, span / 512.0)
    cell = max(float(cell), span / 4096.0)
    nx = int((x1 - x0) / cell) + 1
    ny = int((y1 - y0) / cell) + 1
    order = np.argsort(-ztop, kind="stable").astype(np.int64)
    starts, items = _fill_grid(np.ascontiguousarray(tri), box, order, float(x0), float(y0),
                               cell, nx, ny)
    return MeshIndex(mesh, tri, box, ztop, plane, float(x0), float(y0), cell, nx, ny,
                     starts, items)


@njit(cache=True)
def _inside_xy(tri, t, px, py, rel_eps):
    """Whether (px, py) lies in triangle ``t`` seen from +Z (edge functions, either
    winding), with a slack of ``rel_eps`` times its doubled area."""
    ax = tri[t, 0, 0]
    ay = tri[t, 0, 1]
    bx = tri[t, 1, 0]
    by = tri[t, 1, 1]
    cx = tri[t, 2, 0]
    cy = tri[t, 2, 1]
    area = (bx - ax) * (cy - ay) - (by - ay) * (cx - ax)
    w0 = (bx - px) * (cy - py) - (by - py) * (cx - px)
    w1 = (cx - px) * (ay - py) - (cy - py) * (ax - px)
    w2 = (ax - px) * (by - py) - (ay - py) * (bx - px)
    if area < 0.0:
        w0 = -w0
        w1 = -w1
        w2 = -w2
    eps = -rel_eps * abs(area)
    return w0 >= eps and w1 >= eps and w2 >= eps


@njit(cache=True)
def _bull_v(d, m, rc, a):
    """Stationary point |v| of f(v) = m v - h(sqrt(d^2 + v^2)) for a torus profile.

    Solves q^2 ((a+q)^2 - d^2) = m^2 (rc^2 - q^2) (a+q)^2 for q = rho - a in
    [max(0, d - a), rc] and returns sqrt((a+q)^2 - d^2).
    """
    lo = d - a if d > a else 0.0
    hi = rc
    m2 = m * m
    q = 0.5 * (lo + hi)
    for _ in range(200):
        aq = a + q
        g = aq * aq - d * d
        s = rc * rc - q * q
        F = q * q * g - m2 * s * aq * aq
        if F > 0.0:
            hi = q
        else:
            lo = q
        dF = 2.0 * q * g + 2.0 * q * q * aq - m2 * (-2.0 * q * aq * aq + 2.0 * s * aq)
        qn = q - F / dF if dF != 0.0 else 0.5 * (lo + hi)
        if not (qn > lo and qn < hi):
            qn = 0.5 * (lo + hi)
        if abs(qn - q) <= 1e-15 * (rc + a) or hi - lo <= 1e-15 * (rc + a):
            q = qn
            break
        q = qn
    aq = a + q
    g = aq * aq - d * d
    return math.sqrt(g) if g > 0.0 else 0.0


@njit(cache=True)
def _drop_one(x, y, R, rc, tri, box, ztop, plane, x0, y0, cell, nx, ny, starts, items,
              out_cc, seen, mark, wx, wy, wz, cb, ci):
    """One query; ``cb``, ``ci``: scratch for CELLS_ORDERED cells."""
    a = R - rc
    R2 = R * R
    best = -np.inf
    ccx = np.nan
    ccy = np.nan
    ccz = np.nan
    # warm start: a mesh point (wx, wy, wz) under the cutter (the previous query's
    # contact) bounds the drop from below; only triangles that beat it are tested
    if wz == wz:
        dx = wx - x
        dy = wy - y
        d2 = dx * dx + dy * dy
        if d2 < R2:
            best = wz - height(BULL, R, rc, 0.0, math.sqrt(d2))
            ccx = wx
            ccy = wy
            ccz = wz
    # the mesh point straight under the axis (the highest triangle there) bounds the
    # drop from below too: the tip is the tool's lowest point
    zt = _highest_under(x, y, tri, box, ztop, plane, x0, y0, cell, nx, ny, starts, items,
                        best, 0.0, False)
    if zt > best:
        best = zt
        ccx = x
        ccy = y
        ccz = zt
    ix0 = max(0, int(math.floor((x - R - x0) / cell)))
    ix1 = min(nx - 1, int(math.floor((x + R - x0) / cell)))
    iy0 = max(0, int(math.floor((y - R - y0) / cell)))
    iy1 = min(ny - 1, int(math.floor((y + R - y0) / cell)))
    ncell = (ix1 - ix0 + 1) * (iy1 - iy0 + 1)
    if ix0 > ix1 or iy0 > iy1:
        ncell = 0
    # the cells under the cutter, CELLS_ORDERED at a time (in row order), each lot
    # scanned highest bound first (the top triangle's top lowered by the profile height
    # at the distance from the axis to the cell), up to the first that cannot beat the
    # best contact
    for b0 in range(0, ncell, CELLS_ORDERED):
        m = 0
        for n in range(b0, min(ncell, b0 + CELLS_ORDERED)):
            ix = ix0 + n % (ix1 - ix0 + 1)
            iy = iy0 + n // (ix1 - ix0 + 1)
            c = iy * nx + ix
            k0 = starts[c]
            if k0 == starts[c + 1] or ztop[items[k0]] <= best:
                continue
            gx = x0 + ix * cell
            gy = y0 + iy * cell
            ddx = gx - x if x < gx else (x - gx - cell if x > gx + cell else 0.0)
            ddy = gy - y if y < gy else (y - gy - cell if y > gy + cell else 0.0)
            dcell = math.sqrt(ddx * ddx + ddy * ddy)
            if dcell >= R:
                continue
            bound = ztop[items[k0]] - height(BULL, R, rc, 0.0, dcell)
            if bound <= best:
                continue
            j = m                                   # insertion into cb (descending)
            while j > 0 and cb[j - 1] < bound:
                cb[j] = cb[j - 1]
                ci[j] = ci[j - 1]
                j -= 1
            cb[j] = bound
            ci[j] = c
            m += 1
        for q in range(m):
            if cb[q] <= best:
                break
            c = ci[q]
            k0 = starts[c]
            k1 = starts[c + 1]
            for k in range(k0, k1):
                t = items[k]
                if ztop[t] <= best:
                    break
                if seen[t] == mark:
                    continue      # listed in an earlier cell of this query: tested
                seen[t] = mark
                ddx = box[t, 0] - x if x < box[t, 0] else (x - box[t, 1] if x > box[t, 1] else 0.0)
                ddy = box[t, 2] - y if y < box[t, 2] else (y - box[t, 3] if y > box[t, 3] else 0.0)
                db2 = ddx * ddx + ddy * ddy
                if db2 >= R2:
                    continue
                if ztop[t] - height(BULL, R, rc, 0.0, math.sqrt(db2)) <= best:
                    continue
                # the drop onto the triangle's whole plane (contact at px, py, pz; tool
                # tip at ``tip``) bounds the drop onto it, and is the facet's own drop
                # when the contact lies on the triangle
                nzz = plane[t, 2]
                facet = nzz > 1e-12
                tip = -math.inf
                px = x
                py = y
                pz = 0.0
                if facet:
                    nxx = plane[t, 0]
                    nyy = plane[t, 1]
                    s = math.sqrt(nxx * nxx + nyy * nyy)
                    if s > 1e-14:
                        px = x - a * nxx / s - rc * nxx
                        py = y - a * nyy / s - rc * nyy
                    else:
                        px = x
                        py = y
                    pz = (plane[t, 3] - nxx * px - nyy * py) / nzz
                    tip = pz - rc + rc * nzz
                    if tip <= best:
                        continue
                # vertices
                for i in range(3):
                    vz = tri[t, i, 2]
                    if vz <= best:
                        continue
                    dx = tri[t, i, 0] - x
                    dy = tri[t, i, 1] - y
                    d2 = dx * dx + dy * dy
                    if d2 <= R2:
                        z = vz - height(BULL, R, rc, 0.0, math.sqrt(d2))
                        if z > best:
                            best = z
                            ccx = tri[t, i, 0]
                            ccy = tri[t, i, 1]
                            ccz = vz
                # facet
                if facet:
                    if tip > best:
                        if _inside_xy(tri, t, px, py, 1e-12):
                            best = tip
                            ccx = px
                            ccy = py
                            ccz = pz
                # edges
                for i in range(3):
                    j = (i + 1) % 3
                    x1 = tri[t, i, 0]
                    y1 = tri[t, i, 1]
                    z1 = tri[t, i, 2]
                    x2 = tri[t, j, 0]
                    y2 = tri[t, j, 1]
                    z2 = tri[t, j, 2]
                    if z1 <= best and z2 <= best:
                        continue
                    ex = x2 - x1
                    ey = y2 - y1
                    L2 = ex * ex + ey * ey
                    if L2 < 1e-24:
                        continue
                    L = math.sqrt(L2)
                    tx = ex / L
                    ty = ey / L
                    qx = x - x1
                    qy = y - y1
                    uc = qx * tx + qy * ty
                    d = abs(qx * ty - qy * tx)
                    if d >= R:
                        continue
                    w = math.sqrt(R2 - d * d)
                    lo = uc - w
                    if lo < 0.0:
                        lo = 0.0
                    hi = uc + w
                    if hi > L:
                        hi = L
                    if lo > hi:
                        continue
                    m = (z2 - z1) / L
                    zl = z1 + m * (hi if m > 0.0 else lo)
                    if zl - height(BULL, R, rc, 0.0, d) <= best:
                        continue      # bound: highest edge point, nearest distance
                    vlo = lo - uc
                    vhi = hi - uc
                    if rc == 0.0:
                        v = vhi if m > 0.0 else vlo
                    else:
                        if a == 0.0:
                            v = m * w / math.sqrt(1.0 + m * m)
                        elif m == 0.0:
                            v = 0.0
                        else:
                            v = _bull_v(d, m, rc, a)
                            if m < 0.0:
                                v = -v
                        if v < vlo:
                            v = vlo
                        elif v > vhi:
                            v = vhi
                    u = uc + v
                    zl = z1 + m * u
                    z = zl - height(BULL, R, rc, 0.0, math.sqrt(d * d + v * v))
                    if z > best:
                        best = z
                        ccx = x1 + tx * u
                        ccy = y1 + ty * u
                        ccz = zl
    out_cc[0] = ccx
    out_cc[1] = ccy
    out_cc[2] = ccz
    return best


#: the cells under the cutter are ordered by their bound this many at a time
#: (insertion sort; a ball of radius 3 over 1.2 cells covers 36 to 49)
CELLS_ORDERED = 64


@njit(cache=True)
def _drop_range(xy, p0, p1, R, rc, tri, box, ztop, plane, x0, y0, cell, nx, ny, starts,
                items, z_out, cc_out, seen, mark0):
    """Points ``p0:p1``; ``seen[t] == mark0 + p`` marks triangle ``t`` tested for point
    ``p`` (a triangle is listed in every cell its footprint meets)."""
    wx = np.nan
    wy = np.nan
    wz = np.nan
    cb = np.empty(CELLS_ORDERED)
    ci = np.empty(CELLS_ORDERED, np.int64)
    for p in range(p0, p1):
        z_out[p] = _drop_one(xy[p, 0], xy[p, 1], R, rc, tri, box, ztop, plane, x0, y0,
                             cell, nx, ny, starts, items, cc_out[p], seen, mark0 + p,
                             wx, wy, wz, cb, ci)
        wx = cc_out[p, 0]
        wy = cc_out[p, 1]
        wz = cc_out[p, 2]


@njit(cache=True, nogil=True)
def _drop_chunk(lo, hi, xy, R, rc, tri, box, ztop, plane, x0, y0, cell, nx, ny, starts,
                items, z_out, cc_out):
    """Points ``lo:hi`` with marks of their own (one chunk of a threaded batch)."""
    seen = np.zeros(tri.shape[0], np.int64)
    _drop_range(xy, lo, hi, R, rc, tri, box, ztop, plane, x0, y0, cell, nx, ny, starts,
                items, z_out, cc_out, seen, 1)


#: below this many points a batch runs on one thread: starting the thread pool costs
#: more than it saves (and much more on a loaded machine)
PARALLEL_MIN = 4000


@dataclass
class DropResult:
    """``z``: tool-tip Z per point (``n``,); ``cc``: contact points (``n``, 3), NaN
    where the cutter touches nothing."""

    z: np.ndarray
    cc: np.ndarray


def drop(index: MeshIndex, cutter: Cutter, xy, z_floor: float = -np.inf) -> DropResult:
    """Drop ``cutter`` onto the indexed mesh at each of the points ``xy`` (``(n, 2)``,
    job units); return tip Z (at least ``z_floor``) and contact points."""
    if cutter.kind == DRILL:
        raise ValueError("a drill's cone has no drop-cutter contact: use a flat, ball or "
                         "bull-nose cutter")
    pts = np.ascontiguousarray(np.asarray(xy, dtype=np.float64).reshape(-1, 2))
    z = np.empty(len(pts))
    cc = np.empty((len(pts), 3))
    args = (float(cutter.radius), float(cutter.corner), index.tri, index.box, index.ztop,
            index.plane, index.x0, index.y0, index.cell, index.nx, index.ny, index.starts,
            index.items, z, cc)
    if len(pts) >= PARALLEL_MIN:
        over_range(_drop_chunk, len(pts), pts, *args, chunks_per_thread=32)
    elif len(pts):
        if index.seen is None or index.marks + len(pts) >= 2**62:
            index.seen = np.zeros(len(index.tri), np.int64)
            index.marks = 0
        _drop_range(pts, 0, len(pts), *args, index.seen, index.marks + 1)
        index.marks += len(pts)
    if z_floor > -np.inf:
        np.maximum(z, z_floor, out=z)
    return DropResult(z, cc)


def surface_cutter(tool: Tool) -> Cutter:
    """The cutter of ``tool`` for drop-cutter queries; a drill is a ValueError."""
    if tool.type == "drill":
        raise ValueError(f"tool {tool.number}: a drill cannot finish surfaces")
    return Cutter.of(tool)


def drop_z(index: MeshIndex, cutter: Cutter, x, y, z_floor: float = -np.inf) -> np.ndarray:
    """Tip Z only, for arrays ``x`` and ``y`` of equal shape (result has that shape)."""
    x = np.asarray(x, float)
    y = np.asarray(y, float)
    xy = np.stack([x.ravel(), y.ravel()], axis=1)
    return drop(index, cutter, xy, z_floor).z.reshape(x.shape)


@njit(cache=True, inline="always")
def _highest_under(x, y, tri, box, ztop, plane, x0, y0, cell, nx, ny, starts, items, best,
                   rel_eps, walls):
    """The highest mesh Z straight above or below (x, y) if higher than ``best``, else
    ``best``. ``rel_eps``: the in-triangle slack (of its doubled area); ``walls``: a
    vertical triangle through (x, y) counts at its top (a height field's wall), else
    not at all."""
    ix = int(math.floor((x - x0) / cell))
    iy = int(math.floor((y - y0) / cell))
    if ix < 0 or iy < 0 or ix >= nx or iy >= ny:
        return best
    c = iy * nx + ix
    for k in range(starts[c], starts[c + 1]):
        t = items[k]
        if ztop[t] <= best:
            break
        if box[t, 0] > x or box[t, 1] < x or box[t, 2] > y or box[t, 3] < y:
            continue
        nzz = plane[t, 2]
        if not (walls or nzz > 1e-12) or not _inside_xy(tri, t, x, y, rel_eps):
            continue
        if nzz > 1e-12:
            z = (plane[t, 3] - plane[t, 0] * x - plane[t, 1] * y) / nzz
        else:
            z = ztop[t]
        if z > best:
            best = z
    return best


@njit(cache=True)
def _height_one(x, y, tri, box, ztop, plane, x0, y0, cell, nx, ny, starts, items):
    return _highest_under(x, y, tri, box, ztop, plane, x0, y0, cell, nx, ny, starts, items,
                          -np.inf, 1e-9, True)


@njit(cache=True, nogil=True)
def _height_batch(lo, hi, xs, ys, tri, box, ztop, plane, x0, y0, cell, nx, ny, starts,
                  items, out):
    for p in range(lo, hi):
        out[p] = _height_one(xs[p], ys[p], tri, box, ztop, plane, x0, y0, cell, nx, ny,
                             starts, items)


class MeshHeight:
    """The mesh as a height field (a :class:`millpath.plan.base.Design`): the highest
    triangle above each (x, y), ``-inf`` off the mesh. Job units."""

    def __init__(self, index: MeshIndex):
        self.index = index

    def mesh(self) -> np.ndarray:
        """The triangles (n, 3, 3): the exact verification's reference."""
        return self.index.tri

    def height(self, x, y) -> np.ndarray:
        x = np.asarray(x, float)
        y = np.asarray(y, float)
        shape = np.broadcast_shapes(x.shape, y.shape)
        # writable C arrays: one compiled signature of the kernel for every caller
        xs = np.require(np.broadcast_to(x, shape).ravel(), float, ["C", "W"])
        ys = np.require(np.broadcast_to(y, shape).ravel(), float, ["C", "W"])
        out = np.empty(len(xs))
        ix = self.index
        if len(xs):
            over_range(_height_batch, len(xs), xs, ys, ix.tri, ix.box, ix.ztop, ix.plane,
                       ix.x0, ix.y0, ix.cell, ix.nx, ix.ny, ix.starts, ix.items, out,
                       smallest=PARALLEL_MIN // 2)
        return out.reshape(shape)
