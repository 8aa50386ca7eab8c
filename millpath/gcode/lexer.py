"""Reading one RS274NGC line into a block of words, as LinuxCNC's reader does (the one
grammar of millpath: the interpreter and ``millpath fit`` both read with it).

LinuxCNC drops spaces and tabs outside comments and ignores case, so ``g 1 x 1 . 5``
is ``G1 X1.5``. Comments are ``( ... )`` (not nested) and ``;`` to the end of the line.
Values are numbers, ``[expressions]``, parameters ``#n`` / ``#<name>`` and unary
functions (``sin[30]``, ``atan[1]/[2]``; angles in degrees). Parameter settings
``#n = value`` on a line take effect after the whole line is read. Error messages
follow rs274's wording.
"""

from __future__ import annotations

import math
import re

from millpath.gcode.errors import GCodeError
from millpath.model.limits import MAX_COORDINATE

# modal group of each G code (code x 10), as LinuxCNC's _gees table
G_GROUP: dict[int, int] = {}
for _c in (40, 100, 280, 281, 300, 301, 520, 530, 920, 921, 922, 923):
    G_GROUP[_c] = 0
for _c in (0, 10, 20, 30, 50, 51, 52, 53, 330, 331, 382, 383, 384, 385, 730, 760, 800, 810, 820,
           830, 840, 850, 860, 870, 880, 890):
    G_GROUP[_c] = 1
for _c in (170, 180, 190, 171, 181, 191):
    G_GROUP[_c] = 2
G_GROUP.update({900: 3, 910: 3, 901: 4, 911: 4, 930: 5, 940: 5, 950: 5, 200: 6, 210: 6,
                400: 7, 410: 7, 420: 7, 411: 7, 421: 7, 430: 8, 431: 8, 432: 8, 490: 8,
                980: 10, 990: 10, 540: 12, 550: 12, 560: 12, 570: 12, 580: 12, 590: 12,
                591: 12, 592: 12, 593: 12, 610: 13, 611: 13, 640: 13, 960: 14, 970: 14,
                70: 15, 80: 15})
# modal group of each M code, as LinuxCNC's _ems table
M_GROUP: dict[int, int] = {0: 4, 1: 4, 2: 4, 30: 4, 60: 4, 6: 6, 61: 6, 3: 7, 4: 7, 5: 7,
                           19: 7, 70: 7, 71: 7, 72: 7, 73: 7, 7: 8, 8: 8, 9: 8, 48: 9, 49: 9,
                           50: 9, 51: 9, 52: 9, 53: 9, 62: 5, 63: 5, 64: 5, 65: 5, 66: 5,
                           67: 5, 68: 5}

AXES = "xyzabcuvw@^"
MAX_PARAM = 5602
TOLERANCE_EQUAL = 1e-6
#: rs274 reads lines into a 256-byte buffer: longer lines are "Command too long"
MAX_LINE = 252
#: brackets nested deeper than this are refused (a 252-character line cannot reach it)
MAX_NESTING = 200
INT_MIN = -2**31


def c_int(v: float) -> int:
    """``(int) floor(v)`` as rs274 computes it on x86-64: out of range gives INT_MIN."""
    if -2147483648.0 <= v < 2147483648.0:
        return math.floor(v)
    return INT_MIN


def finite(v: float) -> float:
    """``v``, or rs274's error for a non-finite result."""
    if v - v != 0.0:
        if v != v:
            raise GCodeError("Calculation resulted in 'not a number'")
        raise GCodeError("Calculation resulted in 'infinity'")
    return v


class Block:
    """One line's words. ``words`` maps a letter (lowercase) to its value; ``g`` maps a
    modal group to its G code (x 10, e.g. 411 for G41.1); ``m`` a group to its M code."""

    __slots__ = ("line", "words", "g", "m", "m_count", "settings", "comment", "text",
                 "motion", "empty", "literal")

    def __init__(self, line: int, text: str):
        self.line = line
        self.text = text
        self.words: dict[str, float] = {}
        self.g: dict[int, int] = {}
        self.m: dict[int, int] = {}
        self.m_count = 0
        self.settings: list[tuple[object, float]] = []
        self.literal: dict[str, str] = {}   # a real word's value as written (normalized)
        self.comment = ""
        self.motion = -1
        self.empty = False


_BLANKS = str.maketrans("", "", " \t\r\n")
_DIGITS = re.compile(r"[0-9.]*")
_NUMERAL = re.compile(r"[+-]?(?:[0-9]+\.?[0-9]*|\.[0-9]+)")


