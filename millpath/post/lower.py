"""A tool path rewritten into what a control dialect accepts, the same cut by other means:

- cubic splines (G5) -> straight lines within the tolerance of the curve (halved until
  flat);
- canned drilling cycles the dialect lacks -> the rapids, feeds and dwells LinuxCNC's
  cycle makes (:func:`cycle_moves`);
- arcs of several turns (a P word) -> one arc per turn, the helix's rise shared by angle.

Cutter radius compensation cannot be rewritten without the tool's offset path: a
dialect without it is refused (plan the operation with ``compensation = "cam"``).
Each rewrite is named once in the returned list, for the report.
"""

from __future__ import annotations

import math
from dataclasses import replace

from millpath.model.dialect import Dialect
from millpath.model.toolpath import PLANE_AXES, Move, Toolpath
from millpath.model.units import length_scale


def lower(tp: Toolpath, d: Dialect, tolerance: float) -> tuple[Toolpath, list[str]]:
    """``tp`` with what ``d`` lacks rewritten (see the module docstring); ``tolerance``:
    how far lines may stray from a spline (tool path units). Returns the tool path and
    what was rewritten; ValueError for what cannot be."""
    done: list[str] = []
    out: list[Move] = []
    pos: tuple[float, float, float] | None = None
    initial: float | None = None           # the initial level of a run of cycles

    def note(what: str) -> None:
        if what not in done:
            done.append(what)

    key = None
    for m in tp.moves:
        if m.kind != "drill" or _key(m) != key:
            initial = None              # a new run of cycles (the post writes G80 first)
        key = _key(m) if m.kind == "drill" else None
        if m.kind == "comp" and not d.cutter_comp:
            raise ValueError(f"{d.title} has no cutter radius compensation (G41/G42): "
                             "plan the operation with compensation = \"cam\"")
        if m.kind == "cubic" and not d.g5 and pos is not None:
            out.extend(_spline_lines(pos, m, tolerance))
            note(f"G5 splines written as lines within {tolerance:g} ({d.title} has no G5)")
        elif m.kind == "drill" and m.cycle not in d.cycles and pos is not None:
            if initial is None:
                initial = pos[2]
            moves = cycle_moves(pos, m, initial, tp.units)
            out.extend(moves)
            note(f"{m.cycle} cycles written as moves ({d.title} has no {m.cycle})")
            pos = moves[-1].end
            continue
        elif m.kind == "arc" and m.turns > 1 and not d.arc_turns and pos is not None:
            out.extend(_turns(pos, m))
            note(f"arcs of several turns written one turn per arc ({d.title} has no P "
                 "word on arcs)")
        else:
            out.append(m)
        if m.kind != "comp":
            pos = m.end
    if not done:
        return tp, []
    return replace(tp, moves=out), done


def _key(m: Move) -> tuple:
    """What a run of canned cycles shares (the post starts a new run when it changes)."""
    return (m.cycle, m.end[2], m.r_plane, m.peck, m.dwell, m.retract_initial, m.feed)


def _spline_lines(p0, m: Move, tol: float) -> list[Move]:
    """Lines through points of the cubic from ``p0``, halving it (de Casteljau) until
    each piece's control points lie within ``tol`` of its chord: a cubic lies in the
    hull of its control points, so the chord is then within ``tol`` of the piece."""
    assert m.c1 is not None and m.c2 is not None
    P = ((p0[0], p0[1]), m.c1, m.c2, (m.end[0], m.end[1]))
    ends: list[tuple[float, float]] = []
    stack = [(P, 0)]
    while stack:                        # depth first, first half on top: in order
        q, depth = stack.pop()
        if depth >= 24 or _flat(q, tol):
            ends.append(q[3])
            continue
        a, b = _halves(q)
        stack.append((b, depth + 1))
        stack.append((a, depth + 1))
    out = [Move("line", (x, y, m.end[2]), m.feed, m.op) for x, y in ends[:-1]]
    out.append(Move("line", m.end, m.feed, m.op))
    return out


