"""Stock and machine descriptions (job units: mm or inch)."""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class Stock:
    """An axis-aligned block: ``xmin ymin zmin xmax ymax zmax`` in the part frame."""

    xmin: float
    ymin: float
    zmin: float
    xmax: float
    ymax: float
    zmax: float

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
