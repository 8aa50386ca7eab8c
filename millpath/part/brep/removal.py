"""The volume a recognised feature removes, as an OpenCASCADE solid, checked against
the part's solid before the feature is planned.

A feature recognised from a solid says "everything in this volume is air once the
feature is machined". :func:`removal_solid` builds that volume from the feature's
shape, as the planner will cut it from the stock top (mm, the solid's frame, turned to
its setup):

- a round hole: its cylinder from the stock top down to where its bottom begins, and
  its countersink cone; a through hole to below the part;
- a general pocket (floor, slot, step, through opening, outer profile): the floor's
  region less the material kept above the floor, from the floor up to the stock top
  (a through opening or the outer profile from below the part); within a floor fillet's
  radius of the floor the region is eroded by that radius (the fillet stays).

Every volume is made ``INSET`` smaller than the feature (sides, floor), so a feature
whose walls and floor are the part's faces touches nothing. :func:`overlap` intersects
it with the solid: any material left in it is material the planner would cut into.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import shapely

from millpath.part.step.shapes import HoleShape, PocketShape

#: mm the removal volume is kept inside the feature's faces (the regions' chords stand
#: 0.002 mm off the faces; a gouge shallower than this is not seen)
INSET = 0.01
#: mm3: overlaps smaller than this are the Booleans' slivers, not material
MIN_VOLUME = 1e-4


@dataclass
class Overlap:
    """The part's material inside a feature's removal volume: ``volume`` (mm3) and the
    bounding box of that material (xmin, ymin, zmin, xmax, ymax, zmax, mm)."""

    volume: float
    box: tuple[float, float, float, float, float, float]

    def describe(self, k: float = 1.0, unit: str = "mm") -> str:
        """'the part's material fills 1.2e+03 mm3 of it, z 0 to 12 at (x, y)' in file
        units (``k`` file units per mm)."""
        b = [v * k for v in self.box]
        vol = self.volume * k ** 3
        return (f"the part's material fills {vol:.4g} {unit}3 of the volume it removes "
                f"({b[5] - b[2]:.4g} {unit} high, z {b[2]:.4g} to {b[5]:.4g}, around x "
                f"{(b[0] + b[3]) / 2:.4g} y {(b[1] + b[4]) / 2:.4g})")


def _prism(poly, z0: float, z1: float):
    """A shapely polygon (islands as holes) extruded from ``z0`` to ``z1`` (mm)."""
    from OCP.BRepBuilderAPI import BRepBuilderAPI_MakeFace, BRepBuilderAPI_MakePolygon
    from OCP.BRepPrimAPI import BRepPrimAPI_MakePrism
    from OCP.gp import gp_Pnt, gp_Vec

    def wire(ring):
        mp = BRepBuilderAPI_MakePolygon()
        for x, y in list(ring.coords)[:-1]:
            mp.Add(gp_Pnt(float(x), float(y), z0))
        mp.Close()
        return mp.Wire()

    poly = shapely.geometry.polygon.orient(poly, 1.0)
    mf = BRepBuilderAPI_MakeFace(wire(poly.exterior), True)
    for ring in poly.interiors:
        mf.Add(wire(ring))
    return BRepPrimAPI_MakePrism(mf.Face(), gp_Vec(0.0, 0.0, z1 - z0)).Shape()


def _compound(shapes: list):
    from OCP.BRep import BRep_Builder
    from OCP.TopoDS import TopoDS_Compound
    c = TopoDS_Compound()
    b = BRep_Builder()
    b.MakeCompound(c)
    for s in shapes:
        b.Add(c, s)
    return c


def _polygons(g) -> list:
    g = g.buffer(0)
    return [p for p in getattr(g, "geoms", [g]) if p.geom_type == "Polygon"
            and p.area > 1e-6]


def removal_solid(shape, k: float, z_stock: float, z_part_min: float):
    """The volume ``shape`` (file units, ``k`` file units per mm) removes, in mm, made
    :data:`INSET` smaller; None when it is empty. ``z_stock``: the stock top (mm);
    ``z_part_min``: the part's lowest point (mm)."""
    from OCP.BRepPrimAPI import BRepPrimAPI_MakeCone, BRepPrimAPI_MakeCylinder
    from OCP.gp import gp_Ax2, gp_Dir, gp_Pnt

    top = z_stock + 1.0
    below = z_part_min - 1.0
    pieces = []
    if isinstance(shape, HoleShape):
        x, y, zt = shape.x / k, shape.y / k, shape.z_top / k
        r = shape.diameter / 2.0 / k - INSET
        zb = shape.z_bottom / k
        if r <= 0:
            return None
        if shape.bottom == "through":
            z0 = below
        elif shape.bottom == "conical":
            z0 = zb + (r + INSET) / math.tan(math.radians(shape.tip_angle / 2.0))
        elif shape.bottom in ("spherical", "flat with radius"):
            z0 = zb + shape.bottom_radius / k + INSET
        else:
            z0 = zb + INSET
        if shape.kind == "countersink":
            # the cone from its apex to its rim at the top (offset INSET inwards: the
            # apex rises by INSET / sin(half angle)), then the stock above
            half = math.radians(shape.tip_angle / 2.0)
            apex = zb + INSET / math.sin(half)
            if zt > apex:
                pieces.append(BRepPrimAPI_MakeCone(gp_Ax2(gp_Pnt(x, y, apex), gp_Dir(0, 0, 1)),
                                                   0.0, (zt - apex) * math.tan(half),
                                                   zt - apex).Shape())
            z0 = zt
            r = (zt - apex) * math.tan(half)
        if top - z0 > 1e-6:
            pieces.append(BRepPrimAPI_MakeCylinder(gp_Ax2(gp_Pnt(x, y, z0), gp_Dir(0, 0, 1)),
                                                   r, top - z0).Shape())
    elif isinstance(shape, PocketShape) and shape.profile == "general":
        from shapely import affinity
        s = 1.0 / k
        region = affinity.scale(shape.region, s, s, origin=(0, 0)) if k != 1.0 \
            else shape.region
        keep = shape.keep
        if keep is not None and k != 1.0:
            keep = affinity.scale(keep, s, s, origin=(0, 0))
        free = region.difference(keep) if keep is not None and not keep.is_empty else region
        zf = (shape.z_top - shape.depth) / k
        z0 = below if shape.bottom == "through" else zf + INSET
        fr = shape.floor_radius / k
        upper = zf + fr + INSET if fr > 0 and shape.bottom != "through" else z0
        for p in _polygons(free.buffer(-INSET, join_style="mitre")):
            pieces.append(_prism(p, upper, top))
        if upper > z0:
            for p in _polygons(free.buffer(-(fr + INSET), join_style="mitre")):
                pieces.append(_prism(p, z0, upper))
    if not pieces:
        return None
    return pieces[0] if len(pieces) == 1 else _compound(pieces)


