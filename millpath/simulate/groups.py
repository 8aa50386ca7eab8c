"""Runs of connected chords checked as one coarse chord first (the exact check's pruning).

A *group* is a run of consecutive chords ``i .. j`` of one tool slot and operation
where each chord starts where the previous one ends; its coarse chord runs from
``S[i]`` to ``E[j]`` and its *deviation* is the largest distance of the run's inner
vertices from that coarse chord. Every chord of the run lies within the deviation of
the coarse chord (the points within a distance of a segment form a convex set), so
the tool swept along any of them lies within the deviation of the tool swept along
the coarse chord: a group whose coarse sweep, grown by its deviation, comes near no
triangle (or ray) needs none of its chords looked at. Program units.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numba import njit


@njit(cache=True, error_model="numpy", inline="always")
def _dev2(P, A, B):
    """Squared distance from P to segment A-B."""
    dx, dy, dz = B[0] - A[0], B[1] - A[1], B[2] - A[2]
    wx, wy, wz = P[0] - A[0], P[1] - A[1], P[2] - A[2]
    ll = dx * dx + dy * dy + dz * dz
    u = 0.0
    if ll > 0.0:
        u = min(max((wx * dx + wy * dy + wz * dz) / ll, 0.0), 1.0)
    ex, ey, ez = wx - u * dx, wy - u * dy, wz - u * dz
    return ex * ex + ey * ey + ez * ez


@njit(cache=True, error_model="numpy")
def _groups(S, E, slot, op, dmax, lmax, kmax, start, dev):
    """Fill ``start`` (group first chords) and ``dev``; return the number of groups."""
    n = S.shape[0]
    ng = 0
    i = 0
    d2max = dmax * dmax
    while i < n:
        j = i
        worst = 0.0
        while j + 1 < n and j + 1 - i < kmax:
            k = j + 1
            if (slot[k] != slot[i] or op[k] != op[i] or S[k, 0] != E[j, 0]
                    or S[k, 1] != E[j, 1] or S[k, 2] != E[j, 2]):
                break
            span2 = ((E[k, 0] - S[i, 0]) ** 2 + (E[k, 1] - S[i, 1]) ** 2
                     + (E[k, 2] - S[i, 2]) ** 2)
            if span2 > lmax * lmax:
                break
            w = 0.0
            for v in range(i + 1, k + 1):
                w = max(w, _dev2(S[v], S[i], E[k]))
                if w > d2max:
                    break
            if w > d2max:
                break
            worst = w
            j = k
        start[ng] = i
        dev[ng] = math.sqrt(worst)
        ng += 1
        i = j + 1
    start[ng] = n
    return ng


@dataclass
class ChordGroups:
    """Groups of chords: ``start`` (ngroups + 1,) first chord of each (the last entry
    the number of chords), coarse chords ``S`` -> ``E``, their ``dev``iation."""

    start: np.ndarray
    S: np.ndarray
    E: np.ndarray
    dev: np.ndarray

    @property
    def count(self) -> np.ndarray:
        return np.diff(self.start)

    def chords(self, flagged: np.ndarray) -> np.ndarray:
        """The chord numbers of the groups ``flagged`` (a boolean per group)."""
        return np.flatnonzero(np.repeat(np.asarray(flagged, bool), self.count))


def chord_groups(S: np.ndarray, E: np.ndarray, slot: np.ndarray, op: np.ndarray,
                 dmax: float, lmax: float, kmax: int = 64) -> ChordGroups:
    """Greedy runs of at most ``kmax`` connected chords, deviation at most ``dmax``
    and coarse length at most ``lmax`` (see the module doc)."""
    n = len(S)
    start = np.zeros(n + 1, np.int64)
    dev = np.zeros(max(n, 1))
    S = np.ascontiguousarray(S, float)
    E = np.ascontiguousarray(E, float)
    ng = _groups(S, E, np.ascontiguousarray(slot, np.int64),
                 np.ascontiguousarray(op, np.int64), float(dmax), float(lmax), int(kmax),
                 start, dev) if n else 0
    start = start[:ng + 1].copy()
    return ChordGroups(start, np.ascontiguousarray(S[start[:-1]]),
                       np.ascontiguousarray(E[start[1:] - 1]), dev[:ng].copy())
