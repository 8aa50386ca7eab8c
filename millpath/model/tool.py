"""Cutting tools.

All lengths are in the job's units (mm or inch). A tool's reference point is the tip:
the lowest point of the cutter on its axis. ``stickout`` is measured from the holder
face (the bottom of the first holder cylinder) down to the tip. ``holder`` is a stack of
cylinders ``(diameter, length)`` listed from the holder face upward. Between the tip and
the holder face the tool is the cutter (``flute_length`` long) and then the shank
(``shank_diameter``, default: the cutting diameter).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from typing import Literal

ToolType = Literal["flat", "ball", "bull", "drill"]
TOOL_TYPES: tuple[str, ...] = ("flat", "ball", "bull", "drill")


@dataclass
class Tool:
    """A milling cutter or drill, tip as reference point.

    - ``diameter``: cutting diameter.
    - ``corner_radius``: torus radius of a bull-nose cutter; a ball cutter's is D/2
      (set automatically), a flat cutter's is 0.
    - ``point_angle``: included angle of a drill point in degrees (118 by default).
    - ``length``: gauge length used as the tool length offset (``Z`` in a LinuxCNC tool
      table); defaults to ``stickout`` plus the holder stack, i.e. spindle nose to tip.
    """

    number: int
    type: ToolType = "flat"
    diameter: float = 6.0
    corner_radius: float = 0.0
    flutes: int = 2
    flute_length: float = 20.0
    stickout: float = 30.0
    holder: list[tuple[float, float]] = field(default_factory=list)
    material: str = "carbide"
    point_angle: float = 118.0
    shank_diameter: float | None = None
    length: float | None = None
    comment: str = ""

    def __post_init__(self) -> None:
        if self.type not in TOOL_TYPES:
            raise ValueError(f"tool type must be one of {', '.join(TOOL_TYPES)}, not {self.type!r}")
        if not (self.diameter > 0 and math.isfinite(self.diameter)):
            raise ValueError(f"tool {self.number}: diameter must be a positive number")
        if self.type == "ball":
            self.corner_radius = self.diameter / 2.0
        elif self.type == "flat":
            self.corner_radius = 0.0
        elif self.type == "bull":
            if not (0.0 < self.corner_radius <= self.diameter / 2.0):
                raise ValueError(f"tool {self.number}: bull corner radius must be in (0, D/2]")
        self.holder = [(float(d), float(l)) for d, l in self.holder]

    def scaled(self, k: float) -> "Tool":
        """The same tool with every length multiplied by ``k`` (a change of units)."""
        return replace(self, diameter=self.diameter * k, corner_radius=self.corner_radius * k,
                       flute_length=self.flute_length * k, stickout=self.stickout * k,
                       holder=[(d * k, l * k) for d, l in self.holder],
                       shank_diameter=(None if self.shank_diameter is None
                                       else self.shank_diameter * k),
                       length=None if self.length is None else self.length * k)

    @property
    def radius(self) -> float:
        return self.diameter / 2.0

    @property
    def shank(self) -> float:
        return self.shank_diameter if self.shank_diameter is not None else self.diameter

    @property
    def gauge_length(self) -> float:
        """Spindle nose to tip: the tool length offset written to tool tables."""
        if self.length is not None:
            return self.length
        return self.stickout + sum(l for _, l in self.holder)

    def holder_cylinders(self) -> list[tuple[float, float, float]]:
        """Shank and holder as ``(radius, z_bottom, z_top)`` above the tip.

        The shank runs from the top of the flutes to the holder face; the holder
        cylinders follow upward from the face.
        """
        out: list[tuple[float, float, float]] = []
        if self.stickout > self.flute_length:
            out.append((self.shank / 2.0, self.flute_length, self.stickout))
        z = self.stickout
        for d, l in self.holder:
            out.append((d / 2.0, z, z + l))
            z += l
        return out
