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
from shapely.geometry import box as shp_box
from shapely.geometry.polygon import orient
from shapely.ops import unary_union

from millpath.plan.twod.prism import flat_triangles, polygons_of, wall_triangles


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
            out.append(flat_triangles(frame.difference(area), top))
            out.append(flat_triangles(frame.intersection(area), floor))
        else:
            out.append(flat_triangles(area, floor))
        for poly in polygons_of(area):
            p = orient(poly, 1.0)       # exterior ccw, islands cw: the air on the left
            for ring in [p.exterior, *p.interiors]:
                out.append(wall_triangles(np.asarray(ring.coords), floor, top, box))
        out = [t for t in out if len(t)]
        return np.concatenate(out) if out else np.zeros((0, 3, 3))
