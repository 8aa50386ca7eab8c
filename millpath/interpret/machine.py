"""The interpreter state machine: executes blocks in LinuxCNC's order.

Positions are program coordinates in program units (``units``), like LinuxCNC's
``current_x``: machine position = rotate_xy(program + G92 offset, rotation) + work offset
+ tool offset (``G10 L2 R`` sets the work system's XY rotation, in degrees).
Tool table values are in machine units and converted when read. Motion goes to a
:class:`MotionList`; with cutter radius compensation on, moves wait in a queue until
the next move fixes their end points, as in LinuxCNC. Work systems, G10, G28/G30
references and G92/G52 offsets are set by ``self.offsets``
(:class:`~millpath.interpret.offsets.Offsets`, on this state). Two executors keep their
own state and run on this one: ``self.comp``
(:class:`~millpath.interpret.comp.Compensation`) and ``self.cycles``
(:class:`~millpath.interpret.cycles.Cycles`); o-word flow is
:class:`~millpath.interpret.oword.Flow`. The state (modal state, position, offsets, tool,
parameters, recorded motion) is :class:`~millpath.interpret.state.MachineState`; the
machine adds block execution and the motion executor.
"""

from __future__ import annotations

import math

from millpath.interpret.arcs import arc_center_ijk, arc_center_r
from millpath.interpret.comp import Compensation
from millpath.interpret.cycles import CYCLES, Cycles
from millpath.interpret.errors import GCodeError
from millpath.gcode.lexer import AXES, Block, c_int
from millpath.interpret.offsets import Offsets, rotate
from millpath.model.nurbs import Nurbs
from millpath.interpret.state import MachineState
from millpath.model.toolpath import PLANE_AXES
from millpath.model.units import MM_PER_INCH
from millpath.interpret.store import KIND_CODE

PLANE_OF_G = {170: "XY", 180: "XZ", 190: "YZ"}
T_TRAVERSE, T_FEED, T_ARC, T_CUBIC, T_DWELL, T_NURBS = (
    KIND_CODE[k] for k in ("traverse", "feed", "arc", "cubic", "dwell", "nurbs"))


