"""Round trip: the interpreted motion of a posted program must give back the toolpath.

:func:`compare_toolpath` pairs each toolpath move with the motions the interpreter made
for the program line that carries it (see ``post_with_lines``) and lists every
difference beyond ``tol`` (job units). Moves under cutter radius compensation are moved
by the control on purpose: given the tools' ``radii``, their motion is compared with the
offset path the planner expects (:mod:`millpath.verify.compcheck`), else not at all.
G5 cubics are compared by end point and both control points; canned cycles by where
they leave the tool.
"""

from __future__ import annotations

from collections import defaultdict

import numpy as np

from millpath.interpret.store import KINDS
from millpath.model.motion import Motion
from millpath.model import Toolpath
from millpath.model.toolpath import PLANE_AXES, Move, arc_geometry
from millpath.verify.compcheck import Segment, compensation_diffs

_KIND = {"rapid": "traverse", "line": "feed", "arc": "arc", "cubic": "cubic"}
_STRAIGHT = {"rapid": KINDS.index("traverse"), "line": KINDS.index("feed")}


class _Lines:
    """The motions of a program line, looked up on an interpreter's arrays."""

    def __init__(self, motions, line: np.ndarray, kind: np.ndarray) -> None:
        keep = np.flatnonzero(kind != KINDS.index("dwell"))
        order = np.argsort(line[keep], kind="stable")
        self.index = keep[order]
        self.line = line[keep][order]
        self.motions = motions

    def get(self, line: int, default):
        a, b = np.searchsorted(self.line, [line, line + 1])
        return [self.motions[int(k)] for k in self.index[a:b]] if b > a else default


def _dist(a, b) -> float:
    return max(abs(p - q) for p, q in zip(a, b))


def _segment(m: Move, start, line: int | None) -> Segment:
    if m.kind == "arc" and m.plane == "XY" and m.center is not None:
        return Segment((start[0], start[1]), (m.end[0], m.end[1]), line,
                       (m.center[0], m.center[1]), m.clockwise)
    return Segment((start[0], start[1]), (m.end[0], m.end[1]), line)


def _arc_off(m: Move, start, g: Motion, a1: int, a2: int, samples: int = 33) -> float:
    """How far the planned arc ``m`` (from ``start``; the planned centre) lies from the
    interpreted arc ``g``'s circle, at ``samples`` points of its sweep (in its plane).
    Not the distance between the centres: on a short chord the post's centre, placed
    for the written (rounded) end points, may move along the chord's bisector by many
    times the rounding while the arc itself moves by about the rounding. Without a
    known start, the centres are compared; centres that agree within the tolerance pass
    too (an interpreter printing few decimals rounds its start, end and centre)."""
    centres = max(abs(g.center[a1] - m.center[a1]), abs(g.center[a2] - m.center[a2]))
    if start is None:
        return centres
    r, a0, sweep, _ = arc_geometry(start, m)
    a = a0 + sweep * np.linspace(0.0, 1.0, samples)
    px, py = m.center[a1] + r * np.cos(a), m.center[a2] + r * np.sin(a)
    gc = np.array([g.center[a1], g.center[a2]])
    gr = np.hypot(g.start[a1] - gc[0], g.start[a2] - gc[1])
    return min(centres, float(np.max(np.abs(np.hypot(px - gc[0], py - gc[1]) - gr))))


def _by_line(motions) -> tuple[dict[int, list[Motion]] | None, np.ndarray | None]:
    """Motions of each program line (dwells left out), and for an interpreter's
    ``MotionList`` the arrays of :func:`_agree` (None for other sequences)."""
    arrays = getattr(motions, "arrays", None)
    if arrays is None or getattr(motions, "base", 1) != 0:
        by_line: dict[int, list[Motion]] = defaultdict(list)
        for mo in motions:
            if mo.kind != "dwell":
                by_line[mo.line].append(mo)
        return by_line, None
    return None, arrays()


def _agree(toolpath: Toolpath, move_lines, a: dict, tol: float) -> np.ndarray:
    """Per move: a straight move whose line made exactly one motion, of its kind, ending
    within ``tol`` of it (what the general comparison would pass without a word)."""
    n = len(toolpath.moves)
    kind = np.array([_STRAIGHT.get(m.kind, -1) for m in toolpath.moves], np.int64)
    line = np.array([-1 if v is None else v for v in move_lines], np.int64)
    end = np.array([m.end for m in toolpath.moves], float).reshape(n, 3)
    keep = a["kind"] != KINDS.index("dwell")
    mline = a["line"][keep].astype(np.int64)
    if not len(mline) or not n:
        return np.zeros(n, bool)
    top = int(max(mline.max(), line.max())) + 1
    count = np.bincount(mline, minlength=top)
    first = np.full(top, -1, np.int64)
    first[mline[::-1]] = np.arange(len(mline))[::-1]
    ok = (kind >= 0) & (line >= 0)
    ln = np.where(ok, line, 0)
    k = first[ln]
    ok &= (count[ln] == 1) & (k >= 0)
    k = np.where(ok, k, 0)
    ok &= a["kind"][keep][k] == kind
    ok &= np.abs(a["end"][keep][k] - end).max(axis=1) <= tol
    return ok


