"""Reading a user's text file (job, points, measured grid) with one-line errors."""

from __future__ import annotations

import csv
import math
from pathlib import Path

import numpy as np

from millpath.errors import MillpathError
from millpath.model.limits import MAX_COORDINATE


def read_text(path: str | Path, what: str, error: type[MillpathError] = MillpathError) -> str:
    """The UTF-8 text of ``path``; ``error`` (naming the file) when it is missing, a
    folder or not UTF-8. ``what`` names the file's role in messages ("points file")."""
    p = Path(path)
    try:
        return p.read_text(encoding="utf-8")
    except FileNotFoundError:
        raise error(f"no such {what}", p) from None
    except IsADirectoryError:
        raise error(f"is a folder, not a {what}", p) from None
    except UnicodeDecodeError:
        raise error(f"{what} is not UTF-8 text", p) from None


_WORDS = {2: "two", 3: "three"}



def read_number_rows(path: str | Path, names: str, error: type[MillpathError] = MillpathError
                     ) -> np.ndarray:
    """Rows of finite numbers from a user's points file, ``(n, k)`` for the ``k`` comma
    separated ``names`` ("x, y" or "x, y, z"). Fields are separated by commas,
    semicolons or whitespace; ``#`` starts a comment; one header line may precede the
    first row. ``error`` names the file and line of a bad row."""
    p = Path(path)
    k = len(names.split(","))
    expect = f"expected {_WORDS.get(k, k)} numbers {names}"
    text = read_text(p, "points file", error)
    rows: list[list[float]] = []
    header_seen = False
    for lineno, line in enumerate(text.splitlines(), 1):
        s = line.split("#", 1)[0].strip()
        if not s:
            continue
        if "," in s or ";" in s:
            fields = [f.strip() for f in next(csv.reader([s.replace(";", ",")]))]
        else:
            fields = s.split()
        try:
            vals = [float(f) for f in fields]
        except ValueError:
            if not rows and not header_seen:
                header_seen = True
                continue
            raise error(f"{expect}, got {s!r}", p, lineno) from None
        if len(vals) != k:
            raise error(f"{expect}, got {len(vals)} fields", p, lineno)
        if not all(math.isfinite(v) for v in vals):
            raise error("NaN or infinite coordinate", p, lineno)
        if max(abs(v) for v in vals) > MAX_COORDINATE:
            raise error(f"coordinate out of range (larger than {MAX_COORDINATE:g})", p, lineno)
        rows.append(vals)
    if not rows:
        raise error(f"points file has no {names} rows", p)
    return np.array(rows, dtype=float)