class Machine(MachineState):
    """The RS274NGC interpreter: its state (:class:`MachineState`), block execution, the
    motion executor and the composed executors; see the module docstring."""

    #: All :mod:`millpath.interpret.fastpath` may touch on a Machine (a test holds it
    #: to this): the modal state it checks before taking a line (read), the position,
    #: output point, feed and motion flags it keeps in locals and writes back before
    #: any call into the machine, the motion store it appends to, and the motion entry
    #: points it calls.
    FAST_PATH_INTERFACE = frozenset({
        # read: modal state deciding whether a line may take the fast path
        "units", "plane", "axes", "dist_abs", "ijk_abs", "feed_mode", "state_index",
        "comp.side", "comp.radius", "comp.first", "comp.prog",
        # read and written back: position, output point, feed and motion flags
        "cur", "out", "feed_rate", "motion_mode", "cycles.il_flag", "comp.arc_not_allowed",
        # appended to: the recorded motion
        "store",
        # read and written back by a compensated run (interpret/compfast.py): the queued
        # move and the end point it is checked against
        "comp.queue", "comp.endpoint", "comp.endpoint_valid",
        # called: the motion executors, and G40/G41/G42 of a line without other words
        "motion", "comp.straight2", "comp.arc2", "comp.on_off"})

    def __init__(self, tools: dict, machine_units: str = "inch"):
        super().__init__(tools, machine_units)
        self.comp = Compensation(self)          # the compensation executor and its state
        self.cycles = Cycles(self)              # the canned-cycle executor and its state
        self.offsets = Offsets(self)            # work systems, G10, G28/G30, G52/G92

    # --- block execution ------------------------------------------------------------
    def execute(self, blk: Block) -> None:
        self.check(blk)
        w = blk.words
        g = blk.g
        m = blk.m
        line = blk.line
        if 5 in g:
            self.set_feed_mode(g[5])
        if "f" in w and self.feed_mode != 1:
            self.feed_rate = w["f"]
        if "s" in w:
            self.speed = w["s"]
            self.touch_state()
        if "t" in w:
            self.select_tool(int(w["t"]))
        if 6 in m:
            self.tool_change(m[6], w)
        if 7 in m:
            self.spindle(m[7])
        if 8 in m or 9 in m or 5 in m:
            self.other_m(m)
        if g.get(0) == 40:
            self.comp.enqueue_dwell(line, w["p"])
        if 2 in g:
            self.set_plane(PLANE_OF_G.get(g[2]))
        if 6 in g:
            self.set_units("inch" if g[6] == 200 else "mm")
        if 7 in g:
            self.comp.on_off(g[7], w)
        if 8 in g:
            self.tool_length_offset(g[8], w)
        if 12 in g:
            self.offsets.coordinate_system(g[12])
        if 13 in g and self.comp.side:
            raise GCodeError("Cannot change control mode with cutter radius compensation on")
        if 3 in g:
            self.dist_abs = g[3] == 900
        if 4 in g:
            self.ijk_abs = g[4] == 901
        if 10 in g:
            if self.comp.side:
                raise GCodeError("Cannot change retract mode with cutter radius compensation on")
            self.retract_r_plane = g[10] == 990
        g0 = g.get(0, -1)
        if g0 not in (-1, 40, 530):
            self.offsets.modal_0(g0, blk)
        if blk.motion != -1:
            self.motion(blk.motion, blk)
        if 4 in m:
            self.stop(m[4], line)
        if 6 in m:
            self.resync_after_tool_change()

    def check(self, blk: Block) -> None:
        """LinuxCNC's enhance_block and check_items."""
        w = blk.words
        g = blk.g
        g0 = g.get(0, -1)
        axis = any(a in w for a in AXES)
        covets = g0 in (100, 280, 300, 520, 920)
        motion = -1
        if 1 in g:
            if g[1] == 800:
                if axis and not covets:
                    raise GCodeError("Cannot use axis values with g80")
                if not axis and g0 in (520, 920):
                    raise GCodeError("All axes missing with g52 or g92")
            else:
                if covets:
                    raise GCodeError("Cannot use two g codes that both use axis values")
            motion = g[1]
        elif covets:
            if not axis and g0 in (520, 920):
                raise GCodeError("All axes missing with g52 or g92")
        elif axis and g.get(8) != 431:
            if self.motion_mode in (-1, 800):
                raise GCodeError("Cannot use axis values without a g code that uses them")
            motion = self.motion_mode
        blk.motion = motion
        if "@" in w or "^" in w:
            if motion == -1:
                raise GCodeError("Polar coordinates can only be used for motion")
            if self.plane != "XY":
                raise GCodeError("Cannot use polar coordinate except in G17 plane")
            if "x" in w:
                raise GCodeError("Cannot specify both polar coordinate and X word")
            if "y" in w:
                raise GCodeError("Cannot specify both polar coordinate and Y word")
            if g0 == 530:
                raise GCodeError("Cannot use polar coordinates with G53")
        if g0 == 40:
            if w.get("p", -1.0) == -1.0:               # rs274 reads P-1 as "no P"
                raise GCodeError("Dwell time missing with g4")
            if motion in (20, 30):
                raise GCodeError("G4 not allowed with G2 or G3 because they both use P")
        elif g0 == 100:
            lv = int(w.get("l", -1))
            p = w.get("p", -1.0)
            pi = int(p + 0.5) if p >= 0 else int(p - 0.5)
            if lv not in (0, 1, 2, 10, 11, 20):
                raise GCodeError("Line with G10 does not have L0, L1, L10, L11, L2, or L20")
            if (p + 0.0001) - pi > 0.0002:
                raise GCodeError("P value not an integer with G10")
            if lv in (2, 20) and not 0 <= pi <= 9:
                raise GCodeError(f"P value out of range (0-9) with G10 L{lv}")
            if lv in (1, 10, 11) and pi < 1:
                raise GCodeError(f"P value out of range with G10 L{lv}")
        elif g0 == 530:
            if motion not in (0, 10):
                raise GCodeError("Must use g0 or g1 with g53")
            if g.get(3) == 910 or (g.get(3) != 900 and not self.dist_abs):
                raise GCodeError("Cannot use g53 incremental")
        m = blk.m
        g7 = g.get(7, -1)
        cyc = motion in CYCLES
        for a in "abc":
            if a in w and cyc:
                raise GCodeError({"a": "Cannot put an a in canned cycle",
                                  "b": "Cannot put a b in canned cycle",
                                  "c": "Cannot put a c in canned cycle"}[a])
        if "d" in w and g7 not in (410, 420, 411, 421) and g.get(14) != 960:
            raise GCodeError("D word with no G41, G41.1, G42, G42.1, G71, G71.1, G71.2 or "
                             "G96 to use it")
        if "e" in w and motion != 760 and m.get(5) not in (66, 67, 68):
            raise GCodeError("E word with no G70, G76, M66, M67 or M68 to use it")
        if "h" in w and g.get(8) not in (430, 432) and motion != 760:
            raise GCodeError("H word with no G43 or G76 to use it")
        if "i" in w and motion not in (20, 30, 50, 51, 760, 870) and g0 != 100:
            raise GCodeError("I word with no G2, G3, G5, G5.1, G10, G33.1, G76, or G87 to "
                             "use it")
        if "j" in w and motion not in (20, 30, 50, 51, 760, 870) and g0 != 100:
            raise GCodeError("J word with no G2, G3, G5, G5.1, G10, G76 or G87 to use it")
        if "k" in w and motion not in (20, 30, 330, 331, 760, 870):
            raise GCodeError("K word with no G2, G3, G33, G33.1, G76, or G87 to use it")
        if "l" in w and not (810 <= motion <= 890 or motion in (760, 52, 730) or g0 == 100
                             or g7 in (410, 411, 420, 421) or m.get(5) == 66):
            raise GCodeError("L word with no G10, cutter compensation, canned cycle, "
                             "digital/analog input, M98 or NURBS code")
        if "p" in w:
            if not (g0 in (100, 40) or g.get(13) == 640
                    or motion in (760, 820, 860, 880, 890, 50, 52, 20, 30)
                    or m.get(9) in (50, 51, 52, 53) or m.get(5) in (62, 63, 64, 65, 66)
                    or m.get(7) == 19):
                raise GCodeError("P word with no G2 G3 G4 G10 G64 G5 G5.2 G76 G82 G86 G88 "
                                 "G89 or M50 M51 M52 M53 M62 M63 M64 M65 M66 M98 or user M "
                                 "code to use it")
            p = w["p"]
            pv = c_int(p + 0.5)                        # rs274's round_to_int
            if (motion in (20, 30) or m.get(7) == 19) and abs(pv - p) > 0.001:
                raise GCodeError("P value not an integer with M19 G2 or G3")
            if motion in (20, 30) and pv < 1:
                raise GCodeError("P value should be 1 or greater with G2 or G3")
        if "$" in w and not (m.get(7) in (3, 4, 5, 19) or m.get(9) == 51
                             or motion in (330, 331, 760) or g.get(5) == 950
                             or g.get(14) in (960, 970)):
            raise GCodeError("$ (spindle selection) word with no M3, M4, M5, M19, M51, G33, "
                             "G33.1, G76, G95, G96 or G97 to use it")
        if w.get("q", -1.0) != -1.0 and not (
                motion in (830, 730, 50, 760) or m.get(5) in (66, 67, 68) or g0 == 100
                or m.get(6) == 61 or g.get(13) == 640 or m.get(7) == 19):
            raise GCodeError("Q word with no G5, G10, G64, G73, G76, G83, M19, M66, M67, "
                             "M68 or user M code that uses it")
        if "r" in w and not (motion in (20, 30, 760, 730) or 810 <= motion <= 890
                             or g7 in (411, 421) or g0 == 100 or m.get(7) == 19):
            raise GCodeError("R word with no g code that uses it")
        if g.get(14) == 960 and "s" not in w:
            raise GCodeError("S word missing with G96")

    # --- simple modal settings ------------------------------------------------------
    def set_feed_mode(self, code: int) -> None:
        if code == 930:
            self.feed_mode = 1
        elif code == 940:
            self.feed_mode = 0
            self.feed_rate = 0.0
        else:
            self.feed_mode = 2
            self.feed_rate = 0.0
        self.touch_state()

    def select_tool(self, t: int) -> None:
        if t != 0 and t not in self.tools:
            raise GCodeError(f"Requested tool {t} not found in the tool table")
        self.selected_tool = t

    def tool_data(self, t: int) -> tuple[float, float, float, float]:
        """Table row of tool ``t``; 0 means the spindle's row, which M6 fills (rs274's M61
        changes the tool number but not the row)."""
        if t == 0:
            t = self.spindle_data_tool
        return self.tools.get(t, (0.0, 0.0, 0.0, 0.0))

    def tool_change(self, code: int, w: dict) -> None:
        if code == 6:
            if self.comp.side:
                raise GCodeError("Cannot change tools with cutter radius compensation on")
            self.spindle_dir = 0
            self.spindle_tool = self.selected_tool
            self.spindle_data_tool = self.selected_tool
            self.toolchange_flag = True
        else:                                      # M61
            q = w.get("q", -1.0)
            t = math.floor(q + 0.5)
            if t < 0:
                raise GCodeError("Need non-negative Q-word to specify tool number with M61")
            if t != 0 and t not in self.tools:
                raise GCodeError(f"Requested tool {t} not found in the tool table")
            self.spindle_tool = t
            self.toolchange_flag = True
        self.touch_state()

    def load_spindle(self, t: int) -> None:
        """Start with tool ``t`` in the spindle (selected and changed, as ``T t M6``)."""
        if t not in self.tools:
            raise ValueError(f"tool {t} is not in the tool table")
        self.selected_tool = self.spindle_tool = self.spindle_data_tool = t
        self.touch_state()

    def spindle(self, code: int) -> None:
        if code == 3:
            self.spindle_dir = 1
        elif code == 4:
            self.spindle_dir = -1
        elif code in (5, 19):
            self.spindle_dir = 0
        self.touch_state()

    def other_m(self, m: dict) -> None:
        if m.get(9) is not None and self.comp.side:
            if m[9] == 49:
                raise GCodeError("Cannot disable overrides with cutter radius compensation on")
            raise GCodeError("Cannot enable overrides with cutter radius compensation on")
        if m.get(5) is not None and self.comp.side:
            raise GCodeError("Cannot set motion output with cutter radius compensation on")

    def set_plane(self, plane: str | None) -> None:
        if plane is None:
            raise GCodeError("Cannot do an arc in planes G17.1, G18.1, or G19.1")
        if self.comp.side and plane != self.plane:
            raise GCodeError("Cannot change planes with cutter radius compensation on")
        if self.comp.side and plane == "YZ":
            raise GCodeError("Cutter radius compensation allowed only in XY, XZ planes")
        self.plane = plane
        self.axes = PLANE_AXES[plane]

    def set_units(self, units: str) -> None:
        if units == self.units:
            return
        f = MM_PER_INCH if units == "mm" else 1.0 / MM_PER_INCH
        self.units = units
        self.cur = [v * f for v in self.cur]          # new lists: cur and out may alias
        self.out = [v * f for v in self.out]
        self.comp.prog = [v * f for v in self.comp.prog]
        self.origin = [v * f for v in self.origin]
        self.axis_offset = [v * f for v in self.axis_offset]
        self.tlo_effect = [v * f for v in self.tlo_effect]
        self.comp.scale(f)
        # rs274 re-reads the tool offset and feed from its canon layer, which keeps the
        # numbers it was given: they are not converted (a G43 before G20/G21 keeps its
        # old-unit numbers). Programs set units first, so this only matters for oddities.
        self.touch_state()

    def tool_length_offset(self, code: int, w: dict) -> None:
        if self.comp.side:
            raise GCodeError("Cannot change tool offset with cutter radius compensation on")
        k_mm = MM_PER_INCH if self.units == "inch" else 1.0
        if code == 490:
            new = [0.0, 0.0, 0.0]
            new_mm = (0.0, 0.0, 0.0)
        elif code == 430:
            if "h" in w:
                h = int(w["h"])
                if h != 0 and h not in self.tools:
                    raise GCodeError(f"Requested tool {h} not found in the tool table")
                d = self.tool_data(h)
            else:
                d = self.tool_data(0)
            new = [self.user_to_prog(d[1]), self.user_to_prog(d[2]), self.user_to_prog(d[3])]
            new_mm = (new[0] * k_mm, new[1] * k_mm, new[2] * k_mm)
        elif code == 431:
            new = list(self.tlo)
            mm = list(self.tlo_mm)
            for k, a in enumerate("xyz"):
                if a in w:
                    new[k] = w[a]
                    mm[k] = w[a] * k_mm
            new_mm = (mm[0], mm[1], mm[2])
        else:                                      # G43.2
            if "h" not in w:
                raise GCodeError("G43.2: No axes specified and H word missing")
            h = int(w["h"])
            if h != 0 and h not in self.tools:
                raise GCodeError(f"Requested tool {h} not found in the tool table")
            d = self.tool_data(h)
            new = [self.tlo[0] + self.user_to_prog(d[1]), self.tlo[1] + self.user_to_prog(d[2]),
                   self.tlo[2] + self.user_to_prog(d[3])]
            t = self.tlo_mm
            new_mm = (t[0] + self.user_to_prog(d[1]) * k_mm, t[1] + self.user_to_prog(d[2]) * k_mm,
                      t[2] + self.user_to_prog(d[3]) * k_mm)
        if self._moved_since(self.tlo_mark):
            self.tlo_effect = [0.0, 0.0, 0.0]
        self.tlo_mark = len(self.store)
        d = [self.tlo[k] - new[k] for k in range(3)]
        d[0], d[1] = rotate(d[0], d[1], -self.rotation)
        for k in range(3):
            self.cur[k] += d[k]
            self.tlo_effect[k] += d[k]
        self.tlo = new
        self.tlo_mm = new_mm
        self.sync_out()
        self.touch_state()

    def _moved_since(self, mark: int) -> bool:
        """Whether a move (not a dwell) was emitted after motion number ``mark``."""
        st = self.store
        return any(st.kind_at(j) != T_DWELL for j in range(mark, len(st)))

    def resync_after_tool_change(self) -> None:
        """rs274 re-reads the position from its canon layer after M6/M61, which has not
        seen tool length offset changes made since the last move (a G43 in the M6 block
        does not move the current point)."""
        if not self._moved_since(self.tlo_mark):
            for k in range(3):
                self.cur[k] -= self.tlo_effect[k]
            self.sync_out()
        # rs274's canon layer leaves X and Y at 0 after a G5/G5.1/G5.3 curve (its
        # NURBS_FEED does not keep the end point): when the last move is one, the tool
        # change puts the current point there (program coordinates; Z is kept)
        st = self.store
        j = len(st) - 1
        while j >= st.base and st.kind_at(j) == T_DWELL:
            j -= 1
        if j >= st.base and st.kind_at(j) in (T_CUBIC, T_NURBS):
            self.cur[0] = 0.0
            self.cur[1] = 0.0
            self.sync_out()
        self.tlo_effect = [0.0, 0.0, 0.0]
        self.tlo_mark = len(self.store)

    def find_ends(self, blk: Block) -> list[float]:
        """End point of a move from the block's axis words (LinuxCNC's find_ends)."""
        w = blk.words
        comp_mid = self.comp.side and not self.comp.first
        base = self.comp.prog if comp_mid else self.cur
        if blk.g.get(0) == 530:
            ao, org, tlo = self.axis_offset, self.origin, self.tlo
            cx, cy = rotate(self.cur[0] + ao[0], self.cur[1] + ao[1], self.rotation)
            px = w["x"] - org[0] - tlo[0] if "x" in w else cx
            py = w["y"] - org[1] - tlo[1] if "y" in w else cy
            px, py = rotate(px, py, -self.rotation)
            pz = w["z"] - org[2] - ao[2] - tlo[2] if "z" in w else self.cur[2]
            return [px - ao[0], py - ao[1], pz]
        if self.dist_abs:
            end = [w.get("x", base[0]), w.get("y", base[1]), w.get("z", base[2])]
        else:
            end = [base[0] + w.get("x", 0.0), base[1] + w.get("y", 0.0),
                   base[2] + w.get("z", 0.0)]
        if "@" in w or "^" in w:
            self.polar_end(end, w)
        return end

    def polar_end(self, end: list[float], w: dict) -> None:
        """@ radius and ^ angle (degrees) about the origin of X and Y (LinuxCNC)."""
        px, py = end[0], end[1]
        if self.dist_abs:
            if "@" in w and "^" in w:
                r, t = w["@"], math.radians(w["^"])
            elif "@" in w:
                if px == 0 and py == 0:
                    raise GCodeError("Must specify angle in polar coordinate if at the origin")
                r, t = w["@"], math.atan2(py, px)
            else:
                r, t = math.hypot(py, px), math.radians(w["^"])
            end[0], end[1] = r * math.cos(t), r * math.sin(t)
            return
        if "@" in w:
            if px == 0 and py == 0:
                raise GCodeError("Incremental motion with polar coordinates is indeterminate "
                                 "when at the origin")
            t = math.atan2(py, px)
            r = math.hypot(py, px) + w["@"]
            px, py = r * math.cos(t), r * math.sin(t)
        if "^" in w:
            if px == 0 and py == 0:
                raise GCodeError("G91 motion with polar coordinates is indeterminate when at "
                                 "the origin")
            t = math.atan2(py, px) + math.radians(w["^"])
            r = math.hypot(py, px)
            px, py = r * math.cos(t), r * math.sin(t)
        end[0], end[1] = px, py

    def home(self, code: int, blk: Block) -> None:
        end = self.find_ends(blk)
        if self.comp.side:
            raise GCodeError("Cannot use g28 or g30 with cutter radius comp")
        self.emit(T_TRAVERSE, blk.line, end)
        self.cur = list(end)
        base = 5161 if code == 280 else 5181
        h = [self.user_to_prog(self.params[base + k]) for k in range(3)]
        hx, hy = rotate(h[0] - self.origin[0] - self.tlo[0], h[1] - self.origin[1] - self.tlo[1],
                        -self.rotation)
        home = [hx - self.axis_offset[0], hy - self.axis_offset[1],
                h[2] - self.origin[2] - self.axis_offset[2] - self.tlo[2]]
        w = blk.words
        if any(a in w for a in AXES):
            end = [home[k] if a in w else end[k] for k, a in enumerate("xyz")]
        else:
            end = home
        self.emit(T_TRAVERSE, blk.line, end)
        self.cur = list(end)

    # --- motion ---------------------------------------------------------------------
    def motion(self, code: int, blk: Block) -> None:
        if code not in CYCLES:
            self.cycles.il_flag = False
        if code in (0, 10):
            self.straight(code, blk)
        elif code in (20, 30):
            self.arc(code, blk)
        elif code == 800:
            self.motion_mode = 800
        elif code in CYCLES:
            self.cycles.run(code, blk)
        elif code in (50, 51):
            self.spline(code, blk)
        elif code in (52, 53):
            self.nurbs(code, blk)
        else:
            raise GCodeError(f"G{code // 10}{'.' + str(code % 10) if code % 10 else ''} "
                             "is not supported by this interpreter")

    def inverse_feed_check(self, blk: Block, arc: bool) -> None:
        if self.feed_mode == 1:
            if "f" not in blk.words:
                raise GCodeError("F word missing with inverse time arc move" if arc
                                 else "F word missing with inverse time g1 move")
        elif self.feed_rate == 0.0:
            raise GCodeError("Cannot make arc with zero feed rate" if arc
                             else "Cannot do g1 with zero feed rate")
        elif self.feed_mode == 2 and self.speed == 0.0:
            raise GCodeError("Cannot feed with zero spindle speed in feed per rev mode")

    def move_feed(self, blk: Block) -> float:
        return blk.words.get("f", 0.0) if self.feed_mode == 1 else self.feed_rate

    def straight(self, code: int, blk: Block) -> None:
        self.comp.arc_not_allowed = False
        if code == 10:
            self.inverse_feed_check(blk, False)
        self.motion_mode = code
        end = self.find_ends(blk)
        feed = self.move_feed(blk) if code == 10 else 0.0
        if self.comp.side and self.comp.radius > 0.0:
            if blk.g.get(0) == 530:
                raise GCodeError("Cannot use g53 with cutter radius comp")
            if self.comp.first:
                self.comp.straight1(code, blk.line, end, feed)
            else:
                self.comp.straight2(code, blk.line, end, feed)
            return
        self.emit(T_FEED if code == 10 else T_TRAVERSE, blk.line, end, feed)
        self.cur = end

    def arc(self, code: int, blk: Block) -> None:
        if self.comp.arc_not_allowed:
            raise GCodeError("The move just after exiting cutter compensation mode must be "
                             "straight, not an arc")
        w = blk.words
        ijk = "i" in w or "j" in w or "k" in w
        if "r" not in w and not ijk:
            raise GCodeError("R i j k words all missing for arc")
        if "r" in w and ijk:
            raise GCodeError("Mixed radius ijk format for arc")
        self.inverse_feed_check(blk, True)
        plane = self.plane
        first, second = {"XY": ("i", "j"), "XZ": ("k", "i"), "YZ": ("j", "k")}[plane]
        if ijk:
            bad = {"XY": ("k", "K word given for arc in xy plane"),
                   "YZ": ("i", "I word given for arc in yz plane"),
                   "XZ": ("j", "J word given for arc in xz plane")}[plane]
            if bad[0] in w:
                raise GCodeError(bad[1])
            for letter in (first, second):
                if letter not in w and self.ijk_abs:
                    raise GCodeError(f"{letter.upper()} word missing in absolute center arc")
        else:
            a1, a2 = {"XY": ("x", "y"), "XZ": ("x", "z"), "YZ": ("y", "z")}[plane]
            if a1 not in w and a2 not in w and not (plane == "XY" and ("@" in w or "^" in w)):
                raise GCodeError({"XY": "X and y words missing for arc in xy plane",
                                  "YZ": "Y and z words missing for arc in yz plane",
                                  "XZ": "X and z words missing for arc in xz plane"}[plane])
        end = self.find_ends(blk)
        self.motion_mode = code
        turns = int(math.floor(w["p"] + 0.5)) if "p" in w else 1
        turn = -turns if code == 20 else turns
        off1, off2 = w.get(first, 0.0), w.get(second, 0.0)
        feed = self.move_feed(blk)
        if plane != "YZ" and self.comp.side and self.comp.radius > 0.0:
            if self.comp.first:
                self.comp.arc1(code, blk, end, off1, off2, turn, feed)
            else:
                self.comp.arc2(code, blk.line, w.get("r"), end, off1, off2, turn, feed)
            return
        a1, a2, an = self.axes
        c = self.cur
        if "r" in w:
            c1, c2 = arc_center_r(code == 20, self.units, c[a1], c[a2], end[a1], end[a2],
                                  w["r"])
        else:
            c1, c2, _ = arc_center_ijk(plane, self.units, c[a1], c[a2], end[a1], end[a2],
                                          self.ijk_abs, off1, off2)
        center = [0.0, 0.0, 0.0]
        center[a1], center[a2], center[an] = c1, c2, c[an]
        self.emit(T_ARC, blk.line, end, feed, center, turn)
        self.cur = end

    def spline(self, code: int, blk: Block) -> None:
        w = blk.words
        if self.comp.side:
            raise GCodeError("Cannot convert spline with cutter radius compensation")
        self.inverse_feed_check(blk, True)
        if self.plane != "XY":
            raise GCodeError("Splines must be in the XY plane")
        if any(a in w for a in "zabc"):
            raise GCodeError("Splines may not have motion in Z, A, B, or C")
        c = self.cur
        feed = self.move_feed(blk)
        if code == 51:
            if "i" not in w or "j" not in w:
                raise GCodeError("Must specify both I and J with G5.1")
            q = (c[0] + w["i"], c[1] + w["j"])
            end = self.find_ends(blk)
            c1 = (c[0] + 2.0 / 3.0 * (q[0] - c[0]), c[1] + 2.0 / 3.0 * (q[1] - c[1]))
            c2 = (end[0] + 2.0 / 3.0 * (q[0] - end[0]), end[1] + 2.0 / 3.0 * (q[1] - end[1]))
        else:
            if "i" not in w or "j" not in w:
                if "i" in w or "j" in w:
                    raise GCodeError("Must specify both I and J, or neither")
                c1 = (c[0] + self.spline_i, c[1] + self.spline_j)
            else:
                c1 = (c[0] + w["i"], c[1] + w["j"])
            end = self.find_ends(blk)
            if "p" not in w or "q" not in w:
                raise GCodeError("Must specify both P and Q with G5")
            c2 = (end[0] + w["p"], end[1] + w["q"])
            self.spline_i = -w["p"]
            self.spline_j = -w["q"]
        end[2] = c[2]
        n = len(self.store)
        self.emit(T_CUBIC, blk.line, end, feed)
        self.store.controls[n] = (c1, c2)
        self.cur = [end[0], end[1], c[2]]

    def nurbs(self, code: int, blk: Block) -> None:
        """G5.2 gathers control points (X Y with weight P, order L), G5.3 cuts the curve,
        as LinuxCNC's convert_nurbs: the first point is the current one (weight P on a
        block without X and Y, else 1); the current point moves only at G5.3."""
        w = blk.words
        pts = self.nurbs_points
        if code == 52:
            if ("x" in w) != ("y" in w):
                raise GCodeError("You must specify both X and Y coordinates for Control Points")
            p = w.get("p", -1.0)
            if "x" not in w and p > 0 and pts:
                raise GCodeError("Can specify P without X and Y only for the first control "
                                 "point")
            if p <= 0 and pts:
                raise GCodeError("Must specify positive weight P for every Control Point")
            if self.feed_mode == 0 and self.feed_rate == 0.0:
                raise GCodeError("Cannot make a NURBS with 0 feedrate")
            if self.motion_mode != 52:
                pts.clear()
            if not pts:
                c = self.cur
                pts.append((c[0], c[1], p if "x" not in w and p > 0 else 1.0))
                self.nurbs_order = 3
            lv = int(w.get("l", -1))
            if lv > 3:
                self.nurbs_order = lv
            if "x" in w:
                end = self.find_ends(blk)
                pts.append((end[0], end[1], p))
            self.motion_mode = 52
            return
        if self.motion_mode != 52:
            raise GCodeError("Cannot use G5.3 without G5.2 first")
        if len(pts) < self.nurbs_order:
            raise GCodeError("You must specify a number of control points at least equal "
                             f"to the order L = {self.nurbs_order}")
        c = self.cur
        end = [pts[-1][0], pts[-1][1], c[2]]
        n = len(self.store)
        self.emit(T_NURBS, blk.line, end, self.move_feed(blk))
        self.store.controls[n] = Nurbs(self.nurbs_order, tuple(pts))
        self.cur = end
        self.nurbs_points = []
        self.motion_mode = -1

    def stop(self, code: int, line: int) -> None:
        self.comp.flush(line)
        if code in (2, 30):
            c = self.cur
            for k in range(3):
                c[k] += self.origin[k]
            c[0], c[1] = rotate(c[0], c[1], self.rotation)
            self.origin_index = 1
            self.params[5220] = 1.0
            self.origin = self.offsets.work_offset_params(1)
            self.rotation = self.params[5230]
            c[0], c[1] = rotate(c[0], c[1], -self.rotation)
            for k in range(3):
                c[k] -= self.origin[k]
            self.plane = "XY"
            self.axes = PLANE_AXES["XY"]
            self.dist_abs = True
            self.feed_mode = 0
            self.feed_rate = 0.0
            self.comp.side = 0
            self.comp.first = True
            self.spindle_dir = 0
            self.motion_mode = 10
            self.sync_out()
            self.touch_state()
            self.ended = True
