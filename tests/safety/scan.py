"""Independent checks of a posted program's motion (used by the example tests):
safe approach after each tool change, and no straight plunge of an end mill into
material that no earlier motion has cleared."""

from __future__ import annotations

import numpy as np
from scipy.spatial import cKDTree

from millpath.model.toolpath import Move, sample_move


def tool_change_lines(program: str) -> list[int]:
    """1-based lines holding an M6."""
    out = []
    for i, ln in enumerate(program.splitlines(), 1):
        words = ln.split("(")[0].upper().split()
        if "M6" in words or "M06" in words:
            out.append(i)
    return out


def approach_violations(program: str, motions, safe_z: float) -> list[str]:
    """After each M6: the first motion must be along Z only to at least ``safe_z``, and
    no motion may change X or Y below ``safe_z`` before one did."""
    bad = []
    changes = tool_change_lines(program)
    for c in changes:
        after = [m for m in motions if m.line > c and m.kind != "dwell"]
        nxt = [x for x in changes if x > c]
        if nxt:
            after = [m for m in after if m.line < nxt[0]]
        if not after:
            continue
        first = after[0]
        if first.kind != "traverse" or first.end[2] < safe_z - 1e-9:
            bad.append(f"line {first.line}: first motion after M6 at line {c} goes to "
                       f"Z{first.end[2]:g}, below the safe height {safe_z:g}")
            continue
        # the interpreter starts the move wherever it believes the tool is: XY must not
        # change on it (the tool rises straight up)
        if abs(first.end[0] - first.start[0]) > 1e-9 or abs(first.end[1] - first.start[1]) > 1e-9:
            bad.append(f"line {first.line}: first motion after M6 at line {c} moves X/Y "
                       f"together with Z")
    return bad


def plunge_violations(motions, tools, stock_top: float, step: float = 0.5) -> list[str]:
    """Vertical feed moves of a non-drill tool ending below the stock top where no
    earlier cutting motion of a tool at least as wide swept the whole tool disc at or
    below that depth."""
    bad = []
    pts: list[np.ndarray] = []       # (x, y, z, radius) of earlier cutting samples
    tree = None
    dirty = False
    for m in motions:
        if m.kind not in ("feed", "arc", "traverse") or m.tool not in tools:
            continue
        t = tools[m.tool]
        s, e = np.asarray(m.start), np.asarray(m.end)
        vertical = m.kind == "feed" and np.hypot(*(e[:2] - s[:2])) < 1e-6 and e[2] < s[2] - 1e-9
        if vertical and t.type != "drill" and e[2] < stock_top - 1e-6:
            if dirty and pts:
                arr = np.vstack(pts)
                tree = cKDTree(arr[:, :2])
                dirty = False
            ok = False
            if tree is not None:
                idx = tree.query_ball_point(e[:2], r=max(arr[:, 3].max(), 1e-9))
                for k in idx:
                    x, y, z, r = arr[k]
                    if z <= e[2] + 1e-6 and np.hypot(x - e[0], y - e[1]) <= r - t.radius + 1e-6:
                        ok = True
                        break
            if not ok:
                bad.append(f"line {m.line}: T{m.tool} ({t.type}) plunges straight down to "
                           f"Z{e[2]:g} at X{e[0]:g} Y{e[1]:g} into uncleared material")
        if m.kind == "traverse":
            continue
        mv = Move("line" if m.kind == "feed" else "arc", tuple(m.end), 1.0,
                  center=m.center, plane=m.plane, clockwise=m.rotation < 0,
                  turns=max(1, abs(m.rotation)))
        p = sample_move(tuple(m.start), mv, step)
        pts.append(np.column_stack([p, np.full(len(p), t.radius)]))
        dirty = True
    return bad
