"""Adapter around LinuxCNC's standalone interpreter ``rs274`` (package linuxcnc-uspace).

``rs274 -t TOOLS.tbl -g FILE.ngc`` prints canonical machining calls on stdout
(``STRAIGHT_FEED(x, y, z, a, b, c)``, ``ARC_FEED(...)``, ...) and an error on stderr.
This module runs it in a private ``HOME`` (rs274 keeps its tool table in
``$HOME/.tool.mmap``; shared homes corrupt concurrent runs) and reads the calls back as
:class:`millpath.model.motion.Motion` records, so our interpreter and LinuxCNC can
be compared move by move.

Conventions: coordinates are program coordinates (before work offsets and tool length
offset) in the units in force; rs274 prints 4 decimals, so compare with a tolerance of
at least 1e-4. rs274 reads tool table values as inches whatever the program's units:
``table_units="mm"`` converts the table for it. Each program line is given an ``N``
word equal to its line number (unless it has one) so motions and errors carry their
source line. G5 splines come out as kind ``"nurbs"`` without control points.
"""

from __future__ import annotations

import os
import re
import shutil
import subprocess
import tempfile
from dataclasses import dataclass, field
from pathlib import Path

from millpath.model.units import length_scale
from millpath.model.motion import Motion
from millpath.io.tooltable import ToolEntry, entries_from_tools, format_tool_table

