"""Cutter offset of a linearized contour, built the way LinuxCNC compensates it.

The same programmed contour is used two ways: written with ``G41``/``G42`` so the
control offsets it, or offset here ("CAM") and written as the tool-centre path. For
the two to agree, :func:`compensate` follows LinuxCNC's rules for straight moves
(interp_convert.cc, ``convert_straight_comp1/2``; corner threshold 0.05 rad):

- first move after G41/G42: the tool ends tangent to the move's line at its end point;
- a convex corner (the tool outside the turn, turn > 0.05 rad) gets an arc of the
  tool radius about the programmed vertex;
- a concave corner (turn > 0.05 rad the other way) is trimmed to the intersection of
  the two offset lines (the previous move's end is moved back);
- a near-straight corner (|turn| <= 0.05 rad) joins the previous offset end straight
  to the next offset end;
- moving an end back past the start of its move is a gouge (LinuxCNC's error).

Side convention: ``left`` (G41) = tool left of the path seen in the direction of
travel. Angles in radians, lengths in job units, points (x, y).

:func:`reachable_contour` removes the chords a tool of radius r cannot follow (where
the contour bends round the tool tighter than r): their neighbours are extended to
meet, so the contour stays loop-free and the tool reaches as far as it can into each
corner. The removed runs are the unreachable corners.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from millpath.model.control import CONCAVE_CORNER as SMALL


class CompensationError(ValueError):
    """The contour cannot be compensated (LinuxCNC would refuse it); ``index`` is the
    programmed point where it happened."""

    def __init__(self, message: str, index: int):
        super().__init__(message)
        self.index = index


@dataclass
class Element:
    """A piece of tool-centre path: ``kind`` "line" or "arc" ending at ``end``; an arc
    turns about ``center`` (clockwise when ``clockwise``). ``index`` is the programmed
    move it belongs to."""

    kind: str
    end: tuple[float, float]
    center: tuple[float, float] | None = None
    clockwise: bool = False
    index: int = 0


def compensate(start, points, radius: float, side: str = "left",
               small: float = SMALL) -> list[Element]:
    """Tool-centre path of the straight moves ``start -> points[0] -> points[1] ...``
    made with compensation switched on just before the first move and off (G40) after
    the last, as LinuxCNC builds it.

    ``start`` is where the tool centre is when compensation starts. Raises
    CompensationError where LinuxCNC would stop with an error.
    """
    if side not in ("left", "right"):
        raise ValueError("side must be left or right")
    left = side == "left"
    r = float(radius)
    pts = np.asarray(points, float)
    out: list[Element] = []
    cx, cy = float(start[0]), float(start[1])
    px, py = float(pts[0, 0]), float(pts[0, 1])
    if math.hypot(px - cx, py - cy) <= r:
        raise CompensationError("length of cutter compensation entry move is not "
                                "greater than the tool radius", 0)
    a = math.atan2(py - cy, px - cx) + (math.pi / 2 if left else -math.pi / 2)
    ex, ey = px + r * math.cos(a), py + r * math.sin(a)
    # the queued move: direction used for the gouge check, its end, its start
    q_dir = (math.cos(a), math.sin(a))
    q_end = (ex, ey)
    q_idx = 0
    endpoint = (cx, cy)
    cx, cy = ex, ey
    opx, opy = px, py

    def flush(new_end, check: bool) -> None:
        if check:
            dot = q_dir[0] * (new_end[0] - endpoint[0]) + q_dir[1] * (new_end[1] - endpoint[1])
            if dot < 0:
                raise CompensationError("straight feed in concave corner cannot be reached "
                                        "by the tool without gouging", q_idx)
        out.append(Element("line", (float(new_end[0]), float(new_end[1])), index=q_idx))

    for i in range(1, len(pts)):
        px, py = float(pts[i, 0]), float(pts[i, 1])
        if px == opx and py == opy:
            continue
        theta = math.atan2(cy - opy, cx - opx)
        alpha = math.atan2(py - opy, px - opx)
        if left:
            if theta < alpha:
                theta += 2 * math.pi
            beta = theta - alpha - math.pi / 2
            gamma = math.pi / 2
        else:
            if alpha < theta:
                alpha += 2 * math.pi
            beta = alpha - theta - math.pi / 2
            gamma = -math.pi / 2
        ex = px + r * math.cos(alpha + gamma)
        ey = py + r * math.sin(alpha + gamma)
        mx = opx + r * math.cos(alpha + gamma)
        my = opy + r * math.sin(alpha + gamma)
        concave = beta < -small or beta > math.pi + small
        if not concave and beta > small:
            flush((cx, cy), True)
            out.append(Element("arc", (mx, my), (opx, opy), clockwise=left, index=i))
            endpoint = (mx, my)
        elif concave:
            half = (beta + math.pi) / 2.0
            if half == 0.0:
                raise CompensationError("zero degree inside corner is invalid for cutter "
                                        "compensation", i)
            retreat = r / math.tan(half)
            mx = cx + retreat * math.cos(theta + gamma)
            my = cy + retreat * math.sin(theta + gamma)
            flush((mx, my), True)
            endpoint = (mx, my)
        else:
            flush((cx, cy), False)
            endpoint = (cx, cy)
        q_dir = (px - opx, py - opy)
        q_end = (ex, ey)
        q_idx = i
        cx, cy = ex, ey
        opx, opy = px, py
    out.append(Element("line", (float(q_end[0]), float(q_end[1])), index=q_idx))
    return out


def _turn(t1: np.ndarray, t2: np.ndarray) -> float:
    """Signed turn (radians, counter-clockwise positive) from direction t1 to t2."""
    return math.atan2(t1[0] * t2[1] - t1[1] * t2[0], t1[0] * t2[0] + t1[1] * t2[1])


def _meet(p1, t1, p2, t2):
    """Intersection of the lines p1 + s t1 and p2 + u t2 (None if parallel)."""
    den = t1[0] * t2[1] - t1[1] * t2[0]
    if abs(den) < 1e-12:
        return None
    d = p2 - p1
    s = (d[0] * t2[1] - d[1] * t2[0]) / den
    return p1 + s * t1


@dataclass
class ReachableContour:
    """Result of :func:`reachable_contour`: the programmed contour ``points`` (m, 2,
    closed, last != first), ``kept`` the original chord index of each of its chords
    (chord j runs from points[j] to points[j+1]), and ``removed`` the runs of original
    chord indices the tool cannot follow (each a list)."""

    points: np.ndarray
    kept: list[int]
    removed: list[list[int]]


def reachable_contour(vertices, radius: float, side: str = "left", start: int = 0,
                      small: float = SMALL, keep: np.ndarray | None = None) -> ReachableContour:
    """Drop the chords of the closed polygon ``vertices`` that a tool of ``radius`` on
    ``side`` cannot follow without gouging; extend the neighbours to meet instead.

    Works like a stack: each chord is pushed after checking the corner with the chord
    below it (LinuxCNC's corner rules); when the corner would move the lower chord's
    offset end back past its start (a loop), the lower chord is popped and the corner
    is tried again with the one under it. ``start`` is a chord thought reachable; when
    the contour closes, its offset start is where the corner with the last chord puts
    it (a near-straight join starts it where the last offset ended, not on its own
    offset), and if that leaves it no length the whole is redone from the kept chord
    with the most room. ``keep`` (bool per chord) limits the chords tried, e.g. to
    those whose offset lies on the boundary of the eroded cavity (see
    :func:`chords_on_offset`).
    """
    v = np.asarray(vertices, float)
    n = len(v)
    t = np.roll(v, -1, axis=0) - v
    lens = np.hypot(t[:, 0], t[:, 1])
    if np.any(lens == 0):
        raise ValueError("contour has repeated vertices")
    t = t / lens[:, None]
    sgn = 1.0 if side == "left" else -1.0
    nrm = sgn * np.stack([-t[:, 1], t[:, 0]], axis=1)      # toward the tool side
    r = float(radius)
    tried: set[int] = set()
    fallback = [int(c) for c in np.argsort(-lens) if keep is None or keep[c]]
    for _ in range(8):
        tried.add(start)
        try:
            stack, room = _reach_from(v, t, nrm, r, sgn, start, small, keep)
        except CompensationError:
            stack, room = [], np.zeros(0)            # the start chord itself is cut off
        if len(room) and room[0] > 0.0:
            break
        # the start chord has no length once the closing corner is known, or it is
        # not reachable: start again from the chord with the most room (its neighbours
        # are settled), else from the longest not yet tried
        best = [stack[k][0] for k in np.argsort(-room) if stack[k][0] not in tried]
        best += [c for c in fallback if c not in tried]
        if not best:
            break
        start = int(best[0])
    if not len(room) or room[0] <= 0.0:
        raise CompensationError("the tool cannot follow the contour here: the "
                                "cavity is too narrow for it", int(start))
    # stack[0] and stack[-1] are both the start chord; programmed corner points follow
    kept = [e[0] for e in stack[:-1]]
    pts = np.array([stack[-1][1]] + [e[1] for e in stack[1:-1]])
    kept_set = set(kept)
    removed: list[list[int]] = []
    run: list[int] = []
    for idx in [(start + k) % n for k in range(n)]:
        if idx in kept_set:
            if run:
                removed.append(run)
                run = []
        else:
            run.append(idx)
    if run:
        removed.append(run)
    return ReachableContour(pts, kept, removed)


def _reach_from(v, t, nrm, r: float, sgn: float, start: int, small: float, keep):
    """One pass of :func:`reachable_contour` from chord ``start``: the stack of
    (chord, programmed start point, offset start point), the start chord again last,
    and the room (offset length less the least kept, ``min_len``) of each chord in it
    but the last, the start chord's with its offset start from the closing corner."""
    n = len(v)
    min_len = 1e-6 * r          # a kept move must keep a positive length after trimming
    order = [(start + k) % n for k in range(n)
             if keep is None or keep[(start + k) % n] or k == 0] + [start]
    # stack entries: (chord index, programmed start point, offset start point); ends[i]:
    # the offset end of stack[i]'s chord, known once the chord above it is pushed
    stack: list[tuple[int, np.ndarray, np.ndarray]] = []
    ends: list[np.ndarray] = []
    s0 = order[0]
    stack.append((s0, v[s0], v[s0] + r * nrm[s0]))
    for b in order[1:]:
        while True:
            a, pa, sa = stack[-1]
            if b == (a + 1) % n:
                corner = v[b]
            else:
                corner = _meet(v[a], t[a], v[b], t[b])
                if (corner is None or np.dot(corner - pa, t[a]) <= 0
                        or np.dot(v[(b + 1) % n] - corner, t[b]) <= 0):
                    corner = None
            ok = corner is not None
            if ok:
                turn = sgn * _turn(t[a], t[b])       # > 0: turning toward the tool side
                if turn > small:                     # concave: trim to the intersection
                    if turn > math.pi - small:
                        ok = False
                    else:
                        end_a = _meet(corner + r * nrm[a], t[a], corner + r * nrm[b], t[b])
                        ok = end_a is not None and np.dot(end_a - sa, t[a]) >= min_len
                        start_b = end_a
                elif turn < -small:                  # convex: arc about the corner
                    end_a = corner + r * nrm[a]
                    ok = np.dot(end_a - sa, t[a]) >= min_len
                    start_b = corner + r * nrm[b]
                else:                                # near straight: joined directly
                    end_a = corner + r * nrm[a]
                    ok = np.dot(end_a - sa, t[a]) >= min_len
                    start_b = end_a
            if ok:
                ends.append(end_a)
                stack.append((b, corner, start_b))
                break
            if len(stack) <= 1:
                raise CompensationError("the tool cannot follow the contour here: the "
                                        "cavity is too narrow for it", int(b))
            stack.pop()
            ends.pop()
    room = np.array([float(np.dot(ends[i] - stack[i][2], t[stack[i][0]])) - min_len
                     for i in range(len(stack) - 1)])
    if len(room):
        room[0] = float(np.dot(ends[0] - stack[-1][2], t[s0])) - min_len
    return stack, room


def sample_elements(start, elements: list[Element], step: float) -> np.ndarray:
    """Points (n, 2) along a tool-centre path, about ``step`` apart (for checks)."""
    out = [np.asarray(start, float)[None, :]]
    cur = np.asarray(start, float)
    for e in elements:
        end = np.asarray(e.end, float)
        if e.kind == "line":
            k = max(1, int(math.ceil(np.hypot(*(end - cur)) / step)))
            s = np.linspace(0, 1, k + 1)[1:, None]
            out.append(cur + (end - cur) * s)
        else:
            c = np.asarray(e.center, float)
            rad = float(np.hypot(*(cur - c)))
            a0 = math.atan2(cur[1] - c[1], cur[0] - c[0])
            a1 = math.atan2(end[1] - c[1], end[0] - c[0])
            sweep = a1 - a0
            if e.clockwise and sweep > 0:
                sweep -= 2 * math.pi
            if not e.clockwise and sweep < 0:
                sweep += 2 * math.pi
            k = max(2, int(math.ceil(abs(sweep) * rad / step)))
            a = a0 + sweep * np.linspace(0, 1, k + 1)[1:]
            out.append(np.stack([c[0] + rad * np.cos(a), c[1] + rad * np.sin(a)], axis=1))
        cur = end
    return np.vstack(out)


def chords_on_offset(vertices, radius: float, side: str, eroded, slack: float) -> np.ndarray:
    """True for each chord of the closed polygon ``vertices`` whose offset by ``radius``
    (toward ``side``) touches the boundary of ``eroded`` (the cavity eroded by the
    radius, a shapely geometry) within ``slack`` at its middle or at either end."""
    v = np.asarray(vertices, float)
    w = np.roll(v, -1, axis=0)
    t = w - v
    t /= np.hypot(t[:, 0], t[:, 1])[:, None]
    sgn = 1.0 if side == "left" else -1.0
    nrm = sgn * np.stack([-t[:, 1], t[:, 0]], axis=1) * radius
    ok = np.zeros(len(v), bool)
    for f in (0.5, 0.02, 0.98):
        p = v + (w - v) * f + nrm
        ok |= boundary_distance(eroded, p) <= slack
    return ok


def boundary_distance(geom, points) -> np.ndarray:
    """Distance (n,) from each point (n, 2) to the boundary of the shapely area
    ``geom``, through a search tree over the boundary's segments (fast for long
    outlines)."""
    import shapely
    rings = []
    for g in getattr(geom, "geoms", [geom]):
        if g.is_empty:
            continue
        rings.append(np.asarray(g.exterior.coords))
        rings.extend(np.asarray(h.coords) for h in g.interiors)
    pts = np.asarray(points, float).reshape(-1, 2)
    if not rings:
        return np.full(len(pts), np.inf)
    segs = np.concatenate([np.stack([c[:-1], c[1:]], axis=1) for c in rings])
    tree = shapely.STRtree(shapely.linestrings(segs))
    _, dist = tree.query_nearest(shapely.points(pts), return_distance=True, all_matches=False)
    return dist
