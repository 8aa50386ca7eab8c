"""Helpers for the fitting tests: dense sampling and two-sided distances."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial import cKDTree

from millpath.model.toolpath import Operation, Toolpath, sample_move


def _sample_lines(A: np.ndarray, B: np.ndarray, step: float) -> np.ndarray:
    """Points about ``step`` apart on segments A[k] -> B[k], without the A's."""
    L = np.linalg.norm(B - A, axis=1)
    n = np.maximum(1, np.ceil(L / step).astype(np.int64))
    k = np.repeat(np.arange(len(A)), n)
    first = np.cumsum(n) - n
    t = (np.arange(n.sum()) - first[k] + 1) / n[k]
    return A[k] + (B - A)[k] * t[:, None]


def sample_path(start, moves, step: float) -> np.ndarray:
    """Points about ``step`` apart along ``moves`` (Move objects) from ``start``."""
    out = [np.asarray([start], float)]
    cur = tuple(start)
    run: list[tuple] = []           # ends of consecutive straight moves not yet sampled
    for m in list(moves) + [None]:
        if m is not None and m.kind in ("line", "rapid"):
            run.append(m.end)
            continue
        if run:
            A = np.array([cur] + run[:-1], float)
            out.append(_sample_lines(A, np.array(run, float), step))
            cur = run[-1]
            run = []
        if m is not None and m.kind in ("arc", "cubic"):
            out.append(sample_move(cur, m, step)[1:])
            cur = m.end
    return np.vstack(out)


def directed(A: np.ndarray, B: np.ndarray) -> float:
    """Largest distance from a point of ``A`` to the polyline through ``B``'s points.

    Each point is measured against the segments next to its three nearest points of
    ``B`` (exact for dense ``B``; never smaller than the true distance).
    """
    if len(B) == 1:
        return float(np.max(np.linalg.norm(A - B[0], axis=1)))
    tree = cKDTree(B)
    _, near = tree.query(A, k=min(3, len(B)))
    near = near.reshape(len(A), -1)
    best = np.full(len(A), np.inf)
    for col in range(near.shape[1]):
        for off in (-1, 0):
            s = np.clip(near[:, col] + off, 0, len(B) - 2)
            a, b = B[s], B[s + 1]
            d = b - a
            l2 = np.maximum((d * d).sum(axis=1), 1e-300)
            u = np.clip(((A - a) * d).sum(axis=1) / l2, 0.0, 1.0)
            best = np.minimum(best, np.linalg.norm(A - (a + u[:, None] * d), axis=1))
    return float(best.max())


def hausdorff_moves(start, moves_a, moves_b, step: float) -> float:
    """Two-sided distance between two paths from ``start``, sampled every ``step``."""
    A = sample_path(start, moves_a, step)
    B = sample_path(start, moves_b, step)
    return max(directed(A, B), directed(B, A))


def toolpath_of(points, feed: float = 500.0, units: str = "mm") -> Toolpath:
    """A toolpath: rapid to the first point, then lines through the others."""
    tp = Toolpath(units=units)
    tp.begin(Operation("test", "test", 1))
    p0 = points[0]
    tp.rapid(*p0)
    for p in points[1:]:
        tp.line(*p, feed)
    return tp


@pytest.fixture(scope="session")
def fitkit():
    """The helpers above, as one object."""
    class Kit:
        sample = staticmethod(sample_path)
        directed = staticmethod(directed)
        hausdorff = staticmethod(hausdorff_moves)
        toolpath = staticmethod(toolpath_of)
    return Kit
