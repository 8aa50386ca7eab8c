"""Cutter radius compensation (G40/G41/G42/G41.1/G42.1) as LinuxCNC 2.9 does it.

Works in the compensation plane's (first, second, normal) coordinates: XY = (X, Y, Z),
XZ = (Z, X, Y). The first move after G41/G42 is the entry move (the tool ends a radius
to the side of the programmed end point). Later moves are queued: each new move fixes
the end of the queued ones, which is how convex corners get an arc around the
programmed corner point and concave corners get trimmed. Lengths are program units.
Errors use rs274's messages. The usual XY case also runs in :mod:`compfast` (the same
computation with the state in locals); the two must stay in step.
"""

from __future__ import annotations

import math

from millpath.interpret.arcs import SPIRAL_TOLERANCE, arc_center_ijk, arc_center_r, find_turn
from millpath.interpret.corners import CONCAVE, CONVEX, arc_corner, straight_corner
from millpath.interpret.errors import GCodeError
from millpath.interpret.store import KIND_CODE, PACK, PLANE_CODE

LEFT, RIGHT = 2, 1
_hypot = math.hypot
T_ARC = KIND_CODE["arc"]
T_DWELL = KIND_CODE["dwell"]
HALF_PI = math.pi / 2.0
TOLERANCE_EQUAL = 1e-6


def _inside(side: int, turn: int) -> bool:
    return (side == LEFT and turn > 0) or (side == RIGHT and turn < 0)


