"""The corners of cutter radius compensation, as LinuxCNC 2.9's convert_straight_comp2 and
convert_arc_comp2 compute them: where the tool path of a compensated move ends and where
the queued move before it must end, from the programmed points and the tool's point.

Pure functions of a plane's (first, second) coordinates, program units, angles in
radians; they are the one copy of this geometry, called by the compensation executor
(:mod:`millpath.interpret.comp`: any plane, its queue of moves) and by the compensated
fast path (:mod:`millpath.interpret.compfast`: XY, the state in locals). A corner the
tool cannot cut raises :class:`GCodeError` with rs274's message; compfast catches it and
leaves the line to the executor, which raises it again.

Names: ``left`` is G41 (the tool left of the path), ``radius`` the tool radius;
``(cx, cy)`` the tool's current point, ``(ox, oy)`` the programmed start and
``(px, py)`` / ``(ex, ey)`` the programmed end of the new move; ``turn`` its signed turn
count (+ counter-clockwise, G3). The queued move before it: ``qturn`` the turn of a
queued arc, 0 when the queued move is not an arc (a straight, a dwell or none), ending at
``(qx, qy)`` about the center ``(qc1, qc2)``.
"""

from __future__ import annotations

from math import acos, asin, atan2, cos, hypot, pi, sin, tan

from millpath.interpret.errors import GCodeError
from millpath.model.control import CONCAVE_CORNER as SMALL
HALF_PI = pi / 2.0
TWO_PI = 2 * pi
# the bounds the corner angle is compared with, computed once
_NEG_SMALL, _PI_MINUS, _PI_PLUS = -SMALL, pi - SMALL, pi + SMALL
_NEG_HALF_PI, _THREE_HALF_PI = -HALF_PI, 1.5 * pi
#: the kinds of corner before a compensated move
TANGENT, CONVEX, CONCAVE = 0, 1, 2


def straight_corner(left: bool, radius: float, cx: float, cy: float, ox: float, oy: float,
                    px: float, py: float, qturn: int, qx: float, qy: float, qc1: float,
                    qc2: float) -> tuple[int, float, float, float, float]:
    """The corner before a compensated straight move from (ox, oy) to (px, py), not of
    zero length. Returns ``(corner, x, y, nx, ny)``: TANGENT, CONVEX or CONCAVE; for a
    convex corner the end of its arc about (ox, oy) (a traverse for G0), for a concave
    one where the queued move ends (back along a queued straight, or along a queued arc
    to where the tool touches the new line); the end of the move's tool path."""
    theta = atan2(cy - oy, cx - ox)
    alpha = atan2(py - oy, px - ox)
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
    normal = alpha + gamma
    rc = radius * cos(normal)
    rs = radius * sin(normal)
    if not (beta < _NEG_SMALL or beta > _PI_PLUS or (
            beta > _PI_MINUS and ((not left and qturn > 0) or (left and qturn < 0)))):
        # not concave (concave also: straight on after an arc curving away from the tool)
        if beta > SMALL:
            return CONVEX, ox + rc, oy + rs, px + rc, py + rs
        return TANGENT, 0.0, 0.0, px + rc, py + rs
    if not qturn:
        halfcorner = (beta + pi) / 2.0
        if halfcorner == 0.0:
            raise GCodeError("Zero degree inside corner is invalid for cutter compensation")
        retreat = radius / tan(halfcorner)
        direction = theta + gamma
        return (CONCAVE, cx + retreat * cos(direction), cy + retreat * sin(direction),
                px + rc, py + rs)
    oldrad = hypot(qc2 - qy, qc1 - qx)
    base_dir = atan2(py - oy, px - ox)            # alpha before the turn above
    th = base_dir + HALF_PI if qturn > 0 else base_dir - HALF_PI
    phi = atan2(qc2 - oy, qc1 - ox)
    inside = (left and qturn > 0) or (not left and qturn < 0)
    oldrad_uncomp = oldrad + radius if inside else oldrad - radius
    d = oldrad_uncomp * cos(th - phi)
    lv = (d - radius) / oldrad if inside else (d + radius) / oldrad
    if lv > 1.0 or lv < -1.0:
        raise GCodeError("Arc to straight motion makes a corner the compensated tool can't "
                         "fit in without gouging")
    if (qturn > 0) == inside:
        ang = -acos(lv) + th + pi
    else:
        ang = acos(lv) + th + pi
    return (CONCAVE, qc1 + oldrad * cos(ang), qc2 + oldrad * sin(ang), px + rc,
            py + rs)


