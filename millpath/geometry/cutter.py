"""The cutter: one description of every cutting shape, its profile and its outline.

A cutter is a solid of revolution about the tool axis, its tip at height 0. It is
described by its radius ``R``, corner radius ``rc`` and, for a cone, ``slope`` ``k``
(height per unit radius, ``1 / tan(point angle / 2)``); lengths in the job's units. The
kind follows from those numbers and is one of the codes the compiled kernels take:

- ``FLAT`` end mill: ``rc = 0``;
- ``BALL``: ``rc = R``;
- ``BULL`` (torus): ``0 < rc < R``;
- ``DRILL`` (cone from the tip): ``k > 0``;
- ``CYL``: a shank or holder cylinder, lifted by its bottom height (the exact check's).

:func:`height` is the profile, the height of the cutter's surface above the tip at radial
distance ``r`` (``0 <= r <= R``; beyond ``R`` it holds the value at ``R``), compiled once
and inlined into the drop-cutter, the Z-map sweep, the rest filter and the exact check;
:class:`Cutter` carries the numbers and gives the same profile to Python callers.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numba import njit

FLAT, BALL, BULL, DRILL, CYL = 0, 1, 2, 3, 4

#: a :class:`millpath.model.tool.Tool`'s ``type`` -> its code
KIND = {"flat": FLAT, "ball": BALL, "bull": BULL, "drill": DRILL}
#: a code -> its name
NAME = {v: k for k, v in KIND.items()}


@njit(cache=True, inline="always")
def height(kind: int, R: float, rc: float, k: float, r: float) -> float:
    """Height of the cutter surface above the tip at radial distance ``r``."""
    if kind == FLAT:
        return 0.0
    if kind == BALL:
        q = R * R - r * r
        return R - math.sqrt(q if q > 0.0 else 0.0)
    if kind == DRILL:
        return k * (r if r < R else R)
    a = R - rc
    if r <= a:
        return 0.0
    e = r - a
    q = rc * rc - e * e
    return rc - math.sqrt(q if q > 0.0 else 0.0)


@njit(cache=True)
def _heights(kind, R, rc, k, r):
    out = np.empty(r.size)
    flat = r.ravel()
    for i in range(flat.size):
        out[i] = height(kind, R, rc, k, flat[i])
    return out


@dataclass(frozen=True)
class Cutter:
    """Radius, corner radius and cone slope of a cutter (job units); see the module."""

    radius: float
    corner: float = 0.0
    slope: float = 0.0

    def __post_init__(self) -> None:
        if not (self.radius > 0 and math.isfinite(self.radius)):
            raise ValueError(f"cutter radius must be positive, got {self.radius!r}")
        if not (0.0 <= self.corner <= self.radius):
            raise ValueError(f"corner radius must be in [0, {self.radius}], got {self.corner!r}")
        if not (self.slope >= 0.0 and math.isfinite(self.slope)) or (self.slope and self.corner):
            raise ValueError(f"a cone's slope must be positive with no corner radius, got "
                             f"{self.slope!r}")

    @property
    def kind(self) -> int:
        """The kernels' code: FLAT, BALL, BULL or DRILL."""
        if self.slope > 0.0:
            return DRILL
        if self.corner == 0.0:
            return FLAT
        return BALL if self.corner == self.radius else BULL

    @property
    def name(self) -> str:
        return NAME[self.kind]

    @property
    def row(self) -> tuple[int, float, float, float]:
        """``(kind, R, rc, k)`` as :func:`height` and the kernels take them."""
        return self.kind, float(self.radius), float(self.corner), float(self.slope)

    def height(self, r):
        """:func:`height` at ``r``: a float for a number, an array for an array."""
        if np.ndim(r) == 0:
            return float(height(*self.row, float(r)))
        r = np.asarray(r, float)
        return _heights(*self.row, np.ascontiguousarray(r)).reshape(r.shape)

    @property
    def tip_height(self) -> float:
        """Height of the profile at the full radius: a drill's point, a corner's radius."""
        return self.height(self.radius)

    def outline(self, steps: int = 12) -> list[tuple[float, float]]:
        """``(r, z)`` points of the profile from the tip out to ``(R, tip_height)``; a
        corner is sampled every ``90 / steps`` degrees."""
        a = self.radius - self.corner
        rs = [0.0, a] + [a + self.corner * math.sin(0.5 * math.pi * i / steps)
                         for i in range(1, steps + 1)] + [self.radius]
        out: list[tuple[float, float]] = []
        for r in rs:
            p = (float(r), self.height(r))
            if not out or p[0] > out[-1][0] + 1e-12 * self.radius:
                out.append(p)
        return out

    @classmethod
    def of(cls, tool) -> "Cutter":
        """The cutting part of a :class:`millpath.model.tool.Tool`."""
        if tool.type == "drill":
            return cls(tool.radius, 0.0, 1.0 / math.tan(math.radians(tool.point_angle) / 2.0))
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
