"""Post-processor: a :class:`~millpath.model.Toolpath` as the program text of one control
dialect (:mod:`millpath.model.dialect`; LinuxCNC unless the options name another).

Writes a safe preamble
(``G17 G90 G94 G40 G49 G80``, ``G91.1`` incremental arc centres, ``G20``/``G21``), per
operation a comment, tool change ``Tn M6`` with ``G43 Hn``, spindle (``M3``/``M4``)
and coolant (``M7``/``M8``), then motion: ``G0``/``G1`` with modal motion codes and only
the axes that change, ``G2``/``G3`` with ``I J K`` in ``G17``/``G18``/``G19`` (``P`` for
extra turns), ``G5`` cubic Bezier splines in XY, canned drilling cycles
(``G81 G82 G83 G73 G85 G89`` with ``G98``/``G99``) closed by ``G80``, cutter radius
compensation ``G41``/``G42 Dn`` and ``G40``, and ``M2``. The tool path must hold only
what the dialect accepts (:func:`millpath.post.lower.lower` rewrites the rest): a
dialect whose tool change is a pause writes ``Tn M0`` after a message instead of
``Tn M6`` and ``G43 Hn``; one without mist coolant writes flood (``M8``).

Before a tool change the tool rises so that the new tool, changed where the machine
stands, has its tip at or above the next operation's safe height (a longer tool comes
in lower by the difference in gauge length). After each tool change the tool first
rises straight to the operation's safe height
(its highest move, or ``PostOptions.safe_z`` if higher), then moves in X and Y at that
height, then descends: never X, Y and Z together from the unknown tool-change position.
:class:`PostOptions` (the job's ``[post]`` table) sets coolant, work offset, program
end, N line numbers, a move before ``M6``, a program number and preamble/postamble
blocks.

Numbers: 4 decimals in mm, 5 in inch, trailing zeros dropped, never ``-0``. Arc centres
are recomputed from the *written* (rounded) start and end points so that LinuxCNC sees
equal start and end radii.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from millpath.model import Tool, Toolpath
from millpath.model.dialect import Dialect, dialect
from millpath.model.numbers import plain
from millpath.model.toolpath import PLANE_AXES, Move
from millpath.model.units import default

_PLANE_CODE = {"XY": "G17", "XZ": "G18", "YZ": "G19"}
_IJK = "IJK"


class _Fmt:
    def __init__(self, units: str, point: bool = False):
        self.decimals = int(default("decimals", units))
        self.q = 10.0 ** -self.decimals
        self.spec = f".{self.decimals}f"
        self.point = point              # every length with a decimal point ("10.")

    def r(self, v: float) -> float:
        """The value as it will be written (rounded), as a float."""
        return float(self.s(v))

    def s(self, v: float) -> str:
        t = format(v, self.spec)
        if "." in t:
            t = t.rstrip("0").rstrip(".")
        if t in ("-0", ""):
            t = "0"
        if self.point and "." not in t:
            t += "."
        return t


WORK_OFFSETS = ("G54", "G55", "G56", "G57", "G58", "G59", "G59.1", "G59.2", "G59.3")
TOOL_CHANGES = {"none": "", "G30": "G30", "G53 G0 Z0": "G53 G0 Z0"}


@dataclass
class PostOptions:
    """Program conventions (the job's ``[post]`` table).

    ``coolant``: "flood" | "mist" | "off" for every operation (None: each operation's
    own, flood by default); ``work_offset``: G54 .. G59.3 written in the setup line;
    ``end``: "M2" | "M30"; ``line_numbers``: N words in steps of 10 on every line but
    comments; ``tool_change``: "G30" | "G53 G0 Z0" | "none", the move written before each
    ``M6``; ``program_number``: written first as the comment ``(O<n>)`` (LinuxCNC has no
    program-number O word), or as ``O<n>`` after ``%`` for a control that numbers its
    programs (1 if not given); ``preamble`` / ``postamble``: G-code lines written after the
    setup and before the program end; ``safe_z``: lowest height (job units) of the move
    after a tool change; ``dialect``: the control (:mod:`millpath.model.dialect`).
    """

    coolant: str | None = None
    work_offset: str = "G54"
    end: str = "M2"
    line_numbers: bool = False
    tool_change: str = "none"
    program_number: int | None = None
    preamble: str = ""
    postamble: str = ""
    safe_z: float | None = None
    dialect: str = "linuxcnc"

    def __post_init__(self) -> None:
        dialect(self.dialect)
        if self.coolant not in (None, "flood", "mist", "off"):
            raise ValueError(f"coolant must be flood, mist or off, not {self.coolant!r}")
        if self.work_offset not in WORK_OFFSETS:
            raise ValueError(f"work_offset must be one of {', '.join(WORK_OFFSETS)}")
        if self.end not in ("M2", "M30"):
            raise ValueError("end must be M2 or M30")
        if self.tool_change not in TOOL_CHANGES:
            raise ValueError("tool_change must be G30, \"G53 G0 Z0\" or none")


def round_feed(feed: float, units: str) -> float:
    """The feed as written: a whole number in mm/min, one decimal in in/min
    (``feed_step`` of :mod:`millpath.model.units`), never rounded down to zero."""
    q = default("feed_step", units)
    return max(q, round(round(feed / q) * q, 4))


def _comment(text: str) -> str:
    clean = text.replace("(", "[").replace(")", "]").replace("\n", " ")
    return f"({clean})"


class _Writer:
    def __init__(self, tp: Toolpath, tools: dict[int, Tool], title: str,
                 options: PostOptions | None = None):
        self.opt = options or PostOptions()
        self.fallbacks: list[str] = []
        self.tp = tp
        self.tools = tools
        self.d: Dialect = dialect(self.opt.dialect)
        self.f = _Fmt(tp.units, self.d.decimal_point)
        self.lines: list[str] = []
        self.pos: list[float | None] = [None, None, None]   # last written position
        self.motion: str | None = None
        self.feed: float | None = None
        self._feed_in = math.nan       # the planned feed that ``self.feed`` was written for
        self.plane = "XY"
        self.tool: int | None = None
        self.spindle: float | None = None
        self.coolant = "off"
        self.comp = "off"
        self.cycle_key: tuple | None = None
        self.title = title
        self.changed = False            # a tool change happened and no motion since
        self.safe = 0.0

    # --- helpers ------------------------------------------------------------------
    def emit(self, s: str) -> None:
        if self.d.max_line is not None and not s.startswith("("):
            n = len(s.replace(" ", "")) + (8 if self.opt.line_numbers else 0)
            if n > self.d.max_line:
                raise ValueError(f"{self.d.title} buffers {self.d.max_line} characters of a "
                                 f"block; this one has {n}: {s}")
        self.lines.append(s)

    def fell_back(self, what: str) -> None:
        if what not in self.fallbacks:
            self.fallbacks.append(what)

    def _feed_word(self, feed: float) -> str:
        if feed == self._feed_in and self.feed is not None:
            return ""               # the same planned feed as the move before: written
        if feed <= 0 or not math.isfinite(feed):
            raise ValueError(f"feed move with feed rate {feed!r}")
        self._feed_in = feed
        feed = round_feed(feed, self.tp.units)
        if self.feed is None or abs(feed - self.feed) > 1e-9:
            self.feed = feed
            return " F" + plain(feed)
        return ""

    def _end_cycle(self) -> None:
        if self.cycle_key is not None:
            self.emit("G80")
            self.cycle_key = None
            self.motion = None

    def _set_plane(self, plane: str) -> None:
        if plane != self.plane:
            self.emit(_PLANE_CODE[plane])
            self.plane = plane

    def _axes(self, end, force: bool = False) -> tuple[str, list[float]]:
        """The axis words of a move to ``end`` (those that change, or all with
        ``force``) and the position as written."""
        words = []
        written = []
        pos = self.pos
        s = self.f.s
        for i, a in enumerate("XYZ"):
            t = s(end[i])
            v = float(t)
            written.append(v)
            if force or pos[i] is None or v != pos[i]:
                words.append(a + t)
        return " ".join(words), written

    def _moved(self, end) -> None:
        self.pos = [self.f.r(v) for v in end]

    # --- program parts ------------------------------------------------------------
    def preamble(self) -> None:
        if self.d.program_number:
            self.emit("%")
            self.emit(f"O{self.opt.program_number or 1:04d}")
        elif self.opt.program_number is not None:
            self.emit(f"(O{self.opt.program_number})")
        if self.title:
            self.emit(_comment(self.title))
        self.emit(_comment(f"millpath post: {self.d.title}, units {self.tp.units}"))
        used = sorted({op.tool for op in self.tp.ops})
        for n in used:
            t = self.tools.get(n)
            if t is not None:
                desc = f"T{n} {t.type} D{plain(t.diameter, 4)}"
                if t.type == "bull":
                    desc += f" R{plain(t.corner_radius, 4)}"
                self.emit(_comment(desc + (f" {t.comment}" if t.comment else "")))
        self.emit("G17 G90 G94 G40 G49 G80")
        if self.d.arc_center_code:
            self.emit("G91.1")
        self.emit("G20" if self.tp.units == "inch" else "G21")
        self.emit(self.opt.work_offset)
        self._block(self.opt.preamble)

    def _block(self, text: str) -> None:
        for raw in text.splitlines():
            if raw.strip():
                self.emit(raw.strip())

    def begin_op(self, i: int) -> None:
        op = self.tp.ops[i]
        self._end_cycle()
        if self.comp != "off":
            raise ValueError(f"operation {op.name!r} starts with cutter compensation on")
        self.emit(_comment(f"operation {i + 1}: {op.type} - {op.name}"))
        if op.tool != self.tool:
            zs = [m.end[2] for m in self.tp.moves if m.op == i and m.kind != "comp"]
            safe = max(zs + ([self.opt.safe_z] if self.opt.safe_z is not None else []))
            if self.tool is not None:
                self._lift_for_change(op.tool, safe)
                self.emit("M5")
                if self.coolant != "off":
                    self.emit("M9")
                    self.coolant = "off"
                self.spindle = None
            if TOOL_CHANGES[self.opt.tool_change]:
                self.emit(TOOL_CHANGES[self.opt.tool_change])
            if self.d.tool_change == "pause":
                t = self.tools.get(op.tool)
                what = f"T{op.tool}" + (f" {t.type} D{plain(t.diameter, 4)}" if t else "")
                self.emit(_comment(f"MSG, load {what}, set Z zero at its tip, resume"))
                self.emit(f"T{op.tool} M0")
            else:
                self.emit(f"T{op.tool} M6")
                self.emit(f"G43 H{op.tool}")
            self.tool = op.tool
            self.pos = [None, None, None]
            self.motion = None
            self.changed = True
            self.safe = safe
        if op.spindle != self.spindle:
            if op.spindle == 0:
                self.emit("M5")
            else:
                code = "M3" if op.spindle > 0 else "M4"
                self.emit(f"S{plain(abs(op.spindle), 0)} {code}")
            self.spindle = op.spindle
        coolant = self.opt.coolant or op.coolant
        if coolant == "mist" and not self.d.mist:
            self.fell_back(f"mist coolant written as flood (M8): {self.d.title} has no M7")
            coolant = "flood"
        if coolant != self.coolant:
            self.emit({"flood": "M8", "mist": "M7", "off": "M9"}[coolant])
            self.coolant = coolant

    def _lift_for_change(self, new_tool: int, safe: float) -> None:
        """Before ``M6``: the machine changes tools where it stands, so a longer new tool
        comes in lower by the difference in length. Rise (with the old tool's offset) so
        that the new tool's tip is at or above ``safe``, the next operation's height."""
        old, new = self.tools.get(self.tool), self.tools.get(new_tool)
        if old is None or new is None or self.pos[2] is None:
            return
        need = safe + max(0.0, new.gauge_length - old.gauge_length)
        if self.pos[2] < need - 1e-9:
            z = self.f.s(need + 0.5 * self.f.q)       # written at or above ``need``
            self.emit(f"G0 Z{z}")
            self.motion = "G0"
            self.pos = [self.pos[0], self.pos[1], self.f.r(need + 0.5 * self.f.q)]

    def approach(self, m: Move) -> None:
        """After a tool change: up to the safe height, X and Y there, then (for a first
        move that is not a rapid ending at that height) down to the move's start."""
        self.changed = False
        if m.kind in ("arc", "cubic"):
            raise ValueError(f"a{'n' if m.kind == 'arc' else ''} {m.kind} cannot be the first "
                             "move after a tool change")
        if m.kind == "comp":
            raise ValueError("cutter compensation cannot start right after a tool change")
        safe = max(self.safe, m.end[2])
        self.emit(f"G0 Z{self.f.s(safe)}")
        self.emit(f"X{self.f.s(m.end[0])} Y{self.f.s(m.end[1])}")
        self.motion = "G0"
        self.pos = [self.f.r(m.end[0]), self.f.r(m.end[1]), self.f.r(safe)]

    def move(self, m: Move) -> None:
        k = m.kind
        if self.changed and k != "comp":
            self.approach(m)
        if k != "drill":
            self._end_cycle()
        if k == "rapid":
            ax, written = self._axes(m.end)
            if ax:
                self.emit(("G0 " if self.motion != "G0" else "") + ax)
                self.motion = "G0"
            self.pos = written
        elif k == "line":
            ax, written = self._axes(m.end)
            fw = self._feed_word(m.feed)
            if ax:
                self.emit(("G1 " if self.motion != "G1" else "") + ax + fw)
                self.motion = "G1"
            elif fw:
                self.emit(fw.strip())
            self.pos = written
        elif k == "arc":
            self.arc(m)
        elif k == "cubic":
            self.cubic(m)
        elif k == "drill":
            self.drill(m)
        elif k == "comp":
            self.compensation(m)
        elif k == "dwell":
            if m.dwell > 0:
                self.emit(f"G4 P{round(m.dwell * 1000)}" if self.d.dwell_ms
                          else f"G4 P{plain(m.dwell, 3)}")
        else:
            raise ValueError(f"unknown move kind {k!r}")

    def arc(self, m: Move) -> None:
        if any(p is None for p in self.pos):
            raise ValueError("an arc cannot be the first move after a tool change")
        self._set_plane(m.plane)
        a1, a2, an = PLANE_AXES[m.plane]
        s = [float(p) for p in self.pos]              # written start
        e = [self.f.r(v) for v in m.end]              # written end
        c = m.center
        assert c is not None
        # centre on the bisector of the written chord nearest the planned centre
        s1, s2, e1, e2 = s[a1], s[a2], e[a1], e[a2]
        c1, c2 = c[a1], c[a2]
        d1, d2 = e1 - s1, e2 - s2
        chord = math.hypot(d1, d2)
        if chord > 1e-12:
            m1, m2 = (s1 + e1) / 2, (s2 + e2) / 2
            n1, n2 = -d2 / chord, d1 / chord
            t = (c1 - m1) * n1 + (c2 - m2) * n2
            c1, c2 = m1 + t * n1, m2 + t * n2
        i1, i2 = self.f.r(c1 - s1), self.f.r(c2 - s2)
        r0 = math.hypot(i1, i2)
        r1 = math.hypot(s1 + i1 - e1, s2 + i2 - e2)
        if r0 < 10 * self.f.q:
            raise ValueError(f"arc radius {r0:g} is too small to write")
        if abs(r0 - r1) > 2 * self.f.q and chord > 1e-12:
            raise ValueError(f"arc end point is not on the arc (radius {r0:g} vs {r1:g})")
        code = "G2" if m.clockwise else "G3"
        words = [code]
        axes = "XYZ"
        for ax in (a1, a2, an):
            if ax == an and self.pos[ax] is not None and e[ax] == self.pos[ax]:
                continue
            if ax != an and chord <= 1e-12 and e[ax] == s[ax]:
                continue        # full circle: end = start, axes may be left out
            words.append(axes[ax] + self.f.s(e[ax]))
        words.append(_IJK[a1] + self.f.s(i1))
        words.append(_IJK[a2] + self.f.s(i2))
        if m.turns > 1:
            if not self.d.arc_turns:
                raise ValueError(f"{self.d.title} has no P word on arcs (extra turns)")
            words.append(f"P{m.turns}")
        self.emit(" ".join(words) + self._feed_word(m.feed))
        self.motion = code
        self.pos = list(e)

    def cubic(self, m: Move) -> None:
        if not self.d.g5:
            raise ValueError(f"{self.d.title} has no G5 cubic splines")
        if self.comp != "off":
            raise ValueError("G5 splines cannot be written with cutter compensation on")
        if any(p is None for p in self.pos):
            raise ValueError("a cubic cannot be the first move after a tool change")
        if self.f.r(m.end[2]) != self.pos[2]:
            raise ValueError("G5 cubics stay at constant Z")
        self._set_plane("XY")
        assert m.c1 is not None and m.c2 is not None
        s = self.pos
        i, j = m.c1[0] - s[0], m.c1[1] - s[1]          # type: ignore[operator]
        p, q = m.c2[0] - m.end[0], m.c2[1] - m.end[1]
        self.emit(f"G5 X{self.f.s(m.end[0])} Y{self.f.s(m.end[1])} I{self.f.s(i)} "
                  f"J{self.f.s(j)} P{self.f.s(p)} Q{self.f.s(q)}" + self._feed_word(m.feed))
        self.motion = "G5"
        self._moved(m.end)

    def drill(self, m: Move) -> None:
        if m.cycle not in self.d.cycles:
            raise ValueError(f"{self.d.title} has no {m.cycle} cycle")
        if self.comp != "off":
            raise ValueError("canned cycles cannot be used with cutter compensation on")
        if any(p is None for p in self.pos):
            raise ValueError("a drilling cycle cannot be the first move after a tool change")
        self._set_plane("XY")
        key = (m.cycle, self.f.r(m.end[2]), self.f.r(m.r_plane), m.peck, m.dwell,
               m.retract_initial, m.feed)
        initial_z = self.pos[2]
        if key != self.cycle_key:
            self._end_cycle()
            words = ["G98" if m.retract_initial else "G99", m.cycle,
                     f"X{self.f.s(m.end[0])}", f"Y{self.f.s(m.end[1])}",
                     f"Z{self.f.s(m.end[2])}", f"R{self.f.s(m.r_plane)}"]
            if m.cycle in ("G83", "G73"):
                if m.peck <= 0:
                    raise ValueError(f"{m.cycle} needs a positive peck increment")
                words.append(f"Q{self.f.s(m.peck)}")
            if m.cycle in ("G82", "G89") or (m.dwell and m.cycle in ("G83",)):
                words.append(f"P{round(m.dwell * 1000)}" if self.d.dwell_ms
                             else f"P{plain(m.dwell, 3)}")
            self.feed = None
            self.emit(" ".join(words) + self._feed_word(m.feed))
            self.cycle_key = key
            self.cycle_initial = initial_z
        else:
            self.emit(f"X{self.f.s(m.end[0])} Y{self.f.s(m.end[1])}")
        z_clear = max(self.cycle_initial, self.f.r(m.r_plane)) if m.retract_initial \
            else self.f.r(m.r_plane)
        self.pos = [self.f.r(m.end[0]), self.f.r(m.end[1]), z_clear]

    def compensation(self, m: Move) -> None:
        if not self.d.cutter_comp:
            raise ValueError(f"{self.d.title} has no cutter radius compensation (G41/G42)")
        self._end_cycle()
        self._set_plane("XY")           # LinuxCNC compensates in the XY plane only
        if m.comp == "off":
            self.emit("G40")
        else:
            code = "G41" if m.comp == "left" else "G42"
            self.emit(f"{code} D{m.comp_d}")
        self.comp = m.comp

    def end(self) -> None:
        self._end_cycle()
        if self.comp != "off":
            self.emit("G40")
        self._block(self.opt.postamble)
        self.emit("M5")
        if self.coolant != "off":
            self.emit("M9")
        self.emit(self.opt.end)
        if self.d.program_number:
            self.emit("%")

    def numbered(self) -> list[str]:
        """The lines, with N words in steps of 10 when asked (comments, ``%`` and the
        program number left bare)."""
        if not self.opt.line_numbers:
            return self.lines
        out, n = [], 0
        for ln in self.lines:
            if ln.startswith(("(", "%", "O")):
                out.append(ln)
            else:
                n += 10
                out.append(f"N{n} {ln}")
        return out


@dataclass
class Written:
    """A posted program: its text, the 1-based line that carries each move (None where
    a move writes no motion, e.g. a rapid to where the tool already is) and what was
    written otherwise than planned because the dialect lacks it."""

    text: str
    move_lines: list[int | None]
    fallbacks: list[str]


def post(toolpath: Toolpath, tools: dict[int, Tool], *, title: str = "",
         options: PostOptions | None = None) -> str:
    """Program text in the options' dialect for ``toolpath``; ``tools`` gives tool
    comments.

    Raises ValueError for moves the control cannot run as written (non-positive feeds,
    splines or cycles under cutter compensation, degenerate arcs, what the dialect
    lacks).
    """
    return write(toolpath, tools, title=title, options=options).text


def post_with_lines(toolpath: Toolpath, tools: dict[int, Tool], *, title: str = "",
                    options: PostOptions | None = None) -> tuple[str, list[int | None]]:
    """Like :func:`post`, also returning each move's program line (see :class:`Written`)."""
    w = write(toolpath, tools, title=title, options=options)
    return w.text, w.move_lines


def write(toolpath: Toolpath, tools: dict[int, Tool], *, title: str = "",
          options: PostOptions | None = None) -> Written:
    """The program for ``toolpath`` (see :func:`post`) with its line map and fallbacks."""
    toolpath.check_finite()
    w = _Writer(toolpath, tools, title, options)
    w.preamble()
    current = -1
    where: list[int | None] = []
    for m in toolpath.moves:
        if m.op != current:
            w.begin_op(m.op)
            current = m.op
        before = len(w.lines)
        w.move(m)
        if len(w.lines) == before or m.kind == "comp":
            where.append(None)
        else:
            where.append(len(w.lines))
    w.end()
    return Written("\n".join(w.numbered()) + "\n", where, w.fallbacks)