def normalize(raw: str) -> tuple[str, str]:
    """Remove blanks outside comments, lowercase, replace comments by ``(``.

    Returns (text, last comment)."""
    if "(" not in raw and ";" not in raw and raw.isascii():
        return raw.translate(_BLANKS).lower(), ""     # no comment: the same, at once
    out = []
    comment = ""
    i = 0
    n = len(raw)
    while i < n:
        c = raw[i]
        if c == "(":
            j = i + 1
            while j < n and raw[j] != ")":
                if raw[j] == "(":
                    raise GCodeError("Nested comment found")
                j += 1
            if j >= n:
                raise GCodeError("Unclosed comment found")
            comment = raw[i + 1:j]
            out.append("(")
            i = j + 1
            continue
        if c == ";":
            comment = raw[i + 1:]
            break
        if c in " \t\r\n":
            i += 1
            continue
        out.append(c.lower())
        i += 1
    return "".join(out), comment


class Reader:
    """Reads values from one normalized line; ``params`` are the numbered and named
    parameters (read-only here)."""

    __slots__ = ("s", "i", "params", "named", "depth")

    def __init__(self, s: str, params: list[float], named: dict[str, float]):
        self.s = s
        self.i = 0
        self.params = params
        self.named = named
        self.depth = 0

    def peek(self) -> str:
        return self.s[self.i] if self.i < len(self.s) else ""

    # --- numbers and values ---------------------------------------------------------
    def number(self) -> float:
        s, i = self.s, self.i
        m = _NUMERAL.match(s, i)
        if m is not None:                       # the common case: a plain numeral
            j = m.end()
            if j >= len(s) or not (s[j].isdigit() or s[j] == "."):
                self.i = j
                return finite(float(m.group()))
        j = i
        if j < len(s) and s[j] in "+-":
            j += 1
        j = _DIGITS.match(s, j).end()
        while j < len(s) and (s[j].isdigit() or s[j] == "."):   # digits beyond ASCII
            j += 1
        tok = s[i:j]
        self.i = j
        if not tok and i >= len(s):
            raise GCodeError("No characters found in reading real value")
        body = tok.lstrip("+-")
        try:
            return finite(float(tok))
        except ValueError:
            pass
        m = re.match(r"[+-]?(\d+\.?\d*|\.\d+)", tok)
        if m and body:
            raise GCodeError(f"bad number format (trailing characters) parsing '{tok}'")
        raise GCodeError(f"bad number format (conversion failed) parsing '{body}'")

    def value(self) -> float:
        c = self.s[self.i] if self.i < len(self.s) else ""
        if c == "[":
            self.i += 1
            v = self.expression()
        elif c == "#":
            self.i += 1
            v = self.param_value()
        elif c in "+-" and self.i + 1 < len(self.s) and not (
                self.s[self.i + 1].isdigit() or self.s[self.i + 1] == "."):
            self.i += 1
            v = self.value()
            if c == "-":
                v = -v
        elif "a" <= c <= "z":
            v = self.unary()
        else:
            v = self.number()
        return finite(v)

    def integer(self) -> int:
        """rs274's read_integer_value (values beyond a C int become INT_MIN)."""
        v = self.value()
        r = c_int(v)
        if v - r > 0.9999:
            r = c_int(math.ceil(v))
        elif v - r > 0.0001:
            raise GCodeError("Non integer value for integer")
        return r

    def param_index(self):
        """Index after '#': an int, or a str for a named parameter."""
        if self.peek() == "<":
            j = self.s.find(">", self.i)
            if j < 0:
                raise GCodeError("Named parameter not terminated")
            name = self.s[self.i + 1:j]
            self.i = j + 1
            return name
        n = self.integer()
        if n < 1 or n >= MAX_PARAM:
            raise GCodeError("Parameter number out of range")
        return n

    def param_value(self) -> float:
        idx = self.param_index()
        if isinstance(idx, str):
            if idx not in self.named:
                raise GCodeError(f"Named parameter #<{idx}> not defined")
            return self.named[idx]
        return self.params[idx]

    # --- expressions ----------------------------------------------------------------
    _BINARY = {"**": 6, "*": 5, "/": 5, "mod": 5, "+": 4, "-": 4, "eq": 3, "ne": 3,
               "gt": 3, "ge": 3, "lt": 3, "le": 3, "and": 2, "or": 2, "xor": 2}

    def operation(self) -> str:
        c = self.peek()
        if c == "":
            raise GCodeError("Unclosed expression")
        if c == "]":
            self.i += 1
            return "]"
        if c == "*":
            if self.s.startswith("**", self.i):
                self.i += 2
                return "**"
            self.i += 1
            return "*"
        if c in "+-/":
            self.i += 1
            return c
        for name in ("and", "or", "xor", "mod", "eq", "ne", "gt", "ge", "lt", "le"):
            if self.s.startswith(name, self.i):
                self.i += len(name)
                return name
        if c in "aeglmnox":
            raise GCodeError(f"Unknown operation name starting with {c}")
        raise GCodeError("Unknown operation")

    def expression(self) -> float:
        """Evaluate after '[' up to and including the matching ']'."""
        self.depth += 1
        if self.depth > MAX_NESTING:
            raise GCodeError("Expression nested too deeply")
        values = [self.value()]
        ops: list[str] = []
        while True:
            op = self.operation()
            prec = 1 if op == "]" else self._BINARY[op]
            while ops and self._BINARY[ops[-1]] >= prec:
                b = values.pop()
                a = values.pop()
                values.append(finite(_binary(ops.pop(), a, b)))
            if op == "]":
                self.depth -= 1
                return values[0]
            ops.append(op)
            values.append(self.value())

    _UNARY = ("abs", "acos", "asin", "atan", "cos", "exp", "fix", "fup", "ln", "round",
              "sin", "sqrt", "tan", "exists")

    def unary(self) -> float:
        name = None
        for cand in self._UNARY:
            if self.s.startswith(cand, self.i):
                name = cand
                break
        if name is None:
            c = self.peek()
            if any(u.startswith(c) for u in self._UNARY):
                raise GCodeError(f"Unknown word starting with {c}")
            raise GCodeError("Unknown word where unary operation could be")
        self.i += len(name)
        if self.peek() != "[":
            raise GCodeError("Left bracket missing after unary operation name")
        self.i += 1
        if name == "exists":
            if self.peek() != "#":
                raise GCodeError("Expected # reading parameter")
            self.i += 1
            idx = self.param_index()
            if self.peek() != "]":
                raise GCodeError("Expected ] reading bracketed parameter")
            self.i += 1
            return 1.0 if not isinstance(idx, str) or idx in self.named else 0.0
        a = self.expression()
        if name == "atan":
            if self.peek() != "/":
                raise GCodeError("Slash missing after first atan argument")
            self.i += 1
            if self.peek() != "[":
                raise GCodeError("Left bracket missing after slash with atan")
            self.i += 1
            b = self.expression()
            return math.degrees(math.atan2(a, b))
        return _unary(name, a)


