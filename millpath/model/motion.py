"""Interpreted motion: what a LinuxCNC machine would do, move by move.

Coordinates are the controlled point after cutter radius compensation, in program
units and program coordinates (before work offsets and tool length offset), like
LinuxCNC's canonical calls. ``tool_offset`` is the tool length offset in force
(x, y, z), ``tool`` the tool in the spindle. Arcs: ``plane`` XY/XZ/YZ, ``center``
(normal-axis component = the start's), ``rotation`` signed full-turn count about the
plane normal: +1 counter-clockwise (G3), -1 clockwise (G2), -2 for ``G2 ... P2``.
Cubics (G5, XY only): ``controls`` = the two Bezier control points (x, y). NURBS (G5.2/G5.3,
XY only, Z constant): ``controls`` = a :class:`millpath.model.nurbs.Nurbs`.

``frame`` (:class:`Frame`, set by the interpreter) is what places the program point on
the machine: units, work offset, G92/G52 offset, XY rotation, the tool length offset in
force and the length of the tool really in the spindle
(:func:`millpath.interpret.tip.tip_motions` turns motion into tool tips in the part's frame).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING

from millpath.model.units import length_scale

if TYPE_CHECKING:
    from millpath.model.nurbs import Nurbs

Vec3 = tuple[float, float, float]


@dataclass(frozen=True, slots=True)
class Frame:
    """Where a motion's program coordinates are on the machine (LinuxCNC's emccanon):
    controlled point (mm) = ``scale`` * (rotate_xy(program + ``axis_offset``,
    ``rotation``) + ``origin``) + ``tlo_mm``; the tool tip is the controlled point minus
    ``tool_mm``, the offsets (x, y, z) of the tool in the spindle as the tool table was
    written (G10 L1/L10 changes to the table do not change the tool).

    ``units``: program units ("mm" | "inch"); ``scale``: mm per program unit;
    ``origin`` (G54-G59.3) and ``axis_offset`` (G92/G52) in program units; ``rotation``:
    degrees counter-clockwise (G10 L2 R); ``tlo_mm``: tool length offset as applied
    (G43/G43.1/G43.2), mm; ``tool_mm``: the spindle tool's table offsets, mm."""

    units: str = "mm"
    origin: Vec3 = (0.0, 0.0, 0.0)
    axis_offset: Vec3 = (0.0, 0.0, 0.0)
    rotation: float = 0.0
    tlo_mm: Vec3 = (0.0, 0.0, 0.0)
    tool_mm: Vec3 = (0.0, 0.0, 0.0)

    @property
    def scale(self) -> float:
        return length_scale(self.units, "mm")


@dataclass(slots=True)
class Motion:
    kind: str                       # "traverse" | "feed" | "arc" | "cubic" | "nurbs" | "dwell"
    line: int                       # 1-based source line of the block
    start: Vec3
    end: Vec3
    feed: float = 0.0               # units/min (inverse time: see feed_mode)
    tool_offset: Vec3 = (0.0, 0.0, 0.0)
    tool: int = 0
    plane: str = "XY"
    center: Vec3 | None = None
    rotation: int = 0
    controls: "tuple[tuple[float, float], tuple[float, float]] | Nurbs | None" = None
    dwell: float = 0.0              # seconds, for kind "dwell"
    feed_mode: str = "units_per_minute"   # or "inverse_time"
    spindle: float = 0.0            # rpm (negative: M4)
    frame: Frame | None = field(default=None, compare=False)   # None: tip = program point

    def to_json(self) -> dict:
        d = {"kind": self.kind, "line": self.line, "start": list(self.start),
             "end": list(self.end), "feed": self.feed, "tool_offset": list(self.tool_offset)}
        if self.kind == "arc":
            d.update(plane=self.plane, center=list(self.center or ()), rotation=self.rotation)
        if self.kind == "cubic" and self.controls is not None:
            d["controls"] = [list(self.controls[0]), list(self.controls[1])]
        if self.kind == "nurbs" and self.controls is not None:
            d["order"] = self.controls.order
            d["controls"] = [list(p) for p in self.controls.points]
        if self.kind == "dwell":
            d["seconds"] = self.dwell
        return d
