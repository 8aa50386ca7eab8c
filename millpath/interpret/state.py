"""The interpreter's state, apart from its executors: modal state (units, plane,
distance and feed modes, motion mode, spindle), position (``cur``: the current point;
``out``: the end of the last recorded motion), work offsets, tool length offset, tool
and tool table, numbered and named parameters, and the recorded motion (``store``),
with the unit conversions and the motion output every executor uses.

Positions are program coordinates in program units (``units``); tool table values and
parameters are machine units (``user_to_prog`` / ``prog_to_user`` convert).
"""

from __future__ import annotations

from millpath.interpret.store import KIND_CODE, PACK, MotionList, PLANE_CODE
from millpath.model.motion import Frame
from millpath.model.toolpath import PLANE_AXES
from millpath.model.units import MM_PER_INCH
T_DWELL = KIND_CODE["dwell"]


class MachineState:
    """The interpreter's state and motion output; see the module docstring."""

    def __init__(self, tools: dict, machine_units: str = "inch"):
        if machine_units not in ("inch", "mm"):
            raise ValueError("machine_units must be 'inch' or 'mm'")
        self.tools = tools
        self.table = dict(tools)                # the tool table as written: real tools
        self.machine_units = machine_units
        self.units = "mm"                       # rs274 starts in mm
        self.plane = "XY"
        self.axes = PLANE_AXES["XY"]
        self.dist_abs = True
        self.ijk_abs = False
        self.feed_mode = 0                      # 0 units/min, 1 inverse time, 2 per rev
        self.feed_rate = 0.0
        self.speed = 0.0
        self.spindle_dir = 0
        self.motion_mode = 800                  # G80
        self.cur = [0.0, 0.0, 0.0]
        self.out = [0.0, 0.0, 0.0]              # end of the last emitted motion
        self.origin_index = 1
        self.origin = [0.0, 0.0, 0.0]           # work offset, program units
        self.rotation = 0.0                     # XY rotation of the work system, degrees
        self.axis_offset = [0.0, 0.0, 0.0]      # G92/G52 offset, program units
        self.tlo = [0.0, 0.0, 0.0]              # tool length offset, program units
        self.tlo_mm = (0.0, 0.0, 0.0)           # the same as the machine applies it, mm
        self.params = [0.0] * 5602
        self.params[5220] = 1.0
        self.named: dict[str, float] = {}
        self.selected_tool = 0
        self.spindle_tool = 0
        self.spindle_data_tool = 0              # whose table row pocket 0 holds (M6 only)
        self.toolchange_flag = False
        self.tlo_effect = [0.0, 0.0, 0.0]       # TLO shifts of ``cur`` since the last move
        self.tlo_mark = 0
        self.retract_r_plane = True             # rs274's default retract mode is G99
        self.spline_i = 0.0
        self.spline_j = 0.0
        self.nurbs_points: list[tuple[float, float, float]] = []    # G5.2 (x, y, w)
        self.nurbs_order = 3
        self.store = MotionList()
        self._state_key = None
        self._state_idx = 0
        self.touch_state()
        self.ended = False

    # --- units and output -----------------------------------------------------------
    def user_to_prog(self, v: float) -> float:
        """Machine (tool table, parameter) units to program units."""
        if self.units == self.machine_units:
            return v
        return v * MM_PER_INCH if self.units == "mm" else v / MM_PER_INCH

    def prog_to_user(self, v: float) -> float:
        if self.units == self.machine_units:
            return v
        return v / MM_PER_INCH if self.units == "mm" else v * MM_PER_INCH

    @property
    def state_index(self) -> int:
        """Index in ``store.states`` of the modal state (tool length offset, tool,
        spindle, feed mode) the next motion is recorded with."""
        return self._state_idx

    def frame(self) -> Frame:
        """Where program coordinates are on the machine now (see :class:`Frame`)."""
        row = self.table.get(self.spindle_tool, (0.0, 0.0, 0.0, 0.0))
        k = MM_PER_INCH if self.machine_units == "inch" else 1.0
        return Frame(self.units, tuple(self.origin), tuple(self.axis_offset), self.rotation,
                     self.tlo_mm, (row[1] * k, row[2] * k, row[3] * k))

    def set_up(self, units: str | None = None, params: dict[int, float] | None = None) -> None:
        """The machine as it stands when the program starts: ``units`` the control's
        default units ("mm" | "inch"; rs274's is mm), ``params`` stored parameters
        (machine units: work offsets 5221.., the work system in force 5220, G92 offsets
        5210-5213; a LinuxCNC ``.var`` file). Call before the first block."""
        if units is not None:
            if units not in ("mm", "inch"):
                raise ValueError("units must be 'inch' or 'mm'")
            self.units = units
        for k, v in (params or {}).items():
            self.params[k] = float(v)
        p = self.params
        self.origin_index = int(p[5220]) if 1 <= p[5220] <= 9 else 1
        base = 5201 + 20 * self.origin_index
        self.origin = [self.user_to_prog(p[base + k]) for k in range(3)]
        self.rotation = p[base + 9]
        if p[5210]:
            self.axis_offset = [self.user_to_prog(p[5211 + k]) for k in range(3)]
        self.touch_state()

    def reference(self) -> Frame:
        """The frame program coordinates have now without any tool: the part's frame when
        called before the first block."""
        return Frame(self.units, tuple(self.origin), tuple(self.axis_offset), self.rotation)

    def touch_state(self) -> None:
        key = ((self.tlo[0], self.tlo[1], self.tlo[2]), self.spindle_tool,
               self.speed * self.spindle_dir,
               "inverse_time" if self.feed_mode == 1 else "units_per_minute", self.frame())
        if key != self._state_key:
            self._state_key = key
            self.store.states.append(key)
            self._state_idx = len(self.store.states) - 1

    def emit(self, kind: int, line: int, end, feed: float = 0.0, center=None, rot: int = 0,
             state: int | None = None) -> None:
        o = self.out
        st = self._state_idx if state is None else state
        if center is None:
            self.store.buf += PACK(o[0], o[1], o[2], end[0], end[1], end[2], feed, 0.0, 0.0,
                                   0.0, kind, line, rot, PLANE_CODE[self.plane], st)
        else:
            self.store.buf += PACK(o[0], o[1], o[2], end[0], end[1], end[2], feed, center[0],
                                   center[1], center[2], kind, line, rot,
                                   PLANE_CODE[self.plane], st)
        self.out = [end[0], end[1], end[2]]

    def emit_dwell(self, line: int, seconds: float, state: int | None = None) -> None:
        o = self.out
        self.store.buf += PACK(o[0], o[1], o[2], o[0], o[1], o[2], 0.0, seconds, 0.0, 0.0,
                               T_DWELL, line, 0, PLANE_CODE[self.plane],
                               self._state_idx if state is None else state)

    def sync_out(self) -> None:
        """The current point moved without motion (offsets changed)."""
        self.out = list(self.cur)
        self.touch_state()
