"""Canned cycles G73 G81 G82 G83 G85 G89 expanded into motion as LinuxCNC 2.9 does.

Axes are named as LinuxCNC's cycle code does: ``aa``, ``bb`` the plane's first and
second axes, ``cc`` the normal (XY: X, Y, Z; XZ: Z, X, Y; YZ: Y, Z, X). The initial
level (the normal coordinate when the run of cycles began) is kept until a non-cycle
motion; G98 retracts to it, G99 to R. G83 pecks retract to R; peck cycles back off
0.010 in (0.254 mm). A block that would expand into more than ``MAX_CYCLE_STEPS``
peck-repeat steps is refused (rs274 would run for hours).
"""

from __future__ import annotations

import math

from millpath.interpret.errors import GCodeError
from millpath.model.limits import MAX_CYCLE_STEPS
from millpath.model.units import length_scale

CYCLES = frozenset((730, 810, 820, 830, 840, 850, 860, 870, 880, 890))
_SUPPORTED = frozenset((730, 810, 820, 830, 850, 890))
#: the moves of the cycles without pecks at each hole, once the tool is at the R plane:
#: (1 feed | 0 rapid, to "bottom" / "r" / "clear" height) or ("dwell", None) for P
CYCLE_STEPS = {810: ((1, "bottom"), (0, "clear")),
               820: ((1, "bottom"), ("dwell", None), (0, "clear")),
               850: ((1, "bottom"), (1, "r"), (0, "clear")),
               890: ((1, "bottom"), ("dwell", None), (1, "clear"))}
_NORMAL_LETTER = {"XY": "z", "XZ": "y", "YZ": "x"}
_PLANE_LETTERS = {"XY": ("x", "y"), "XZ": ("z", "x"), "YZ": ("y", "z")}


