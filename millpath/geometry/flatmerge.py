"""Horizontal triangles of one height merged into few: their union, triangulated again.

A height-field mesh (:mod:`millpath.geometry.heightmesh`) covers a flat floor or top
with many small cells where a wall runs near it. For each height the horizontal
triangles (all three corners at exactly that Z) are replaced by a constrained Delaunay
triangulation of their union: the same points of the plane (exactly: the boundary is
made of the triangles' own edges, no vertex moves), far fewer triangles. The union's
boundary is found by cancelling edges: on each axis-parallel line the triangles' edges
are summed as directed intervals (a piece to the left of the line runs one way, a piece
to its right the other; covered from both sides is inside), other edges cancel against
the same edge run the other way. Triangles wind counter-clockwise seen from above, in
and out. Any consistent unit.
"""

from __future__ import annotations

import numpy as np
import shapely


def merge_horizontal(tri: np.ndarray, block: float | None = None,
                     min_count: int = 8) -> np.ndarray:
    """``tri`` (n, 3, 3) with each height's horizontal triangles (when there are at
    least ``min_count`` of them) replaced by a triangulation of their union, made
    separately in square blocks of side ``block`` (by the triangles' centroids; None:
    one block) so each polygon stays small. Other triangles are kept as they are, in
    front."""
    tri = np.asarray(tri, float).reshape(-1, 3, 3)
    z = tri[:, :, 2]
    flat = (z[:, 0] == z[:, 1]) & (z[:, 1] == z[:, 2])
    a = tri[:, 1, :2] - tri[:, 0, :2]
    b = tri[:, 2, :2] - tri[:, 0, :2]
    area2 = a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0]
    levels, counts = np.unique(z[flat, 0], return_counts=True)
    take = flat & np.isin(z[:, 0], levels[counts >= min_count])
    out = [tri[~take]]
    sel = np.flatnonzero(take & (area2 != 0.0))         # (no-area ones cover nothing)
    if not len(sel):
        return np.ascontiguousarray(out[0])
    # groups: (height, block)
    _, key = np.unique(z[sel, 0], return_inverse=True)
    key = key.ravel().astype(np.int64)
    if block is not None and block > 0:
        c = tri[sel, :, :2].mean(axis=1)
        bi = np.floor((c[:, 0] - c[:, 0].min()) / block).astype(np.int64)
        bj = np.floor((c[:, 1] - c[:, 1].min()) / block).astype(np.int64)
        key = (key * (bi.max() + 1) + bi) * (bj.max() + 1) + bj
    _, group = np.unique(key, return_inverse=True)
    group = group.ravel()
    t2 = tri[sel, :, :2].copy()
    cw = area2[sel] < 0
    t2[cw] = t2[cw][:, ::-1]
    edges, eg = _boundary(t2, group)
    order = np.argsort(group, kind="stable")
    gstart = np.searchsorted(group[order], np.arange(group.max() + 2))
    estart = np.searchsorted(eg, np.arange(group.max() + 2))
    for g in range(len(gstart) - 1):
        rows = sel[order[gstart[g]:gstart[g + 1]]]
        polys = _faces(edges[estart[g]:estart[g + 1]])
        whole = float(np.abs(area2[rows]).sum()) / 2.0
        got = float(sum(p.area for p in polys))
        if not polys or abs(got - whole) > 1e-9 * max(whole, 1e-300):
            out.append(tri[rows])        # (not a clean coverage: kept as it is)
            continue
        out.append(_triangulate(polys, float(z[rows[0], 0])))
    return np.ascontiguousarray(np.concatenate(out))


