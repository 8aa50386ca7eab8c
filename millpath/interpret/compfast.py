"""Compensated runs: G0-G3 lines under G41/G42 in G17, executed with the whole state in
local variables (the hot loop of a compensated program).

The same computation as :class:`millpath.interpret.comp.Compensation`'s
``straight2``, ``arc2`` and ``move_endpoint_and_flush`` (LinuxCNC's
convert_straight_comp2, convert_arc_comp2, move_endpoint_and_flush) for the usual case,
XY with at most one queued move, written out in one function: no method calls, lists or
queue entries per move. The queued move lives in a handful of locals and goes back to
``machine.queue`` (its list format) when the run ends.

A line this code does not take (another shape, another plane, a zero-length move, a
second queued move) or one that would fail (any G-code error: gouges, bad arcs) ends
the run *before* anything of that line is changed or recorded, so the machine's own
code executes it from the same state and raises the same error: behaviour and
messages are the machine's; only the time differs. Lengths are program units.
"""

from __future__ import annotations

from math import acos, asin, atan2, cos, hypot, pi, sin, tan

from millpath.interpret.arcs import (RADIUS_TOLERANCE, SPIRAL_RELATIVE, SPIRAL_TOLERANCE,
                                     TINY)
from millpath.interpret.comp import LEFT, RIGHT, SMALL
from millpath.interpret.store import KIND_CODE, PACK

