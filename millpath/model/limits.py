"""Bounds on the work a job may ask for, so that a typo (a stepdown of 1e-9, a stock top
of 1e23) is refused up front with the numbers that caused it instead of exhausting
memory or time. Every bound can be raised in the job's ``[limits]`` table.

Lengths are in the job's units; counts are plain numbers.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, fields

#: largest stock side, per unit system: a 10 m machine table
MAX_EXTENT = {"mm": 10_000.0, "inch": 400.0}


@dataclass(frozen=True)
class Limits:
    """``max_extent``: largest stock side (job units); ``max_layers``: depth passes of one
    operation (stock height / stepdown); ``max_passes``: side-by-side passes of one
    operation across the stock (largest XY side / stepover)."""

    max_extent: float = MAX_EXTENT["mm"]
    max_layers: int = 2_000
    max_passes: int = 20_000

    @classmethod
    def default_for(cls, units: str) -> "Limits":
        return cls(max_extent=MAX_EXTENT[units])

    @classmethod
    def keys(cls) -> tuple[str, ...]:
        return tuple(f.name for f in fields(cls))


def count_needed(span: float, step: float) -> float:
    """How many steps of ``step`` cover ``span`` (a float, so that absurd requests are
    measured without building anything); ``inf`` for a step that is not positive."""
    if not (step > 0) or not math.isfinite(step):
        return math.inf
    return math.ceil(max(span, 0.0) / step - 1e-9)
