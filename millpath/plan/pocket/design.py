"""The designed part of a pocket operation: a height field (for the simulator) and its
exact triangle mesh (for the grid-free proof).

The pocket's regions are those of :func:`millpath.plan.twod.geometry.load_regions`: from
a drawing, every wall within ``CURVE_FRACTION x tolerance`` (1/20 of the operation's
tolerance) of the drawn curve and never inside the drawn material, so a gouge measured
against this design is the true one or more (by at most that bound). The mesh's walls
are the regions' own edges, not a resampling of them. Job units.
"""

from __future__ import annotations

import numpy as np
import shapely
from shapely.geometry import Polygon, box as shp_box
from shapely.geometry.polygon import orient
from shapely.ops import unary_union


class PocketDesign:
    """``floor`` inside the pocket polygons (islands excluded), ``top`` elsewhere (job
    units)."""

    def __init__(self, polygons, floor: float, top: float):
        self.area = unary_union(polygons)
        shapely.prepare(self.area)
        self.floor = float(floor)
        self.top = float(top)

    def height(self, x, y):
        x = np.asarray(x, float)
        y = np.asarray(y, float)
        inside = shapely.contains_xy(self.area, x, y)
        return np.where(inside, self.floor, self.top)

    def mesh(self, box=None) -> np.ndarray:
        """Triangles (n, 3, 3), normals out of the material: the floor over the pocket,
        a vertical wall (two triangles) on every edge of its outlines and islands from
        the floor to the top, and, given the stock ``box`` (xmin, ymin, zmin, xmax, ymax,
        zmax), the top over the rest of the box; floor and walls clipped to the box.
        The walls are exactly the regions' edges (see the module docstring for how far
        they are from a drawing's curves); the size is linear in the number of edges
        (about 4 triangles per edge)."""
        area = self.area
        top, floor = self.top, self.floor
        out: list[np.ndarray] = []
        if box is not None:
            frame = shp_box(box[0], box[1], box[3], box[4])
            out.append(_flat(frame.difference(area), top))
            out.append(_flat(frame.intersection(area), floor))
        else:
            out.append(_flat(area, floor))
        for poly in _polygons(area):
            p = orient(poly, 1.0)       # exterior ccw, islands cw: the air on the left
            for ring in [p.exterior, *p.interiors]:
                c = np.asarray(ring.coords)[:, :2]
                a, b = c[:-1], c[1:]
                if box is not None:
                    a, b = _clip(a, b, box[0], box[1], box[3], box[4])
                if not len(a):
                    continue
                af = np.column_stack([a, np.full(len(a), floor)])
                bf = np.column_stack([b, np.full(len(b), floor)])
                at = np.column_stack([a, np.full(len(a), top)])
                bt = np.column_stack([b, np.full(len(b), top)])
                # the air is left of a -> b: the wall's normal points to it
                out.append(np.stack([bf, af, at], axis=1))
                out.append(np.stack([bf, at, bt], axis=1))
        out = [t for t in out if len(t)]
        return np.concatenate(out) if out else np.zeros((0, 3, 3))


def _polygons(geom) -> list[Polygon]:
    if geom.is_empty:
        return []
    if isinstance(geom, Polygon):
        return [geom]
    return [g for g in getattr(geom, "geoms", []) if isinstance(g, Polygon) and not g.is_empty]


def _flat(geom, z: float) -> np.ndarray:
    """Triangles (n, 3, 3) of the polygons of ``geom`` at height ``z``, counter-clockwise
    seen from above (constrained Delaunay: their vertices are the polygons' own)."""
    tris = []
    for poly in _polygons(geom):
        for t in shapely.constrained_delaunay_triangles(poly).geoms:
            c = np.asarray(t.exterior.coords)[:3, :2]
            tris.append(c)
    if not tris:
        return np.zeros((0, 3, 3))
    c = np.asarray(tris)
    ccw = ((c[:, 1, 0] - c[:, 0, 0]) * (c[:, 2, 1] - c[:, 0, 1])
           - (c[:, 1, 1] - c[:, 0, 1]) * (c[:, 2, 0] - c[:, 0, 0])) > 0
    c[~ccw] = c[~ccw][:, ::-1]
    return np.concatenate([c, np.full(c.shape[:2] + (1,), z)], axis=2)


def _clip(a: np.ndarray, b: np.ndarray, x0: float, y0: float, x1: float, y1: float):
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