_CALL = re.compile(r"^\s*\d+\s+(N\S*)\s+([A-Z_][A-Z0-9_]*)\((.*)\)\s*$")
_NUM = re.compile(r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?")
_PLANES = {"CANON_PLANE_XY": "XY", "CANON_PLANE_XZ": "XZ", "CANON_PLANE_YZ": "YZ"}
#: ARC_FEED(first_end, second_end, first_axis, second_axis, rotation, axis_end, a, b, c)
_AXES = {"XY": (0, 1, 2), "XZ": (2, 0, 1), "YZ": (1, 2, 0)}
_N_WORD = re.compile(r"^\s*(/?)\s*([nN]\s*\d+)?")


@dataclass
class Rs274Result:
    ok: bool
    error: str | None
    error_line: int | None
    motions: list[Motion] = field(default_factory=list)
    units: str = "mm"
    error_block: str | None = None
    returncode: int = 0
    stdout: str = ""


def find_rs274() -> str | None:
    exe = shutil.which("rs274")
    if exe:
        return exe
    for p in ("/usr/bin/rs274", "/usr/lib/linuxcnc/rs274"):
        if os.access(p, os.X_OK):
            return p
    return None


def rs274_available() -> bool:
    return find_rs274() is not None


def number_lines(text: str) -> str:
    """Give every line without an N word the word ``N<line number>`` (1-based).

    Lines starting with ``%`` and blank lines stay as they are; a block-delete slash
    stays first. Programs longer than 99,999 lines are returned unchanged (LinuxCNC's
    limit on N).
    """
    lines = text.split("\n")
    if len(lines) > 99999:
        return text
    out = []
    for i, line in enumerate(lines, 1):
        s = line.lstrip()
        if not s or s.startswith("%"):
            out.append(line)
            continue
        m = _N_WORD.match(line)
        if m and m.group(2):
            out.append(line)
            continue
        if s.startswith("/"):
            out.append("/N%d %s" % (i, s[1:]))
        else:
            out.append("N%d %s" % (i, s))
    return "\n".join(out)


def _table_text(tools, table_units: str) -> str:
    if tools is None:
        return ""
    if isinstance(tools, (str, Path)) and Path(tools).is_file():
        from millpath.io.tooltable import read_tool_table
        entries = read_tool_table(tools)
    elif isinstance(tools, dict):
        entries = entries_from_tools(tools)
    else:
        entries = list(tools)
    if table_units == "mm":
        k = length_scale("mm", "inch")
        entries = [ToolEntry(e.number, e.pocket, e.diameter * k,
                             {a: v * k for a, v in e.offsets.items()}, e.front_angle,
                             e.back_angle, e.orientation, e.comment) for e in entries]
    return format_tool_table(entries)


def run_rs274(program: str | Path, tools=None, *, table_units: str = "mm",
              timeout: float = 120.0, number: bool = True) -> Rs274Result:
    """Run rs274 on ``program`` (text or path) with ``tools`` (dict of Tool, list of
    ToolEntry or a tool table path) whose lengths are in ``table_units``."""
    exe = find_rs274()
    if exe is None:
        raise FileNotFoundError("rs274 not found: apt-get install -y --no-install-recommends "
                                "linuxcnc-uspace")
    text = Path(program).read_text() if isinstance(program, Path) else program
    if number:
        text = number_lines(text)
    with tempfile.TemporaryDirectory(prefix="millpath-rs274-") as home:
        ngc = os.path.join(home, "program.ngc")
        tbl = os.path.join(home, "tools.tbl")
        with open(ngc, "w") as fh:
            fh.write(text if text.endswith("\n") else text + "\n")
        with open(tbl, "w") as fh:
            fh.write(_table_text(tools, table_units) or "T0 P0 ;empty\n")
        env = dict(os.environ, HOME=home)
        p = subprocess.run([exe, "-t", tbl, "-g", ngc], capture_output=True, text=True,
                           timeout=timeout, stdin=subprocess.DEVNULL, cwd=home, env=env)
    motions, units = parse_canon(p.stdout)
    err_lines = [l for l in p.stderr.splitlines() if l.strip() and l.strip() != "executing"]
    error = err_lines[0].strip() if err_lines else None
    block = err_lines[1].strip() if len(err_lines) > 1 else None
    if p.returncode != 0 and error is None:
        error = f"rs274 exited with status {p.returncode}"
    line = None
    if block:
        m = re.match(r"\s*/?\s*[nN]\s*(\d+)", block)
        if m:
            line = int(m.group(1))
    return Rs274Result(ok=p.returncode == 0 and error is None, error=error, error_line=line,
                       motions=motions, units=units, error_block=block,
                       returncode=p.returncode, stdout=p.stdout)


def parse_canon(text: str) -> tuple[list[Motion], str]:
    """Read rs274's canonical output into motions; returns (motions, final units)."""
    units = "mm"
    plane = "XY"
    feed = 0.0
    tlo = (0.0, 0.0, 0.0)
    tool = selected = 0
    spindle = 0.0
    pos = [0.0, 0.0, 0.0]
    out: list[Motion] = []
    for raw in text.splitlines():
        m = _CALL.match(raw)
        if not m:
            continue
        nword, name, args = m.group(1), m.group(2), m.group(3)
        line = int(nword[1:]) if nword[1:].isdigit() else 0
        if name == "COMMENT" or name == "MESSAGE":
            continue
        nums = [float(x) for x in _NUM.findall(args)]
        if name == "USE_LENGTH_UNITS":
            new = "inch" if "INCHES" in args else "mm"
            if new != units:
                f = length_scale(units, new)
                pos = [v * f for v in pos]
                tlo = tuple(v * f for v in tlo)
                units = new
        elif name == "SELECT_PLANE":
            plane = _PLANES.get(args.strip(), plane)
        elif name == "SET_FEED_RATE":
            feed = nums[0]
        elif name == "USE_TOOL_LENGTH_OFFSET":
            # the controlled point stays where it is: in program terms it moves by the
            # change of offset (rs274 prints the next move from the new position)
            new_tlo = (nums[0], nums[1], nums[2])
            pos = [p + o - n for p, o, n in zip(pos, tlo, new_tlo)]
            tlo = new_tlo
        elif name == "SELECT_TOOL":
            selected = int(nums[0])
        elif name == "CHANGE_TOOL":            # its argument is the tool table's slot
            tool = selected
        elif name == "SET_SPINDLE_SPEED":
            spindle = nums[-1]
        elif name in ("STRAIGHT_TRAVERSE", "STRAIGHT_FEED"):
            end = (nums[0], nums[1], nums[2])
            kind = "traverse" if name == "STRAIGHT_TRAVERSE" else "feed"
            out.append(Motion(kind, line, tuple(pos), end, 0.0 if kind == "traverse" else feed,
                              tlo, tool, plane, spindle=spindle))
            pos = list(end)
        elif name == "ARC_FEED":
            fe, se, fa, sa, rot, ae = nums[:6]
            i1, i2, i3 = _AXES[plane]
            end = [0.0, 0.0, 0.0]
            end[i1], end[i2], end[i3] = fe, se, ae
            c = [0.0, 0.0, 0.0]
            c[i1], c[i2], c[i3] = fa, sa, pos[i3]
            out.append(Motion("arc", line, tuple(pos), tuple(end), feed, tlo, tool, plane,
                              center=tuple(c), rotation=int(rot), spindle=spindle))
            pos = end
        elif name.startswith("NURBS"):
            out.append(Motion("nurbs", line, tuple(pos), tuple(pos), feed, tlo, tool, plane,
                              spindle=spindle))
            pos = [float("nan"), float("nan"), pos[2]]   # rs274 does not print the end
        elif name == "DWELL":
            out.append(Motion("dwell", line, tuple(pos), tuple(pos), 0.0, tlo, tool, plane,
                              dwell=nums[0], spindle=spindle))
    return out, units
