"""The part a profile operation makes: the drawing extruded (for the simulator a height
field, for the grid-free proof its triangles).

The part's material (XY, :func:`millpath.plan.twod.contours.material`) stands from
the stock bottom to the stock ``top``. On every contour the operation cuts, a vertical
wall faces the air from ``floor`` (the operation's bottom, at least the stock bottom)
up to the top, and beside it the slot the tool cuts: a floor ``band`` wide (the tool's
flat bottom's reach less the tolerance) at the bottom; a cut below the stock has no
floor (its walls end at the stock bottom). Elsewhere the waste is not designed: the mesh is open there and nothing is
measured against it (leads and entries run in it). The contours are those of
:func:`millpath.plan.twod.geometry.load_regions`: within 1/20 of the tolerance of a
drawing's curves, on their air side, so a gouge measured against this design is the
true one or more. Job units.
"""

from __future__ import annotations

import numpy as np
import shapely
from shapely.geometry import box as shp_box
from shapely.ops import unary_union

from millpath.plan.twod.prism import flat_triangles, wall_triangles


class ProfileDesign:
    """``material``: the part's material seen from above; ``walls``: each cut contour as
    a closed ring (n, 2) travelled with the air on its left; ``band``: the slots' floor
    area (XY); ``floor``, ``top`` (Z); ``through``: the cut goes through the stock
    (``-inf`` in the height field); ``with_floor``: the slots' floor is part of the mesh
    (not when the cut goes below the stock: the band is then open to below)."""

    def __init__(self, material, walls: list[np.ndarray], band, floor: float, top: float,
                 through: bool, with_floor: bool = True):
        self.material = material
        self.walls = walls
        self.band = band
        shapely.prepare(self.material)
        shapely.prepare(self.band)
        self.floor = float(floor)
        self.top = float(top)
        self.through = bool(through)
        self.with_floor = bool(with_floor)

    def height(self, x, y):
        """The top of the part at (x, y): the floor (``-inf`` through the stock) in the
        slots beside the walls, the stock top elsewhere (waste is left standing)."""
        x = np.asarray(x, float)
        y = np.asarray(y, float)
        cut = shapely.contains_xy(self.band, x, y)
        return np.where(cut, -np.inf if self.through else self.floor, self.top)

    def waste(self, x, y):
        """Where nothing is designed (bool): neither the part's material nor a slot
        beside a wall. Leads and entries may cut there; the Z-map comparison and its
        pictures leave those cells out, as the mesh leaves them open."""
        x = np.asarray(x, float)
        y = np.asarray(y, float)
        return ~(shapely.contains_xy(self.material, x, y)
                 | shapely.contains_xy(self.band, x, y))

    def mesh(self, box=None) -> np.ndarray:
        """Triangles (n, 3, 3), normals out of the material: the top over the material,
        the walls from the floor (the stock bottom of ``box`` through it) to the top,
        and the slots' floor (see ``with_floor``); clipped to the stock ``box`` (xmin, ymin,
        zmin, xmax, ymax, zmax) when given. About 4 triangles per wall edge."""
        mat = self.material
        band = self.band
        z0 = self.floor
        if box is not None:
            frame = shp_box(box[0], box[1], box[3], box[4])
            mat = mat.intersection(frame)
            band = band.intersection(frame)
            z0 = max(z0, box[2])
        out = [flat_triangles(mat, self.top)]
        if self.with_floor:
            out.append(flat_triangles(band, self.floor))
        for ring in self.walls:
            out.append(wall_triangles(ring, z0, self.top, box))
        out = [t for t in out if len(t)]
        return np.concatenate(out) if out else np.zeros((0, 3, 3))


def slot_band(contours, width: float, quad_segs: int = 16):
    """The floor beside each contour in ``contours`` (each with ``polygon`` and
    ``tool_outside``), ``width`` wide on its tool side."""
    parts = []
    for c in contours:
        if c.tool_outside:
            parts.append(c.polygon.buffer(width, quad_segs=quad_segs).difference(c.polygon))
        else:
            parts.append(c.polygon.difference(c.polygon.buffer(-width, quad_segs=quad_segs)))
    return unary_union(parts)
