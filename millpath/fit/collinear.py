"""Collinear points merged: runs of G1 moves whose inner points lie within a tolerance of
one straight line become one move (``millpath run`` does it even without ``fit``).

Only runs of consecutive linear feed moves of one operation at one feed are merged, as
in :func:`millpath.fit.fit_toolpath`; moves under cutter radius compensation, rapids,
arcs, cubics and cycles stay as they are. ``tolerance`` (toolpath units): every dropped
point is within it of the segment that replaces it (the distance to the segment, not
the infinite line, so a path that turns back is never merged across the turn).

An operation that promises its own ``tolerance`` (a chordal error already spent by its
planner: surfaces, die contours) is merged only within half a step of the post's number
grid (0.00005 mm / 0.000005 in), what the rounding of the program moves it anyway, so
its promise holds: straight and flat stretches still become one move.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from millpath.model.toolpath import Toolpath
from millpath.model.units import default


@njit(cache=True)
def kept_points(P: np.ndarray, tol: float) -> np.ndarray:
    """Indices of the points of polyline ``P`` (n, 3) kept: the first, the last, and
    those where a straight segment from the last kept point would pass further than
    ``tol`` from a skipped point (greedy, one pass)."""
    n = P.shape[0]
    keep = np.zeros(n, dtype=np.bool_)
    keep[0] = True
    keep[n - 1] = True
    a = 0
    j = 2
    while j < n:
        ok = True
        d = P[j] - P[a]
        dd = d[0] * d[0] + d[1] * d[1] + d[2] * d[2]
        for k in range(a + 1, j):
            v = P[k] - P[a]
            t = 0.0
            if dd > 0.0:
                t = (v[0] * d[0] + v[1] * d[1] + v[2] * d[2]) / dd
                t = min(1.0, max(0.0, t))
            e0 = v[0] - t * d[0]
            e1 = v[1] - t * d[1]
            e2 = v[2] - t * d[2]
            if e0 * e0 + e1 * e1 + e2 * e2 > tol * tol:
                ok = False
                break
        if not ok:
            a = j - 1
            keep[a] = True
        j += 1
    return np.nonzero(keep)[0]


def rebuild_line_runs(toolpath: Toolpath, replace) -> Toolpath:
    """A new toolpath in which every run of two or more feed lines (same operation, same
    feed, outside cutter compensation, starting where the tool is known) is replaced by
    ``replace(start, run)`` (``start``: the tool position before the run; returns the
    moves to write instead); every other move is kept as it is."""
    out = Toolpath(units=toolpath.units, moves=[], ops=list(toolpath.ops))
    moves = toolpath.moves
    comp_on = False
    start = None            # where the tool is, if a run may start there
    i, n = 0, len(moves)
    while i < n:
        m = moves[i]
        if m.kind == "line" and not comp_on and start is not None:
            j = i
            while (j < n and moves[j].kind == "line" and moves[j].op == m.op
                   and moves[j].feed == m.feed):
                j += 1
            run = moves[i:j]
            out.moves.extend(replace(start, run) if len(run) >= 2 else run)
            start = moves[j - 1].end if j < n and moves[j].op == m.op else None
            i = j
            continue
        out.moves.append(m)
        if m.kind == "comp":
            comp_on = m.comp != "off"
            start = None
        elif m.kind == "drill" or comp_on or (i + 1 < n and moves[i + 1].op != m.op):
            start = None
        else:
            start = m.end
        i += 1
    return out


def merge_collinear(toolpath: Toolpath, tolerance: float) -> Toolpath:
    """A new toolpath whose line runs keep only the points needed within ``tolerance``
    (within the post's half grid step for operations with their own tolerance)."""
    grid = 0.5 * 10.0 ** -default("decimals", toolpath.units)

    def merged(start, run):
        P = np.array([start] + [r.end for r in run], dtype=float)
        op = run[0].op
        op_tol = toolpath.ops[op].tolerance if op < len(toolpath.ops) else None
        tol = min(tolerance, grid) if op_tol is not None else tolerance
        idx = kept_points(P, float(tol))
        return [run[k - 1] for k in idx[1:]]
    return rebuild_line_runs(toolpath, merged)
