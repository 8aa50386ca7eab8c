"""Where each key of a TOML text is written: the line of every key and table header,
named by its path as job errors name keys (``units``, ``stock.box``,
``operations[2].feed``: the n-th table of an array of tables is ``name[n]``, from 0).

Errors name their key first (``operations[0].bogus: unknown key``); :func:`place`
gives such an error the line of that key, or of the nearest enclosing table written
in the text (a key inside an inline table, or an item of a list, is placed on the line
where its table or list begins).
"""

from __future__ import annotations

import re

from millpath.errors import JobError, JobErrors

_HEADER = re.compile(r"\s*(\[\[?)\s*(.+?)\s*(\]\]?)\s*(?:#.*)?$")
_KEY = re.compile(r"""\s*((?:[A-Za-z0-9_-]+|"[^"\n]*"|'[^'\n]*')"""
                  r"""(?:\s*\.\s*(?:[A-Za-z0-9_-]+|"[^"\n]*"|'[^'\n]*'))*)\s*=""")
_PART = re.compile(r"""[A-Za-z0-9_-]+|"[^"\n]*"|'[^'\n]*'""")
#: the key path an error message starts with
_NAMED = re.compile(r"\.?([A-Za-z0-9_-]+(?:\[\d+\])*(?:\.[A-Za-z0-9_-]+(?:\[\d+\])*)*):")
_LAST = re.compile(r"(?:\[\d+\]|\.[A-Za-z0-9_-]+)$")


def _parts(dotted: str) -> list[str]:
    return [p.strip("\"'") for p in _PART.findall(dotted)]


def _scan(text: str, depth: int, quote: str) -> tuple[int, str]:
    """Bracket depth and open multi-line string quote after ``text`` (one line), given
    those before it; strings and comments are skipped."""
    i, n = 0, len(text)
    while i < n:
        if quote:
            j = text.find(quote, i)
            if j < 0:
                return depth, quote
            i, quote = j + 3, ""
            continue
        c = text[i]
        if c == "#":
            break
        if text.startswith(('"""', "'''"), i):
            quote, i = text[i:i + 3], i + 3
            continue
        if c in "\"'":
            j = i + 1
            while j < n and text[j] != c:
                j += 2 if c == '"' and text[j] == "\\" else 1
            i = j + 1
            continue
        if c in "[{":
            depth += 1
        elif c in "]}":
            depth = max(depth - 1, 0)
        i += 1
    return depth, quote


def key_lines(text: str) -> dict[str, int]:
    """Key path -> 1-based line where it is written, for every key and table header
    outside multi-line values (the first line wins when a path repeats)."""
    lines: dict[str, int] = {}
    counts: dict[str, int] = {}           # array of tables (path without indices) -> n
    prefix = ""
    depth, quote = 0, ""
    for number, line in enumerate(text.splitlines(), 1):
        rest = line
        if depth == 0 and not quote:
            head = _HEADER.match(line)
            key = None if head else _KEY.match(line)
            if head:
                parts = _parts(head.group(2))
                if head.group(1) == "[[":
                    plain = ".".join(parts)
                    counts[plain] = counts.get(plain, 0) + 1
                prefix = _indexed(parts, counts)
                lines.setdefault(prefix, number)
                rest = ""
            elif key:
                path = ".".join(([prefix] if prefix else []) + _parts(key.group(1)))
                lines.setdefault(path, number)
                rest = line[key.end():]
        depth, quote = _scan(rest, depth, quote)
    return lines


def _indexed(parts: list[str], counts: dict[str, int]) -> str:
    """A table header's path with the current index of each array of tables in it."""
    out: list[str] = []
    for k in range(len(parts)):
        plain = ".".join(parts[:k + 1])
        out.append(parts[k] + (f"[{counts[plain] - 1}]" if plain in counts else ""))
    return ".".join(out)


def line_of(message: str, lines: dict[str, int]) -> int | None:
    """The line of the key ``message`` names first, or of its nearest enclosing key or
    table written in the text; None when it names none."""
    m = _NAMED.match(message)
    path = m.group(1) if m else ""
    while path:
        if path in lines:
            return lines[path]
        shorter = _LAST.sub("", path)
        if shorter == path:
            return None
        path = shorter
    return None


def place(error: JobError, text: str) -> JobError:
    """``error`` (one or several) with each problem lacking a line given the line of
    the key it names in ``text``; several are put in the order of their lines."""
    lines = key_lines(text)
    errors = error.errors if isinstance(error, JobErrors) else [error]
    for e in errors:
        if e.line is None:
            e.line = line_of(e.message, lines)
    if isinstance(error, JobErrors):
        return JobErrors(sorted(errors, key=lambda e: e.line or 0))
    return error