def _unary(name: str, a: float) -> float:
    if name == "abs":
        return abs(a)
    if name == "acos":
        if a < -1.0 or a > 1.0:
            raise GCodeError("Argument to acos out of range")
        return math.degrees(math.acos(a))
    if name == "asin":
        if a < -1.0 or a > 1.0:
            raise GCodeError("Argument to asin out of range")
        return math.degrees(math.asin(a))
    if name == "cos":
        return math.cos(math.radians(a))
    if name == "sin":
        return math.sin(math.radians(a))
    if name == "tan":
        return math.tan(math.radians(a))
    if name == "exp":
        try:
            return math.exp(a)
        except OverflowError:
            raise GCodeError("Calculation resulted in 'infinity'") from None
    if name == "fix":
        return float(math.floor(a)) if math.isfinite(a) else a
    if name == "fup":
        return float(math.ceil(a)) if math.isfinite(a) else a
    if name == "round":
        if not math.isfinite(a):
            return a
        return float(math.floor(a + 0.5) if a >= 0 else -math.floor(-a + 0.5))
    if name == "ln":
        if a <= 0.0:
            raise GCodeError("Zero or negative argument to ln")
        return math.log(a)
    if name == "sqrt":
        if a < 0.0:
            raise GCodeError("Negative argument to sqrt")
        return math.sqrt(a)
    raise GCodeError("Unknown operation")


def _binary(op: str, a: float, b: float) -> float:
    if op == "+":
        return a + b
    if op == "-":
        return a - b
    if op == "*":
        return a * b
    if op == "/":
        if b == 0.0:
            raise GCodeError("Attempt to divide by zero")
        return a / b
    if op == "mod":
        if b == 0.0:
            raise GCodeError("Calculation resulted in 'not a number'")    # fmod(a, 0)
        r = math.fmod(a, b)
        return r + abs(b) if r < 0.0 else r
    if op == "**":
        if a < 0.0 and b != math.floor(b):
            raise GCodeError("Attempt to raise negative to non integer power")
        try:
            return float(a ** b)
        except (OverflowError, ZeroDivisionError):
            raise GCodeError("Calculation resulted in 'infinity'") from None
    if op == "eq":
        return 1.0 if abs(a - b) < TOLERANCE_EQUAL else 0.0
    if op == "ne":
        return 0.0 if abs(a - b) < TOLERANCE_EQUAL else 1.0
    if op == "gt":
        return 1.0 if a > b else 0.0
    if op == "ge":
        return 1.0 if a >= b else 0.0
    if op == "lt":
        return 1.0 if a < b else 0.0
    if op == "le":
        return 1.0 if a <= b else 0.0
    if op == "and":
        return 0.0 if a == 0.0 or b == 0.0 else 1.0
    if op == "or":
        return 1.0 if a != 0.0 or b != 0.0 else 0.0
    if op == "xor":
        return 1.0 if (a != 0.0) != (b != 0.0) else 0.0
    raise GCodeError("Unknown operation")


