"""Chord refinement of a cutter-location polyline against the sampled surface.

:func:`refine_worst` checks ``checks`` evenly spaced interior points of each chord of
``P`` (rows x, y, z in job units), asks ``judge`` how far each is out and what Z it
should have, and inserts the worst point of every chord that is out by more than
``limit`` (chords shorter than ``min_len`` in XY are left), up to 20 rounds.
"""

from __future__ import annotations

from typing import Callable

import numpy as np

from millpath.plan.surface.sampler import Sampler

#: judge(Q (m, k, 3) interior points, zt (m, k) safe tip Z there) ->
#: (how far out (m, k), larger is worse; the Z a point inserted there gets (m, k))
Judge = Callable[[np.ndarray, np.ndarray], tuple[np.ndarray, np.ndarray]]


def refine_worst(sampler: Sampler, P: np.ndarray, judge: Judge, limit: float,
                 min_len: float, checks: int) -> np.ndarray:
    """``P`` with the worst interior point of each chord out by more than ``limit``
    inserted, until none is (or 20 rounds)."""
    t = np.arange(1, checks + 1) / (checks + 1.0)
    for _ in range(20):
        if len(P) < 2:
            break
        A, B = P[:-1], P[1:]
        Q = A[:, None, :] + (B - A)[:, None, :] * t[None, :, None]      # (m, k, 3)
        zt, _ = sampler.z_safe(Q[..., 0].ravel(), Q[..., 1].ravel())
        over, want = judge(Q, zt.reshape(len(A), checks))
        seg = np.hypot(B[:, 0] - A[:, 0], B[:, 1] - A[:, 1])
        worst = np.argmax(over, axis=1)
        rows = np.arange(len(A))
        bad = (over[rows, worst] > limit) & (seg > min_len)
        if not bad.any():
            break
        new = Q[rows, worst].copy()
        new[:, 2] = want[rows, worst]
        idx = np.nonzero(bad)[0]
        P = np.insert(P, idx + 1, new[idx], axis=0)
    return P


def refine_steps(sampler: Sampler, P: np.ndarray, judge: Judge, limit: float,
                 min_len: float) -> np.ndarray:
    """``P`` with the chords that rise or fall by more than ``limit`` checked where
    evenly spaced points miss a step of the surface (a cutter beside a vertical wall:
    the safe Z jumps from the low end's to the high end's just short of the high end).
    Points at ``1/2, 1/4, 1/8 ...`` of the chord from its high end, down to where the
    chord is within ``limit / 2`` of the high end's Z; the worst point out by more than
    ``limit / 2`` is inserted, up to 20 rounds. A step left between two checks is at
    most twice the nearer one's excess: within ``limit``."""
    for _ in range(20):
        if len(P) < 2:
            break
        A, B = P[:-1], P[1:]
        dz = np.abs(B[:, 2] - A[:, 2])
        seg = np.hypot(B[:, 0] - A[:, 0], B[:, 1] - A[:, 1])
        rows = np.flatnonzero((dz > limit) & (seg > min_len))
        if not len(rows):
            break
        k = int(np.ceil(np.log2(2.0 * dz[rows].max() / limit)))
        s = 0.5 ** np.arange(1, k + 1)                       # from the high end
        hi = np.where((B[rows, 2] >= A[rows, 2])[:, None], B[rows], A[rows])
        lo = np.where((B[rows, 2] >= A[rows, 2])[:, None], A[rows], B[rows])
        Q = hi[:, None, :] + (lo - hi)[:, None, :] * s[None, :, None]     # (m, k, 3)
        zt, _ = sampler.z_safe(Q[..., 0].ravel(), Q[..., 1].ravel())
        over, want = judge(Q, zt.reshape(len(rows), k))
        worst = np.argmax(over, axis=1)
        r = np.arange(len(rows))
        bad = over[r, worst] > 0.5 * limit
        if not bad.any():
            break
        new = Q[r, worst].copy()
        new[:, 2] = want[r, worst]
        P = np.insert(P, rows[bad] + 1, new[bad], axis=0)
    return P
