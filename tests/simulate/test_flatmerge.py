"""Flat regions of a height-field reference merged into few triangles
(millpath.geometry.flatmerge, issue 15): a 100 x 60 plate, top z = 0, with three round
through holes and a rectangular pocket 3 deep. The merged mesh must cover exactly the
same points at each height (the test's own union of the unmerged triangles, and the
analytic areas), keep every other triangle, and be far smaller."""

from __future__ import annotations

import math

import numpy as np
import shapely

from millpath.geometry.heightmesh import height_field_mesh

HOLES = [(20.0, 30.0, 8.0), (50.0, 15.0, 5.0), (50.0, 45.0, 3.5)]     # x, y, radius
POCKET = (65.0, 10.0, 90.0, 50.0)                                      # x0, y0, x1, y1
FLOOR = -20.0                                                          # under the holes
MIN_SIZE = 0.05


class Plate:
    def height(self, x, y):
        x, y = np.broadcast_arrays(np.asarray(x, float), np.asarray(y, float))
        z = np.zeros(x.shape)
        x0, y0, x1, y1 = POCKET
        z[(x >= x0) & (x <= x1) & (y >= y0) & (y <= y1)] = -3.0
        for cx, cy, r in HOLES:
            z[np.hypot(x - cx, y - cy) <= r] = -np.inf
        return z


def _mesh(merge):
    return height_field_mesh(Plate(), (0.0, 0.0, 100.0, 60.0), size=2.0, min_size=MIN_SIZE,
                             flat_tol=0.0005, floor=FLOOR, merge=merge)


def _level(tri, z):
    zz = tri[:, :, 2]
    sel = (zz[:, 0] == z) & (zz[:, 1] == z) & (zz[:, 2] == z)
    return tri[sel]


def _union(tri):
    polys = shapely.polygons(tri[:, :, :2])
    return shapely.union_all(polys[shapely.area(polys) > 0])


def test_same_surface_far_fewer_triangles():
    raw = _mesh(False)
    merged = _mesh(True)
    assert len(merged) < 0.5 * len(raw)
    for z in (0.0, -3.0, FLOOR):
        a, b = _union(_level(raw, z)), _union(_level(merged, z))
        assert shapely.area(shapely.symmetric_difference(a, b)) < 1e-9 * a.area
        # no overlaps: the triangles' areas add up to their union's
        t = _level(merged, z)
        e = np.cross(t[:, 1] - t[:, 0], t[:, 2] - t[:, 0])
        assert np.all(e[:, 2] > 0)                 # counter-clockwise from above
        assert abs(e[:, 2].sum() / 2 - b.area) < 1e-9 * b.area
    # every other triangle (the walls) kept as it was (its corners put exactly on the
    # cell lines: moved by rounding only)
    def others(t):
        zz = t[:, :, 2]
        k = ~((zz[:, 0] == zz[:, 1]) & (zz[:, 1] == zz[:, 2]))
        return np.sort(t[k].reshape(-1, 9), axis=0)
    o1, o2 = others(raw), others(merged)
    assert o1.shape == o2.shape and np.allclose(o1, o2, rtol=0.0, atol=1e-9)


def test_areas_match_the_plate():
    merged = _mesh(True)
    holes = sum(math.pi * r * r for _, _, r in HOLES)
    x0, y0, x1, y1 = POCKET
    pocket = (x1 - x0) * (y1 - y0)
    # the hole walls are chords of the circles with their ends on them: each hole's
    # area is short by at most its perimeter times the sagitta of a chord across
    # a smallest cell
    slack = sum(2 * math.pi * r * (2 * MIN_SIZE ** 2) / (8 * r) for _, _, r in HOLES)
    top = _union(_level(merged, 0.0)).area
    assert abs(top - (100 * 60 - pocket - holes)) <= slack
    assert abs(_union(_level(merged, -3.0)).area - pocket) < 1e-9
    assert abs(_union(_level(merged, FLOOR)).area - holes) <= slack


def test_points_at_their_height():
    """Random points (fixed seed) away from the walls lie on a merged triangle at the
    plate's height there, and on none at another height."""
    merged = _mesh(True)
    rng = np.random.default_rng(15)
    p = rng.uniform([0, 0], [100, 60], size=(3000, 2))
    d = np.full(len(p), np.inf)
    for cx, cy, r in HOLES:
        d = np.minimum(d, np.abs(np.hypot(p[:, 0] - cx, p[:, 1] - cy) - r))
    x0, y0, x1, y1 = POCKET
    inside = (p[:, 0] > x0) & (p[:, 0] < x1) & (p[:, 1] > y0) & (p[:, 1] < y1)
    edge = np.minimum.reduce([np.abs(p[:, 0] - x0), np.abs(p[:, 0] - x1),
                              np.abs(p[:, 1] - y0), np.abs(p[:, 1] - y1)])
    d = np.where(inside | (edge < 0.1), np.minimum(d, edge), d)
    p = p[d > 2 * MIN_SIZE]
    want = Plate().height(p[:, 0], p[:, 1])
    want = np.where(np.isfinite(want), want, FLOOR)
    pts = shapely.points(p)
    for z in (0.0, -3.0, FLOOR):
        u = _union(_level(merged, z))
        on = shapely.covers(u, pts)
        assert np.array_equal(on, want == z)
