"""The finished die block as a height field: stock top outside the cavity, the cavity
floor inside (``-inf`` for a through cavity). Lengths in job units."""

from __future__ import annotations

import numpy as np
import shapely
from shapely.geometry import Polygon


class CavityDesign:
    """``height(x, y)``: ``top`` outside ``outline`` (a shapely Polygon of the true
    curve, densely sampled), ``floor`` inside it. ``deepest``: the lowest the tool goes
    (a through cavity's breakthrough), above which its walls are whole."""

    def __init__(self, outline: Polygon, top: float, floor: float,
                 deepest: float | None = None):
        self.outline = outline
        shapely.prepare(self.outline)
        self.top = float(top)
        self.floor = float(floor)
        self.deepest = None if deepest is None else float(deepest)

    def height(self, x: np.ndarray, y: np.ndarray) -> np.ndarray:
        x = np.asarray(x, float)
        y = np.asarray(y, float)
        inside = shapely.contains_xy(self.outline, x, y)
        return np.where(inside, self.floor, self.top)

    def mesh(self, box=None) -> np.ndarray:
        """Triangles (n, 3, 3), normals out of the material: the floor, the walls along
        the outline's edges (points on the true curve) and, given the stock ``box``
        (xmin, ymin, zmin, xmax, ymax, zmax), the top around the cavity. A through cavity
        (``-inf`` floor) has its walls run down to 1 unit below the box and below the
        deepest cut: a wall's lower edge within the tool's reach would be a rim the
        tool passes under, not the part."""
        from shapely.geometry import box as shp_box
        from shapely.geometry.polygon import orient
        poly = orient(self.outline, 1.0)
        floor = self.floor
        if not np.isfinite(floor):
            low = [z for z in (box[2] if box is not None else None, self.deepest)
                   if z is not None]
            floor = (min(low) - 1.0) if low else self.top - 1e3
        out = []

        def flat(geom, z):
            tris = shapely.constrained_delaunay_triangles(geom)
            for t in getattr(tris, "geoms", []):
                c = np.asarray(t.exterior.coords)[:3]
                ccw = ((c[1, 0] - c[0, 0]) * (c[2, 1] - c[0, 1])
                       - (c[1, 1] - c[0, 1]) * (c[2, 0] - c[0, 0])) > 0
                c = c if ccw else c[::-1]
                out.append([(c[0, 0], c[0, 1], z), (c[1, 0], c[1, 1], z), (c[2, 0], c[2, 1], z)])

        if np.isfinite(self.floor):
            flat(poly, floor)
        if box is not None:
            flat(shp_box(box[0], box[1], box[3], box[4]).difference(poly), self.top)
        ring = np.asarray(poly.exterior.coords)
        for a, b in zip(ring[:-1], ring[1:]):
            # inside (air) is left of a -> b: the wall faces it
            out.append([(b[0], b[1], floor), (a[0], a[1], floor), (a[0], a[1], self.top)])
            out.append([(b[0], b[1], floor), (a[0], a[1], self.top), (b[0], b[1], self.top)])
        return np.asarray(out, float).reshape(-1, 3, 3)
