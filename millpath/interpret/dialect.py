"""A program of another control's dialect, read as that control reads it: the words it
refuses are errors at their line, and what it does otherwise than LinuxCNC is rewritten,
line for line, into the LinuxCNC blocks that make the same motion, for the interpreter.

Where a control differs (for the dialects of :mod:`millpath.model.dialect`):

- the codes, letters, parameters and expressions it lacks, a P word on an arc and a
  block longer than its line buffer (blanks and comments left out) are refused;
- GRBL and Fanuc start in G0 motion mode (LinuxCNC starts with none); a streamed
  program needs no M2 or M30 (one is read after its last line);
- Fanuc-style controls: ``O<n>`` after ``%`` names the program; a length (X Y Z I J K
  R Q) written without a decimal point counts least increments (``X10`` is 0.010 mm,
  0.0010 in); P of a dwell (G4) or of G82/G89 is in milliseconds;
- with a ``pause`` tool change, ``M0`` after a ``T`` word is the operator's tool change
  with Z set to zero at the new tool's tip: read as ``M6 G43 H<n>`` (the new tool's own
  length compensated), then the pause; a tool the table lacks is read as ``T0``, no
  tool in the spindle, and its change as ``M6 G49`` (the programmed point is the tip).
"""

from __future__ import annotations

import re
from collections.abc import Collection

from millpath.gcode.lexer import MAX_PARAM, normalize, read_block
from millpath.interpret.errors import GCodeError
from millpath.model.dialect import LINUXCNC, Dialect

_ARCS = (20, 30)
_COMMENTS = re.compile(r"(\([^)]*\)|;.*$)")     # a block's comments, split out whole
_BARE_LENGTH = re.compile(r"([xyzijkrqXYZIJKRQ])\s*([+-]?)\s*([0-9]+)(?![0-9.])")
_P_WORD = re.compile(r"[pP]\s*([+]?[0-9]+\.?[0-9]*)")
_T_WORD = re.compile(r"[tT]\s*[+]?[0-9][0-9 ]*(?:\.[0-9 ]*)?")


def as_linuxcnc(text: str, d: Dialect, known: Collection[int] = ()
                ) -> tuple[str, tuple[int, str] | None]:
    """``text`` of dialect ``d`` as LinuxCNC blocks with the same line numbers, and the
    first refused line (1-based line, message) or None. LinuxCNC text is returned as is.
    ``known``: the tool table's numbers (a tool change to a tool not in it leaves no
    tool in the spindle: its tip is the programmed point, as set by the operator)."""
    if d is LINUXCNC:
        return text, None
    params = [0.0] * (MAX_PARAM + 1)
    out = []
    pending: int | None = None          # a T word waiting for its M0
    first_motion = True
    motion: int | None = None
    inch = False
    lines = text.split("\n")
    for n, raw in enumerate(lines, start=1):
        s = raw.strip()
        if not s or s == "%":
            out.append(raw)
            continue
        if d.program_number and s[:1] in ("o", "O") and n <= 3:
            out.append(f"({s.replace('(', '[').replace(')', ']')})")     # the program number
            continue
        why = _bare_refusal(raw, d)
        if not why:
            try:
                blk = read_block(raw, n, params, {})
            except GCodeError as e:
                return text, (n, str(e))
            if blk.g.get(1) is not None:
                motion = blk.g[1]
            why = _refusal(blk, d, motion)
        if why:
            return text, (n, f"{d.title} does not accept this block: {why}")
        extra = ""
        if blk.g.get(6) is not None:
            inch = blk.g[6] == 200
        if d.decimal_point:
            raw = _code_sub(raw, _BARE_LENGTH, _increments(0.0001 if inch else 0.001))
        if d.dwell_ms and "p" in blk.words and (blk.g.get(0) == 40 or motion in (820, 890)):
            raw = _code_sub(raw, _P_WORD, lambda m: f"P{float(m.group(1)) / 1000.0!r}")
        if first_motion and blk.g.get(1) is not None:
            first_motion = False
        elif first_motion and d.starts_in_g0 and blk.g.get(0, 530) == 530 \
                and any(a in blk.words for a in "xyz"):
            extra += " G0"              # the motion mode the control starts in
            motion = 0
            first_motion = False
        if "t" in blk.words:
            pending = int(blk.words["t"])
            if pending not in known:
                raw = _code_sub(raw, _T_WORD, "T0")
        if d.tool_change == "pause" and blk.m.get(4) == 0 and pending is not None:
            extra += f" M6 G43 H{pending}" if pending in known else " M6 G49"
            pending = None
        out.append(_with(raw, extra) if extra else raw)
    if not d.needs_end:
        out.append("M2")                # after the last line: the stream just stops
    return "\n".join(out), None


def _increments(step: float):
    """A replacement for a length written without a decimal point: it counts ``step``."""
    def repl(m: re.Match) -> str:
        return f"{m.group(1)}{m.group(2)}{int(m.group(3)) * step:.6f}"
    return repl


def _code_sub(raw: str, pattern: re.Pattern, repl) -> str:
    """``raw`` with ``pattern`` replaced outside its comments."""
    parts = _COMMENTS.split(raw)
    return "".join(p if p[:1] in ("(", ";") else pattern.sub(repl, p) for p in parts)


def _with(raw: str, extra: str) -> str:
    """``raw`` with the words ``extra`` added before its ``;`` comment, if any."""
    parts = _COMMENTS.split(raw)
    for k, p in enumerate(parts):
        if p.startswith(";"):
            return "".join(parts[:k]) + extra + " " + "".join(parts[k:])
    return raw + extra


def _bare_refusal(raw: str, d: Dialect) -> str:
    """Why ``d`` refuses the block's text ('' if it does not)."""
    if d.parameters and d.max_line is None:
        return ""
    try:
        text, _ = normalize(raw)        # blanks and comments out (a comment is one "(")
    except GCodeError:
        return ""                       # the reader names the bad comment
    bare = text.replace("(", "")
    if not d.parameters and ("#" in bare or "[" in bare or bare[:1] == "o"):
        return "no parameters, expressions or O-words"
    if d.max_line is not None and len(bare) > d.max_line:
        return f"{len(bare)} characters, more than its {d.max_line}"
    return ""


def _refusal(blk, d: Dialect, motion: int | None) -> str:
    """Why ``d`` refuses the block ('' if it does not)."""
    for code in blk.g.values():
        if not d.accepts_g(code):
            return f"G{_code(code)}"
    for code in blk.m.values():
        if not d.accepts_m(code):
            return f"M{code}"
    for letter in blk.words:
        if letter.isalpha() and letter not in d.letters:
            return f"the {letter.upper()} word"
    if not d.arc_turns and motion in _ARCS and "p" in blk.words and 40 not in blk.g.values():
        return "a P word on an arc"
    return ""


def _code(code10: int) -> str:
    return str(code10 // 10) if code10 % 10 == 0 else f"{code10 // 10}.{code10 % 10}"
