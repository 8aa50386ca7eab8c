"""What a machine control accepts and how it reads a program: one :class:`Dialect` per
control family, used by the post (what it may write) and by the interpreter (what it
refuses, and how it reads tool changes).

G codes are stored as the lexer keeps them, the code times ten (``G91.1`` is 911); M
codes as their number. Lengths are in the program's units.
"""

from __future__ import annotations

from dataclasses import dataclass


def _codes(*codes: float) -> frozenset[int]:
    return frozenset(round(c * 10) for c in codes)


@dataclass(frozen=True)
class Dialect:
    """A control's program rules.

    ``g_codes`` / ``m_codes``: every code the control accepts; ``letters``: the
    word letters it accepts; ``g5``: cubic splines (G5); ``cycles``: the canned cycles it
    runs (others are written as moves); ``cutter_comp``: G41/G42 with D; ``arc_turns``:
    a P word on G2/G3 for extra turns (else one arc per turn); ``mist``: M7;
    ``tool_change``: ``"M6"`` (automatic, then ``G43 Hn``) or ``"pause"`` (``Tn M0``: the
    operator changes the tool and sets Z zero at its tip, so every tool runs with its
    own length compensated); ``max_line``: characters of a block the control buffers,
    blanks and comments left out (None: no limit); ``parameters``: ``#`` parameters,
    expressions and O-words; ``needs_end``: a program must end with M2 or M30 (a
    streamed program just stops); ``extension``: the program file's suffix;
    ``arc_center_code``: ``G91.1`` (incremental arc centres) is a code of the control
    (where it is not, I J K are incremental anyway); ``decimal_point``: a length written
    without a decimal point counts least increments (0.001 mm, 0.0001 in), so every
    length is written with one; ``dwell_ms``: P of a dwell or cycle is in milliseconds;
    ``program_number``: the program sits between ``%`` lines, headed by ``O<n>``;
    ``starts_in_g0``: G0 is the motion mode at power-on (LinuxCNC has none);
    ``tool_table``: the file the control reads its tools from, written beside the
    program (None: the tools are listed in the program's header comments only).
    """

    name: str
    title: str
    g_codes: frozenset[int]
    m_codes: frozenset[int]
    letters: frozenset[str]
    g5: bool
    cycles: frozenset[str]
    cutter_comp: bool
    arc_turns: bool
    mist: bool
    tool_change: str
    max_line: int | None
    parameters: bool
    needs_end: bool
    extension: str
    arc_center_code: bool = True
    decimal_point: bool = False
    dwell_ms: bool = False
    program_number: bool = False
    starts_in_g0: bool = False
    tool_table: str | None = None

    def accepts_g(self, code10: int) -> bool:
        return code10 in self.g_codes

    def accepts_m(self, code: int) -> bool:
        return code in self.m_codes


#: LinuxCNC 2.9 (what millpath's interpreter and rs274 read)
LINUXCNC = Dialect(
    name="linuxcnc", title="LinuxCNC 2.9",
    g_codes=_codes(0, 1, 2, 3, 4, 5, 5.1, 5.2, 5.3, 7, 8, 10, 17, 17.1, 18, 18.1, 19, 19.1,
                   20, 21, 28, 28.1, 30, 30.1, 33, 33.1, 38.2, 38.3, 38.4, 38.5, 40, 41,
                   41.1, 42, 42.1, 43, 43.1, 43.2, 49, 52, 53, 54, 55, 56, 57, 58, 59,
                   59.1, 59.2, 59.3, 61, 61.1, 64, 73, 76, 80, 81, 82, 83, 84, 85, 86, 87,
                   88, 89, 90, 90.1, 91, 91.1, 92, 92.1, 92.2, 92.3, 93, 94, 95, 96, 97, 98,
                   99),
    m_codes=frozenset((0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 30, 48, 49, 50, 51, 52, 53, 60, 61, 62,
                       63, 64, 65, 66, 67, 68, 70, 71, 72, 73, 98, 99, *range(100, 200))),
    letters=frozenset("abcdefhijklmnpqrstuvwxyz"),
    g5=True, cycles=frozenset(("G73", "G81", "G82", "G83", "G85", "G89")),
    cutter_comp=True, arc_turns=True, mist=True, tool_change="M6", max_line=None,
    parameters=True, needs_end=True, extension=".ngc", tool_table="tools.tbl")

