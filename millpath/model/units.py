"""Unit-dependent defaults in one table: each value in millimetres and in inches (the
inch value is a round number near the converted one, not an exact conversion), read by
the strategies, the fitter, the post and the job loader, and quoted by the keys'
descriptions (``millpath keys``).

``DEFAULTS[name](units)`` is the value for a job in ``units`` ("mm" or "inch");
``str(DEFAULTS[name])`` is "5 mm / 0.2 in" for documentation. :func:`as_written` is
a coordinate as a program with ``DEFAULTS["decimals"]`` digits gives it back.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class PerUnits:
    """One default: ``mm`` for metric jobs, ``inch`` for inch jobs."""

    mm: float
    inch: float

    def __call__(self, units: str) -> float:
        return self.inch if units == "inch" else self.mm

    def __str__(self) -> str:
        return f"{self.mm:g} mm / {self.inch:g} in"


DEFAULTS: dict[str, PerUnits] = {
    # heights above the material (job units)
    "safe_clearance": PerUnits(5.0, 0.2),        # retract plane above the top
    "feed_clearance": PerUnits(1.0, 0.04),       # feeds start / holder and links clear by
    "entry_clearance": PerUnits(0.5, 0.02),      # 2.5D entries start above the material
    "breakthrough": PerUnits(0.5, 0.02),         # through features cut below the bottom
    # tolerances (job units)
    "path_tolerance": PerUnits(0.005, 0.0002),   # fitting / chords along passes
    "chord_tolerance": PerUnits(0.01, 0.0004),   # meshing solids, feature geometry
    "drawing_tolerance": PerUnits(0.01, 0.0005),  # DXF arcs and splines; viewer's neutral band
    "scallop": PerUnits(0.01, 0.0004),           # surface-finish cusp height
    "taper_cusp": PerUnits(0.02, 0.0008),        # features: cusp on a hole's cone bottom
    "roundtrip": PerUnits(2e-4, 2e-5),           # program vs plan after the post's rounding
    "verify_accuracy": PerUnits(0.001, 0.00004),  # bound on the exact gouge / left figures
    "wear_margin": PerUnits(0.1, 0.004),         # profile, control compensation: concave
                                                 # corners rounded to the tool radius + this
    # stock left, steps (job units)
    "features_allowance": PerUnits(0.2, 0.008),  # wall stock left for the finish pass
    "rough_allowance": PerUnits(0.3, 0.012),     # surface-rough: stock left on the surface
    "rough_stepdown": PerUnits(2.0, 0.08),       # surface-rough: depth per layer
    "choose_tool_min_size": PerUnits(0.5, 0.02),  # smallest feature size choose_tool considers
    "sample_step": PerUnits(0.25, 0.01),         # grid-pocket: path sampling for the report
    "max_arc_radius": PerUnits(2540.0, 100.0),   # grid-pocket: arcs larger are lines
    # feeds (job units/min)
    "finish_feed": PerUnits(1000.0, 40.0),       # surface-finish
    "rough_feed": PerUnits(1500.0, 60.0),        # surface-rough
    "feed_step": PerUnits(1.0, 0.1),             # feeds are rounded to this
    # program text
    "decimals": PerUnits(4, 5),                  # digits after the point of coordinates
}


def default(name: str, units: str) -> float:
    """``DEFAULTS[name]`` for a job in ``units``."""
    return DEFAULTS[name](units)


#: millimetres per inch, and per foot
MM_PER_INCH = 25.4
MM_PER_FOOT = 304.8


def length_scale(from_units: str, to_units: str) -> float:
    """Factor turning a length in ``from_units`` into ``to_units`` ("mm" or "inch")."""
    if from_units == to_units:
        return 1.0
    return MM_PER_INCH if from_units == "inch" else 1.0 / MM_PER_INCH


def as_written(values, decimals: int) -> np.ndarray:
    """``values`` (any shape, any length unit) as a program written with ``decimals``
    digits after the point gives them back: each the float of Python's
    ``format(v, f".{decimals}f")``, the post-processor's text (the exact binary value
    rounded to the nearest multiple of ``10 ** -decimals``, an exact tie to even).

    ``np.round(v / q) * q`` is not that: the division rounds, so a value just above a
    half step (27.00625 is 27.006250000000001...) can go down where the text goes up."""
    a = np.asarray(values, dtype=float)
    scale = 10.0 ** decimals                    # exact for the decimals in use
    x = a * scale
    out = np.round(x) / scale                   # k / 10**d: the float the text reads as
    # within a millionth of a step of a half step the product's own rounding may decide
    # (its error stays below that up to 10**9 steps): those few are rounded as the text is
    near = np.flatnonzero(np.abs(x - np.floor(x) - 0.5) < 1e-6)
    if len(near):
        spec = f".{decimals}f"
        flat, src = out.reshape(-1), a.reshape(-1)
        for k in near:
            flat[k] = float(format(float(src[k]), spec))
        out = flat.reshape(a.shape)
    return out + 0.0                            # never -0.0