# rs274 without an INI has axes X Y Z A B C: U V W are bad characters
_REAL_WORDS = set("abcdefijkpqrsxyz")
#: words whose value is a length, an angle, a feed or a speed: at most MAX_COORDINATE in
#: magnitude (rs274 takes any finite number; 1e20 mm is a typo, not a position)
_BOUNDED = frozenset("xyzabcijkrqfs@^")


def _bounded(c: str, v: float) -> float:
    if abs(v) > MAX_COORDINATE:
        raise GCodeError(f"{c.upper()} word {v:g} is larger than the {MAX_COORDINATE:g} "
                         "limit")
    return v


def read_block(raw: str, line: int, params: list[float], named: dict[str, float]) -> Block:
    """Parse one source line into a Block (general path: comments, expressions, ...)."""
    text, comment = normalize(raw)
    blk = Block(line, raw)
    blk.comment = comment
    if text.startswith("/"):
        text = text[1:]          # block delete is off, as in rs274 by default
    rd = Reader(text, params, named)
    s = text
    n = len(s)
    words = blk.words
    if rd.i < n and s[rd.i] == "n":
        rd.i += 1
        j = rd.i
        while j < n and (s[j].isdigit() or s[j] == "."):
            j += 1
        if j == rd.i:
            raise GCodeError("Bad format unsigned integer")
        rd.i = j
    while rd.i < n:
        c = s[rd.i]
        if c == "(":
            rd.i += 1
            continue
        if c in "@^":                       # polar radius and angle (degrees)
            rd.i += 1
            if c in words:
                raise GCodeError(f"Multiple {c} words on one line")
            words[c] = _bounded(c, rd.value())
            continue
        if c == "$":
            rd.i += 1
            if "$" in words:
                raise GCodeError("Multiple spindle choice ($) words on one line")
            words["$"] = rd.value()
            continue
        if c == "#":
            rd.i += 1
            idx = rd.param_index()
            if rd.peek() != "=":
                raise GCodeError("Equal sign missing in parameter setting")
            if idx == "_value":
                raise GCodeError("Cannot assign to read-only parameter #<_value>")
            rd.i += 1
            blk.settings.append((idx, rd.value()))
            continue
        if not ("a" <= c <= "z"):
            if c.isprintable():
                raise GCodeError(f"Bad character '{c}' used")
            raise GCodeError(f"Bad character '\\{ord(c) & 0xff:03o}' used")
        rd.i += 1
        if c == "g":
            v = rd.value() * 10.0
            code = c_int(v + 0.5)
            if code < 0:
                raise GCodeError("Negative g code used")
            if abs(v - code) > 0.0001 or code > 999:
                raise GCodeError("G-code out of range")
            grp = G_GROUP.get(code)
            if grp is None:
                raise GCodeError("Unknown g code used")
            if grp in blk.g:
                old = blk.g[grp]
                if grp == 1 and (old == 800 or code == 800):
                    code = old if code == 800 else code    # G80 gives way, as in rs274
                else:
                    raise GCodeError("Two g codes used from same modal group")
            blk.g[grp] = code
        elif c == "m":
            code = rd.integer()
            if code < 0:
                raise GCodeError("Negative m code used")
            grp = M_GROUP.get(code)
            if grp is None:
                raise GCodeError(f"Unknown m code used: M{code}")
            if grp in blk.m:
                raise GCodeError("Two m codes used from same modal group")
            blk.m[grp] = code
            blk.m_count += 1
        elif c in "htl":
            if c in words:
                raise GCodeError(f"Multiple {c} words on one line")
            v = rd.integer()
            if v < 0 and c != "h":
                raise GCodeError({"l": "Negative l word used",
                                  "t": "Negative tool id (tool not found)"}[c])
            words[c] = float(v)
        elif c == "n":
            raise GCodeError("Bad character 'n' used")
        elif c == "o":
            raise GCodeError("Unknown control command in o word")
        elif c in _REAL_WORDS:
            if c in words:
                raise GCodeError(f"Multiple {c} words on one line")
            start = rd.i
            v = rd.value()
            blk.literal[c] = s[start:rd.i]
            if c == "f" and v < 0.0:
                raise GCodeError("Negative f word used")
            if c == "s" and v < 0.0:
                raise GCodeError("Negative spindle speed used")
            words[c] = _bounded(c, v) if c in _BOUNDED else v
        else:
            raise GCodeError(f"Bad character '{c}' used")
    if blk.m_count > 4:
        raise GCodeError("Too many m codes on line")
    blk.empty = not (words or blk.g or blk.m or blk.settings)
    return blk
