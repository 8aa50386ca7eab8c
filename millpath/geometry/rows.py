"""Unique rows of 2-D arrays (welding mesh vertices, counting the triangles on each edge).

The same result as ``np.unique(a, axis=0, return_inverse=True, return_counts=True)``
(rows in lexicographic order) from one ``lexsort`` of the columns, about three times
faster: ``np.unique`` sorts the rows as opaque byte strings.
"""

from __future__ import annotations

import numpy as np


def unique_rows(a: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(unique rows in lexicographic order, index of each row of ``a`` among them,
    how many rows of ``a`` each is). ``a``: (n, k), no NaN."""
    a = np.asarray(a)
    if a.ndim != 2:
        raise ValueError("unique_rows needs a 2-D array")
    n = len(a)
    if n == 0:
        return a.copy(), np.zeros(0, np.int64), np.zeros(0, np.int64)
    order = np.lexsort(a.T[::-1])
    s = a[order]
    new = np.ones(n, bool)
    new[1:] = (s[1:] != s[:-1]).any(axis=1)
    group = np.cumsum(new) - 1
    inverse = np.empty(n, np.int64)
    inverse[order] = group
    return s[new], inverse, np.bincount(group)