def _flat(q, tol: float) -> bool:
    (x0, y0), (x3, y3) = q[0], q[3]
    dx, dy = x3 - x0, y3 - y0
    L = math.hypot(dx, dy)
    for x, y in (q[1], q[2]):
        if L > 1e-12:
            d = abs((x - x0) * dy - (y - y0) * dx) / L
            t = ((x - x0) * dx + (y - y0) * dy) / (L * L)
            if t < 0 or t > 1:          # beyond the chord's ends: the distance to them
                d = math.hypot(x - (x0 if t < 0 else x3), y - (y0 if t < 0 else y3))
        else:
            d = math.hypot(x - x0, y - y0)
        if d > tol:
            return False
    return True


def _halves(q):
    def mid(a, b):
        return ((a[0] + b[0]) / 2, (a[1] + b[1]) / 2)
    p01, p12, p23 = mid(q[0], q[1]), mid(q[1], q[2]), mid(q[2], q[3])
    p012, p123 = mid(p01, p12), mid(p12, p23)
    c = mid(p012, p123)
    return (q[0], p01, p012, c), (c, p123, p23, q[3])


def cycle_moves(pos, m: Move, initial: float, units: str) -> list[Move]:
    """The moves of canned cycle ``m`` (XY plane) from ``pos`` as LinuxCNC makes them;
    ``initial``: the Z where the run of cycles began (G98 returns there, at least to R).

    If the initial Z is below R, rapid up to R first; rapid in XY at the clearance
    height, down to R; then feed to the bottom (G83: pecks of ``peck``, each followed by
    a rapid back to R and down to 0.010 in above the depth reached; G73: a 0.010 in
    back-off after each peck), dwell (G82, G89), and leave: rapid to the clearance (G81,
    G82, G83, G73), feed to R then rapid (G85), feed (G89)."""
    x, y, bottom = m.end
    r = m.r_plane
    z = pos[2]
    old = initial
    out: list[Move] = []

    def go(kind: str, zz: float, xx: float = x, yy: float = y) -> None:
        out.append(Move(kind, (xx, yy, zz), m.feed if kind == "line" else 0.0, m.op))

    if old < r:                         # preliminary motion up to R
        go("rapid", r, pos[0], pos[1])
        old = z = r
    clear = old if m.retract_initial else r
    if z > r:
        go("rapid", z)
    else:
        go("rapid", clear)
    go("rapid", r)
    c = m.cycle
    if c in ("G81", "G82"):
        go("line", bottom)
        if c == "G82" and m.dwell > 0:
            out.append(Move("dwell", (x, y, bottom), 0.0, m.op, dwell=m.dwell))
        go("rapid", clear)
    elif c in ("G85", "G89"):
        go("line", bottom)
        if c == "G89" and m.dwell > 0:
            out.append(Move("dwell", (x, y, bottom), 0.0, m.op, dwell=m.dwell))
        go("line", r if c == "G85" else clear)
        if c == "G85":
            go("rapid", clear)
    elif c in ("G83", "G73"):
        q = m.peck
        if q <= 0:
            raise ValueError(f"{c} needs a positive peck increment")
        delta = 0.010 * length_scale("inch", units)
        depth = r - q
        while depth > bottom:
            go("line", depth)
            if c == "G83":
                go("rapid", r)
            go("rapid", depth + delta)
            depth -= q
        go("line", bottom)
        go("rapid", clear)
    else:
        raise ValueError(f"unknown drilling cycle {c!r}")
    return [mv for i, mv in enumerate(out)
            if i == 0 or mv.end != out[i - 1].end or mv.kind != out[i - 1].kind
            or mv.kind == "dwell"]


def _turns(p0, m: Move) -> list[Move]:
    """An arc of ``m.turns`` turns from ``p0`` as that many arcs: full turns first, each
    rising its share of the helix by angle, then the rest to the end."""
    a1, a2, an = PLANE_AXES[m.plane]
    c = m.center
    assert c is not None
    t0 = math.atan2(p0[a2] - c[a2], p0[a1] - c[a1])
    t1 = math.atan2(m.end[a2] - c[a2], m.end[a1] - c[a1])
    sweep = (t0 - t1) if m.clockwise else (t1 - t0)
    sweep %= 2 * math.pi
    if sweep < 1e-12:
        sweep = 2 * math.pi
    total = sweep + 2 * math.pi * (m.turns - 1)
    out = []
    for k in range(1, m.turns):
        end = list(p0)
        end[an] = p0[an] + (m.end[an] - p0[an]) * (2 * math.pi * k / total)
        out.append(replace(m, end=tuple(end), turns=1))
    out.append(replace(m, turns=1))
    return out
