"""An independent gouge oracle: OpenCASCADE solids, no millpath geometry.

The design is a solid; a flat end mill (radius ``r``, cutting ``h`` up from its tip)
swept along a straight move is the exact solid of its sweep (a vertical move: one
cylinder; a level move: a stadium extruded by ``h``). How deep the tool went into the
design is the largest ``d`` for which the sweep eroded by ``d`` (radius ``r - d``, tip
raised by ``d``) still meets the design: the deepest design point inside the sweep, the
figure millpath's exact check reports. Found by halving ``d`` with
``BRepExtrema_DistShapeShape`` (distance 0, or one solid inside the other, means they
meet) to ``tol``.
"""

from __future__ import annotations

import math

from OCP.BRepAlgoAPI import BRepAlgoAPI_Cut, BRepAlgoAPI_Fuse
from OCP.BRepBuilderAPI import (BRepBuilderAPI_MakeEdge, BRepBuilderAPI_MakeFace,
                                BRepBuilderAPI_MakeWire)
from OCP.BRepExtrema import BRepExtrema_DistShapeShape
from OCP.BRepPrimAPI import BRepPrimAPI_MakeBox, BRepPrimAPI_MakeCylinder, BRepPrimAPI_MakePrism
from OCP.GC import GC_MakeArcOfCircle, GC_MakeSegment
from OCP.gp import gp_Ax2, gp_Dir, gp_Pnt, gp_Vec


def box(x0, y0, z0, x1, y1, z1):
    return BRepPrimAPI_MakeBox(gp_Pnt(x0, y0, z0), gp_Pnt(x1, y1, z1)).Shape()


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
    d = BRepExtrema_DistShapeShape(a, b)
    d.Perform()
    return d.Value() < 1e-9 or d.InnerSolution()


def move_depth(design, p, q, r: float, h: float, tol: float = 1e-5) -> float:
    """How deep the move from tip ``p`` to ``q`` cuts into ``design`` (0 when it does
    not meet it), within ``tol``."""
    if not meets(design, flat_sweep(p, q, r, h)):
        return 0.0
    lo, hi = 0.0, r
    while hi - lo > tol:
        d = 0.5 * (lo + hi)
        pe = (p[0], p[1], p[2] + d)
        qe = (q[0], q[1], q[2] + d)
        if meets(design, flat_sweep(pe, qe, r - d, h - 2 * d)):
            lo = d
        else:
            hi = d
    return lo
