"""Join open drawing pieces into closed loops.

A piece is a polyline flattened from one entity; a loop is a closed chain of pieces.
Pieces whose ends meet within ``join_tolerance`` (job units) are joined end to end
(reversed where needed); a chain that cannot be closed is a GeometryError naming the
entity at the open end and the place of the gap.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from millpath.errors import GeometryError


@dataclass
class Piece:
    """A flattened entity: ``points`` (n, 2), ``handle`` of its DXF entity (or a key
    name), ``closed`` if the entity itself is closed (circle, closed polyline)."""

    points: np.ndarray
    handle: str
    closed: bool = False


@dataclass
class Loop:
    """A closed polyline (first point not repeated) and the entities it came from."""

    points: np.ndarray
    handles: list[str] = field(default_factory=list)

    @property
    def name(self) -> str:
        h = self.handles
        return f"entity {h[0]}" if len(h) == 1 else f"entities {', '.join(h[:4])}" + (
            " ..." if len(h) > 4 else "")


def _dedupe(pts: np.ndarray, eps: float) -> np.ndarray:
    keep = np.ones(len(pts), bool)
    if len(pts) > 1:
        keep[1:] = np.hypot(*(np.diff(pts, axis=0).T)) > eps
    return pts[keep]


def join_pieces(pieces: list[Piece], join_tolerance: float, file=None) -> list[Loop]:
    """Closed loops from ``pieces``; GeometryError for a chain left open."""
    loops: list[Loop] = []
    eps = join_tolerance * 1e-3
    open_pieces: list[Piece] = []
    for p in pieces:
        pts = _dedupe(np.asarray(p.points, float), eps)
        if len(pts) < 2:
            continue
        gap = float(np.hypot(*(pts[-1] - pts[0])))
        if p.closed or (len(pts) > 2 and gap <= join_tolerance):
            # a closed entity repeats its first point or not (a circle's chords within
            # the join tolerance are edges, not a gap)
            if gap <= (eps if p.closed else join_tolerance):
                pts = pts[:-1]
            if len(pts) >= 3:
                loops.append(Loop(pts, [p.handle]))
            continue
        open_pieces.append(Piece(pts, p.handle))
    used = [False] * len(open_pieces)
    ends = np.array([[q.points[0], q.points[-1]] for q in open_pieces]).reshape(-1, 2, 2) \
        if open_pieces else np.zeros((0, 2, 2))
    for i, p in enumerate(open_pieces):
        if used[i]:
            continue
        used[i] = True
        chain = [p.points]
        handles = [p.handle]
        start = p.points[0]
        while True:
            cur = chain[-1][-1]
            if len(handles) > 1 and math.hypot(*(cur - start)) <= join_tolerance:
                break
            best, best_d, best_rev = -1, math.inf, False
            for j in range(len(open_pieces)):
                if used[j]:
                    continue
                d0 = math.hypot(*(ends[j, 0] - cur))
                d1 = math.hypot(*(ends[j, 1] - cur))
                if d0 < best_d:
                    best, best_d, best_rev = j, d0, False
                if d1 < best_d:
                    best, best_d, best_rev = j, d1, True
            if best < 0 or best_d > join_tolerance:
                near = ""
                if best >= 0:
                    near = (f"; the nearest free end is {best_d:.4g} away "
                            f"(entity {open_pieces[best].handle})")
                raise GeometryError(
                    f"open contour: the chain ends at ({cur[0]:.4f}, {cur[1]:.4f}), "
                    f"{math.hypot(*(cur - start)):.4g} from its start "
                    f"({start[0]:.4f}, {start[1]:.4f}) and nothing joins it within "
                    f"{join_tolerance:g}{near}", file, entity=f"entity {handles[-1]}")
            used[best] = True
            q = open_pieces[best].points
            chain.append(q[::-1] if best_rev else q)
            handles.append(open_pieces[best].handle)
        pts = np.vstack([chain[0]] + [c[1:] for c in chain[1:]])
        pts = _dedupe(pts, eps)
        if math.hypot(*(pts[-1] - pts[0])) <= join_tolerance:
            pts = pts[:-1]
        if len(pts) >= 3:
            loops.append(Loop(pts, handles))
    return loops