def compare_toolpath(toolpath: Toolpath, move_lines: list[int | None],
                     motions: list[Motion], tol: float,
                     radii: dict[int, float] | None = None) -> list[str]:
    """Differences between the planned ``toolpath`` and interpreted ``motions``.

    ``radii``: tool number -> radius in the toolpath's units, as the interpreter's tool
    table has it; with it, moves under G41/G42 are checked against the offset path of
    the programmed contour, without it they are not compared."""
    by_line, arrays = _by_line(motions)
    agree = None
    if arrays is not None:
        # an interpreter's records: straight moves checked on the arrays, the others
        # (and any that differ) one by one below
        agree = _agree(toolpath, move_lines, arrays, tol)
        by_line = _Lines(motions, arrays["line"], arrays["kind"])
    diffs: list[str] = []
    comp, comp_d, comp_at = "off", 0, 0
    block: list[Segment] = []
    pos = None
    for i, (m, line) in enumerate(zip(toolpath.moves, move_lines)):
        if m.kind == "comp":
            if comp != "off" and radii is not None:
                diffs += _block_diffs(block, by_line, radii, comp, comp_d, tol, comp_at)
            comp, comp_d, comp_at = m.comp, m.comp_d, i
            block = []
            continue
        if comp != "off":
            if pos is not None and m.kind in ("line", "arc"):
                block.append(_segment(m, pos, line))
            pos = m.end
            continue
        if m.kind == "dwell" or (agree is not None and agree[i]):
            pos = m.end                 # a dwell stands where the tool is
            continue
        got = by_line.get(line, []) if line is not None else []
        if m.kind in ("rapid", "line"):
            if not got:
                if pos is not None and _dist(pos, m.end) > tol:
                    diffs.append(f"move {i} ({m.kind}): no motion at line {line}")
            elif len(got) != 1 or got[0].kind != _KIND[m.kind]:
                diffs.append(f"move {i} ({m.kind}) line {line}: got "
                             f"{[g.kind for g in got]}")
            elif _dist(got[0].end, m.end) > tol:
                diffs.append(f"move {i} ({m.kind}) line {line}: end {got[0].end} "
                             f"vs planned {m.end}")
        elif m.kind == "arc":
            if len(got) != 1 or got[0].kind != "arc":
                diffs.append(f"move {i} (arc) line {line}: got {[g.kind for g in got]}")
            else:
                g = got[0]
                a1, a2, _ = PLANE_AXES[m.plane]
                rot = -m.turns if m.clockwise else m.turns
                if _dist(g.end, m.end) > tol:
                    diffs.append(f"move {i} (arc) line {line}: end {g.end} vs {m.end}")
                assert m.center is not None and g.center is not None
                off = _arc_off(m, pos, g, a1, a2)
                if off > tol:
                    diffs.append(f"move {i} (arc) line {line}: center {g.center} vs "
                                 f"{m.center}, the arc {off:.4g} off the planned one")
                if g.plane != m.plane or g.rotation != rot:
                    diffs.append(f"move {i} (arc) line {line}: plane/rotation "
                                 f"{g.plane}/{g.rotation} vs {m.plane}/{rot}")
        elif m.kind == "cubic":
            if len(got) != 1 or got[0].kind not in ("cubic", "nurbs"):
                diffs.append(f"move {i} (cubic) line {line}: got {[g.kind for g in got]}")
            elif got[0].kind == "cubic":
                g = got[0]
                if _dist(g.end, m.end) > tol:
                    diffs.append(f"move {i} (cubic) line {line}: end {g.end} vs {m.end}")
                assert m.c1 is not None and m.c2 is not None
                if g.controls is None or max(_dist(g.controls[0], m.c1),
                                             _dist(g.controls[1], m.c2)) > tol:
                    diffs.append(f"move {i} (cubic) line {line}: control points "
                                 f"{g.controls} vs {(m.c1, m.c2)}")
        elif m.kind == "drill":
            if not got:
                diffs.append(f"move {i} (drill) line {line}: no motion")
            else:
                bottom = min(g.end[2] for g in got)
                if abs(bottom - m.end[2]) > tol or _dist(got[-1].end[:2], m.end[:2]) > tol:
                    diffs.append(f"move {i} (drill) line {line}: hole at "
                                 f"{got[-1].end[:2]} to {bottom} vs {m.end}")
        if m.kind == "drill" and got:
            pos = got[-1].end
        else:
            pos = m.end
        if len(diffs) > 50:
            diffs.append("... (more differences not listed)")
            break
    if comp != "off" and radii is not None and len(diffs) <= 50:
        diffs += _block_diffs(block, by_line, radii, comp, comp_d, tol, comp_at)
    return diffs


def _block_diffs(block: list[Segment], by_line, radii: dict[int, float], side: str,
                 d: int, tol: float, at: int) -> list[str]:
    """One compensated block's motion (``by_line``: line -> motions) against the offset
    of its programmed contour."""
    where = f"move {at} (G{41 if side == 'left' else 42} D{d})"
    if d not in radii:
        return [f"{where}: tool {d} is not in the tool table"]
    lines = dict.fromkeys(s.line for s in block if s.line is not None)
    got = [mo for ln in lines for mo in by_line.get(ln, [])]
    return compensation_diffs(block, got, radii[d], side, tol, where)

