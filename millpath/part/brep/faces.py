"""The faces of a solid as records: surface kind, outward normal, axis, radius, extent.

Face ids are 1-based, in the order OpenCASCADE maps the solid's faces (the order of the
file's ADVANCED_FACE list for a solid read from STEP). Lengths in mm (the shape's).
Normals point out of the material. A face of revolution (cylinder, cone, sphere, torus)
is ``concave`` when its outward normal points towards its axis (a hole's wall, a fillet
between a floor and a wall); ``uspan`` is its angle around the axis (radians).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np

@dataclass
class FaceInfo:
    id: int
    kind: str                              # plane | cylinder | cone | sphere | torus | free-form
    face: Any = field(repr=False)
    normal: np.ndarray | None = None       # plane: outward unit normal
    axis: np.ndarray | None = None         # revolution: unit axis direction
    centre: np.ndarray | None = None       # revolution: a point on the axis (sphere: centre)
    radius: float = 0.0                    # cylinder, sphere; torus: minor radius
    major: float = 0.0                     # torus: major radius
    half_angle: float = 0.0                # cone: semi-angle (radians)
    concave: bool = False
    uspan: float = 0.0
    box: tuple[float, float, float, float, float, float] = (0, 0, 0, 0, 0, 0)
    neighbours: set[int] = field(default_factory=set)
    area: float = 0.0

    @property
    def zmin(self) -> float:
        return self.box[2]

    @property
    def zmax(self) -> float:
        return self.box[5]

    def vertical_axis(self, tol: float = 1e-6) -> bool:
        return self.axis is not None and abs(abs(self.axis[2]) - 1.0) < tol

    def horizontal(self, tol: float = 1e-6) -> int:
        """+1 for a plane facing up, -1 facing down, 0 otherwise."""
        if self.kind != "plane" or self.normal is None:
            return 0
        if self.normal[2] > 1 - tol:
            return 1
        if self.normal[2] < -1 + tol:
            return -1
        return 0

    def vertical_wall(self, tol: float = 1e-6) -> bool:
        if self.kind == "plane":
            return abs(self.normal[2]) < tol
        return self.kind == "cylinder" and self.vertical_axis(tol)


def _vec(d) -> np.ndarray:
    return np.array([d.X(), d.Y(), d.Z()])


def as_face(shape):
    """``shape`` as a TopoDS_Face (OCP 7: ``TopoDS.Face_s``, OCP 8: ``TopoDS.Face``)."""
    from OCP.TopoDS import TopoDS
    return (getattr(TopoDS, "Face_s", None) or TopoDS.Face)(shape)


def as_edge(shape):
    """``shape`` as a TopoDS_Edge (OCP 7 and 8)."""
    from OCP.TopoDS import TopoDS
    return (getattr(TopoDS, "Edge_s", None) or TopoDS.Edge)(shape)


def shape_map():
    """An empty indexed map of shapes (OCP 7 and 8 name it differently)."""
    try:
        from OCP.TopTools import TopTools_IndexedMapOfShape
        return TopTools_IndexedMapOfShape()
    except ImportError:
        from OCP.collections import IndexedMap_TopoDS_Shape_TopTools_ShapeMapHasher as M
        return M()


def ancestor_map():
    """An empty indexed map of shapes to lists of shapes (OCP 7 and 8)."""
    try:
        from OCP.TopTools import TopTools_IndexedDataMapOfShapeListOfShape
        return TopTools_IndexedDataMapOfShapeListOfShape()
    except ImportError:
        from OCP.collections import (
            IndexedDataMap_TopoDS_Shape_List_TopoDS_Shape_TopTools_ShapeMapHasher as M)
        return M()


def face_table(solid) -> list[FaceInfo]:
    """Records of every face of ``solid``, with neighbours (faces sharing an edge)."""
    from OCP.BRepAdaptor import BRepAdaptor_Surface
    from OCP.BRepBndLib import BRepBndLib
    from OCP.BRepGProp import BRepGProp_Face
    from OCP.BRepTools import BRepTools
    from OCP.Bnd import Bnd_Box
    from OCP.GeomAbs import (GeomAbs_Cone, GeomAbs_Cylinder, GeomAbs_Plane, GeomAbs_Sphere,
                             GeomAbs_Torus)
    from OCP.gp import gp_Pnt, gp_Vec
    from OCP.TopAbs import TopAbs_EDGE, TopAbs_FACE
    from OCP.TopExp import TopExp, TopExp_Explorer
    fmap = shape_map()
    TopExp.MapShapes_s(solid, TopAbs_FACE, fmap)
    kinds = {GeomAbs_Plane: "plane", GeomAbs_Cylinder: "cylinder", GeomAbs_Cone: "cone",
             GeomAbs_Sphere: "sphere", GeomAbs_Torus: "torus"}
    out: list[FaceInfo] = []
    for i in range(1, fmap.Extent() + 1):
        f = as_face(fmap.FindKey(i))
        a = BRepAdaptor_Surface(f, True)
        kind = kinds.get(a.GetType(), "free-form")
        info = FaceInfo(i, kind, f)
        b = Bnd_Box()
        if kind == "free-form":           # poles' box is loose: the optimal one
            BRepBndLib.AddOptimal_s(f, b, False, False)
        else:
            BRepBndLib.Add_s(f, b, False)
        b.SetGap(0.0)
        lo, hi = b.CornerMin(), b.CornerMax()
        info.box = (lo.X(), lo.Y(), lo.Z(), hi.X(), hi.Y(), hi.Z())
        u0, u1, v0, v1 = BRepTools.UVBounds_s(f)
        info.uspan = u1 - u0
        um, vm = (u0 + u1) / 2.0, (v0 + v1) / 2.0
        p, n = gp_Pnt(), gp_Vec()
        BRepGProp_Face(f).Normal(um, vm, p, n)
        nn = _vec(n)
        ln = float(np.linalg.norm(nn))
        nn = nn / ln if ln > 0 else nn
        pt = _vec(p)
        if kind == "plane":
            info.normal = nn
        elif kind in ("cylinder", "cone", "sphere", "torus"):
            g = {"cylinder": a.Cylinder, "cone": a.Cone, "sphere": a.Sphere,
                 "torus": a.Torus}[kind]()
            info.axis = _vec(g.Position().Direction())
            info.centre = _vec(g.Location())
            if kind in ("cylinder", "sphere"):
                info.radius = g.Radius()
            elif kind == "torus":
                info.radius, info.major = g.MinorRadius(), g.MajorRadius()
            else:
                info.radius = g.RefRadius()
                info.half_angle = abs(g.SemiAngle())
            if kind == "sphere":
                info.concave = float(nn @ (info.centre - pt)) > 0
            elif kind == "torus":
                # the tube's centre circle point nearest pt; concave if the normal points at it
                w = pt - info.centre
                w = w - info.axis * float(w @ info.axis)
                lw = np.linalg.norm(w)
                c = info.centre + (w / lw * info.major if lw > 0 else 0.0)
                info.concave = float(nn @ (c - pt)) > 0
            else:
                w = pt - info.centre
                radial = w - info.axis * float(w @ info.axis)
                info.concave = float(nn @ radial) < 0
        out.append(info)
    emap = shape_map()
    TopExp.MapShapes_s(solid, TopAbs_EDGE, emap)
    owners: dict[int, list[int]] = {}
    for info in out:
        ex = TopExp_Explorer(info.face, TopAbs_EDGE)
        while ex.More():
            owners.setdefault(emap.FindIndex(ex.Current()), []).append(info.id)
            ex.Next()
    for ids in owners.values():
        for x in ids:
            for y in ids:
                if x != y:
                    out[x - 1].neighbours.add(y)
    return out


def angle_step(radius: float, sagitta: float) -> float:
    """Largest angle (radians) of a chord within ``sagitta`` of a circle, at most 10 deg."""
    if radius <= sagitta:
        return math.radians(10.0)
    return min(math.radians(10.0), 2.0 * math.acos(1.0 - sagitta / radius))
