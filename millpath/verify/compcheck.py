"""Round trip under cutter radius compensation (G41/G42, XY plane).

Between G41/G42 and G40 the control moves the tool centre off the programmed contour on
purpose: on the left of the direction of travel for G41, the right for G42, by the
radius of the tool the D word names (LinuxCNC's tool table diameter / 2). What the
planner expects is therefore not a point-by-point copy of its moves but the offset
path: every point the interpreted tool centre reaches for a programmed move must lie
exactly that radius from the programmed contour near it (from one of that move's
segment and its two neighbours, the entry move included, and no nearer to any of
them), and on the programmed side wherever the nearest contour point is inside a
segment. A straight offset, an intersection at an
inside corner and the arc about an outside corner all satisfy it; a wrong radius, side
or coordinate does not. (Whether the tool comes too near another, far part of the
contour is a gouge, for the gouge check, not a round-trip difference.)
One exception is LinuxCNC's own: where the contour turns by less than
:data:`millpath.model.control.CONCAVE_CORNER` radians, the control joins the two offsets
straight, without a corner arc or intersection, so the tool centre at that corner is ``r`` from the
segment before and ``r cos(turn)`` from the next one: there (and only there) the next
segment may be ``r (1 - cos(turn))`` nearer.

Checked points: the end of every interpreted motion of the block's program lines and
the middle of every arc motion (the start of the first motion is where the tool was
before the entry move). Coordinates in program units, XY only.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from millpath.model.control import CONCAVE_CORNER
from millpath.model.motion import Motion

TWO_PI = 2 * math.pi


def sweep(a0, a1, clockwise):
    """Signed angle (radians, + counter-clockwise) an arc turns from angle ``a0`` to
    ``a1``: a full turn when they are equal. Works on numpy arrays."""
    ccw = (a1 - a0) % TWO_PI
    cw = (a0 - a1) % TWO_PI
    return np.where(clockwise, -np.where(cw > 0, cw, TWO_PI), np.where(ccw > 0, ccw, TWO_PI))


@dataclass(frozen=True)
class Segment:
    """A programmed XY segment of a compensated block, on program line ``line``: a line
    from ``start`` to ``end``, or an arc about ``center`` (``clockwise`` as G2)."""

    start: tuple[float, float]
    end: tuple[float, float]
    line: int | None = None
    center: tuple[float, float] | None = None
    clockwise: bool = False


@dataclass
class _Segments:
    """The block's segments as arrays (M,): lines use ``a``/``b``, arcs ``c``, ``r``,
    ``a0`` and ``sweep`` (radians, + counter-clockwise) as well."""

    a: np.ndarray
    b: np.ndarray
    is_arc: np.ndarray
    c: np.ndarray
    r: np.ndarray
    a0: np.ndarray
    sweep: np.ndarray

    @classmethod
    def of(cls, segments: list[Segment]) -> "_Segments":
        a = np.array([s.start for s in segments], float).reshape(-1, 2)
        b = np.array([s.end for s in segments], float).reshape(-1, 2)
        is_arc = np.array([s.center is not None for s in segments], bool)
        c = np.array([s.center if s.center is not None else (0.0, 0.0) for s in segments],
                     float).reshape(-1, 2)
        r = np.hypot(*(a - c).T)
        a0 = np.arctan2(a[:, 1] - c[:, 1], a[:, 0] - c[:, 0])
        a1 = np.arctan2(b[:, 1] - c[:, 1], b[:, 0] - c[:, 0])
        cw = np.array([s.clockwise for s in segments], bool)
        return cls(a, b, is_arc, c, r, a0, sweep(a0, a1, cw))

    def tangents(self) -> tuple[np.ndarray, np.ndarray]:
        """Directions of travel (radians) at each segment's start and end."""
        line = np.arctan2(self.b[:, 1] - self.a[:, 1], self.b[:, 0] - self.a[:, 0])
        quarter = np.copysign(math.pi / 2, self.sweep)
        return (np.where(self.is_arc, self.a0 + quarter, line),
                np.where(self.is_arc, self.a0 + self.sweep + quarter, line))

    def distance(self, p: np.ndarray, j: np.ndarray):
        """For points ``p`` (K, 2) and segment indices ``j`` (K,): the distance, whether
        the nearest point is inside the segment (not an end), and the side the point is
        on (+1 left of the direction of travel, -1 right)."""
        a, b = self.a[j], self.b[j]
        d = b - a
        ll = np.einsum("ij,ij->i", d, d)
        ap = p - a
        t = np.einsum("ij,ij->i", ap, d) / np.where(ll > 0, ll, 1.0)
        inside_l = (t > 1e-9) & (t < 1 - 1e-9)
        off = ap - np.clip(t, 0.0, 1.0)[:, None] * d
        dist_l = np.hypot(off[:, 0], off[:, 1])
        side_l = np.sign(d[:, 0] * off[:, 1] - d[:, 1] * off[:, 0])
        # arcs
        rel = p - self.c[j]
        rho = np.hypot(rel[:, 0], rel[:, 1])
        ang = np.arctan2(rel[:, 1], rel[:, 0])
        sw = self.sweep[j]
        along = np.where(sw >= 0, ang - self.a0[j], self.a0[j] - ang) % TWO_PI
        inside_a = along < np.abs(sw) - 1e-12
        ends = np.minimum(np.hypot(*(p - a).T), np.hypot(*(p - b).T))
        dist_a = np.where(inside_a, np.abs(rho - self.r[j]), ends)
        # the left of a counter-clockwise arc is towards its centre
        left = np.where(sw >= 0, rho < self.r[j], rho > self.r[j])
        arc = self.is_arc[j]
        return (np.where(arc, dist_a, dist_l), np.where(arc, inside_a, inside_l),
                np.where(arc, np.where(left, 1.0, -1.0), side_l))


