"""Independent checks of a posted program's motion (used by the example tests):
safe approach after each tool change, and no straight plunge of an end mill into
material that no earlier motion has cleared."""

from __future__ import annotations

import numpy as np


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


def plunge_violations(motions, tools, stock, resolution: float) -> list[str]:
    """Vertical feed moves of a non-drill tool whose bottom meets material: the Z-map
    simulation of every motion before it (millpath.simulate, independent of the
    planners) still has material more than 1 % of the tool diameter above the cutter's
    surface (tip at the move's end) within half a radius of its axis."""
    from millpath.geometry.cutter import Cutter
    from millpath.simulate.path import Segments, motion_segments
    from millpath.simulate.simulator import sweep
    from millpath.simulate.zmap import ZMap
    from millpath.simulate.approach import approach_from_above

    motions = approach_from_above(list(motions), stock.zmax)
    zmap = ZMap.from_stock(stock, resolution)
    segs = motion_segments(motions, resolution / 20.0)
    xs, ys = zmap.xs(), zmap.ys()
    bad, done = [], 0
    for k, m in enumerate(motions):
        if m.kind != "feed" or m.tool not in tools or tools[m.tool].type == "drill":
            continue
        s, e = np.asarray(m.start), np.asarray(m.end)
        if np.hypot(*(e[:2] - s[:2])) > 1e-6 or e[2] >= s[2] - 1e-9 or e[2] >= stock.zmax:
            continue
        keep = (segs.motion >= done) & (segs.motion < k)
        sweep(zmap, Segments(segs.start[keep], segs.end[keep], segs.motion[keep],
                             segs.rapid[keep], segs.tool[keep]), tools, len(motions))
        done = k
        t = tools[m.tool]
        rho = np.sqrt((xs[None, :] - e[0]) ** 2 + (ys[:, None] - e[1]) ** 2)
        near = rho <= 0.5 * t.radius
        if not near.any():
            continue
        cutter = e[2] + Cutter.of(t).height(rho[near])
        over = zmap.heights[near] - cutter
        top = float(zmap.heights[near][np.argmax(over)])
        if over.max() > 0.01 * t.diameter:
            bad.append(f"line {m.line}: T{m.tool} ({t.type}) plunges straight down to "
                       f"Z{e[2]:g} at X{e[0]:g} Y{e[1]:g} into material up to Z{top:g}")
    return bad
