"""Reading curve points from a job's ``points`` list or a CSV file.

CSV: one point a line, ``x, y`` (commas, semicolons or whitespace between the two
numbers); blank lines are skipped, ``#`` starts a comment, and a first line that is
not numeric is taken as a header (see :func:`millpath.io.text.read_number_rows`). Coordinates are in the job's units. Errors name
the file and the line.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from millpath.errors import GeometryError, JobError
from millpath.io.text import read_number_rows

def read_points_csv(path: str | Path) -> np.ndarray:
    """Points (n, 2) from a CSV file; GeometryError naming FILE:LINE on bad rows."""
    p = Path(path)
    pts = read_number_rows(p, "x, y", GeometryError)
    if len(pts) % 4:
        raise GeometryError(f"four points per segment are needed, the file has {len(pts)}", p)
    return pts


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