def _join_slack(seg: _Segments, radius: float) -> np.ndarray:
    """Per segment, how much nearer than ``radius`` the control may bring the tool
    centre: ``r (1 - cos(turn))`` at a junction joined straight (see module doc)."""
    t0, t1 = seg.tangents()
    slack = np.zeros(len(t0))
    if len(t0) > 1:
        turn = np.abs((t0[1:] - t1[:-1] + math.pi) % TWO_PI - math.pi)
        s = np.where((turn > 1e-12) & (turn <= CONCAVE_CORNER + 1e-9),
                     radius * (1 - np.cos(turn)), 0.0)
        slack[:-1] = np.maximum(slack[:-1], s)
        slack[1:] = np.maximum(slack[1:], s)
    return slack


def _points(motions: list[Motion]) -> tuple[np.ndarray, list[int]]:
    """Motion ends, and the middle of every arc in the XY plane, with their lines."""
    pts: list[tuple[float, float]] = []
    lines: list[int] = []
    for mo in motions:
        pts.append((mo.end[0], mo.end[1]))
        lines.append(mo.line)
        if mo.kind == "arc" and mo.plane == "XY" and mo.center is not None:
            cx, cy = mo.center[0], mo.center[1]
            a0 = math.atan2(mo.start[1] - cy, mo.start[0] - cx)
            a1 = math.atan2(mo.end[1] - cy, mo.end[0] - cx)
            sw = float(sweep(np.float64(a0), np.float64(a1), mo.rotation < 0))
            rr = math.hypot(mo.start[0] - cx, mo.start[1] - cy)
            am = a0 + sw / 2
            pts.append((cx + rr * math.cos(am), cy + rr * math.sin(am)))
            lines.append(mo.line)
    return np.asarray(pts, float).reshape(-1, 2), lines


def compensation_diffs(segments: list[Segment], motions: list[Motion], radius: float,
                       side: str, tol: float, where: str) -> list[str]:
    """Differences between the interpreted ``motions`` of one compensated block and the
    offset path of its programmed ``segments`` (``side`` "left" = G41, "right" = G42,
    ``radius`` in program units). ``where`` prefixes each message (the move)."""
    if not segments or not motions:
        return [f"{where}: no motion under cutter compensation"] if segments else []
    seg = _Segments.of(segments)
    slack = _join_slack(seg, radius)
    index = {s.line: k for k, s in enumerate(segments) if s.line is not None}
    pts, lines = _points(motions)
    k = np.array([index.get(ln, -1) for ln in lines], int)
    if (k < 0).any():
        first = lines[int(np.flatnonzero(k < 0)[0])]
        return [f"{where} line {first}: motion under cutter compensation on a line the "
                f"plan has no move for"]
    m = len(segments)
    best = np.full(len(pts), np.inf)
    inside = np.zeros(len(pts), bool)
    sides = np.zeros(len(pts))
    on_offset = np.zeros(len(pts), bool)
    too_near = np.zeros(len(pts), bool)
    for o in (-1, 0, 1):
        j = np.clip(k + o, 0, m - 1)
        dist, ins, sd = seg.distance(pts, j)
        on_offset |= np.abs(dist - radius) <= tol
        too_near |= radius - dist > tol + slack[j]
        better = dist < best
        best = np.where(better, dist, best)
        inside = np.where(better, ins, inside)
        sides = np.where(better, sd, sides)
    want = 1.0 if side == "left" else -1.0
    wrong_side = inside & (sides != want) & (best > tol)
    bad = ~on_offset | too_near | wrong_side
    diffs: list[str] = []
    for i in np.flatnonzero(bad)[:51]:
        x, y = pts[i]
        what = (f"on the {'right' if want > 0 else 'left'} of the contour"
                if wrong_side[i] else f"{best[i]:.6g} from the programmed contour")
        diffs.append(f"{where} line {lines[i]}: tool centre at ({x:.6g}, {y:.6g}) is "
                     f"{what}, expected {radius:.6g} on its {side} (cutter compensation)")
    return diffs
