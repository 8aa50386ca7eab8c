"""An independent gouge oracle: OpenCASCADE solids, no millpath geometry.

The design is a block with boxes taken out of it (:class:`BoxCut`); a flat end mill
(radius ``r``, cutting ``h`` up from its tip) swept along a straight move is the exact
solid of its sweep (a vertical move: one cylinder; a level move: a stadium extruded by
``h``). How deep the tool went into the design is the depth of its deepest point below
the design's surface: the largest ``d`` for which the sweep still meets the design
eroded by ``d`` (the block shrunk by ``d``, less each removed box grown by ``d`` with
its edges and corners rounded to ``d``: the exact erosion). Found by halving ``d`` with
``BRepExtrema_DistShapeShape`` (distance 0, or one solid inside the other, means they
meet) to ``tol``.
"""

from __future__ import annotations

import math

from OCP.BRepAlgoAPI import BRepAlgoAPI_Cut, BRepAlgoAPI_Fuse
from OCP.BRepBuilderAPI import (BRepBuilderAPI_MakeEdge, BRepBuilderAPI_MakeFace,
                                BRepBuilderAPI_MakeWire)
from OCP.BRepExtrema import BRepExtrema_DistShapeShape
from OCP.BRepFilletAPI import BRepFilletAPI_MakeFillet
from OCP.TopAbs import TopAbs_EDGE, TopAbs_FACE
from OCP.TopExp import TopExp_Explorer
from OCP.TopoDS import TopoDS
from OCP.BRepPrimAPI import BRepPrimAPI_MakeBox, BRepPrimAPI_MakeCylinder, BRepPrimAPI_MakePrism
from OCP.GC import GC_MakeArcOfCircle, GC_MakeSegment
from OCP.gp import gp_Ax2, gp_Dir, gp_Pnt, gp_Vec


def box(x0, y0, z0, x1, y1, z1):
    return BRepPrimAPI_MakeBox(gp_Pnt(x0, y0, z0), gp_Pnt(x1, y1, z1)).Shape()


def rounded_box(b, d: float):
    """Box ``b`` (x0, y0, z0, x1, y1, z1) grown by ``d`` with every edge rounded to
    ``d``: the points within ``d`` of the box."""
    x0, y0, z0, x1, y1, z1 = b
    shape = box(x0 - d, y0 - d, z0 - d, x1 + d, y1 + d, z1 + d)
    if d <= 1e-9:
        return shape
    f = BRepFilletAPI_MakeFillet(shape)
    ex = TopExp_Explorer(shape, TopAbs_EDGE)
    while ex.More():
        f.Add(d, TopoDS.Edge(ex.Current()))
        ex.Next()
    return f.Shape()


class BoxCut:
    """A design: the block ``outer`` less the boxes ``removed`` (each x0, y0, z0, x1, y1,
    z1)."""

    def __init__(self, outer, removed):
        self.outer = tuple(outer)
        self.removed = [tuple(b) for b in removed]

    def eroded(self, d: float):
        """The points of the design at least ``d`` below its surface."""
        x0, y0, z0, x1, y1, z1 = self.outer
        if min(x1 - x0, y1 - y0, z1 - z0) <= 2 * d:
            return None
        shape = box(x0 + d, y0 + d, z0 + d, x1 - d, y1 - d, z1 - d)
        for b in self.removed:
            shape = cut(shape, rounded_box(b, d))
        return shape


def cut(a, b):
    return BRepAlgoAPI_Cut(a, b).Shape()


def fuse(a, b):
    return BRepAlgoAPI_Fuse(a, b).Shape()


def flat_sweep(p, q, r: float, h: float):
    """The solid a flat end mill of radius ``r`` and cutting length ``h`` sweeps from
    tip ``p`` to tip ``q``: level and vertical moves only (others raise ValueError)."""
    dx, dy, dz = q[0] - p[0], q[1] - p[1], q[2] - p[2]
    L = math.hypot(dx, dy)
    if L < 1e-12:
        z0 = min(p[2], q[2])
        return BRepPrimAPI_MakeCylinder(gp_Ax2(gp_Pnt(p[0], p[1], z0), gp_Dir(0, 0, 1)), r,
                                        h + abs(dz)).Shape()
    if abs(dz) > 1e-12:
        raise ValueError("only level and vertical moves")
    ux, uy = -dy / L * r, dx / L * r                 # to the left of the move, length r
    z = p[2]
    a1, a2 = gp_Pnt(p[0] + ux, p[1] + uy, z), gp_Pnt(q[0] + ux, q[1] + uy, z)
    b1, b2 = gp_Pnt(q[0] - ux, q[1] - uy, z), gp_Pnt(p[0] - ux, p[1] - uy, z)
    front = gp_Pnt(q[0] + dx / L * r, q[1] + dy / L * r, z)
    back = gp_Pnt(p[0] - dx / L * r, p[1] - dy / L * r, z)
    w = BRepBuilderAPI_MakeWire()
    w.Add(BRepBuilderAPI_MakeEdge(GC_MakeSegment(a1, a2).Value()).Edge())
    w.Add(BRepBuilderAPI_MakeEdge(GC_MakeArcOfCircle(a2, front, b1).Value()).Edge())
    w.Add(BRepBuilderAPI_MakeEdge(GC_MakeSegment(b1, b2).Value()).Edge())
    w.Add(BRepBuilderAPI_MakeEdge(GC_MakeArcOfCircle(b2, back, a1).Value()).Edge())
    face = BRepBuilderAPI_MakeFace(w.Wire()).Face()
    return BRepPrimAPI_MakePrism(face, gp_Vec(0, 0, h)).Shape()


def meets(a, b) -> bool:
    """Whether solids ``a`` and ``b`` share a point (an empty ``a``, None or without
    faces, meets nothing)."""
    if a is None or not TopExp_Explorer(a, TopAbs_FACE).More():
        return False
    d = BRepExtrema_DistShapeShape(a, b)
    d.Perform()
    if not d.IsDone() or d.NbSolution() == 0:
        return False
    return d.Value() < 1e-9 or d.InnerSolution()


def move_depth(design: BoxCut, p, q, r: float, h: float, tol: float = 1e-5) -> float:
    """How deep the move from tip ``p`` to ``q`` cuts below the surface of ``design``
    (0 when it does not meet it), within ``tol``."""
    sweep = flat_sweep(p, q, r, h)
    if not meets(design.eroded(0.0), sweep):
        return 0.0
    lo, hi = 0.0, r + abs(q[2] - p[2]) + h
    while hi - lo > tol:
        d = 0.5 * (lo + hi)
        if meets(design.eroded(d), sweep):
            lo = d
        else:
            hi = d
    return lo
