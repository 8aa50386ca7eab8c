"""A cutter for drop-cutter queries is its profile: radius and corner radius.

One profile covers the three shapes (job units, mm or inch):

- flat (cylindrical): ``corner = 0``;
- ball: ``corner = radius``;
- bull-nose (torus): ``0 < corner < radius``.

The profile height above the tip at radial distance ``r <= radius`` is
``h(r) = 0`` for ``r <= radius - corner`` and ``corner - sqrt(corner^2 - (r - radius + corner)^2)``
beyond. Tool holders and shanks are flat profiles lifted by their bottom height.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from millpath.model.tool import Tool


@dataclass(frozen=True)
class Cutter:
    """Radius and corner radius (job units); ``corner`` in [0, radius]."""

    radius: float
    corner: float = 0.0

    def __post_init__(self) -> None:
        if not (self.radius > 0 and math.isfinite(self.radius)):
            raise ValueError(f"cutter radius must be positive, got {self.radius!r}")
        if not (0.0 <= self.corner <= self.radius):
            raise ValueError(f"corner radius must be in [0, {self.radius}], got {self.corner!r}")

    @property
    def kind(self) -> str:
        if self.corner == 0.0:
            return "flat"
        if self.corner == self.radius:
            return "ball"
        return "bull"

    def height(self, r: float) -> float:
        """Height of the cutter surface above the tip at radial distance ``r``."""
        a = self.radius - self.corner
        if r <= a:
            return 0.0
        d = min(r - a, self.corner)
        return self.corner - math.sqrt(max(self.corner * self.corner - d * d, 0.0))

    @classmethod
    def from_tool(cls, tool: Tool) -> "Cutter":
        if tool.type == "drill":
            raise ValueError(f"tool {tool.number}: a drill cannot finish surfaces")
        return cls(tool.radius, tool.corner_radius)

    @classmethod
    def parse(cls, spec: str) -> "Cutter":
        """``ball:D``, ``flat:D`` or ``bull:D:R`` (diameter D, corner radius R)."""
        parts = spec.strip().lower().split(":")
        try:
            nums = [float(p) for p in parts[1:]]
        except ValueError:
            raise ValueError(f"bad tool {spec!r}: numbers expected after the shape") from None
        shape = parts[0]
        if shape in ("ball", "flat") and len(nums) == 1 and nums[0] > 0:
            return cls(nums[0] / 2.0, nums[0] / 2.0 if shape == "ball" else 0.0)
        if shape == "bull" and len(nums) == 2 and nums[0] > 0:
            return cls(nums[0] / 2.0, nums[1])
        raise ValueError(f"bad tool {spec!r}: expected ball:D, flat:D or bull:D:R")
