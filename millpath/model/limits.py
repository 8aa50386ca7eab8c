"""Bounds on the work a job may ask for, so that a typo (a stepdown of 1e-9, a stock top
of 1e23) is refused up front with the numbers that caused it instead of exhausting
memory or time. Every bound can be raised in the job's ``[limits]`` table.

Lengths are in the job's units; counts are plain numbers.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, fields

from millpath.model.units import PerUnits

#: largest stock side, per unit system: a 10 m machine table
MAX_EXTENT = PerUnits(10_000.0, 400.0)


@dataclass(frozen=True)
class Limits:
    """``max_extent``: largest stock side (job units); ``max_layers``: depth passes of one
    operation (stock height / stepdown); ``max_passes``: side-by-side passes of one
    operation across the stock (largest XY side / stepover). Each field's ``metadata``
    holds its meaning and unit as the job's ``[limits]`` keys state them
    (:meth:`described`)."""

    max_extent: float = field(default=MAX_EXTENT.mm, metadata={
        "unit": "length", "doc": "largest stock side", "per_units": MAX_EXTENT})
    max_layers: int = field(default=2_000, metadata={
        "unit": "count", "doc": "depth passes of one operation: stock height / stepdown"})
    max_passes: int = field(default=20_000, metadata={
        "unit": "count",
        "doc": "side-by-side passes of one operation: largest stock side / stepover"})

    @classmethod
    def default_for(cls, units: str) -> "Limits":
        return cls(max_extent=MAX_EXTENT(units))

    @classmethod
    def keys(cls) -> tuple[str, ...]:
        return tuple(f.name for f in fields(cls))

    @classmethod
    def described(cls) -> tuple[tuple[str, str, str, str], ...]:
        """(name, type "float" or "int", unit, meaning with its default) of each bound."""
        return tuple((f.name, f.type, f.metadata["unit"],
                      f"{f.metadata['doc']} (default {f.metadata.get('per_units', f.default)})")
                     for f in fields(cls))


def count_needed(span: float, step: float) -> float:
    """How many steps of ``step`` cover ``span`` (a float, so that absurd requests are
    measured without building anything); ``inf`` for a step that is not positive."""
    if not (step > 0) or not math.isfinite(step):
        return math.inf
    return math.ceil(max(span, 0.0) / step - 1e-9)
