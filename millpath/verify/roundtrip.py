"""Round trip: the interpreted motion of a posted program must give back the toolpath.

:func:`compare_toolpath` pairs each toolpath move with the motions the interpreter made
for the program line that carries it (see ``post_with_lines``) and lists every
difference beyond ``tol`` (job units). Moves under cutter radius compensation are moved
by the control on purpose and are not compared point by point; canned cycles are
compared by where they leave the tool.
"""

from __future__ import annotations

from collections import defaultdict

import numpy as np

from millpath.interpret.store import KINDS
from millpath.model.motion import Motion
from millpath.model import Toolpath
from millpath.model.toolpath import PLANE_AXES

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
                     motions: list[Motion], tol: float) -> list[str]:
    """Differences between the planned ``toolpath`` and interpreted ``motions``."""
    by_line, arrays = _by_line(motions)
    agree = None
    if arrays is not None:
        # an interpreter's records: straight moves checked on the arrays, the others
        # (and any that differ) one by one below
        agree = _agree(toolpath, move_lines, arrays, tol)
        by_line = _Lines(motions, arrays["line"], arrays["kind"])
    diffs: list[str] = []
    comp = "off"
    pos = None
    for i, (m, line) in enumerate(zip(toolpath.moves, move_lines)):
        if m.kind == "comp":
            comp = m.comp
            continue
        if comp != "off" or (agree is not None and agree[i]):
            pos = m.end
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
                if max(abs(g.center[a1] - m.center[a1]), abs(g.center[a2] - m.center[a2])) > tol:
                    diffs.append(f"move {i} (arc) line {line}: center {g.center} vs "
                                 f"{m.center}")
                if g.plane != m.plane or g.rotation != rot:
                    diffs.append(f"move {i} (arc) line {line}: plane/rotation "
                                 f"{g.plane}/{g.rotation} vs {m.plane}/{rot}")
        elif m.kind == "cubic":
            if len(got) != 1 or got[0].kind not in ("cubic", "nurbs"):
                diffs.append(f"move {i} (cubic) line {line}: got {[g.kind for g in got]}")
            elif got[0].kind == "cubic" and _dist(got[0].end, m.end) > tol:
                diffs.append(f"move {i} (cubic) line {line}: end {got[0].end} vs {m.end}")
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
    return diffs

