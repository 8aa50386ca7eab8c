"""Reading curve points from a job's ``points`` list or a CSV file.

CSV: one point a line, ``x, y`` (commas, semicolons or whitespace between the two
numbers); blank lines and lines starting with ``#`` are skipped, and a first line that
is not numeric is taken as a header. Coordinates are in the job's units. Errors name
the file and the line.
"""

from __future__ import annotations

import math
import re
from pathlib import Path

import numpy as np

from millpath.errors import GeometryError, JobError
from millpath.io.text import read_text

_SPLIT = re.compile(r"[,;\s]+")


def read_points_csv(path: str | Path) -> np.ndarray:
    """Points (n, 2) from a CSV file; GeometryError naming FILE:LINE on bad rows."""
    p = Path(path)
    text = read_text(p, "points file", JobError)
    pts: list[tuple[float, float]] = []
    first_data = True
    for lineno, raw in enumerate(text.splitlines(), 1):
        line = raw.strip()
        if not line or line.startswith("#"):
            continue
        fields = [f for f in _SPLIT.split(line) if f]
        try:
            vals = [float(f) for f in fields]
        except ValueError:
            if first_data and not pts:
                first_data = False          # header line
                continue
            raise GeometryError(f"expected two numbers x, y, got {line!r}", p, lineno) from None
        first_data = False
        if len(vals) != 2:
            raise GeometryError(f"expected two numbers x, y, got {len(vals)}", p, lineno)
        if not all(math.isfinite(v) for v in vals):
            raise GeometryError("coordinates must be finite", p, lineno)
        pts.append((vals[0], vals[1]))
    if not pts:
        raise GeometryError("no points in the file", p)
    if len(pts) % 4:
        raise GeometryError(f"four points per segment are needed, the file has {len(pts)}", p)
    return np.array(pts, float)


def points_from_params(points, points_file, job_file=None, where: str = "") -> np.ndarray:
    """The outline points from either the ``points`` list or the ``points_file`` CSV."""
    if (points is None) == (points_file is None):
        raise JobError(f"{where}: give exactly one of points and points_file", job_file)
    if points_file is not None:
        return read_points_csv(points_file)
    arr = np.array([[float(v) for v in q[:2]] for q in points], float)
    if any(len(q) != 2 for q in points):
        raise JobError(f"{where}.points: each point is [x, y]", job_file)
    if len(arr) % 4:
        raise JobError(f"{where}.points: four points per segment are needed, "
                       f"got {len(arr)}", job_file)
    return arr