def _boundary(t2: np.ndarray, group: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Directed boundary edges (k, 2, 2) of the union of each group's counter-clockwise
    2D triangles ``t2`` (m, 3, 2), which meet edge to edge or with vertices inside each
    other's edges (a quadtree's T-junctions), and their groups (sorted)."""
    A = t2.reshape(-1, 2)
    B = np.roll(t2, -1, axis=1).reshape(-1, 2)
    G = np.repeat(group, 3).astype(float)
    vert = A[:, 0] == B[:, 0]
    horz = (A[:, 1] == B[:, 1]) & ~vert
    edges, groups = [], []
    for axis_line, sel in ((0, vert), (1, horz)):
        if not sel.any():
            continue
        pos = 1 - axis_line                     # the coordinate along the line
        c = A[sel, axis_line]
        a, b = A[sel, pos], B[sel, pos]
        d = np.where(b > a, 1, -1)
        lo, hi = np.minimum(a, b), np.maximum(a, b)
        gg = np.concatenate([G[sel], G[sel]])
        keys = np.concatenate([c, c])
        at = np.concatenate([lo, hi])
        dl = np.concatenate([d, -d])
        o = np.lexsort((at, keys, gg))
        gg, keys, at, dl = gg[o], keys[o], at[o], dl[o]
        net = np.cumsum(dl)
        # net direction on [at[i], at[i + 1]) of line keys[i] of group gg[i]
        same = (keys[:-1] == keys[1:]) & (gg[:-1] == gg[1:])
        seg = np.flatnonzero(same & (net[:-1] != 0) & (at[1:] > at[:-1]))
        if not len(seg):
            continue
        # join runs of segments on one line with one direction (vertices where
        # nothing changes are T-junctions of the cells, not corners of the union)
        brk = np.ones(len(seg), bool)
        brk[1:] = ~_contiguous(seg, at, keys, gg, net)
        first = np.flatnonzero(brk)
        last = np.append(first[1:], len(seg)) - 1
        s0, s1 = seg[first], seg[last] + 1
        cc, p0, p1, nd = keys[s0], at[s0], at[s1], net[s0]
        start = np.where(nd > 0, p0, p1)
        end = np.where(nd > 0, p1, p0)
        if axis_line == 0:
            e = np.stack([np.stack([cc, start], 1), np.stack([cc, end], 1)], 1)
        else:
            e = np.stack([np.stack([start, cc], 1), np.stack([end, cc], 1)], 1)
        edges.append(e)
        groups.append(gg[s0])
    other = ~(vert | horz)
    if other.any():
        # an edge is on the boundary when it is not also run the other way: edges
        # put in one order of their ends, runs of equal ones summed with their sense
        a, b, g = A[other], B[other], G[other]
        fwd = (a[:, 0] < b[:, 0]) | ((a[:, 0] == b[:, 0]) & (a[:, 1] < b[:, 1]))
        p = np.where(fwd[:, None], a, b)
        q = np.where(fwd[:, None], b, a)
        o = np.lexsort((q[:, 1], q[:, 0], p[:, 1], p[:, 0], g))
        cols = np.stack([g[o], p[o, 0], p[o, 1], q[o, 0], q[o, 1]], axis=1)
        new = np.ones(len(o), bool)
        new[1:] = (cols[1:] != cols[:-1]).any(axis=1)
        first = np.flatnonzero(new)
        sense = np.add.reduceat(np.where(fwd[o], 1, -1), first)
        k = first[sense != 0]
        sn = sense[sense != 0]
        pk, qk = p[o[k]], q[o[k]]
        e = np.where((sn > 0)[:, None, None], np.stack([pk, qk], 1), np.stack([qk, pk], 1))
        edges.append(e)
        groups.append(g[o[k]])
    if not edges:
        return np.zeros((0, 2, 2)), np.zeros(0, np.int64)
    E = np.concatenate(edges)
    g = np.concatenate(groups).astype(np.int64)
    o = np.argsort(g, kind="stable")
    return E[o], g[o]


def _faces(E: np.ndarray) -> list:
    """Polygons bounded by the directed edges ``E`` (k, 2, 2) with the region on
    their left."""
    if not len(E):
        return []
    faces = shapely.get_parts(shapely.polygonize(shapely.linestrings(E)))
    if not len(faces):
        return []
    # a face is in the union when the boundary runs counter-clockwise round it: its
    # outer ring's first edge, counter-clockwise, is one of the directed edges
    directed = set(map(tuple, E.reshape(-1, 4).tolist()))
    keep = []
    for f in shapely.orient_polygons(faces):
        r = f.exterior.coords
        if (r[0][0], r[0][1], r[1][0], r[1][1]) in directed:
            keep.append(f)
    return keep


def _contiguous(seg, at, keys, gg, net):
    """For consecutive boundary segments: whether they are on one line of one group,
    end to start, with the same direction (a T-junction between them, not a corner)."""
    a, b = seg[:-1], seg[1:]
    return (keys[a] == keys[b]) & (gg[a] == gg[b]) & (at[a + 1] == at[b]) & (net[a] == net[b])


def _triangulate(polys: list, z: float) -> np.ndarray:
    """Constrained Delaunay triangles (k, 3, 3) of ``polys`` at height ``z``,
    counter-clockwise seen from above."""
    tris = shapely.get_parts(shapely.constrained_delaunay_triangles(
        shapely.multipolygons(polys)))
    c = shapely.get_coordinates(shapely.get_exterior_ring(tris)).reshape(-1, 4, 2)[:, :3]
    a = c[:, 1] - c[:, 0]
    b = c[:, 2] - c[:, 0]
    cw = a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0] < 0
    c[cw] = c[cw][:, ::-1]
    return np.concatenate([c, np.full((len(c), 3, 1), z)], axis=2)