#: GRBL 1.1 as built by default (no M7, no canned cycles, no tool changer, 80-character
#: line buffer)
GRBL = Dialect(
    name="grbl", title="GRBL 1.1",
    g_codes=_codes(0, 1, 2, 3, 4, 10, 17, 18, 19, 20, 21, 28, 28.1, 30, 30.1, 38.2, 38.3,
                   38.4, 38.5, 40, 43.1, 49, 53, 54, 55, 56, 57, 58, 59, 61, 80, 90, 91,
                   91.1, 92, 92.1, 93, 94),
    m_codes=frozenset((0, 1, 2, 30, 3, 4, 5, 8, 9)),
    letters=frozenset("fijklnprstxyz"),
    g5=False, cycles=frozenset(), cutter_comp=False, arc_turns=False, mist=False,
    tool_change="pause", max_line=79, parameters=False, needs_end=False, extension=".nc",
    starts_in_g0=True)

_FANUC_G = _codes(0, 1, 2, 3, 4, 10, 17, 18, 19, 20, 21, 28, 30, 40, 41, 42, 43, 49, 52, 53,
                  54, 55, 56, 57, 58, 59, 73, 74, 76, 80, 81, 82, 83, 84, 85, 86, 87, 88, 89,
                  90, 91, 92, 94, 95, 98, 99)
_FANUC_M = frozenset((0, 1, 2, 3, 4, 5, 6, 8, 9, 30, 98, 99))

#: Fanuc 0i-MF style (ISO code): every length with a decimal point, dwell P in
#: milliseconds, no G91.1 (I J K always incremental), no G5, no M7, program O-number
#: between % lines
FANUC = Dialect(
    name="fanuc", title="Fanuc 0i", g_codes=_FANUC_G, m_codes=_FANUC_M,
    letters=frozenset("dfhijklmnopqrstxyz"),
    g5=False, cycles=frozenset(("G73", "G81", "G82", "G83", "G85", "G89")),
    cutter_comp=True, arc_turns=False, mist=False, tool_change="M6", max_line=None,
    parameters=False, needs_end=True, extension=".nc", arc_center_code=False,
    decimal_point=True, dwell_ms=True, program_number=True, starts_in_g0=True)

#: Haas mills (Fanuc-style programming; the codes millpath writes are read alike)
HAAS = Dialect(**{**FANUC.__dict__, "name": "haas", "title": "Haas (Fanuc-style)",
                  "g_codes": _FANUC_G | _codes(187), "m_codes": _FANUC_M | {88, 89}})

#: Mach3 / Mach4: LinuxCNC-like, without G5, O-word subroutines or P turns on arcs
MACH3 = Dialect(
    name="mach3", title="Mach3/Mach4",
    g_codes=_codes(0, 1, 2, 3, 4, 10, 12, 13, 15, 16, 17, 18, 19, 20, 21, 28, 28.1, 30,
                   31, 40, 41, 42, 43, 49, 50, 51, 52, 53, 54, 55, 56, 57, 58, 59, 61, 64,
                   68, 69, 73, 80, 81, 82, 83, 84, 85, 86, 87, 88, 89, 90, 90.1, 91, 91.1,
                   92, 92.1, 92.2, 92.3, 93, 94, 95, 98, 99),
    m_codes=frozenset((0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 30, 47, 48, 49, 98, 99)),
    letters=frozenset("abcdefhijklmnpqrstuvwxyz"),
    g5=False, cycles=frozenset(("G73", "G81", "G82", "G83", "G85", "G89")),
    cutter_comp=True, arc_turns=False, mist=True, tool_change="M6", max_line=None,
    parameters=False, needs_end=True, extension=".tap")

DIALECTS = {d.name: d for d in (LINUXCNC, GRBL, FANUC, HAAS, MACH3)}


def dialect(name: str) -> Dialect:
    """The dialect called ``name`` (ValueError naming the known ones)."""
    try:
        return DIALECTS[name]
    except KeyError:
        raise ValueError(f"unknown dialect {name!r} (known: {', '.join(DIALECTS)})") from None
