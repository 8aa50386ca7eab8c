"""Every bound on what a user may write and on the work it may ask for, in one table, so
that a typo (a stepdown of 1e-9, a stock top of 1e23, ``G1 X1e20``, a DXF circle of
radius 1e300) is refused at once, naming the file, line or key where it was written,
instead of exhausting memory or time, being accepted as garbage or failing later in a
text millpath generated itself.

Two kinds:

- fixed bounds (module constants), checked by the readers where each number is read:
  the magnitude of any number in a text input, the nesting depth and digits of what a
  parser reads, the work one program may make (loop iterations, motions, canned-cycle
  steps) and the points a drawn curve may be cut into;
- a job's bounds (:class:`Limits`), raised in the job's ``[limits]`` table: stock size,
  layers, passes and Z-map cells; with per-unit bounds on tools and tolerances
  (:data:`TOOL_DIAMETER`, :func:`tolerance_floor`).

Lengths are in the file's or the job's units (mm or inch); counts are plain numbers.
The ``check_*`` functions return a message (without the file or key, which the caller
adds) or ``None``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, fields

from millpath.model.units import PerUnits, default

# --- numbers as written ------------------------------------------------------------------
#: largest magnitude of any number written in a text input (G-code words, tool tables,
#: points, grid, mesh and DXF coordinates), in that file's units: no machine is a
#: thousand kilometres long; a larger number is a typo, a wrong column or a unit mix-up
MAX_COORDINATE = 1e9
#: deepest nesting of brackets a parser reads (TOML arrays and inline tables, Part 21
#: parameter lists): real files nest a few levels; Python's recursion stops near 1000
MAX_NESTING = 64
#: most digits of an integer literal (TOML): Python refuses to convert more than 4300
MAX_DIGITS = 1000

# --- work of one program (interpreter) ---------------------------------------------------
#: jumps back to the top of a loop, in all; a ``repeat`` asking for more is refused
#: before it starts
MAX_LOOP_ITERATIONS = 1_000_000
#: jumps back without any motion in between: an endless loop
MAX_IDLE_ITERATIONS = 100_000
#: motions a program with loops or subroutines may make (about 100 bytes each)
MAX_MOTIONS = 2_000_000
#: characters a program with loops or subroutines may read, counting every executed line
#: (about a microsecond each) plus ``FLOW_LINE_CHARS`` for the line itself
MAX_FLOW_CHARS = 5_000_000
FLOW_LINE_CHARS = 8
#: (repeats x pecks) one canned-cycle block may expand into (a few moves each)
MAX_CYCLE_STEPS = 1_000_000

# --- planning ----------------------------------------------------------------------------
#: pass lines of one surface-finish zigzag, and waterline levels of one surface
MAX_PASS_LINES = 5000
MAX_LEVELS = 3000
#: drop-cutter raster nodes of one surface-rough (about 1 GB)
MAX_ROUGH_RASTER = 10_000_000
#: cells of one grid-pocket grid
MAX_GRID_CELLS = 4_000_000

# --- surfaces ----------------------------------------------------------------------------
#: cells per direction a Bezier net or measured grid is meshed into (two triangles each)
MAX_DIVISIONS = 1000
#: finest chordal tolerance a STEP surface is meshed within (its units)
MIN_CHORD_TOLERANCE = 0.001

# --- drawings ----------------------------------------------------------------------------
#: points the curves of one drawing may be cut into at the chordal tolerance
MAX_CURVE_POINTS = 2_000_000

# --- tools and tolerances (job units) ----------------------------------------------------
#: a tool's cutting diameter: from a micro end mill to a large face mill
TOOL_DIAMETER = (PerUnits(0.01, 0.0004), PerUnits(1000.0, 40.0))
#: largest chordal or fitting tolerance: coarser is not machining
MAX_TOLERANCE = PerUnits(1.0, 0.04)
#: largest stock side, per unit system: a 10 m machine table
MAX_EXTENT = PerUnits(10_000.0, 400.0)


@dataclass(frozen=True)
class Limits:
    """``max_extent``: largest stock side (job units); ``max_layers``: depth passes of one
    operation (stock height / stepdown); ``max_passes``: side-by-side passes of one
    operation across the stock (largest XY side / stepover); ``max_cells``: cells of the
    simulation's Z-map (stock area / resolution squared). Each field's ``metadata``
    holds its meaning and unit as the job's ``[limits]`` keys state them
    (:meth:`described`)."""

    max_extent: float = field(default=MAX_EXTENT.mm, metadata={
        "unit": "length", "doc": "largest stock side; also the largest tool length",
        "per_units": MAX_EXTENT, "max": 1e6})
    max_layers: int = field(default=2_000, metadata={
        "unit": "count", "doc": "depth passes of one operation: stock height / stepdown"})
    max_passes: int = field(default=20_000, metadata={
        "unit": "count",
        "doc": "side-by-side passes of one operation: largest stock side / stepover"})
    max_cells: int = field(default=16_000_000, metadata={
        "unit": "count",
        "doc": "cells of the simulation's Z-map: stock length x width / resolution^2 "
               "(about 60 bytes each)"})

    @classmethod
    def default_for(cls, units: str) -> "Limits":
        return cls(max_extent=MAX_EXTENT(units))

    @classmethod
    def raised(cls, values: dict) -> tuple[str, str] | None:
        """(key, message) of a bound raised beyond what millpath can hold (a length of
        a million units would overflow the tool table's numbers), else None."""
        for f in fields(cls):
            top = f.metadata.get("max")
            v = values.get(f.name)
            if top is not None and v is not None and v > top:
                return f.name, f"at most {top:g}, got {v:g}"
        return None

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
    return float(math.ceil(max(span, 0.0) / step - 1e-9))


def check_coordinate(value: float) -> str | None:
    """A number written in a text input: finite and at most :data:`MAX_COORDINATE`."""
    if not math.isfinite(value):
        return f"{value} is not a finite number"
    if abs(value) > MAX_COORDINATE:
        return f"{value:g} is larger than the {MAX_COORDINATE:g} limit"
    return None


def check_tool_diameter(d: float, units: str) -> str | None:
    """A tool's diameter (job units) within :data:`TOOL_DIAMETER`."""
    lo, hi = TOOL_DIAMETER[0](units), TOOL_DIAMETER[1](units)
    if not (lo <= d <= hi):
        return (f"a diameter of {d:g} {units} is outside {lo:g} .. {hi:g} {units} "
                f"(wrong units?)")
    return None


def check_length(value: float, units: str, limit: float, what: str = "length") -> str | None:
    """A length (job units) that must fit on the machine: at most ``limit`` (the job's
    ``max_extent``)."""
    if value > limit:
        return (f"a {what} of {value:g} {units} is larger than the {limit:g} {units} limit "
                f"(wrong units? raise [limits] max_extent if the machine is that big)")
    return None


def tolerance_floor(units: str) -> float:
    """Smallest tolerance a program can hold: twice the step of its last decimal (the
    post rounds every coordinate to it)."""
    return 2.0 * 10.0 ** -int(default("decimals", units))


def check_tolerance(t: float, units: str) -> str | None:
    """A fitting or chordal tolerance (job units) between :func:`tolerance_floor` and
    :data:`MAX_TOLERANCE`."""
    lo, hi = tolerance_floor(units), MAX_TOLERANCE(units)
    if t < lo:
        return (f"{t:g} {units} is finer than the program's {int(default('decimals', units))} "
                f"decimals can hold (at least {lo:g} {units})")
    if t > hi:
        return f"{t:g} {units} is coarser than the {hi:g} {units} limit"
    return None


def check_cells(width: float, length: float, resolution: float, limit: int) -> str | None:
    """A Z-map of cells ``resolution`` wide over ``width`` x ``length``: at most ``limit``
    cells; the message names a resolution that fits."""
    n = count_needed(width, resolution) * count_needed(length, resolution)
    if n > limit:
        fits = math.sqrt(max(width, 1e-300) * max(length, 1e-300) / limit)
        return (f"{resolution:g} makes {n:.3g} cells over the stock, more than the limit of "
                f"{limit} (use {_round_up(fits):g} or more, or raise [limits] max_cells)")
    return None


def _round_up(v: float) -> float:
    """``v`` rounded up to two significant digits."""
    if not (v > 0 and math.isfinite(v)):
        return v
    e = math.floor(math.log10(v)) - 1
    return math.ceil(v / 10.0 ** e) * 10.0 ** e
