"""TOML input: parsing with errors naming file and line, and validation of tables
against small schemas, with errors naming key and file.

A schema maps each allowed key to a :class:`Param`. Unknown keys, missing required
keys, wrong types, NaN and out-of-range values are each a :class:`JobError`; a table's
are all found in one pass. No number may be larger than
:data:`~millpath.model.limits.MAX_COORDINATE`.
"""

from __future__ import annotations

import math
import re
import tomllib
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Callable

from millpath.errors import JobError, JobErrors, Problems
from millpath.model.limits import MAX_DIGITS, MAX_NESTING, check_coordinate

REQUIRED = object()


@dataclass(frozen=True)
class Param:
    """One key: ``kind`` is "float", "int", "bool", "str", "path", "list", "table",
    "floats" (list of numbers), "points" (list of [x, y(, z)]) or "any"."""

    kind: str
    default: Any = REQUIRED
    choices: tuple | None = None
    positive: bool = False
    nonneg: bool = False
    doc: str = ""
    length: int | None = None   # exact list length for "floats"
    check: Callable[[Any], str | None] | None = None
    unit: str = ""              # see UNITS: what the number is measured in


#: ``Param.unit`` values and how ``millpath keys`` / docs/jobs.md print them
UNITS = {
    "": "",
    "length": "job units (mm or in)",
    "feed": "job units/min",
    "rpm": "rev/min",
    "deg": "degrees",
    "s": "seconds",
    "count": "count",
    "ratio": "fraction",
}


def _is_num(v: Any) -> bool:
    return isinstance(v, (int, float)) and not isinstance(v, bool)


def _finite(v: Any, key: str, file: str | None) -> bool:
    """Whether the number ``v`` is finite; an integer too large for a float is an error."""
    try:
        return math.isfinite(float(v))
    except OverflowError:
        raise JobError(f"{key}: the number {str(v)[:12]}... is too large", file) from None


def _check_number(v: Any, key: str, p: Param, file: str | None) -> float:
    if not _is_num(v):
        raise JobError(f"{key}: expected a number, got {type(v).__name__} {v!r}", file)
    if not _finite(v, key, file):
        raise JobError(f"{key}: must be finite, got {v!r}", file)
    bad = check_coordinate(float(v))
    if bad:
        raise JobError(f"{key}: {bad}", file)
    if p.positive and v <= 0:
        raise JobError(f"{key}: must be positive, got {v!r}", file)
    if p.nonneg and v < 0:
        raise JobError(f"{key}: must not be negative, got {v!r}", file)
    return v


def _floats(v: Any, key: str, file: str | None) -> list[float]:
    if not isinstance(v, list) or not all(_is_num(x) for x in v):
        raise JobError(f"{key}: expected a list of numbers", file)
    if not all(_finite(x, key, file) for x in v):
        raise JobError(f"{key}: numbers must be finite", file)
    for x in v:
        bad = check_coordinate(float(x))
        if bad:
            raise JobError(f"{key}: {bad}", file)
    return [float(x) for x in v]


def validate(table: Any, schema: dict[str, Param], where: str, file: str | Path | None,
             base_dir: Path | None = None, problems: Problems | None = None
             ) -> dict[str, Any]:
    """Check ``table`` against ``schema``; return a dict with defaults filled in.

    Every unknown key, missing key and bad value of the table is found: without
    ``problems`` they are raised together as :class:`JobErrors`; with it they are
    recorded there and the bad keys take their default (None when required).
    ``where`` prefixes key names in messages (e.g. ``operations[2]``). Paths (kind
    "path") are resolved relative to ``base_dir``.
    """
    f = str(file) if file is not None else None
    if not isinstance(table, dict):
        raise JobError(f"{where}: expected a table", f)
    found: list[JobError] = []
    out: dict[str, Any] = {}
    for key in table:
        if key not in schema:
            allowed = ", ".join(sorted(schema))
            found.append(JobError(f"{where}.{key}: unknown key (allowed: {allowed})", f))
    for key, p in schema.items():
        name = f"{where}.{key}" if where else key
        default = None if p.default is REQUIRED else p.default
        if key not in table:
            if p.default is REQUIRED:
                found.append(JobError(f"{name}: missing required key", f))
            out[key] = default
            continue
        try:
            out[key] = _value(table[key], p, name, f, base_dir)
        except JobError as e:
            found.append(e)
            out[key] = default
    if found and problems is None:
        raise JobErrors(found)
    for e in found:
        problems.add(e)
    return out


