"""Compensated runs: G0-G3 lines under G41/G42 in G17, executed with the whole state in
local variables (the hot loop of a compensated program).

The same computation as :class:`millpath.interpret.comp.Compensation`'s
``straight2``, ``arc2`` and ``move_endpoint_and_flush`` (LinuxCNC's
convert_straight_comp2, convert_arc_comp2, move_endpoint_and_flush) for the usual case,
XY with at most one queued move, in one function: the corners' geometry is the
executor's own (:mod:`millpath.interpret.corners`, arc centers and checks from
:mod:`millpath.interpret.arcs`); the queue handling is written out, with no method
calls, lists or queue entries per move. The queued move lives in a handful of locals and
goes back to ``machine.queue`` (its list format) when the run ends.

A line this code does not take (another shape, another plane, a zero-length move, a
second queued move) or one that would fail (any G-code error: gouges, bad arcs) ends
the run *before* anything of that line is changed or recorded, so the machine's own
code executes it from the same state and raises the same error: behaviour and
messages are the machine's; only the time differs. Lengths are program units.
"""

from __future__ import annotations

from math import atan2, hypot

from millpath.interpret.arcs import (RADIUS_TOLERANCE, SPIRAL_TOLERANCE, arc_center_r,
                                     check_arc)
from millpath.interpret.comp import LEFT
from millpath.interpret.corners import CONCAVE, CONVEX, TWO_PI, arc_corner, straight_corner
from millpath.interpret.errors import GCodeError
from millpath.interpret.store import KIND_CODE, PACK

T_ARC = KIND_CODE["arc"]
#: queued move kinds (``machine.queue`` entries start with "S" or "A")
NONE, STRAIGHT, ARC = 0, 1, 2


