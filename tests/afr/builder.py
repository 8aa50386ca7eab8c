"""Solids made with OpenCASCADE's modelling operators (BRepPrimAPI, BRepAlgoAPI,
BRepFilletAPI) and written as STEP AP214 or AP242: the fixtures of the recognition
tests. Lengths in mm, the part's bottom at z = 0, machined from +Z."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np


def box(x0, y0, z0, x1, y1, z1):
    from OCP.BRepPrimAPI import BRepPrimAPI_MakeBox
    from OCP.gp import gp_Pnt
    return BRepPrimAPI_MakeBox(gp_Pnt(x0, y0, z0), gp_Pnt(x1, y1, z1)).Shape()


def cylinder(x, y, z0, r, h):
    from OCP.BRepPrimAPI import BRepPrimAPI_MakeCylinder
    from OCP.gp import gp_Ax2, gp_Dir, gp_Pnt
    return BRepPrimAPI_MakeCylinder(gp_Ax2(gp_Pnt(x, y, z0), gp_Dir(0, 0, 1)), r, h).Shape()


def cone(x, y, z0, r0, r1, h):
    """Frustum from radius ``r0`` at ``z0`` to ``r1`` at ``z0 + h``."""
    from OCP.BRepPrimAPI import BRepPrimAPI_MakeCone
    from OCP.gp import gp_Ax2, gp_Dir, gp_Pnt
    return BRepPrimAPI_MakeCone(gp_Ax2(gp_Pnt(x, y, z0), gp_Dir(0, 0, 1)), r0, r1, h).Shape()


def sphere(x, y, z, r):
    from OCP.BRepPrimAPI import BRepPrimAPI_MakeSphere
    from OCP.gp import gp_Pnt
    return BRepPrimAPI_MakeSphere(gp_Pnt(x, y, z), r).Shape()


def cut(a, *tools):
    from OCP.BRepAlgoAPI import BRepAlgoAPI_Cut
    for t in tools:
        a = BRepAlgoAPI_Cut(a, t).Shape()
    return a


def fuse(a, *others):
    from OCP.BRepAlgoAPI import BRepAlgoAPI_Fuse
    for t in others:
        a = BRepAlgoAPI_Fuse(a, t).Shape()
    return a


def rounded_rect(x0, y0, x1, y1, z0, h, r):
    """A box with vertical edges rounded to ``r`` (a pocket with corner radius r)."""
    if r <= 0:
        return box(x0, y0, z0, x1, y1, z0 + h)
    core = fuse(box(x0 + r, y0, z0, x1 - r, y1, z0 + h), box(x0, y0 + r, z0, x1, y1 - r, z0 + h))
    for cx, cy in ((x0 + r, y0 + r), (x1 - r, y0 + r), (x0 + r, y1 - r), (x1 - r, y1 - r)):
        core = fuse(core, cylinder(cx, cy, z0, r, h))
    return core


def obround(xa, y, xb, z0, h, w):
    """A slot body from (xa, y) to (xb, y), width w, half-circle ends."""
    r = w / 2.0
    return fuse(box(xa, y - r, z0, xb, y + r, z0 + h), cylinder(xa, y, z0, r, h),
                cylinder(xb, y, z0, r, h))


def unify(shape):
    """Merge coplanar / cocylindrical faces the Booleans split (as a CAD system would)."""
    from OCP.ShapeUpgrade import ShapeUpgrade_UnifySameDomain
    u = ShapeUpgrade_UnifySameDomain(shape, True, True, True)
    u.Build()
    return u.Shape()


def write_step(shape, path: Path, schema: str = "AP214") -> Path:
    """Write ``shape`` as STEP (``schema``: 'AP214' or 'AP242' or 'AP203')."""
    from OCP.Interface import Interface_Static
    from OCP.STEPControl import STEPControl_AsIs, STEPControl_Writer
    names = {"AP214": "AP214IS", "AP242": "AP242DIS", "AP203": "AP203"}
    Interface_Static.SetCVal_s("write.step.schema", names[schema])
    w = STEPControl_Writer()
    w.Transfer(shape, STEPControl_AsIs)
    assert w.Write(str(path)) == 1
    return path


# --- the parts ---------------------------------------------------------------------------
T = 30.0        # plate thickness


def holes_plate():
    """120 x 80 x 30 plate: through, flat, drilled (118 deg), spherical holes, a
    counterbore (16/8.5) and a countersink (90 deg, 12 top / 6 hole)."""
    p = box(0, 0, 0, 120, 80, T)
    cot = 1.0 / math.tan(math.radians(59.0))
    p = cut(p,
            cylinder(15, 15, -1, 4.0, T + 2),                                  # through 8
            cylinder(40, 15, T - 12, 5.0, 13),                                 # flat 10 x 12
            cylinder(65, 15, T - 15, 3.0, 16), cone(65, 15, T - 15 - 3 * cot, 0, 3.0, 3 * cot),
            cylinder(90, 15, T - 10, 5.0, 11), sphere(90, 15, T - 10, 5.0),    # spherical
            cylinder(20, 55, T - 6, 8.0, 7), cylinder(20, 55, -1, 4.25, T + 2),  # counterbore
            cone(60, 55, T - 3, 3.0, 6.0, 3.0), cylinder(60, 55, -1, 3.0, T + 2))  # c-sink
    return unify(p)


def pockets_plate():
    """150 x 100 x 30: a closed pocket (60 x 40, corner r 6, 10 deep) with a round island
    (d 12) and a counterbored hole in its floor; a nested pocket; a straight obround slot
    (w 10) breaking into a second pocket; an open step along one side."""
    p = box(0, 0, 0, 150, 100, T)
    # pocket A with an island and a counterbored hole in its floor
    a = cut(rounded_rect(10, 10, 70, 50, T - 10, 11, 6.0), cylinder(25, 30, T - 10, 6.0, 11))
    p = cut(p, a, cylinder(55, 30, T - 14, 6.0, 5), cylinder(55, 30, -1, 3.0, T))
    # pocket B (40 x 30, r 5, 8 deep) with a nested pocket (20 x 14, r 5, 5 deeper)
    p = cut(p, rounded_rect(90, 10, 130, 40, T - 8, 9, 5.0),
            rounded_rect(100, 18, 120, 32, T - 13, 6, 5.0))
    # slot from x 95 to 125 at y 62 (w 10, 6 deep) breaking into pocket C (12 deep)
    p = cut(p, obround(95, 62, 125, T - 6, 7, 10.0),
            rounded_rect(120, 52, 145, 72, T - 12, 13, 5.0))
    # open step along y = 100: 12 wide, 5 deep
    p = cut(p, box(-1, 88, T - 5, 151, 101, T + 1))
    return unify(p)


def narrow_slot():
    """60 x 40 x 20 block with a 3 mm wide straight slot (too narrow for a 6 mm tool)
    and a 20 x 20 pocket."""
    p = box(0, 0, 0, 60, 40, 20)
    return unify(cut(p, box(10, 5, 15, 50, 8, 21), rounded_rect(20, 15, 40, 35, 12, 9, 4.0)))


def fillet_pocket():
    """80 x 60 x 25 block with a 50 x 30 pocket (corner r 6, 8 deep) whose floor meets
    its walls in a 1.5 mm fillet, and a free-form (B-spline) dimple 2 mm deep in the top
    at (70, 52), which is reported, not machined."""
    from OCP.BRepFilletAPI import BRepFilletAPI_MakeFillet
    from OCP.TopAbs import TopAbs_EDGE, TopAbs_FACE
    from OCP.TopExp import TopExp_Explorer
    from millpath.part.brep.faces import as_edge, as_face
    p = cut(box(0, 0, 0, 80, 60, 25), rounded_rect(15, 15, 65, 45, 17, 9, 6.0))
    p = unify(p)
    mk = BRepFilletAPI_MakeFillet(p)
    ex = TopExp_Explorer(p, TopAbs_FACE)
    while ex.More():
        f = as_face(ex.Current())
        ex.Next()
        from OCP.BRepAdaptor import BRepAdaptor_Surface
        from OCP.GeomAbs import GeomAbs_Plane
        a = BRepAdaptor_Surface(f)
        if a.GetType() == GeomAbs_Plane and abs(a.Plane().Axis().Direction().Z()) > 0.5 \
                and abs(a.Plane().Location().Z() - 17.0) < 1e-9:
            e = TopExp_Explorer(f, TopAbs_EDGE)
            while e.More():
                mk.Add(1.5, as_edge(e.Current()))
                e.Next()
    mk.Build()
    from OCP.BRepBuilderAPI import BRepBuilderAPI_NurbsConvert
    dimple = BRepBuilderAPI_NurbsConvert(sphere(70.0, 52.0, 27.0, 4.0), True).Shape()
    return cut(mk.Shape(), dimple)


def many_holes(n_side: int):
    """A plate with ``n_side`` x ``n_side`` counterbored holes and pockets (benchmarks)."""
    pitch = 12.0
    w = n_side * pitch + 10
    p = box(0, 0, 0, w, w, 20)
    tools = []
    for i in range(n_side):
        for j in range(n_side):
            x, y = 5 + pitch * (i + 0.5), 5 + pitch * (j + 0.5)
            if (i + j) % 3 == 2:
                tools.append(rounded_rect(x - 4, y - 4, x + 4, y + 4, 15, 6, 2.0))
            else:
                tools += [cylinder(x, y, 16, 4.0, 5), cylinder(x, y, -1, 2.0, 22)]
    from OCP.BRepAlgoAPI import BRepAlgoAPI_Cut
    try:
        from OCP.TopTools import TopTools_ListOfShape
    except ImportError:                       # OCP 8
        from OCP.collections import List_TopoDS_Shape as TopTools_ListOfShape
    args, tl = TopTools_ListOfShape(), TopTools_ListOfShape()
    args.Append(p)
    for t in tools:
        tl.Append(t)
    c = BRepAlgoAPI_Cut()
    c.SetArguments(args)
    c.SetTools(tl)
    c.Build()
    return c.Shape()


def top_heights(shape, xs: np.ndarray, ys: np.ndarray, zmax: float) -> np.ndarray:
    """Exact Z of the solid's top surface above each (x, y) by casting rays down onto the
    B-rep (OpenCASCADE's curve-face intersector); -inf where the ray misses."""
    from OCP.gp import gp_Dir, gp_Lin, gp_Pnt
    from OCP.IntCurvesFace import IntCurvesFace_ShapeIntersector
    it = IntCurvesFace_ShapeIntersector()
    it.Load(shape, 1e-7)
    out = np.full(len(xs), -np.inf)
    for i, (x, y) in enumerate(zip(xs, ys)):
        it.Perform(gp_Lin(gp_Pnt(float(x), float(y), zmax + 10.0), gp_Dir(0, 0, -1)),
                   -1e9, 1e9)
        if it.IsDone() and it.NbPnt():
            out[i] = max(it.Pnt(k).Z() for k in range(1, it.NbPnt() + 1))
    return out


def raised_plate():
    """100 x 60 plate, z 10 to 30, on two 10 mm legs along its short ends, with a 10 mm
    through hole at (50, 30) over the air between the legs: the hole's cylinder ends
    above the part's lowest point with nothing under it."""
    p = fuse(box(0, 0, 10, 100, 60, T), box(0, 0, 0, 10, 60, 10), box(90, 0, 0, 100, 60, 10))
    return unify(cut(p, cylinder(50, 30, 5, 5.0, T)))


def window_over_bar():
    """80 x 60 frame, z 20 to 40, with a 40 x 30 window through it (x 20-60, y 15-45)
    and a round bar (r 8, axis along X at y 30, z 10) under it, held by two blocks
    (x 0-10 and 70-80, y 22-38, z 2-20): no face of the bar looks up, so no floor
    level crosses it. Through the window the bar's material lies between y 22 and
    38, z 2 to 18."""
    from OCP.BRepPrimAPI import BRepPrimAPI_MakeCylinder
    from OCP.gp import gp_Ax2, gp_Dir, gp_Pnt
    frame = cut(box(0, 0, 20, 80, 60, 40), box(20, 15, 19, 60, 45, 41))
    bar = BRepPrimAPI_MakeCylinder(gp_Ax2(gp_Pnt(0, 30, 10), gp_Dir(1, 0, 0)), 8.0,
                                   80.0).Shape()
    return unify(fuse(frame, bar, box(0, 22, 2, 10, 38, 20), box(70, 22, 2, 80, 38, 20)))
