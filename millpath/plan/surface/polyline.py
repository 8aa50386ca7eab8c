"""Polyline helpers of the surface strategies, compiled (numba): merging collinear
points and densifying. Points are rows of job-unit coordinates (2 or 3 columns)."""

from __future__ import annotations

import numpy as np
from numba import njit


@njit(cache=True)
def _merge_keep(P, tol):
    n = P.shape[0]
    dim = P.shape[1]
    keep = np.empty(n, np.int64)
    keep[0] = 0
    nk = 1
    a = 0
    i = 2
    tol2 = tol * tol
    while i < n:
        L2 = 0.0
        for c in range(dim):
            d = P[i, c] - P[a, c]
            L2 += d * d
        worst = 0.0
        for j in range(a + 1, i):
            t = 0.0
            if L2 > 0.0:
                for c in range(dim):
                    t += (P[j, c] - P[a, c]) * (P[i, c] - P[a, c])
                t /= L2
                if t < 0.0:
                    t = 0.0
                elif t > 1.0:
                    t = 1.0
            d2 = 0.0
            for c in range(dim):
                e = P[j, c] - (P[a, c] + t * (P[i, c] - P[a, c]))
                d2 += e * e
            if d2 > worst:
                worst = d2
                if worst > tol2:
                    break
        if worst > tol2:
            keep[nk] = i - 1
            nk += 1
            a = i - 1
        i += 1
    keep[nk] = n - 1
    nk += 1
    return keep[:nk]


def merge_collinear(P: np.ndarray, tol: float) -> np.ndarray:
    """Drop interior points within ``tol`` of the chord joining their neighbours kept so
    far (greedy, forward; distances in all the columns, i.e. 3D for rows x, y, z)."""
    if len(P) < 3:
        return P
    return P[collinear_keep(P, tol)]


def collinear_keep(P: np.ndarray, tol: float) -> np.ndarray:
    """Indices of the rows :func:`merge_collinear` keeps (increasing)."""
    if len(P) < 3:
        return np.arange(len(P))
    return _merge_keep(np.ascontiguousarray(P, dtype=np.float64), float(tol))


def chord_offsets(P: np.ndarray, keep: np.ndarray) -> np.ndarray:
    """For each chord between consecutive kept rows ``keep`` of ``P``: the largest
    distance (all columns) of the rows it replaces from it; 0 where it replaces none."""
    out = np.zeros(max(len(keep) - 1, 0))
    drop = np.setdiff1d(np.arange(len(P)), keep, assume_unique=True)
    if len(drop) == 0 or len(keep) < 2:
        return out
    seg = np.searchsorted(keep, drop) - 1
    A, B = P[keep[seg]], P[keep[seg + 1]]
    d = B - A
    L2 = np.einsum("ij,ij->i", d, d)
    t = np.clip(np.einsum("ij,ij->i", P[drop] - A, d) / np.where(L2 > 0, L2, 1.0), 0.0, 1.0)
    np.maximum.at(out, seg, np.linalg.norm(P[drop] - (A + t[:, None] * d), axis=1))
    return out


def densify(P: np.ndarray, step: float) -> np.ndarray:
    """Points along the polyline ``P`` no more than ``step`` apart (its vertices kept)."""
    if len(P) < 2:
        return P
    d = np.linalg.norm(np.diff(P, axis=0), axis=1)
    k = np.maximum(1, np.ceil(d / step).astype(np.int64))
    seg = np.repeat(np.arange(len(d)), k)
    start = np.cumsum(k) - k
    t = (np.arange(int(k.sum())) - np.repeat(start, k)) / np.repeat(k, k)
    out = P[seg] + (P[seg + 1] - P[seg]) * t[:, None]
    return np.concatenate([out, P[-1:]])
