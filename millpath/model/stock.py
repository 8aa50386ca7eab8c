"""Stock and machine descriptions (job units: mm or inch)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class Stock:
    """An axis-aligned block: ``xmin ymin zmin xmax ymax zmax`` in the part frame; or a
    bar with a vertical axis, ``cylinder = (cx, cy, radius)`` from ``zmin`` to ``zmax``,
    whose bounding box the six numbers then are."""

    xmin: float
    ymin: float
    zmin: float
    xmax: float
    ymax: float
    zmax: float
    cylinder: tuple[float, float, float] | None = None

    @classmethod
    def from_cylinder(cls, cx: float, cy: float, radius: float, zmin: float,
                      zmax: float) -> "Stock":
        """A vertical bar of ``radius`` centred on (cx, cy) from ``zmin`` to ``zmax``."""
        if not (radius > 0 and zmin < zmax):
            raise ValueError("a cylinder needs a positive radius and zmin below zmax")
        r = float(radius)
        return cls(cx - r, cy - r, float(zmin), cx + r, cy + r, float(zmax),
                   (float(cx), float(cy), r))

    def inside_xy(self, x, y):
        """True where (x, y) is over the stock (inside the box, or the bar's circle)."""
        x, y = np.asarray(x, float), np.asarray(y, float)
        if self.cylinder is None:
            return (x >= self.xmin) & (x <= self.xmax) & (y >= self.ymin) & (y <= self.ymax)
        cx, cy, r = self.cylinder
        return (x - cx) ** 2 + (y - cy) ** 2 <= r * r

    def nearest_xy(self, x, y):
        """The point of the stock's footprint (box or bar's circle) nearest to (x, y):
        numbers or arrays of equal shape."""
        if self.cylinder is None:
            return np.clip(x, self.xmin, self.xmax), np.clip(y, self.ymin, self.ymax)
        cx, cy, r = self.cylinder
        d = np.hypot(np.subtract(x, cx), np.subtract(y, cy))
        k = np.where(d > r, r / np.maximum(d, 1e-300), 1.0)
        return cx + (np.subtract(x, cx)) * k, cy + (np.subtract(y, cy)) * k

    @classmethod
    def from_box(cls, box) -> "Stock":
        b = [float(v) for v in box]
        if len(b) != 6:
            raise ValueError("needs 6 numbers: xmin ymin zmin xmax ymax zmax")
        if not (b[0] < b[3] and b[1] < b[4] and b[2] < b[5]):
            raise ValueError("each min must be below its max")
        return cls(*b)

    @property
    def box(self) -> tuple[float, float, float, float, float, float]:
        return (self.xmin, self.ymin, self.zmin, self.xmax, self.ymax, self.zmax)

    @property
    def size(self) -> tuple[float, float, float]:
        return (self.xmax - self.xmin, self.ymax - self.ymin, self.zmax - self.zmin)


@dataclass(frozen=True)
class Machine:
    """Machine limits for cycle time: rates in units/min, acceleration in units/s^2."""

    rapid: float = 5000.0
    max_feed: float = 3000.0
    acceleration: float = 500.0

    @classmethod
    def default_for(cls, units: str) -> "Machine":
        if units == "inch":
            return cls(rapid=200.0, max_feed=120.0, acceleration=20.0)
        return cls()
