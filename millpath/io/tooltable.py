"""LinuxCNC tool table files: ``T1 P1 D6.000 Z50.000 ;comment``.

Each line: ``T`` tool number, ``P`` pocket, offsets ``X Y Z A B C U V W``, ``D``
diameter, ``I J Q`` (lathe), then ``;`` and a comment. Values are in the machine's
units: LinuxCNC (and its standalone ``rs274``) reads them in the machine's units
whatever the program's (rs274: inch). millpath writes them in the machine units of the
job (``[machine] units``) with a first comment line ``; millpath tool table, values in
UNITS (machine units)`` that :func:`table_units` reads back.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass, field, replace
from pathlib import Path

from millpath.errors import MillpathError
from millpath.model.limits import MAX_COORDINATE
from millpath.model.numbers import plain
from millpath.model.units import length_scale

_FIELDS = "XYZABCUVWDIJQ"
#: largest magnitude accepted for any value (lengths in machine units, tool numbers)
MAX_VALUE = MAX_COORDINATE


@dataclass
class ToolEntry:
    """One tool table row. ``offsets`` maps axis letters (X..W) to length offsets."""

    number: int
    pocket: int
    diameter: float = 0.0
    offsets: dict[str, float] = field(default_factory=dict)
    front_angle: float = 0.0
    back_angle: float = 0.0
    orientation: int = 0
    comment: str = ""

    @property
    def z(self) -> float:
        return self.offsets.get("Z", 0.0)


def format_tool_table(entries: list[ToolEntry]) -> str:
    lines = []
    for e in sorted(entries, key=lambda e: e.number):
        parts = [f"T{e.number}", f"P{e.pocket}"]
        for a in "XYZABCUVW":
            if a in e.offsets:
                parts.append(f"{a}{plain(e.offsets[a], 6)}")
        parts.append(f"D{plain(e.diameter, 6)}")
        if e.front_angle:
            parts.append(f"I{plain(e.front_angle, 6)}")
        if e.back_angle:
            parts.append(f"J{plain(e.back_angle, 6)}")
        if e.orientation:
            parts.append(f"Q{e.orientation}")
        line = " ".join(parts)
        if e.comment:
            line += " ;" + e.comment.replace("\n", " ")
        lines.append(line)
    return "\n".join(lines) + "\n"


def parse_tool_table(text: str, file: str | Path | None = None) -> list[ToolEntry]:
    """Parse a LinuxCNC tool table; errors name the file and line."""
    out: list[ToolEntry] = []
    seen: set[int] = set()
    for lineno, raw in enumerate(text.splitlines(), 1):
        body, _, comment = raw.partition(";")
        body = body.strip()
        if not body:
            continue
        words: dict[str, float] = {}
        for w in body.split():
            letter, val = w[0].upper(), w[1:]
            if letter not in "TP" + _FIELDS:
                raise MillpathError(f"unknown word {w!r} in tool table", file, lineno)
            if letter in words:
                raise MillpathError(f"word {letter} given twice", file, lineno)
            try:
                num = float(val)
            except ValueError:
                raise MillpathError(f"bad number in word {w!r}", file, lineno) from None
            if not math.isfinite(num):
                raise MillpathError(f"non-finite number in word {w!r}", file, lineno)
            if abs(num) > MAX_VALUE:
                raise MillpathError(f"number out of range in word {w!r} (limit "
                                    f"{MAX_VALUE:g})", file, lineno)
            words[letter] = num
        if "T" not in words:
            raise MillpathError("tool table line without a T word", file, lineno)
        t = words["T"]
        if t != int(t) or t < 0:
            raise MillpathError(f"tool number must be a non-negative integer, got {t:g}",
                                file, lineno)
        if int(t) in seen:
            raise MillpathError(f"tool {int(t)} listed twice", file, lineno)
        seen.add(int(t))
        out.append(ToolEntry(
            number=int(t), pocket=int(words.get("P", t)), diameter=words.get("D", 0.0),
            offsets={a: words[a] for a in "XYZABCUVW" if a in words},
            front_angle=words.get("I", 0.0), back_angle=words.get("J", 0.0),
            orientation=int(words.get("Q", 0)), comment=comment.strip()))
    return out


def read_tool_table(path: str | Path) -> list[ToolEntry]:
    p = Path(path)
    return parse_tool_table(p.read_text(encoding="utf-8", errors="replace"), p)


def entries_from_tools(tools) -> list[ToolEntry]:
    """Tool table rows for millpath Tools (Z = gauge length, D = diameter)."""
    seq = tools.values() if isinstance(tools, dict) else tools
    return [ToolEntry(number=t.number, pocket=t.number, diameter=t.diameter,
                      offsets={"Z": t.gauge_length},
                      comment=t.comment or f"{t.type} D{t.diameter:g}"
                      + (f" R{t.corner_radius:g}" if t.type == "bull" else ""))
            for t in seq]


_HEADER_RE = re.compile(r"^\s*;.*\bvalues in (mm|inch)\b")


def header(units: str) -> str:
    """The first line millpath writes in a tool table in ``units``."""
    return f"; millpath tool table, values in {units} (machine units)\n"


def table_units(text: str) -> str | None:
    """Units stated by a tool table's header comment (``mm``/``inch``), else None."""
    for raw in text.splitlines()[:5]:
        m = _HEADER_RE.match(raw)
        if m:
            return m.group(1)
    return None


def file_table_units(path: str | Path) -> str | None:
    try:
        return table_units(Path(path).read_text(encoding="utf-8", errors="replace"))
    except OSError:
        return None


def convert_entries(entries: list[ToolEntry], from_units: str, to_units: str) -> list[ToolEntry]:
    """Rows with lengths (offsets X..W except the angles A B C, diameter) converted."""
    if from_units == to_units:
        return list(entries)
    k = length_scale(from_units, to_units)
    return [replace(e, diameter=e.diameter * k,
                    offsets={a: (v if a in "ABC" else v * k) for a, v in e.offsets.items()})
            for e in entries]


def tool_table_text(tools, tool_units: str, machine_units: str) -> str:
    """A whole tool table for millpath Tools (lengths in ``tool_units``) written in the
    machine's units, header line first."""
    rows = convert_entries(entries_from_tools(tools), tool_units, machine_units)
    return header(machine_units) + format_tool_table(rows)
