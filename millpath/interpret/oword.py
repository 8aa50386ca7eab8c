"""O-word control flow: subroutines and loops within one program, as LinuxCNC runs them.

Supported: ``o<name>``/``oN`` ``sub`` ... ``endsub [v]``, ``call [args]``, ``return [v]``,
``if``/``elseif``/``else``/``endif``, ``while``/``endwhile``, ``do`` ... ``while``,
``repeat [n]``/``endrepeat``, ``break``, ``continue``. A call makes ``#1``-``#30`` and
named parameters not starting with ``_`` local; ``#<_value>`` holds the value returned.
Labels pair the statements (``o100 if`` ... ``o100 endif``). Subroutines in other files
are not searched for.

Work is bounded (:mod:`millpath.model.limits`): a call nested ``MAX_CALL_DEPTH`` deep is
rs274's "Too many subroutine levels"; a ``repeat`` of more than ``MAX_LOOP_ITERATIONS``
is refused before it starts; a loop that jumps back ``MAX_IDLE_ITERATIONS`` times
without making motion, or ``MAX_LOOP_ITERATIONS`` times in all, is stopped as endless,
and so is a program with loops that has made ``MAX_MOTIONS`` motions.
"""

from __future__ import annotations

import re

from millpath.interpret.errors import GCodeError
from millpath.gcode.lexer import Reader, normalize
from millpath.model.limits import MAX_IDLE_ITERATIONS, MAX_LOOP_ITERATIONS, MAX_MOTIONS

_OLINE = re.compile(r"^(?:n\d+(?:\.\d*)?)?o(<[^>]*>|\d+)([a-z]+)(.*)$")
_PREFILTER = re.compile(r"[ \t]*/?[ \t]*(?:[nN][ \t]*[\d.]+[ \t]*)?[oO]")
#: rs274 refuses the tenth nested call
MAX_CALL_DEPTH = 9
_KEYWORDS = ("sub", "endsub", "call", "return", "if", "elseif", "else", "endif", "while",
             "endwhile", "do", "repeat", "endrepeat", "break", "continue")


_OWORD_START = re.compile(r"(?i)[ \t]*/?[ \t]*(?:n[ \t]*[\d.]+[ \t]*)?o[ \t]*[<\d]")


def has_owords(text: str) -> bool:
    """Whether a line of ``text`` starts with an o-word (after an optional block delete
    and line number). Only the lines holding an ``o`` or ``O`` are tried."""
    for letter in "oO":
        i = text.find(letter)
        while i >= 0:
            start = text.rfind("\n", 0, i) + 1
            if _OWORD_START.match(text, start):
                return True
            end = text.find("\n", i)
            if end < 0:
                break
            i = text.find(letter, end)
    return False


def parse_oline(raw: str):
    """(label, keyword, rest) for an o-word line, else None."""
    text, _ = normalize(raw)
    text = text.lstrip("/")
    m = _OLINE.match(text)
    if m is None:
        return None
    label, kw, rest = m.group(1), m.group(2), m.group(3)
    if label.startswith("<"):
        label = label[1:-1]
    else:
        label = str(int(label))
    if kw not in _KEYWORDS:
        raise GCodeError("Unknown control command in o word")
    return label, kw, rest


