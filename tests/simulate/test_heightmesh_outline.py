"""The exact check's height-field mesh of a grid-pocket design against the design itself
(millpath.geometry.heightmesh through design_triangles): a star outline, whose slanted
walls cross the lines where a measured bottom's bilinear pieces meet, and its corners.
The truth is shapely's point-in-polygon and the bottom's own interpolation: off the
outline by more than the accuracy, every point of every triangle over the part of the
pocket a 3 mm end mill reaches lies within 3 accuracies of the design's height there
(the floor's flat cells are checked at their centre and edge midpoints only: across a
line of the bilinear bottom they stand off it by up to 2.5 accuracies; the star's acute
tips, narrower than the quadtree's first cells, are not checked)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import shapely
from shapely.geometry import Polygon

from millpath.model import Stock
from millpath.part.surface.grid import MeasuredGrid
from millpath.plan.gridpocket.operation import PocketDesign
from millpath.simulate.exact import design_triangles

JOB = Path(__file__).resolve().parents[1] / "generated" / "jobs" / "open-wall-gouge"
STAR = [[31.717, 61.469], [31.095, 55.229], [19.794, 36.05], [38.534, 23.582],
        [42.189, 23.109]]
ACCURACY = 0.001


def _truth(poly, surface, x, y):
    inside = shapely.contains_xy(poly, x, y)
    z = np.zeros(x.shape)
    z[inside] = np.minimum(surface.height(x[inside], y[inside]), 0.0)
    return z


def test_mesh_follows_outline_over_measured_grid_lines():
    poly = Polygon(STAR)
    surface = MeasuredGrid.from_csv(JOB / "bottom.csv")
    design = PocketDesign(poly, surface, 0.0)
    tri = design_triangles(design, Stock(0.0, 0.0, -18.7, 52.2, 71.5, 0.0), ACCURACY, 0.56)
    # points of each triangle: its centroid and points towards each corner
    w = np.array([[1, 1, 1], [4, 1, 1], [1, 4, 1], [1, 1, 4]], float)
    w /= w.sum(axis=1)[:, None]
    pts = np.einsum("kc,tcd->tkd", w, tri).reshape(-1, 3)
    d = shapely.distance(poly.exterior, shapely.points(pts[:, 0], pts[:, 1]))
    reach = poly.buffer(-1.5).buffer(1.5 + 2 * ACCURACY)
    off = (d > ACCURACY) & (shapely.contains_xy(reach, pts[:, 0], pts[:, 1])
                            | ~shapely.contains_xy(poly, pts[:, 0], pts[:, 1]))
    err = pts[off, 2] - _truth(poly, surface, pts[off, 0], pts[off, 1])
    assert np.abs(err).max() <= 3 * ACCURACY, (np.abs(err).max(), pts[off][np.argmax(np.abs(err))])


def test_wall_pass_point_is_clear_of_the_mesh():
    """The tool centre of the wall pass, 1.49994 from the slanted wall where it crosses
    the measured grid's line y = 32.699: no mesh point within the tool's radius (1.5)
    stands above the tip's height plus the accuracy."""
    poly = Polygon(STAR)
    surface = MeasuredGrid.from_csv(JOB / "bottom.csv")
    design = PocketDesign(poly, surface, 0.0)
    tri = design_triangles(design, Stock(0.0, 0.0, -18.7, 52.2, 71.5, 0.0), ACCURACY, 0.56)
    centre, tip = np.array([25.5072, 34.0505]), -12.6485
    assert abs(poly.exterior.distance(shapely.Point(*centre)) - 1.499938) < 1e-5
    v = tri.reshape(-1, 3)
    near = np.hypot(*(v[:, :2] - centre).T) < 1.5 - ACCURACY
    assert near.sum() > 10
    assert v[near, 2].max() <= tip + ACCURACY
