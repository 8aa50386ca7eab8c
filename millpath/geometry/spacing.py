"""Points spaced along many segments at once (vectorized): the check points of chords,
the samples of a path."""

from __future__ import annotations

import numpy as np


def points_along(A: np.ndarray, B: np.ndarray, n: np.ndarray,
                 start: bool = False) -> tuple[np.ndarray, np.ndarray]:
    """(points, segment of each): ``n[i]`` points on each segment ``A[i] -> B[i]``
    (rows of any number of columns), evenly spaced, in order. Interior points at
    ``k / (n + 1)``, k = 1..n (neither end); with ``start`` at ``k / n``, k = 0..n-1 (the
    start, not the end). ``n``: integers, at least 1 with ``start``."""
    n = np.asarray(n, np.int64)
    row = np.repeat(np.arange(len(n)), n)
    k = np.arange(int(n.sum())) - np.repeat(np.cumsum(n) - n, n)
    t = k / n[row] if start else (k + 1.0) / (n[row] + 1.0)
    return A[row] + (B - A)[row] * t[:, None], row