def comp_run(m, lines: list[str], k: int, end_k: int, first, second, base: int) -> int:
    """Execute ``lines[k:end_k]`` on machine ``m`` while they are compensated G0-G3 moves
    in G17 (``first``, ``second``: the fast path's line regexes, groups
    (g, x, y, z, i, j, k, r, f)); return the index of the first line not executed.
    Line ``k`` is source line ``base + k + 1``. Call only with compensation on and past
    its entry move (``comp_side``, ``comp_radius > 0``, not ``comp_first``)."""
    if (m.plane != "XY" or not m.dist_abs or m.feed_mode != 0 or len(m.comp.queue) > 1):
        return k
    queue = m.comp.queue
    qt = NONE
    qkind = qline = qturn = qstate = 0
    qa = qb = qx = qy = qz = qc1 = qc2 = qfeed = qd2 = 0.0
    if queue:
        q = queue[0]
        if q[0] == "S":
            qt = STRAIGHT
            _, qkind, qline, qa, qb, qd2, qx, qy, qz, qfeed, qstate = q
        elif q[0] == "A":
            qt = ARC
            _, qline, qa, qx, qy, qc1, qc2, qturn, qz, qfeed, qstate = q
            if qturn != 1 and qturn != -1:
                return k                           # a queued P-turn arc: the machine's code
        else:
            return k                               # a queued dwell: the machine's code
    cx, cy, cz = m.cur
    px, py, pz = m.comp.prog
    ox, oy, oz = m.out
    e0, e1 = m.comp.endpoint
    evalid = m.comp.endpoint_valid
    feed_rate = m.feed_rate
    mode = m.motion_mode
    ijk_ok = not m.ijk_abs                        # arcs: only incremental I/J
    arcs_ok = ijk_ok and not m.comp.arc_not_allowed
    side = m.comp.side
    left = side == LEFT
    radius = m.comp.radius
    units = m.units
    rtol = RADIUS_TOLERANCE[units]
    stol = SPIRAL_TOLERANCE[units]
    slack = 0.0254 if units == "mm" else 0.001     # rs274 2.9's arc end check
    state = m.state_index
    corner_turn = -1 if left else 1
    buf = m.store.buf
    pack = PACK
    start = k
    try:
        while k < end_k:
            line = lines[k]
            mt = first(line)
            if mt is None:
                mt = second(line)
                if mt is None:
                    return k
            g, x, y, z, i, j, kk, r, f = mt.groups()
            if g is None:
                if x is None and y is None and z is None:
                    return k
                code = mode
            else:
                code = (ord(g) - 48) * 10
            if kk is not None or (f is not None and f[0] == "-"):
                return k
            fr = feed_rate if f is None else float(f)
            ex = px if x is None else float(x)
            ey = py if y is None else float(y)
            ez = pz if z is None else float(z)
            n = base + k + 1
            # Each move decides (1) where the queued move ends: ``ux, uy`` (the queued
            # move is checked there first when ``check``), (2) a corner move to
            # ``mid_x, mid_y``: 0 none, 1 arc, 2 traverse, (3) the new end point
            # (``set_end``: ``ne0, ne1``), (4) the new current point ``nx, ny``.
            if code == 0 or code == 10:
                # --- convert_straight_comp2 ---------------------------------------
                if i is not None or j is not None or r is not None:
                    return k
                if code == 10:
                    if fr == 0.0:
                        return k
                    mfeed = fr
                else:
                    mfeed = 0.0
                if ey == py and ex == px:
                    return k                       # queued without a flush: the machine's
                shape, ux, uy, nx, ny = straight_corner(left, radius, cx, cy, px, py, ex, ey,
                                                        qturn, qx, qy, qc1, qc2)
                if shape == CONVEX:
                    # flush to the current point, then an arc around the programmed
                    # corner (a traverse for G0)
                    mid_x, mid_y = ux, uy
                    ux, uy = cx, cy
                    check = qt != NONE
                    corner = 1 if code == 10 else 2
                    set_end, ne0, ne1 = True, mid_x, mid_y
                elif shape == CONCAVE:
                    # flush to a trimmed point
                    check = qt != NONE
                    corner = 0
                    set_end, ne0, ne1 = check, ux, uy      # unchanged with nothing queued
                else:
                    # dequeue as it is, the end point is the current point
                    ux, uy = qx, qy
                    check = False
                    corner = 0
                    set_end, ne0, ne1 = True, cx, cy
            elif code == 20 or code == 30:
                # --- convert_arc_comp2 --------------------------------------------
                if not arcs_ok or (r is None) == (i is None and j is None):
                    return k
                if fr == 0.0:
                    return k
                mfeed = fr
                if r is not None:
                    if x is None and y is None:
                        return k
                    centerx, centery = arc_center_r(code == 20, units, px, py, ex, ey,
                                                    float(r))
                else:
                    centerx = px if i is None else px + float(i)
                    centery = py if j is None else py + float(j)
                    check_arc("XY", px, py, centerx, centery, ex, ey, rtol, stol)
                turn = -1 if code == 20 else 1
                shape, ux, uy, nx, ny = arc_corner(left, radius, code == 30, turn, cx, cy,
                                                   px, py, ex, ey, centerx, centery, qturn,
                                                   qx, qy, qc1, qc2)
                if shape == CONCAVE:
                    # flush to a trimmed point
                    check = qt != NONE
                    corner = 0
                    set_end, ne0, ne1 = check, ux, uy
                else:
                    # convex (a corner arc) or tangent: dequeue as it is
                    check = False
                    if shape == CONVEX:
                        corner = 1
                        mid_x, mid_y = ux, uy
                        set_end, ne0, ne1 = True, mid_x, mid_y
                    else:
                        corner = 0
                        set_end, ne0, ne1 = True, cx, cy
                    ux, uy = qx, qy
            else:
                return k
            if check:
                # move_endpoint_and_flush(ux, uy): the queued move's checks
                if qt == STRAIGHT:
                    if evalid and qa * (ux - e0) + qb * (uy - e1) < 0:
                        return k
                else:
                    if abs(hypot(qx - qc1, qy - qc2) - hypot(ux - qc1, uy - qc2)) > 0.01:
                        return k
                    if qa and evalid:
                        a0 = atan2(e1 - qc2, e0 - qc1)
                        a1 = atan2(uy - qc2, ux - qc1)
                        if qturn > 0:
                            if a1 <= a0:
                                a1 += TWO_PI
                        elif a0 <= a1:
                            a0 += TWO_PI
                        if abs(a1 - a0) > abs(qa) + slack:
                            return k
            # --- commit: nothing below can fail -----------------------------------
            if qt == STRAIGHT:
                buf += pack(ox, oy, oz, ux, uy, qz, qfeed, 0.0, 0.0, 0.0,
                            qkind, qline, 0, 0, qstate)
                ox, oy, oz = ux, uy, qz
            elif qt == ARC:
                buf += pack(ox, oy, oz, ux, uy, qz, qfeed, qc1, qc2, oz,
                            T_ARC, qline, qturn, 0, qstate)
                ox, oy, oz = ux, uy, qz
            if corner == 1:
                buf += pack(ox, oy, oz, mid_x, mid_y, cz, mfeed, px, py, oz, T_ARC, n,
                            corner_turn, 0, state)
                ox, oy, oz = mid_x, mid_y, cz
            elif corner == 2:
                buf += pack(ox, oy, oz, mid_x, mid_y, cz, 0.0, 0.0, 0.0, 0.0, 0, n, 0, 0,
                            state)
                ox, oy, oz = mid_x, mid_y, cz
            if set_end:
                e0, e1 = ne0, ne1
                evalid = True
            qline = n
            qstate = state
            qz = ez
            qfeed = mfeed
            qx, qy = nx, ny
            if code <= 10:
                qt = STRAIGHT
                qturn = 0
                qkind = 1 if code == 10 else 0
                qa, qb, qd2 = ex - px, ey - py, ez - pz
                arcs_ok = ijk_ok
            else:
                qt = ARC
                qturn = turn
                qc1, qc2 = centerx, centery
                # find_turn(px, py, centerx, centery, turn, ex, ey), written out
                a0 = atan2(py - centery, px - centerx)
                a1 = atan2(ey - centery, ex - centerx)
                if turn > 0:
                    if a1 <= a0:
                        a1 += TWO_PI
                else:
                    if a0 <= a1:
                        a0 += TWO_PI
                qa = (a1 - a0) + 0.0
            feed_rate = fr
            mode = code
            cx, cy, cz = nx, ny, ez
            px, py, pz = ex, ey, ez
            k += 1
        return k
    except GCodeError:
        return k                # a corner or arc the tool cannot cut: the machine's error
    finally:
        if k > start:
            m.cur = [cx, cy, cz]
            m.comp.prog = [px, py, pz]
            m.out = [ox, oy, oz]
            m.comp.endpoint = [e0, e1]
            m.comp.endpoint_valid = evalid
            m.feed_rate = feed_rate
            m.motion_mode = mode
            m.cycles.il_flag = False
            m.comp.arc_not_allowed = False      # arcs ran only when allowed; a straight allows
            if qt == STRAIGHT:
                m.comp.queue = [["S", qkind, qline, qa, qb, qd2, qx, qy, qz, qfeed, qstate]]
            elif qt == ARC:
                m.comp.queue = [["A", qline, qa, qx, qy, qc1, qc2, qturn, qz, qfeed, qstate]]
            else:
                m.comp.queue = []