class Flow:
    """Control flow state for one program (list of lines)."""

    def __init__(self, lines: list[str], machine):
        self.lines = lines
        self.m = machine
        self.ol: dict[int, tuple[str, str, str]] = {}
        for i, raw in enumerate(lines):
            if _PREFILTER.match(raw):
                try:
                    p = parse_oline(raw)
                except GCodeError:
                    p = None
                if p is not None:
                    self.ol[i] = p
        self.subs: dict[str, int] = {}
        for i, (lab, kw, _) in self.ol.items():
            if kw == "sub":
                self.subs[lab] = i
        self.frames: list[tuple[int, list[float], dict[str, float]]] = []
        self.if_done: dict[str, bool] = {}
        self.repeat: dict[str, int] = {}
        self.iterations = 0
        self.idle = 0
        self.moves_seen = -1

    def back(self, target: int) -> int:
        """Count one jump back to the top of a loop; stop endless loops."""
        self.iterations += 1
        n = len(self.m.store)
        if n == self.moves_seen:
            self.idle += 1
            if self.idle >= MAX_IDLE_ITERATIONS:
                raise GCodeError(f"loop ran {MAX_IDLE_ITERATIONS} times without motion: "
                                 "endless loop?")
        else:
            self.idle = 0
            self.moves_seen = n
        if self.iterations > MAX_LOOP_ITERATIONS:
            raise GCodeError(f"loops ran more than {MAX_LOOP_ITERATIONS} times in all: "
                             "endless loop?")
        if n > MAX_MOTIONS:
            raise GCodeError(f"the program's loops made more than {MAX_MOTIONS} motions: "
                             "endless loop?")
        return target

    def find(self, start: int, label: str, kws: tuple[str, ...]) -> int:
        for i in range(start + 1, len(self.lines)):
            p = self.ol.get(i)
            if p and p[0] == label and p[1] in kws:
                return i
        raise GCodeError(f"EOF in file seeking o-word: o<{label}> from line: {start + 1}")

    def find_back(self, start: int, label: str, kws: tuple[str, ...]) -> int:
        for i in range(start - 1, -1, -1):
            p = self.ol.get(i)
            if p and p[0] == label and p[1] in kws:
                return i
        raise GCodeError(f"o-word o<{label}> has no start")

    def value(self, rest: str) -> float | None:
        if not rest:
            return None
        rd = Reader(rest, self.m.params, self.m.named)
        if rd.peek() != "[":
            raise GCodeError("Left bracket missing after 'if'")
        rd.i += 1
        return rd.expression()

    def args(self, rest: str) -> list[float]:
        rd = Reader(rest, self.m.params, self.m.named)
        out = []
        while rd.i < len(rest):
            if rd.peek() == "(":                    # a comment between arguments
                rd.i += 1
                continue
            if rd.peek() != "[":
                raise GCodeError("Unexpected character after O-word")
            rd.i += 1
            out.append(rd.expression())
        return out

    def is_do_end(self, i: int, label: str) -> bool:
        """A ``while`` closes a ``do`` loop when a ``do`` with its label comes before."""
        for j in range(i - 1, -1, -1):
            p = self.ol.get(j)
            if p and p[0] == label:
                if p[1] == "do":
                    return True
                if p[1] in ("while", "endwhile", "endrepeat", "repeat", "endif", "if"):
                    return False
        return False

    def step(self, i: int) -> int:
        """Execute the o-word line ``i``; return the index of the next line to run."""
        label, kw, rest = self.ol[i]
        m = self.m
        if kw == "sub":
            end = self.find(i, label, ("endsub",))
            for j in range(i + 1, end):
                p = self.ol.get(j)
                if p and p[1] == "sub":
                    err = GCodeError("Nested subroutine definition")
                    err.line = j + 1
                    raise err
            return end + 1
        if kw == "call":
            if label not in self.subs:
                raise GCodeError(f"Unknown oword name: |{label}|")
            if len(self.frames) >= MAX_CALL_DEPTH:
                raise GCodeError("Too many subroutine levels")
            vals = self.args(rest)
            saved = m.params[1:31]
            local = {k: v for k, v in m.named.items() if not k.startswith("_")}
            self.frames.append((i, saved, local))
            for k in range(1, 31):
                m.params[k] = vals[k - 1] if k <= len(vals) else 0.0
            for k in list(m.named):
                if not k.startswith("_"):
                    del m.named[k]
            return self.subs[label] + 1
        if kw in ("endsub", "return"):
            v = self.value(rest)
            if not self.frames:
                if kw == "return":
                    raise GCodeError("return outside of a subroutine")
                return i + 1
            if v is not None:
                m.named["_value"] = v
            ret, saved, local = self.frames.pop()
            m.params[1:31] = saved
            for k in list(m.named):
                if not k.startswith("_"):
                    del m.named[k]
            m.named.update(local)
            return ret + 1
        if kw == "if":
            c = self.value(rest)
            self.if_done[label] = bool(c)
            if c:
                return i + 1
            return self.find(i, label, ("elseif", "else", "endif"))
        if kw == "elseif":
            if self.if_done.get(label):
                return self.find(i, label, ("endif",)) + 1
            c = self.value(rest)
            if c:
                self.if_done[label] = True
                return i + 1
            return self.find(i, label, ("elseif", "else", "endif"))
        if kw == "else":
            if self.if_done.get(label):
                return self.find(i, label, ("endif",)) + 1
            return i + 1
        if kw == "endif":
            return i + 1
        if kw == "do":
            return i + 1
        if kw == "while":
            c = self.value(rest)
            if self.is_do_end(i, label):
                return self.back(self.find_back(i, label, ("do",)) + 1) if c else i + 1
            return i + 1 if c else self.find(i, label, ("endwhile",)) + 1
        if kw == "endwhile":
            return self.back(self.find_back(i, label, ("while",)))
        if kw == "repeat":
            n = self.value(rest)
            if n is not None and n > MAX_LOOP_ITERATIONS - self.iterations:
                raise GCodeError(f"repeat {n:.15g} times: more than the "
                                 f"{MAX_LOOP_ITERATIONS} loop iterations a program may run")
            self.repeat[label] = int(min(n or 0, 2.0 ** 62))
            if self.repeat[label] > 0:
                return i + 1
            return self.find(i, label, ("endrepeat",)) + 1
        if kw == "endrepeat":
            self.repeat[label] = self.repeat.get(label, 0) - 1
            if self.repeat[label] > 0:
                return self.back(self.find_back(i, label, ("repeat",)) + 1)
            return i + 1
        if kw == "break":
            j = self.find(i, label, ("endwhile", "endrepeat", "while"))
            return j + 1
        if kw == "continue":
            j = self.find(i, label, ("endwhile", "endrepeat", "while"))
            if self.ol[j][1] == "endrepeat":
                return j
            if self.ol[j][1] == "endwhile":
                return self.back(self.find_back(i, label, ("while",)))
            return j
        raise GCodeError("Unknown control command in o word")