def arc_corner(left: bool, radius: float, ccw: bool, turn: int, cx: float, cy: float,
               ox: float, oy: float, ex: float, ey: float, c1: float, c2: float,
               qturn: int, qx: float, qy: float, qc1: float,
               qc2: float) -> tuple[int, float, float, float, float]:
    """The corner before a compensated arc (G3 when ``ccw``) from (ox, oy) to (ex, ey)
    about (c1, c2). Returns ``(corner, x, y, nx, ny)`` as :func:`straight_corner` does:
    for a concave corner, where the tool on the queued straight or arc first touches the
    arc's offset. Raises when the tool does not fit inside the arc."""
    arc_radius = hypot(c1 - ex, c2 - ey)
    theta = atan2(cy - oy, cx - ox)
    theta = theta - HALF_PI if left else theta + HALF_PI
    delta = atan2(c2 - oy, c1 - ox)
    alpha = delta - HALF_PI if ccw else delta + HALF_PI
    beta = theta - alpha if left else alpha - theta
    if beta > _THREE_HALF_PI:
        beta -= TWO_PI
    elif beta < _NEG_HALF_PI:
        beta += TWO_PI
    if left == ccw:
        gamma = atan2(c2 - ey, c1 - ex)
        if arc_radius <= radius:
            raise GCodeError("Tool radius not less than arc radius with comp")
    else:
        gamma = atan2(ey - c2, ex - c1)
        delta = delta + pi
    nx = ex + radius * cos(gamma)
    ny = ey + radius * sin(gamma)
    inside = (left and turn > 0) or (not left and turn < 0)
    if not (beta < _NEG_SMALL or beta > _PI_PLUS or (abs(beta - pi) < SMALL and not inside)):
        if beta > SMALL:
            return CONVEX, ox + radius * cos(delta), oy + radius * sin(delta), nx, ny
        return TANGENT, 0.0, 0.0, nx, ny
    if not qturn:
        cyy = arc_radius * sin(beta - HALF_PI)
        if inside:
            dist_from_center = arc_radius - radius
            lv = (cyy + radius) / dist_from_center
        else:
            dist_from_center = arc_radius + radius
            lv = (cyy - radius) / dist_from_center
        if lv > 1.0 or lv < -1.0:
            raise GCodeError("Arc move in concave corner cannot be reached by the tool "
                             "without gouging")
        if inside:
            ang = theta + asin(lv) if turn > 0 else theta - asin(lv)
        elif turn > 0:
            ang = theta + pi - asin(lv)
        else:
            ang = theta + pi + asin(lv)
        return (CONCAVE, c1 + dist_from_center * cos(ang), c2 + dist_from_center * sin(ang),
                nx, ny)
    oldrad = hypot(qc2 - qy, qc1 - qx)
    newrad = arc_radius - radius if inside else arc_radius + radius
    arc_cc = hypot(qc2 - c2, qc1 - c1)
    if oldrad == 0 or arc_cc == 0:
        raise GCodeError("Arc to arc motion is invalid because the arcs have the same "
                         "center")
    a = (oldrad ** 2 + arc_cc ** 2 - newrad ** 2) / (2 * oldrad * arc_cc)
    if a > 1.0 or a < -1.0:
        raise GCodeError("Arc to arc motion makes a corner the compensated tool can't fit "
                         "in without gouging")
    pullback = acos(a)
    cc_dir = atan2(c2 - qc2, c1 - qc1)
    if ((left and qturn > 0) or (not left and qturn < 0)) == (turn > 0):
        direction = cc_dir + pullback
    else:
        direction = cc_dir - pullback
    return CONCAVE, qc1 + oldrad * cos(direction), qc2 + oldrad * sin(direction), nx, ny