def bounds(shape) -> tuple[float, float, float, float, float, float]:
    """Tight axis-aligned bounds of an OpenCASCADE shape (mm)."""
    from OCP.Bnd import Bnd_Box
    from OCP.BRepBndLib import BRepBndLib
    b = Bnd_Box()
    BRepBndLib.AddOptimal_s(shape, b, False, False)
    b.SetGap(0.0)
    lo, hi = b.CornerMin(), b.CornerMax()
    return (lo.X(), lo.Y(), lo.Z(), hi.X(), hi.Y(), hi.Z())


def volume(shape) -> float:
    """Volume of an OpenCASCADE shape (mm3)."""
    from OCP.BRepGProp import BRepGProp
    from OCP.GProp import GProp_GProps
    g = GProp_GProps()
    BRepGProp.VolumeProperties_s(shape, g)
    return abs(g.Mass())


def overlap(solid, removal) -> Overlap | None:
    """The part's material inside ``removal`` (None when there is none)."""
    from OCP.BRepAlgoAPI import BRepAlgoAPI_Common
    if removal is None:
        return None
    a, b = bounds(solid), bounds(removal)
    if any(a[i] > b[i + 3] or b[i] > a[i + 3] for i in range(3)):
        return None
    op = BRepAlgoAPI_Common(solid, removal)
    op.Build()
    if not op.IsDone():
        return None
    common = op.Shape()
    v = volume(common)
    if v < MIN_VOLUME:
        return None
    return Overlap(v, bounds(common))
