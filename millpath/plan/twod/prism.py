"""Triangles of 2.5D designs: flat faces of polygons and vertical walls on their rings,
for the grid-free proof (:func:`millpath.simulate.exact.design_triangles`).

Arrays are (n, 3, 3) triangles in job units; flat faces are counter-clockwise seen from
above; a wall on the edge a -> b faces the side left of it (its normal points there).
"""

from __future__ import annotations

import numpy as np
import shapely
from shapely.geometry import Polygon


def polygons_of(geom) -> list[Polygon]:
    """The non-empty polygons of a (multi)polygon or collection."""
    if geom is None or geom.is_empty:
        return []
    if isinstance(geom, Polygon):
        return [geom]
    return [g for g in getattr(geom, "geoms", []) if isinstance(g, Polygon) and not g.is_empty]


def flat_triangles(geom, z: float) -> np.ndarray:
    """Triangles (n, 3, 3) of the polygons of ``geom`` at height ``z``, counter-clockwise
    seen from above (constrained Delaunay: their vertices are the polygons' own)."""
    tris = []
    for poly in polygons_of(geom):
        for t in shapely.constrained_delaunay_triangles(poly).geoms:
            tris.append(np.asarray(t.exterior.coords)[:3, :2])
    if not tris:
        return np.zeros((0, 3, 3))
    c = np.asarray(tris)
    ccw = ((c[:, 1, 0] - c[:, 0, 0]) * (c[:, 2, 1] - c[:, 0, 1])
           - (c[:, 1, 1] - c[:, 0, 1]) * (c[:, 2, 0] - c[:, 0, 0])) > 0
    c[~ccw] = c[~ccw][:, ::-1]
    return np.concatenate([c, np.full(c.shape[:2] + (1,), z)], axis=2)


def wall_triangles(ring: np.ndarray, z0: float, z1: float, box=None) -> np.ndarray:
    """Two triangles per edge of the closed polyline ``ring`` ((n, 2), first point
    repeated or not) from ``z0`` up to ``z1``, facing left of the direction of travel;
    with ``box`` (xmin, ymin, zmin, xmax, ymax, zmax) the edges clipped to its XY."""
    c = np.asarray(ring, float)[:, :2]
    if len(c) and np.any(c[0] != c[-1]):
        c = np.vstack([c, c[:1]])
    a, b = c[:-1], c[1:]
    if box is not None:
        a, b = clip_segments(a, b, box[0], box[1], box[3], box[4])
    if not len(a) or z1 <= z0:
        return np.zeros((0, 3, 3))
    af = np.column_stack([a, np.full(len(a), z0)])
    bf = np.column_stack([b, np.full(len(b), z0)])
    at = np.column_stack([a, np.full(len(a), z1)])
    bt = np.column_stack([b, np.full(len(b), z1)])
    return np.concatenate([np.stack([bf, af, at], axis=1), np.stack([bf, at, bt], axis=1)])


def clip_segments(a: np.ndarray, b: np.ndarray, x0: float, y0: float, x1: float, y1: float):
    """Segments ``a -> b`` (n, 2) clipped to the rectangle (Liang-Barsky), direction
    kept; segments outside it (or reduced to a point) dropped."""
    d = b - a
    t0 = np.zeros(len(a))
    t1 = np.ones(len(a))
    keep = np.ones(len(a), bool)
    for p, q in ((-d[:, 0], a[:, 0] - x0), (d[:, 0], x1 - a[:, 0]),
                 (-d[:, 1], a[:, 1] - y0), (d[:, 1], y1 - a[:, 1])):
        par = p == 0
        keep &= ~(par & (q < 0))
        with np.errstate(divide="ignore", invalid="ignore"):
            r = np.where(par, 0.0, q / np.where(par, 1.0, p))
        t0 = np.where(~par & (p < 0), np.maximum(t0, r), t0)
        t1 = np.where(~par & (p > 0), np.minimum(t1, r), t1)
    keep &= t1 > t0
    a2 = a + t0[:, None] * d
    b2 = a + t1[:, None] * d
    return a2[keep], b2[keep]
