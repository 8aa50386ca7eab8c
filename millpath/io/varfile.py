"""LinuxCNC parameter files (``.var``) and work offsets given on the command line.

A ``.var`` file holds the numbered parameters the control keeps between runs, one
``NUMBER VALUE`` pair a line, values in the machine's units: 5161-5166 (G28 home),
5181-5186 (G30), 5210-5219 (G92 offsets and whether they apply), 5220 (the work system
in force: 1 = G54 ... 9 = G59.3), 5221-5230 (G54 X Y Z ... R), and 20 more for each of
G55 .. G59.3. Blank lines are skipped; anything else is an error naming the line.
"""

from __future__ import annotations

import math
from pathlib import Path

from millpath.errors import MillpathError
from millpath.io.text import MAX_COORDINATE

#: the parameters a ``.var`` file may set (LinuxCNC's persistent range)
FIRST, LAST = 5161, 5390


def read_var(path: str | Path) -> dict[int, float]:
    """The parameters of a LinuxCNC ``.var`` file, ``{number: value}`` (machine units)."""
    p = Path(path)
    if not p.is_file():
        raise MillpathError("parameter file not found", p)
    out: dict[int, float] = {}
    text = p.read_text(encoding="utf-8", errors="replace")
    for n, raw in enumerate(text.splitlines(), 1):
        words = raw.split()
        if not words:
            continue
        if len(words) != 2:
            raise MillpathError(f"expected 'NUMBER VALUE', got {raw.strip()[:40]!r}", p, n)
        try:
            num = int(words[0])
            val = float(words[1])
        except ValueError:
            raise MillpathError(f"expected 'NUMBER VALUE', got {raw.strip()[:40]!r}",
                                p, n) from None
        if not FIRST <= num <= LAST:
            raise MillpathError(f"parameter {num} is not one LinuxCNC keeps in its "
                                f"parameter file ({FIRST}-{LAST})", p, n)
        if not (math.isfinite(val) and abs(val) <= MAX_COORDINATE):
            raise MillpathError(f"parameter {num}: {words[1]} is out of range "
                                f"(at most {MAX_COORDINATE:g})", p, n)
        out[num] = val
    sys_ = out.get(5220, 1.0)
    if sys_ != int(sys_) or not 1 <= sys_ <= 9:
        raise MillpathError(f"parameter 5220 (the work system) must be 1 to 9, not {sys_:g}", p)
    return out


def work_offset_params(text: str) -> dict[int, float]:
    """``--work-offset X,Y,Z``: G54's offsets (machine units) as parameters 5221-5223."""
    try:
        vals = [float(v) for v in text.replace(" ", "").split(",")]
        if len(vals) != 3 or not all(math.isfinite(v) and abs(v) <= MAX_COORDINATE
                                     for v in vals):
            raise ValueError
    except ValueError:
        raise MillpathError(f"--work-offset: expected X,Y,Z (machine units), got {text!r}"
                            ) from None
    return {5221: vals[0], 5222: vals[1], 5223: vals[2]}


def length_params() -> set[int]:
    """The parameters of the range that are X, Y or Z lengths (the rest are angles, flags
    and the work system's number)."""
    bases = [5161, 5181, 5211] + [5221 + 20 * k for k in range(9)]
    return {b + k for b in bases for k in range(3)}


def convert_params(params: dict[int, float], k: float) -> dict[int, float]:
    """``params`` with their lengths multiplied by ``k`` (a change of machine units)."""
    if k == 1.0:
        return dict(params)
    lengths = length_params()
    return {n: v * k if n in lengths else v for n, v in params.items()}