class Compensation:
    """The compensation executor: its state (side, radius, whether the entry move is
    next, the programmed point ``prog``, the queued moves and the end point they are
    checked against) and its moves, run on machine ``m``'s state (position ``cur`` and
    ``out``, plane, units, tool table, motion store)."""

    def __init__(self, machine) -> None:
        self.m = machine
        self.side = 0                   # 0 off, LEFT (G41), RIGHT (G42)
        self.radius = 0.0               # tool radius, program units
        self.first = True               # the next move is the entry move
        self.prog = [0.0, 0.0, 0.0]     # programmed (uncompensated) point
        self.queue: list[list] = []
        self.endpoint = [0.0, 0.0]
        self.endpoint_valid = False
        self.arc_not_allowed = False    # just left compensation: the next move is straight

    # --- plane mapping ----------------------------------------------------------------
    def _pc(self, v) -> tuple[float, float, float]:
        a1, a2, an = self.m.axes
        return v[a1], v[a2], v[an]

    def _xyz(self, p1: float, p2: float, p3: float) -> list[float]:
        a1, a2, an = self.m.axes
        out = [0.0, 0.0, 0.0]
        out[a1], out[a2], out[an] = p1, p2, p3
        return out

    def _set_current(self, p1: float, p2: float, p3: float) -> None:
        self.m.cur = self._xyz(p1, p2, p3)

    def _set_program(self, p1: float, p2: float, p3: float) -> None:
        self.prog = self._xyz(p1, p2, p3)

    # --- G40 / G41 / G42 --------------------------------------------------------------
    def on_off(self, code: int, w: dict) -> None:
        if code == 400:
            if self.side and self.radius > 0.0 and not self.first:
                cx, cy, _ = self._pc(self.m.cur)
                self.move_endpoint_and_flush(cx, cy)
                self.dequeue()
                self.m.cur = list(self.prog)
                self.arc_not_allowed = True
            self.side = 0
            self.first = True
            return
        side = LEFT if code in (410, 411) else RIGHT
        if self.m.plane not in ("XY", "XZ"):
            raise GCodeError("Cutter radius compensation allowed only in XY, XZ planes")
        if self.side:
            raise GCodeError("Cannot turn cutter radius comp on when on")
        if code in (411, 421):
            if "d" not in w:
                raise GCodeError(f"G{code // 10}.1 with no D word")
            radius = w["d"] / 2.0
        else:
            if "d" in w:
                d = w["d"]
                tool = int(d + 0.5)
                if abs(tool - d) >= 0.0001:
                    raise GCodeError(f"G{code // 10} requires D word to be a whole number")
                if tool < 0:
                    raise GCodeError("Negative d word tool radius index used")
                if tool != 0 and tool not in self.m.tools:
                    raise GCodeError(f"Requested tool {tool} not found in the tool table")
                data = self.m.tool_data(tool)
            else:
                data = self.m.tool_data(0)
            radius = self.m.user_to_prog(data[0]) / 2.0
        if radius < 0.0:
            radius = -radius
            side = LEFT if side == RIGHT else RIGHT
        self.radius = radius
        self.side = side

    # --- the queue --------------------------------------------------------------------
    def set_endpoint(self, x: float, y: float) -> None:
        self.endpoint = [x, y]
        self.endpoint_valid = True

    def enqueue_straight(self, kind: int, line: int, d, x: float, y: float, z: float,
                         feed: float) -> None:
        self.queue.append(["S", kind, line, d[0], d[1], d[2], x, y, z, feed, self.m.state_index])

    def enqueue_arc(self, line: int, original: float, e1: float, e2: float, c1: float,
                    c2: float, turn: int, e3: float, feed: float) -> None:
        self.queue.append(["A", line, original, e1, e2, c1, c2, turn, e3, feed,
                           self.m.state_index])

    def corner_move(self, arc: bool, line: int, x: float, y: float, z: float, c1: float,
                    c2: float, feed: float) -> None:
        """The move around a convex corner to (x, y, z) (plane coordinates), with the
        queue empty: an arc about the programmed corner (c1, c2) (G1 and arcs), or a
        traverse (G0). Emitted at once; (x, y) becomes the end point."""
        turn = -1 if self.side == LEFT else 1
        if self.m.axes[0] == 0:
            # XY: plane coordinates are x, y, z
            o0, o1, o2 = self.m.out
            if arc:
                self.m.store.buf += PACK(o0, o1, o2, x, y, z, feed, c1, c2, o2, T_ARC, line,
                                         turn, PLANE_CODE[self.m.plane], self.m.state_index)
            else:
                self.m.store.buf += PACK(o0, o1, o2, x, y, z, 0.0, 0.0, 0.0, 0.0, 0, line, 0,
                                         PLANE_CODE[self.m.plane], self.m.state_index)
            self.m.out = [x, y, z]
        else:
            if arc:
                self.queue.append(["A", line, 0.0, x, y, c1, c2, turn, z, feed,
                                   self.m.state_index])
            else:
                self.queue.append(["S", 0, line, 0.0, 0.0, 0.0, x, y, z, 0.0,
                                   self.m.state_index])
            self.dequeue()
        self.set_endpoint(x, y)

    def queued_arc(self) -> tuple[int, float, float, float, float]:
        """The queued move as :mod:`corners` takes it: (turn, end1, end2, center1,
        center2) of a queued arc first in the queue, turn 0 for anything else."""
        if self.queue and self.queue[0][0] == "A":
            q = self.queue[0]
            return q[7], q[3], q[4], q[5], q[6]
        return 0, 0.0, 0.0, 0.0, 0.0

    def enqueue_dwell(self, line: int, seconds: float) -> None:
        if not self.queue:
            self.m.emit_dwell(line, seconds)
        else:
            self.queue.append(["D", line, seconds, self.m.state_index])

    def dequeue(self) -> None:
        self.endpoint_valid = False
        if not self.queue:
            return
        a1, a2, an = self.m.axes
        pcode = PLANE_CODE[self.m.plane]
        buf = self.m.store.buf
        o = self.m.out
        if a1 == 0:
            # XY: plane coordinates are x, y, z; pack the queued moves as they are
            o0, o1, o2 = o
            for q in self.queue:
                t = q[0]
                if t == "S":
                    buf += PACK(o0, o1, o2, q[6], q[7], q[8], q[9], 0.0, 0.0, 0.0,
                                q[1], q[2], 0, pcode, q[10])
                    o0, o1, o2 = q[6], q[7], q[8]
                elif t == "A":
                    buf += PACK(o0, o1, o2, q[3], q[4], q[8], q[9], q[5], q[6], o2,
                                T_ARC, q[1], q[7], pcode, q[10])
                    o0, o1, o2 = q[3], q[4], q[8]
                else:
                    buf += PACK(o0, o1, o2, o0, o1, o2, 0.0, q[2], 0.0, 0.0,
                                T_DWELL, q[1], 0, pcode, q[3])
            self.m.out = [o0, o1, o2]
            self.queue = []
            return
        for q in self.queue:
            if q[0] == "S":
                e = [0.0, 0.0, 0.0]
                e[a1], e[a2], e[an] = q[6], q[7], q[8]
                buf += PACK(o[0], o[1], o[2], e[0], e[1], e[2], q[9], 0.0, 0.0, 0.0,
                            q[1], q[2], 0, pcode, q[10])
                o = e
            elif q[0] == "A":
                e = [0.0, 0.0, 0.0]
                e[a1], e[a2], e[an] = q[3], q[4], q[8]
                c = [0.0, 0.0, 0.0]
                c[a1], c[a2], c[an] = q[5], q[6], o[an]
                buf += PACK(o[0], o[1], o[2], e[0], e[1], e[2], q[9], c[0], c[1], c[2],
                            T_ARC, q[1], q[7], pcode, q[10])
                o = e
            else:
                buf += PACK(o[0], o[1], o[2], o[0], o[1], o[2], 0.0, q[2], 0.0, 0.0,
                            T_DWELL, q[1], 0, pcode, q[3])
        self.m.out = o
        self.queue = []

    def move_endpoint_and_flush(self, x: float, y: float) -> None:
        """Give the queued moves the end ``x, y`` (plane coordinates), check for gouges,
        emit them, and make ``x, y`` the new end point."""
        queue = self.queue
        if not queue:
            return
        e0, e1 = self.endpoint
        valid = self.endpoint_valid
        dx, dy = x - e0, y - e1
        if len(queue) == 1 and self.m.axes[0] == 0:
            # the usual case in XY: one queued move, moved and packed in one step
            q = queue[0]
            t = q[0]
            o0, o1, o2 = self.m.out
            if t == "S":
                if valid and q[3] * dx + q[4] * dy < 0:
                    self._gouge_straight(q[1])
                self.m.store.buf += PACK(o0, o1, o2, x, y, q[8], q[9], 0.0, 0.0, 0.0,
                                       q[1], q[2], 0, PLANE_CODE[self.m.plane], q[10])
                self.m.out = [x, y, q[8]]
                self.queue = []
                self.endpoint = [x, y]
                self.endpoint_valid = True
                return
            if t == "A":
                c1, c2 = q[5], q[6]
                r1 = _hypot(q[3] - c1, q[4] - c2)
                r2 = _hypot(x - c1, y - c2)
                if abs(r1 - r2) > 0.01 or (q[2] and valid):
                    self._check_arc(q, e0, e1, x, y, valid)     # raises if invalid
                self.m.store.buf += PACK(o0, o1, o2, x, y, q[8], q[9], q[5], q[6], o2,
                                       T_ARC, q[1], q[7], PLANE_CODE[self.m.plane], q[10])
                self.m.out = [x, y, q[8]]
                self.queue = []
                self.endpoint = [x, y]
                self.endpoint_valid = True
                return
        for q in queue:
            if q[0] == "S":
                if valid and q[3] * dx + q[4] * dy < 0:
                    self._gouge_straight(q[1])
                q[6], q[7] = x, y
            elif q[0] == "A":
                self._check_arc(q, e0, e1, x, y, valid)
                q[3], q[4] = x, y
        self.dequeue()
        self.endpoint = [x, y]
        self.endpoint_valid = True

    @staticmethod
    def _gouge_straight(kind: int) -> None:
        if kind == 0:
            raise GCodeError("Straight traverse in concave corner cannot be reached by the "
                             "tool without gouging")
        raise GCodeError("Straight feed in concave corner cannot be reached by the tool "
                         "without gouging")

    def _check_arc(self, q: list, e0: float, e1: float, x: float, y: float,
                   valid: bool) -> None:
        """Raise if moving queued arc ``q``'s end to ``x, y`` is invalid (LinuxCNC's
        checks in move_endpoint_and_flush)."""
        r1 = math.hypot(q[3] - q[5], q[4] - q[6])
        l1 = q[2]
        r2 = math.hypot(x - q[5], y - q[6])
        l2 = find_turn(e0, e1, q[5], q[6], q[7], x, y)
        if abs(r1 - r2) > 0.01:
            raise GCodeError("BUG: cutter compensation has generated an invalid arc "
                             f"with mismatched radii r1 {r1:f} r2 {r2:f}\n")
        # rs274 2.9 allows 0.001 rad in inch programs, 0.0254 in mm programs
        slack = 0.0254 if self.m.units == "mm" else 0.001
        if l1 and valid and abs(l2) > abs(l1) + slack:
            raise GCodeError("Arc move in concave corner cannot be reached by the "
                             "tool without gouging")

    def flush(self, line: int) -> None:
        """M0/M1/M2/M30: emit what is queued."""
        cx, cy, _ = self._pc(self.m.cur)
        self.move_endpoint_and_flush(cx, cy)
        self.dequeue()

    def scale(self, f: float) -> None:
        self.radius *= f
        if not self.queue:
            return
        for q in self.queue:
            self.endpoint[0] *= f
            self.endpoint[1] *= f
            if q[0] == "S":
                q[6] *= f
                q[7] *= f
                q[8] *= f
            elif q[0] == "A":
                for k in (3, 4, 5, 6, 8):
                    q[k] *= f

    # --- straight moves ---------------------------------------------------------------
    def straight1(self, move: int, line: int, end, feed: float) -> None:
        radius = self.radius
        side = self.side
        cx, cy, cz = self._pc(self.m.cur)
        px, py, pz = self._pc(end)
        distance = math.hypot(px - cx, py - cy)
        if distance <= radius:
            raise GCodeError("Length of cutter compensation entry move is not greater than "
                             "the tool radius")
        alpha = math.atan2(py - cy, px - cx) + (HALF_PI if side == LEFT else -HALF_PI)
        end_x = px + radius * math.cos(alpha)
        end_y = py + radius * math.sin(alpha)
        self.set_endpoint(cx, cy)
        self.enqueue_straight(0 if move == 0 else 1, line, (math.cos(alpha), math.sin(alpha), 0.0),
                              end_x, end_y, pz, feed)
        self.first = False
        self._set_current(end_x, end_y, pz)
        self._set_program(px, py, pz)

    def straight2(self, move: int, line: int, end, feed: float) -> None:
        kind = 0 if move == 0 else 1
        a1, a2, an = self.m.axes
        c, p = self.m.cur, self.prog
        cx, cy, cz = c[a1], c[a2], c[an]
        end_x, end_y = cx, cy
        opx, opy, opz = p[a1], p[a2], p[an]
        px, py, pz = end[a1], end[a2], end[an]
        if py == opy and px == opx:
            self.enqueue_straight(kind, line, (px - opx, py - opy, pz - opz), cx, cy, pz, feed)
        else:
            side = self.side
            radius = self.radius
            corner, mid_x, mid_y, end_x, end_y = straight_corner(
                side == LEFT, radius, cx, cy, opx, opy, px, py, *self.queued_arc())
            if corner == CONVEX:
                self.move_endpoint_and_flush(cx, cy)
                self.corner_move(move == 10, line, mid_x, mid_y, cz, opx, opy, feed)
            elif corner == CONCAVE:
                self.move_endpoint_and_flush(mid_x, mid_y)
            else:
                self.dequeue()
                self.set_endpoint(cx, cy)
            self.queue.append(["S", kind, line, px - opx, py - opy, pz - opz, end_x, end_y, pz,
                               feed, self.m.state_index])
        if a1 == 0:                              # XY plane
            self.m.cur = [end_x, end_y, pz]
            self.prog = [px, py, pz]
        else:
            c = [0.0, 0.0, 0.0]
            c[a1], c[a2], c[an] = end_x, end_y, pz
            self.m.cur = c
            p = [0.0, 0.0, 0.0]
            p[a1], p[a2], p[an] = px, py, pz
            self.prog = p

    # --- arcs -------------------------------------------------------------------------
    def arc1(self, move: int, blk, end, off1: float, off2: float, turn: int,
                  feed: float) -> None:
        side = self.side
        radius = self.radius
        cx, cy, cz = self._pc(self.m.cur)
        ex, ey, ez = self._pc(end)
        if math.hypot(ex - cx, ey - cy) <= radius:
            raise GCodeError("Radius of cutter compensation entry arc is not greater than the "
                             "tool radius")
        w = blk.words
        if "r" in w:
            if abs(w["r"]) <= radius and _inside(side, 1 if move == 30 else -1):
                raise GCodeError("Tool radius not less than arc radius with comp")
            center_x, center_y = arc_center_r(move == 20, self.m.units, cx, cy, ex, ey, w["r"])
        else:
            center_x, center_y, arc_radius = arc_center_ijk(
                self.m.plane, self.m.units, cx, cy, ex, ey, self.m.ijk_abs, off1, off2)
            if arc_radius <= radius and _inside(side, 1 if move == 30 else -1):
                raise GCodeError("Tool radius not less than arc radius with comp")
        if _inside(side, turn):
            gamma = math.atan2(center_y - ey, center_x - ex)
        else:
            gamma = math.atan2(ey - center_y, ex - center_x)
        self.first = False
        self._set_program(ex, ey, ez)
        ex += radius * math.cos(gamma)
        ey += radius * math.sin(gamma)
        b_len = math.hypot(cy - ey, cx - ex) / 2.0
        ab_ang = math.atan2(center_y - ey, center_x - ex)
        a_ang = math.atan2(cy - ey, cx - ex) - ab_ang
        if abs(math.cos(a_ang)) < TOLERANCE_EQUAL:
            raise GCodeError("Tool radius not less than arc radius with comp")
        c_len = b_len / math.cos(a_ang)
        center_x = ex + c_len * math.cos(ab_ang)
        center_y = ey + c_len * math.sin(ab_ang)
        if abs(math.hypot(center_x - ex, center_y - ey)
               - math.hypot(center_x - cx, center_y - cy)) > SPIRAL_TOLERANCE[self.m.units]:
            raise GCodeError("Bug in tool radius comp")
        self.enqueue_arc(blk.line, find_turn(cx, cy, center_x, center_y, turn, ex, ey),
                         ex, ey, center_x, center_y, turn, ez, feed)
        self._set_current(ex, ey, ez)

    def arc2(self, move: int, line: int, r_word: float | None, end, off1: float,
                  off2: float, turn: int, feed: float) -> None:
        """A compensated arc after the entry move (``r_word``: the R value, or None for
        I/J/K centers ``off1``, ``off2``), LinuxCNC's convert_arc_comp2."""
        a1, a2, an = self.m.axes
        p, c = self.prog, self.m.cur
        opx, opy = p[a1], p[a2]
        cx, cy, cz = c[a1], c[a2], c[an]
        end_x, end_y, end_z = end[a1], end[a2], end[an]
        if r_word is not None:
            centerx, centery = arc_center_r(move == 20, self.m.units, opx, opy, end_x, end_y,
                                            r_word)
        else:
            centerx, centery, _ = arc_center_ijk(self.m.plane, self.m.units, opx, opy, end_x,
                                                    end_y, self.m.ijk_abs, off1, off2)
        side = self.side
        tool_radius = self.radius
        corner, midx, midy, new_end_x, new_end_y = arc_corner(
            side == LEFT, tool_radius, move == 30, turn, cx, cy, opx, opy, end_x, end_y,
            centerx, centery, *self.queued_arc())
        if corner == CONCAVE:
            self.move_endpoint_and_flush(midx, midy)
        elif corner == CONVEX:
            self.dequeue()
            self.corner_move(True, line, midx, midy, cz, opx, opy, feed)
        else:
            self.dequeue()
            self.set_endpoint(cx, cy)
        self.enqueue_arc(line, find_turn(opx, opy, centerx, centery, turn, end_x, end_y),
                         new_end_x, new_end_y, centerx, centery, turn, end_z, feed)
        if a1 == 0:
            self.prog = [end_x, end_y, end_z]
            self.m.cur = [new_end_x, new_end_y, end_z]
        else:
            self._set_program(end_x, end_y, end_z)
            self._set_current(new_end_x, new_end_y, end_z)