def _value(v: Any, p: Param, name: str, f: str | None, base_dir: Path | None) -> Any:
    """The value ``v`` of key ``name`` checked against ``p``; JobError if it is bad."""
    if p.kind == "float":
        v = float(_check_number(v, name, p, f))
    elif p.kind == "int":
        if not isinstance(v, int) or isinstance(v, bool):
            raise JobError(f"{name}: expected an integer, got {v!r}", f)
        _check_number(v, name, p, f)
    elif p.kind == "bool":
        if not isinstance(v, bool):
            raise JobError(f"{name}: expected true or false, got {v!r}", f)
    elif p.kind in ("str", "path"):
        if not isinstance(v, str):
            raise JobError(f"{name}: expected a string, got {v!r}", f)
        if p.kind == "path":
            path = Path(v)
            if not path.is_absolute() and base_dir is not None:
                path = base_dir / path
            v = path
    elif p.kind == "floats":
        v = _floats(v, name, f)
        if p.length is not None and len(v) != p.length:
            raise JobError(f"{name}: expected {p.length} numbers, got {len(v)}", f)
        for x in v:
            if p.positive and x <= 0:
                raise JobError(f"{name}: numbers must be positive", f)
    elif p.kind == "points":
        if not isinstance(v, list) or not v:
            raise JobError(f"{name}: expected a list of points", f)
        pts = []
        for i, q in enumerate(v):
            pts.append(_floats(q, f"{name}[{i}]", f))
            if len(pts[-1]) not in (2, 3):
                raise JobError(f"{name}[{i}]: a point has 2 or 3 coordinates", f)
        v = pts
    elif p.kind == "list":
        if not isinstance(v, list):
            raise JobError(f"{name}: expected a list, got {v!r}", f)
    elif p.kind == "table":
        if not isinstance(v, dict):
            raise JobError(f"{name}: expected a table, got {v!r}", f)
    if p.choices is not None and v not in p.choices:
        raise JobError(f"{name}: must be one of {', '.join(map(repr, p.choices))}, "
                       f"got {v!r}", f)
    if p.check is not None:
        msg = p.check(v)
        if msg:
            raise JobError(f"{name}: {msg}", f)
    return v


#: what the TOML bounds scan stops at: string and comment openings, brackets, line ends
#: and integer literals longer than MAX_DIGITS
_TOML_TOKEN = re.compile(r'"""|\'\'\'|["\'#\[\]{}\n]|[0-9][0-9_]{%d,}' % MAX_DIGITS)
_TOML_BASIC = re.compile(r'(?:[^"\\\n]|\\.)*"')
_TOML_MULTI_BASIC = re.compile(r'(?:[^"\\]|\\.|"(?!""))*"""', re.DOTALL)


def toml_bounds(text: str) -> tuple[int, str] | None:
    """(line, message) where ``text`` nests arrays or inline tables more than
    :data:`~millpath.model.limits.MAX_NESTING` deep or writes an integer of more than
    :data:`~millpath.model.limits.MAX_DIGITS` digits (Python's parser would raise
    RecursionError or refuse the conversion); None when within bounds. Strings and
    comments are skipped; what is not TOML is left to the parser."""
    depth = 0
    line = 1
    i = 0
    n = len(text)
    while True:
        m = _TOML_TOKEN.search(text, i)
        if m is None:
            return None
        t = m.group()
        i = m.end()
        if t == "\n":
            line += 1
        elif t == "#":
            j = text.find("\n", i)
            i = n if j < 0 else j
        elif t in ('"""', "\'\'\'"):
            if t == "\'\'\'":
                j = text.find(t, i)
                end = -1 if j < 0 else j + 3
            else:
                mm = _TOML_MULTI_BASIC.match(text, i)
                end = -1 if mm is None else mm.end()
            if end < 0:
                return None
            line += text.count("\n", i, end)
            i = end
        elif t == '"':
            mm = _TOML_BASIC.match(text, i)
            if mm is None:
                return None
            i = mm.end()
        elif t == "\'":
            j = text.find("\'", i)
            if j < 0 or "\n" in text[i:j]:
                return None
            i = j + 1
        elif t in "[{":
            depth += 1
            if depth > MAX_NESTING:
                return line, f"arrays and tables nested more than {MAX_NESTING} deep"
        elif t in "]}":
            depth = max(depth - 1, 0)
        else:
            return line, f"a number of {len(t.replace('_', ''))} digits (at most {MAX_DIGITS})"


def parse_toml(text: str, path: Path | None) -> dict:
    """tomllib.loads with errors as JobError naming the file and line; nesting and
    number lengths beyond Python's own limits are refused first (:func:`toml_bounds`)."""
    bad = toml_bounds(text)
    if bad is not None:
        raise JobError(f"invalid TOML: {bad[1]}", path, bad[0])
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as e:
        msg = str(e)
        line = None
        m = re.search(r"\s*\(at line (\d+), column \d+\)", msg)
        if m:
            line = int(m.group(1))
            msg = msg[:m.start()] + msg[m.end():]
        elif "(at end of document)" in msg:
            line = text.count("\n") + (0 if text.endswith("\n") else 1)
            msg = msg.replace(" (at end of document)", " at end of file")
        raise JobError(f"invalid TOML: {msg}", path, line) from None
    deep = _too_deep(data) if isinstance(data, dict) else None
    if deep is not None:
        raise JobError(f"invalid TOML: keys nested more than {MAX_NESTING} deep "
                       f"({'.'.join(deep[:4])}...)", path)
    return data


def _too_deep(data: Any) -> list[str] | None:
    """The key path to a value nested more than MAX_NESTING tables and arrays deep
    (dotted keys make such tables without brackets), else None; walked without
    recursion."""
    stack: list[tuple[Any, int, Any]] = [(data, 0, None)]   # value, depth, (key, parent)
    while stack:
        v, depth, link = stack.pop()
        if depth > MAX_NESTING:
            path: list[str] = []
            while link is not None:
                path.append(link[0])
                link = link[1]
            return path[::-1]
        items = v.items() if isinstance(v, dict) else enumerate(v)
        for k, x in items:
            if isinstance(x, (dict, list)):
                stack.append((x, depth + 1, (str(k) if isinstance(k, str) else f"[{k}]",
                                             link)))
    return None