T_ARC = KIND_CODE["arc"]
HALF_PI = pi / 2.0
TWO_PI = 2 * pi
ONE_MINUS_TINY = 1.0 - TINY
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
    arcs_ok = not m.ijk_abs and not m.comp.arc_not_allowed
    side = m.comp.side
    left = side == LEFT
    right = side == RIGHT
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
                theta = atan2(cy - py, cx - px)
                alpha = atan2(ey - py, ex - px)
                if left:
                    if theta < alpha:
                        theta = theta + TWO_PI
                    beta = (theta - alpha) - HALF_PI
                    gamma = HALF_PI
                else:
                    if alpha < theta:
                        alpha = alpha + TWO_PI
                    beta = (alpha - theta) - HALF_PI
                    gamma = -HALF_PI
                rc = radius * cos(alpha + gamma)
                rs = radius * sin(alpha + gamma)
                nx = ex + rc
                ny = ey + rs
                if beta < -SMALL or beta > pi + SMALL:
                    concave = True
                elif (beta > pi - SMALL and qt == ARC
                      and ((right and qturn > 0) or (left and qturn < 0))):
                    concave = True
                else:
                    concave = False
                if not concave and beta > SMALL:
                    # convex corner: flush to the current point, then an arc around the
                    # programmed corner (a traverse for G0)
                    ux, uy = cx, cy
                    check = qt != NONE
                    corner = 1 if code == 10 else 2
                    mid_x = px + rc
                    mid_y = py + rs
                    set_end, ne0, ne1 = True, mid_x, mid_y
                elif concave:
                    if qt != ARC:
                        halfcorner = (beta + pi) / 2.0
                        if halfcorner == 0.0:
                            return k
                        retreat = radius / tan(halfcorner)
                        ux = cx + retreat * cos(theta + gamma)
                        uy = cy + retreat * sin(theta + gamma)
                    else:
                        oldrad = hypot(qc2 - qy, qc1 - qx)
                        base_dir = atan2(ey - py, ex - px)
                        th = base_dir + HALF_PI if qturn > 0 else base_dir - HALF_PI
                        phi = atan2(qc2 - py, qc1 - px)
                        inside = (left and qturn > 0) or (right and qturn < 0)
                        oldrad_uncomp = oldrad + radius if inside else oldrad - radius
                        d = oldrad_uncomp * cos(th - phi)
                        if inside:
                            lv = (d - radius) / oldrad
                            if lv > 1.0 or lv < -1.0:
                                return k
                            if qturn > 0:
                                ang = -acos(lv) + th + pi
                            else:
                                ang = acos(lv) + th + pi
                        else:
                            lv = (d + radius) / oldrad
                            if lv > 1.0 or lv < -1.0:
                                return k
                            if qturn > 0:
                                ang = acos(lv) + th + pi
                            else:
                                ang = -acos(lv) + th + pi
                        ux = qc1 + oldrad * cos(ang)
                        uy = qc2 + oldrad * sin(ang)
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
                    # arc_center_r(code == 20, units, px, py, ex, ey, R), written out;
                    # its errors go to the machine's code
                    if ex == px and ey == py:
                        return k
                    radius_word = float(r)
                    abs_r = abs(radius_word)
                    mx = (ex + px) / 2.0
                    my = (ey + py) / 2.0
                    half = hypot(mx - ex, my - ey)
                    if half - abs_r > rtol:
                        return k
                    if abs_r == 0.0 or half / abs_r > ONE_MINUS_TINY:
                        half = abs_r
                    theta = atan2(ey - py, ex - px)
                    if ((code == 20 and radius_word > 0)
                            or (code != 20 and radius_word < 0)):
                        theta = theta - HALF_PI
                    else:
                        theta = theta + HALF_PI
                    off = abs_r * cos(asin(half / abs_r) if abs_r else 0.0)
                    centerx = mx + off * cos(theta)
                    centery = my + off * sin(theta)
                else:
                    centerx = px if i is None else px + float(i)
                    centery = py if j is None else py + float(j)
                    r1 = hypot(centerx - px, centery - py)
                    r2 = hypot(centerx - ex, centery - ey)
                    if r1 < rtol or r2 < rtol:
                        return k
                    abs_err = abs(r1 - r2)
                    if abs_err > stol and abs_err / max(r1, r2) > SPIRAL_RELATIVE:
                        return k
                turn = -1 if code == 20 else 1
                arc_radius = hypot(centerx - ex, centery - ey)
                theta = atan2(cy - py, cx - px)
                theta = theta - HALF_PI if left else theta + HALF_PI
                delta = atan2(centery - py, centerx - px)
                alpha = delta - HALF_PI if code == 30 else delta + HALF_PI
                beta = theta - alpha if left else alpha - theta
                if beta > 1.5 * pi:
                    beta -= TWO_PI
                elif beta < -HALF_PI:
                    beta += TWO_PI
                if (left and code == 30) or (right and code == 20):
                    gamma = atan2(centery - ey, centerx - ex)
                    if arc_radius <= radius:
                        return k
                else:
                    gamma = atan2(ey - centery, ex - centerx)
                    delta = delta + pi
                nx = ex + radius * cos(gamma)
                ny = ey + radius * sin(gamma)
                inside = (left and turn > 0) or (right and turn < 0)
                if beta < -SMALL or beta > pi + SMALL or (abs(beta - pi) < SMALL
                                                          and not inside):
                    # concave: flush to a trimmed point
                    if qt != ARC:
                        cyy = arc_radius * sin(beta - HALF_PI)
                        if inside:
                            dist_from_center = arc_radius - radius
                            lv = (cyy + radius) / dist_from_center
                            if lv > 1.0 or lv < -1.0:
                                return k
                            ang = theta + asin(lv) if turn > 0 else theta - asin(lv)
                        else:
                            dist_from_center = arc_radius + radius
                            lv = (cyy - radius) / dist_from_center
                            if lv > 1.0 or lv < -1.0:
                                return k
                            if turn > 0:
                                ang = theta + pi - asin(lv)
                            else:
                                ang = theta + pi + asin(lv)
                        ux = centerx + dist_from_center * cos(ang)
                        uy = centery + dist_from_center * sin(ang)
                    else:
                        oldrad = hypot(qc2 - qy, qc1 - qx)
                        newrad = arc_radius - radius if inside else arc_radius + radius
                        arc_cc = hypot(qc2 - centery, qc1 - centerx)
                        if oldrad == 0 or arc_cc == 0:
                            return k
                        a = (oldrad ** 2 + arc_cc ** 2 - newrad ** 2) / (2 * oldrad * arc_cc)
                        if a > 1.0 or a < -1.0:
                            return k
                        pullback = acos(a)
                        cc_dir = atan2(centery - qc2, centerx - qc1)
                        if (left and qturn > 0) or (right and qturn < 0):
                            direction = cc_dir + pullback if turn > 0 else cc_dir - pullback
                        else:
                            direction = cc_dir - pullback if turn > 0 else cc_dir + pullback
                        ux = qc1 + oldrad * cos(direction)
                        uy = qc2 + oldrad * sin(direction)
                    check = qt != NONE
                    corner = 0
                    set_end, ne0, ne1 = check, ux, uy
                else:
                    # convex (a corner arc) or tangent: dequeue as it is
                    ux, uy = qx, qy
                    check = False
                    if beta > SMALL:
                        corner = 1
                        mid_x = px + radius * cos(delta)
                        mid_y = py + radius * sin(delta)
                        set_end, ne0, ne1 = True, mid_x, mid_y
                    else:
                        corner = 0
                        set_end, ne0, ne1 = True, cx, cy
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
            qline, qstate, qz, qfeed = n, state, ez, mfeed
            qx, qy = nx, ny
            if code <= 10:
                qt = STRAIGHT
                qkind = 1 if code == 10 else 0
                qa, qb, qd2 = ex - px, ey - py, ez - pz
                arcs_ok = not m.ijk_abs
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