class Cycles:
    """The canned-cycle executor: its state (the initial level ``il`` and whether it is
    set, the last R, P, Q and normal-axis values) and the expansion of a cycle block into
    moves on machine ``m`` (position, plane, feed, retract mode, motion store)."""

    def __init__(self, machine) -> None:
        self.m = machine
        self.il = 0.0                   # initial level (normal axis), program units
        self.il_flag = False            # set by the first cycle of a run
        self.cc = 0.0
        self.r = 0.0
        self.p = 0.0
        self.q = 0.0

    def _cyc_move(self, kind: int, line: int, a: float, b: float, c: float) -> None:
        a1, a2, an = self.m.axes
        end = [0.0, 0.0, 0.0]
        end[a1], end[a2], end[an] = a, b, c
        self.m.emit(kind, line, end, self.m.feed_rate if kind == 1 else 0.0)
        self.m.cur = end

    def run(self, motion: int, blk) -> None:
        """Execute cycle ``motion`` (G code x 10) of block ``blk``."""
        w = blk.words
        line = blk.line
        if motion not in _SUPPORTED:
            raise GCodeError(f"G{motion // 10} is not supported by this interpreter")
        if self.m.feed_rate == 0.0:
            raise GCodeError("Cannot feed with zero feed rate")
        if self.m.feed_mode == 1:
            raise GCodeError("Cannot use inverse time feed with canned cycles")
        if self.m.comp.side:
            raise GCodeError("Cannot use canned cycles with cutter compensation on")
        if "r" in w:
            r_word = w["r"]
        elif self.m.motion_mode == motion:
            r_word = self.r
        else:
            raise GCodeError("R clearance plane unspecified in cycle")
        repeats = int(w.get("l", 1))
        if "l" in w and repeats == 0:
            raise GCodeError("Cannot do zero repeats of cycle")
        plane = self.m.plane
        la, lb = _PLANE_LETTERS[plane]
        lc = _NORMAL_LETTER[plane]
        a1, a2, an = self.m.axes
        cur = self.m.cur
        if self.m.motion_mode != motion and lc not in w:
            raise GCodeError({"XY": "Z value unspecified in xy plane canned cycle",
                              "XZ": "Y value unspecified in xz plane canned cycle",
                              "YZ": "X value unspecified in yz plane canned cycle"}[plane])
        c_word = w.get(lc, self.cc)
        if self.il_flag:
            old_cc = self.il
        else:
            old_cc = self.il = cur[an]
            self.il_flag = True
        rad_inc = theta_inc = 0.0
        if self.m.dist_abs:
            inc_a = inc_b = 0.0
            r = r_word
            cc = c_word
            if "@" in w or "^" in w:          # polar (G17 only): about the XY origin
                radius = w["@"] if "@" in w else math.hypot(cur[1], cur[0])
                theta = (math.radians(w["^"]) if "^" in w
                         else math.atan2(cur[1], cur[0]))
                aa, bb = radius * math.cos(theta), radius * math.sin(theta)
            else:
                aa = w.get(la, cur[a1])
                bb = w.get(lb, cur[a2])
        else:
            inc_a = w.get(la, 0.0)
            inc_b = w.get(lb, 0.0)
            rad_inc = w.get("@", 0.0)
            theta_inc = math.radians(w.get("^", 0.0))
            r = r_word + old_cc
            cc = r + c_word
            aa = cur[a1]
            bb = cur[a2]
        if r < cc:
            raise GCodeError({"XY": "R less than z in cycle in xy plane",
                              "XZ": "R less than y in cycle in xz plane",
                              "YZ": "R less than x in cycle in yz plane"}[plane])
        current_cc = cur[an]
        if old_cc < r:
            self._cyc_move(0, line, cur[a1], cur[a2], r)
            old_cc = r
            current_cc = r
        clear_cc = r if self.m.retract_r_plane else old_cc
        p = q = 0.0
        if motion in (820, 890):               # rs274 reads P-1 / Q-1 as missing words
            p = w.get("p", -1.0)
            if self.m.motion_mode != motion and p == -1.0:
                raise GCodeError(f"Dwell time p word missing with g{motion // 10}")
            if p == -1.0:
                p = self.p
        if motion in (730, 830):
            q = w.get("q", -1.0)
            if self.m.motion_mode != motion and q == -1.0:
                raise GCodeError(f"Q word missing with g{motion // 10}")
            if q == -1.0:
                q = self.q
        pecks = (r - q - cc) / q + 2.0 if motion in (730, 830) and q > 0.0 else 1.0
        if repeats * pecks > MAX_CYCLE_STEPS:
            raise GCodeError(f"canned cycle would make more than {MAX_CYCLE_STEPS} moves "
                             f"({repeats} repeats, {pecks:.3g} pecks each)")
        units = self.m.units
        delta = 0.010 * length_scale("inch", units)
        for rep in range(repeats):
            aa += inc_a
            bb += inc_b
            for inc, is_radius in ((rad_inc, True), (theta_inc, False)):
                if inc:
                    if aa == 0 and bb == 0:
                        raise GCodeError("Incremental motion with polar coordinates is "
                                         "indeterminate when at the origin")
                    t = math.atan2(bb, aa) + (0.0 if is_radius else inc)
                    rr = math.hypot(bb, aa) + (inc if is_radius else 0.0)
                    aa, bb = rr * math.cos(t), rr * math.sin(t)
            if rep == 0 and current_cc > r:
                self._cyc_move(0, line, aa, bb, current_cc)
                self._cyc_move(0, line, aa, bb, r)
            else:
                self._cyc_move(0, line, aa, bb, clear_cc)
                if clear_cc > r:
                    self._cyc_move(0, line, aa, bb, r)
            if motion in CYCLE_STEPS:
                at = {"bottom": cc, "r": r, "clear": clear_cc}
                for kind, where in CYCLE_STEPS[motion]:
                    if kind == "dwell":
                        self.m.emit_dwell(line, p)
                    else:
                        self._cyc_move(kind, line, aa, bb, at[where])
            elif motion in (730, 830):
                if q <= 0.0:
                    raise GCodeError("Negative or zero q value used")
                depth = r - q
                while depth > cc:
                    if depth - q == depth:
                        raise GCodeError("Q word too small for the depth of the cycle")
                    self._cyc_move(1, line, aa, bb, depth)
                    if motion == 830:
                        self._cyc_move(0, line, aa, bb, r)
                    self._cyc_move(0, line, aa, bb, depth + delta)
                    depth -= q
                self._cyc_move(1, line, aa, bb, cc)
                self._cyc_move(0, line, aa, bb, clear_cc)
        if motion in (820, 890):
            self.p = p
        if motion in (730, 830):
            self.q = q
        end = [0.0, 0.0, 0.0]
        end[a1], end[a2], end[an] = aa, bb, clear_cc
        self.m.cur = end
        self.cc = c_word
        self.r = r_word
        self.m.motion_mode = motion
