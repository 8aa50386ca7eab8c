"""Compensated runs: G0-G3 lines under G41/G42 in G17, executed with the whole state in
local variables (the hot loop of a compensated program).

The same computation as :class:`millpath.interpret.comp.CompMixin`'s
``straight_comp2``, ``arc_comp2`` and ``move_endpoint_and_flush`` (LinuxCNC's
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
                                     arc_center_r)
from millpath.interpret.comp import LEFT, RIGHT, SMALL
from millpath.interpret.errors import GCodeError
from millpath.interpret.store import KIND_CODE, PACK

T_ARC = KIND_CODE["arc"]
HALF_PI = pi / 2.0
TWO_PI = 2 * pi
#: queued move kinds (``machine.queue`` entries start with "S" or "A")
NONE, STRAIGHT, ARC = 0, 1, 2


def comp_run(m, lines: list[str], k: int, end_k: int, first, second, base: int) -> int:
    """Execute ``lines[k:end_k]`` on machine ``m`` while they are compensated G0-G3 moves
    in G17 (``first``, ``second``: the fast path's line regexes, groups
    (g, x, y, z, i, j, k, r, f)); return the index of the first line not executed.
    Line ``k`` is source line ``base + k + 1``. Call only with compensation on and past
    its entry move (``comp_side``, ``comp_radius > 0``, not ``comp_first``)."""
    if (m.plane != "XY" or not m.dist_abs or m.feed_mode != 0 or len(m.queue) > 1):
        return k
    queue = m.queue
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
    px, py, pz = m.prog
    ox, oy, oz = m.out
    e0, e1 = m.endpoint
    evalid = m.endpoint_valid
    feed_rate = m.feed_rate
    mode = m.motion_mode
    arcs_ok = not m.ijk_abs and not m.arc_not_allowed
    side = m.comp_side
    left = side == LEFT
    right = side == RIGHT
    radius = m.comp_radius
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
            if code == 0 or code == 10:
                # --- convert_straight_comp2 ---------------------------------------
                if i is not None or j is not None or r is not None:
                    return k
                if code == 10:
                    if fr == 0.0:
                        return k
                    mfeed = fr
                    kind = 1
                else:
                    mfeed = 0.0
                    kind = 0
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
                end_x = ex + rc
                end_y = ey + rs
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
                    fx, fy = cx, cy
                    mid_x = px + rc
                    mid_y = py + rs
                    corner = True
                    flush = qt != NONE
                elif concave:
                    corner = False
                    flush = qt != NONE
                    if qt != ARC:
                        halfcorner = (beta + pi) / 2.0
                        if halfcorner == 0.0:
                            return k
                        retreat = radius / tan(halfcorner)
                        fx = cx + retreat * cos(theta + gamma)
                        fy = cy + retreat * sin(theta + gamma)
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
                        fx = qc1 + oldrad * cos(ang)
                        fy = qc2 + oldrad * sin(ang)
                else:
                    corner = flush = False
                    fx = fy = 0.0
                if flush:
                    # move_endpoint_and_flush(fx, fy), checked before anything is packed
                    if qt == STRAIGHT:
                        if evalid and qa * (fx - e0) + qb * (fy - e1) < 0:
                            return k
                    else:
                        # the queued arc's end moves to fx, fy: LinuxCNC's checks
                        if abs(hypot(qx - qc1, qy - qc2) - hypot(fx - qc1, fy - qc2)) > 0.01:
                            return k
                        if qa and evalid:
                            a0 = atan2(e1 - qc2, e0 - qc1)
                            a1 = atan2(fy - qc2, fx - qc1)
                            if qturn > 0:
                                if a1 <= a0:
                                    a1 += TWO_PI
                            elif a0 <= a1:
                                a0 += TWO_PI
                            if abs(a1 - a0) > abs(qa) + slack:
                                return k
                # --- commit: nothing below can fail -------------------------------
                if flush:
                    if qt == STRAIGHT:
                        buf += pack(ox, oy, oz, fx, fy, qz, qfeed, 0.0, 0.0, 0.0,
                                    qkind, qline, 0, 0, qstate)
                    else:
                        buf += pack(ox, oy, oz, fx, fy, qz, qfeed, qc1, qc2, oz,
                                    T_ARC, qline, qturn, 0, qstate)
                    ox, oy, oz = fx, fy, qz
                    e0, e1 = fx, fy
                    evalid = True
                if corner:
                    if code == 10:
                        buf += pack(ox, oy, oz, mid_x, mid_y, cz, mfeed, px, py, oz,
                                    T_ARC, n, corner_turn, 0, state)
                    else:
                        buf += pack(ox, oy, oz, mid_x, mid_y, cz, 0.0, 0.0, 0.0, 0.0,
                                    0, n, 0, 0, state)
                    ox, oy, oz = mid_x, mid_y, cz
                    e0, e1 = mid_x, mid_y
                    evalid = True
                elif not concave:
                    # dequeue as it is, the end point is the current point
                    if qt == STRAIGHT:
                        buf += pack(ox, oy, oz, qx, qy, qz, qfeed, 0.0, 0.0, 0.0,
                                    qkind, qline, 0, 0, qstate)
                        ox, oy, oz = qx, qy, qz
                    elif qt == ARC:
                        buf += pack(ox, oy, oz, qx, qy, qz, qfeed, qc1, qc2, oz,
                                    T_ARC, qline, qturn, 0, qstate)
                        ox, oy, oz = qx, qy, qz
                    e0, e1 = cx, cy
                    evalid = True
                qt = STRAIGHT
                qkind, qline, qstate = kind, n, state
                qa, qb, qd2 = ex - px, ey - py, ez - pz
                qx, qy, qz, qfeed = end_x, end_y, ez, mfeed
                arcs_ok = not m.ijk_abs
            elif code == 20 or code == 30:
                # --- convert_arc_comp2 --------------------------------------------
                if not arcs_ok or (r is None) == (i is None and j is None):
                    return k
                if fr == 0.0:
                    return k
                if r is not None:
                    if x is None and y is None:
                        return k
                    try:
                        centerx, centery = arc_center_r(code == 20, units, px, py, ex, ey,
                                                        float(r))
                    except GCodeError:
                        return k
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
                new_end_x = ex + radius * cos(gamma)
                new_end_y = ey + radius * sin(gamma)
                inside = (left and turn > 0) or (right and turn < 0)
                if beta < -SMALL or beta > pi + SMALL or (abs(beta - pi) < SMALL
                                                          and not inside):
                    how = 0                        # concave: flush to a trimmed point
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
                        fx = centerx + dist_from_center * cos(ang)
                        fy = centery + dist_from_center * sin(ang)
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
                        fx = qc1 + oldrad * cos(direction)
                        fy = qc2 + oldrad * sin(direction)
                    if qt == STRAIGHT:
                        if evalid and qa * (fx - e0) + qb * (fy - e1) < 0:
                            return k
                    elif qt == ARC:
                        if abs(hypot(qx - qc1, qy - qc2) - hypot(fx - qc1, fy - qc2)) > 0.01:
                            return k
                        if qa and evalid:
                            a0 = atan2(e1 - qc2, e0 - qc1)
                            a1 = atan2(fy - qc2, fx - qc1)
                            if qturn > 0:
                                if a1 <= a0:
                                    a1 += TWO_PI
                            elif a0 <= a1:
                                a0 += TWO_PI
                            if abs(a1 - a0) > abs(qa) + slack:
                                return k
                elif beta > SMALL:
                    how = 1                        # convex: dequeue, corner arc
                else:
                    how = 2                        # tangent: dequeue
                # --- commit: nothing below can fail -------------------------------
                if how == 0:
                    if qt == STRAIGHT:
                        buf += pack(ox, oy, oz, fx, fy, qz, qfeed, 0.0, 0.0, 0.0,
                                    qkind, qline, 0, 0, qstate)
                        ox, oy, oz = fx, fy, qz
                        e0, e1 = fx, fy
                        evalid = True
                    elif qt == ARC:
                        buf += pack(ox, oy, oz, fx, fy, qz, qfeed, qc1, qc2, oz,
                                    T_ARC, qline, qturn, 0, qstate)
                        ox, oy, oz = fx, fy, qz
                        e0, e1 = fx, fy
                        evalid = True
                else:
                    if qt == STRAIGHT:
                        buf += pack(ox, oy, oz, qx, qy, qz, qfeed, 0.0, 0.0, 0.0,
                                    qkind, qline, 0, 0, qstate)
                        ox, oy, oz = qx, qy, qz
                    elif qt == ARC:
                        buf += pack(ox, oy, oz, qx, qy, qz, qfeed, qc1, qc2, oz,
                                    T_ARC, qline, qturn, 0, qstate)
                        ox, oy, oz = qx, qy, qz
                    if how == 1:
                        midx = px + radius * cos(delta)
                        midy = py + radius * sin(delta)
                        buf += pack(ox, oy, oz, midx, midy, cz, fr, px, py, oz, T_ARC, n,
                                    corner_turn, 0, state)
                        ox, oy, oz = midx, midy, cz
                        e0, e1 = midx, midy
                    else:
                        e0, e1 = cx, cy
                    evalid = True
                qt = ARC
                qline, qstate, qturn = n, state, turn
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
                qx, qy, qc1, qc2, qz, qfeed = new_end_x, new_end_y, centerx, centery, ez, fr
            else:
                return k
            feed_rate = fr
            mode = code
            cx, cy, cz = (end_x, end_y, ez) if code <= 10 else (new_end_x, new_end_y, ez)
            px, py, pz = ex, ey, ez
            k += 1
        return k
    finally:
        if k > start:
            m.cur = [cx, cy, cz]
            m.prog = [px, py, pz]
            m.out = [ox, oy, oz]
            m.endpoint = [e0, e1]
            m.endpoint_valid = evalid
            m.feed_rate = feed_rate
            m.motion_mode = mode
            m.cycle_il_flag = False
            m.arc_not_allowed = False      # arcs ran only when allowed; a straight allows
            if qt == STRAIGHT:
                m.queue = [["S", qkind, qline, qa, qb, qd2, qx, qy, qz, qfeed, qstate]]
            elif qt == ARC:
                m.queue = [["A", qline, qa, qx, qy, qc1, qc2, qturn, qz, qfeed, qstate]]
            else:
                m.queue = []

