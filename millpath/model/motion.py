"""Interpreted motion: what a LinuxCNC machine would do, move by move.

Coordinates are the controlled point after cutter radius compensation, in program
units and program coordinates (before work offsets and tool length offset), like
LinuxCNC's canonical calls. ``tool_offset`` is the tool length offset in force
(x, y, z), ``tool`` the tool in the spindle. Arcs: ``plane`` XY/XZ/YZ, ``center``
(normal-axis component = the start's), ``rotation`` signed full-turn count about the
plane normal: +1 counter-clockwise (G3), -1 clockwise (G2), -2 for ``G2 ... P2``.
Cubics (G5, XY only): ``controls`` = the two Bezier control points (x, y). NURBS (G5.2/G5.3,
XY only, Z constant): ``controls`` = a :class:`millpath.model.nurbs.Nurbs`.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from millpath.model.nurbs import Nurbs

Vec3 = tuple[float, float, float]


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
