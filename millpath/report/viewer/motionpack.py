"""Interpreted motion as the viewer's arrays: one polyline through every motion.

Coordinates are the tool tip in program units (:class:`millpath.interpret.motion.Motion`).
Motion ``k`` runs along ``points[first[k] .. last[k]]`` (inclusive): straight moves are
their two end points, arcs and cubics are chords within ``chord_tol`` of the curve, a
dwell is one point. Consecutive motions share the joining point. Decimation is for
display only: arcs and cubics get a coarser chord tolerance when the polyline would
exceed ``max_points``; every motion keeps its own entry (the slider runs over all of
them) and its exact end point.

Operations: motion ``k`` belongs to the last operation whose ``first_line`` is at or
before the motion's program line.
"""

from __future__ import annotations

import bisect
import re
from dataclasses import dataclass

import numpy as np

from millpath.interpret.motion import Motion
from millpath.simulate.path import motion_points
from millpath.program import LineMap

KIND_CODES = {"traverse": 0, "feed": 1, "arc": 2, "cubic": 3, "dwell": 4, "nurbs": 5}
MAX_POINTS = 3_000_000


@dataclass
class ViewOperation:
    """A run of the program shown as one item of the operations list: a name, the tool
    it uses and the 1-based program line where it starts."""

    name: str
    tool: int
    first_line: int


@dataclass
class PackedMotion:
    """Arrays of :func:`pack_motions` (see the module docstring)."""

    points: np.ndarray        # (n, 3) float32
    first: np.ndarray         # (m,) int32
    last: np.ndarray          # (m,) int32
    kind: np.ndarray          # (m,) uint8, KIND_CODES
    feed: np.ndarray          # (m,) float32, units/min (0 for traverses and dwells)
    line: np.ndarray          # (m,) int32, 1-based program line
    op: np.ndarray            # (m,) uint16, index into the operations
    tool: np.ndarray          # (m,) uint32, tool in the spindle
    chord_tol: float          # display chord tolerance used for arcs and cubics


_OP_COMMENT = re.compile(r"^\s*\(\s*operation\s+\d+\s*:\s*(?P<name>[^)]*)\)", re.I)
_TOOL_CHANGE = re.compile(r"(?<![A-Z0-9.])T\s*(?P<t>\d+)[^;(]*?M\s*0*6(?![0-9])", re.I)


def operations_from_program(program: str, motions: list[Motion]) -> list[ViewOperation]:
    """Operations of a program read from its text: a comment ``(operation N: NAME)``
    (as millpath posts them) starts one; failing those, each tool change ``T.. M6``
    does; failing both, the whole program is one operation. The tool of each is the
    tool of its first motion."""
    starts: list[tuple[int, str]] = []
    lines = program.splitlines()
    for i, text in enumerate(lines, start=1):
        m = _OP_COMMENT.match(text)
        if m:
            starts.append((i, m.group("name").strip()))
    if not starts:
        for i, text in enumerate(lines, start=1):
            code = text.split(";", 1)[0]
            m = _TOOL_CHANGE.search(re.sub(r"\([^)]*\)", "", code))
            if m:
                starts.append((i, f"T{int(m.group('t'))}"))
    if not starts:
        starts = [(1, "program")]
    keys = [s for s, _ in starts]
    tools = [0] * len(starts)
    seen = [False] * len(starts)
    for mo in motions:
        k = max(bisect.bisect_right(keys, mo.line) - 1, 0)
        if not seen[k] and mo.kind != "dwell":
            tools[k] = mo.tool
            seen[k] = True
    return [ViewOperation(name, tools[k], line) for k, (line, name) in enumerate(starts)]


def operations_from_toolpath(toolpath, move_lines: list[int | None]) -> list[ViewOperation]:
    """Operations of a posted :class:`millpath.model.Toolpath`: each starts at the
    program line of its first move (``move_lines[i]``: line of move ``i``, as
    :func:`millpath.post.writer.post_with_lines` returns them)."""
    first = LineMap.of_toolpath(toolpath, move_lines).first_lines()
    out = [ViewOperation(o.name or o.type, o.tool, first[i])
           for i, o in enumerate(toolpath.ops) if i in first]
    return sorted(out, key=lambda o: o.first_line)


def _pack(motions: list[Motion], chord_tol: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    m = len(motions)
    first = np.empty(m, np.int32)
    last = np.empty(m, np.int32)
    flat: list[float] = []                 # x, y, z of the points, in order
    extend = flat.extend
    n = 0
    cur: tuple | None = None
    for k, mo in enumerate(motions):
        s = tuple(mo.start)
        if cur is None or s != cur:
            extend(s)
            n += 1
        first[k] = n - 1
        kind = mo.kind
        if kind == "arc" or kind == "cubic" or kind == "nurbs":
            pts = motion_points(mo, chord_tol)[1:]
            extend(pts.ravel().tolist())
            n += len(pts)
            cur = tuple(mo.end)
        elif kind == "dwell":
            cur = s
        else:
            e = tuple(mo.end)
            extend(e)
            n += 1
            cur = e
        last[k] = n - 1
    return np.asarray(flat, np.float32).reshape(-1, 3), first, last


def pack_motions(motions: list[Motion], operations: list[ViewOperation], *,
                 chord_tol: float, max_points: int = MAX_POINTS) -> PackedMotion:
    """Pack ``motions`` (program units) for the page. ``chord_tol`` is the display chord
    tolerance of arcs and cubics, doubled until the polyline has at most ``max_points``
    points (or every curve is down to its fewest chords)."""
    tol = float(chord_tol)
    while True:
        points, first, last = _pack(motions, tol)
        if len(points) <= max_points or len(points) <= 2 * len(motions) + 1:
            break
        tol *= 2.0
    keys = [o.first_line for o in operations] or [1]
    lines = np.fromiter((mo.line for mo in motions), np.int64, len(motions))
    op = np.clip(np.searchsorted(np.asarray(keys), lines, side="right") - 1, 0, None)
    return PackedMotion(
        points=points, first=first, last=last,
        kind=np.fromiter((KIND_CODES[mo.kind] for mo in motions), np.uint8, len(motions)),
        feed=np.fromiter((mo.feed if mo.kind in ("feed", "arc", "cubic", "nurbs") else 0.0
                          for mo in motions), np.float32, len(motions)),
        line=lines.astype(np.int32), op=op.astype(np.uint16),
        tool=np.fromiter((mo.tool for mo in motions), np.uint32, len(motions)),
        chord_tol=tol)
