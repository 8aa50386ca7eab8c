"""ISO 10303-21 ("Part 21", STEP physical file) reader: tokens, grammar, instance graph.

Grammar (the subset of ISO 10303-21:2002 edition 2 that exchange files use)::

    file      = "ISO-10303-21;" header data+ "END-ISO-10303-21;"
    header    = "HEADER;" (record ";")* "ENDSEC;"
    data      = "DATA" ["(" params ")"] ";" (instance)* "ENDSEC;"
    instance  = "#" id "=" (record | "(" record+ ")") ";"      -- simple | complex
    record    = KEYWORD "(" [param ("," param)*] ")"
    param     = INTEGER | REAL | STRING | "#" id | ENUM | BINARY | "$" | "*"
              | "(" [param ("," param)*] ")" | KEYWORD "(" param ")"   -- typed value

Values become Python objects: ``int``, ``float``, ``str`` (decoded: ``''``, ``\\\\``,
``\\X\\hh``, ``\\X2\\...\\X0\\``, ``\\X4\\...\\X0\\``, ``\\S\\c``), :class:`Ref`, :class:`Enum`,
``None`` for ``$``, :data:`DERIVED` for ``*``, :class:`Binary`, :class:`Typed` and
``list`` for aggregates. Comments ``/* ... */`` and line breaks anywhere between tokens
are allowed. Errors raise :class:`~millpath.errors.MillpathError` naming the file, the
line and the instance id (``#12``).

Speed: the tokenizer is one ``re.findall`` pass over the text (token strings built in
C); the parser is one loop over the tokens dispatching on their first character, with
an explicit stack for nested lists. References are collected while parsing, so the
dangling-reference check and the inverse index need no second walk. Token positions
(for error lines) are recovered only when there is an error; instance lines are found
lazily by one scan for ``#n=``.
"""

from __future__ import annotations

import bisect
import gc
import re
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Iterator

from millpath.errors import MillpathError
from millpath.model.limits import MAX_NESTING


class StepError(MillpathError):
    """A malformed Part 21 file (message names file, line and instance id)."""


# --- value types -----------------------------------------------------------------------
#: entity names of geometry and topology (points, directions, placements, curves,
#: surfaces, vertices, edges, loops, faces, shells, solids): their references form a tree
_TREE = re.compile(r"POINT|DIRECTION|VECTOR|PLACEMENT|LINE|CIRCLE|ELLIPSE|PARABOLA"
                   r"|HYPERBOLA|CURVE|SURFACE|PLANE|EDGE|VERTEX|LOOP|BOUND|FACE|SHELL|BREP"
                   r"|SOLID|PATH|SPLINE|BEZIER")


class Ref(int):
    """An instance reference ``#n`` (an int subclass; equal refs compare equal)."""

    __slots__ = ()

    def __repr__(self) -> str:
        return f"#{int(self)}"


class Enum(str):
    """An enumeration or logical value ``.NAME.`` (stored without the dots)."""

    __slots__ = ()

    def __repr__(self) -> str:
        return f".{str(self)}."


class Binary(str):
    """A binary value ``"0ABC"``: the hex digits, first digit = count of unused bits."""

    __slots__ = ()


class _Derived:
    """The ``*`` value: an attribute derived in a subtype (singleton :data:`DERIVED`)."""

    _inst = None

    def __new__(cls):
        if cls._inst is None:
            cls._inst = super().__new__(cls)
        return cls._inst

    def __repr__(self) -> str:
        return "*"


DERIVED = _Derived()


@dataclass(slots=True)
class Typed:
    """A typed parameter such as ``LENGTH_MEASURE(12.5)``: ``name`` and its ``value``."""

    name: str
    value: Any


Record = tuple[str, list]          # (ENTITY_NAME, parameters)


@dataclass(slots=True)
class Instance:
    """One entity instance ``#id``: a simple one has one record, a complex one several
    (in file order, normally alphabetical). ``offset`` is its position in the text."""

    id: int
    records: list[Record]
    offset: int = 0

    @property
    def complex(self) -> bool:
        return len(self.records) > 1

    @property
    def type(self) -> str:
        """Entity name of a simple instance; names joined by ``+`` for a complex one."""
        if len(self.records) == 1:
            return self.records[0][0]
        return "+".join(r[0] for r in self.records)

    def names(self) -> list[str]:
        return [r[0] for r in self.records]

    def has(self, name: str) -> bool:
        for r in self.records:
            if r[0] == name:
                return True
        return False

    def get(self, name: str) -> list | None:
        """Parameters of the record ``name`` (None if the instance has no such record)."""
        for r in self.records:
            if r[0] == name:
                return r[1]
        return None

    @property
    def params(self) -> list:
        """Parameters of a simple instance (the first record's for a complex one)."""
        return self.records[0][1]


@dataclass
class StepFile:
    """A parsed exchange structure: header records and the instance graph."""

    header: list[Record] = field(default_factory=list)
    instances: dict[int, Instance] = field(default_factory=dict)
    file: str | None = None
    text: str = field(default="", repr=False)
    _by_type: dict[str, list[int]] | None = field(default=None, repr=False)
    _inverse: dict[int, list[int]] | None = field(default=None, repr=False)
    _lines: list[int] | None = field(default=None, repr=False)
    _pairs: tuple[list[int], list[int]] | None = field(default=None, repr=False)
    _offsets: dict[int, int] | None = field(default=None, repr=False)

    # --- header -------------------------------------------------------------------------
    def header_record(self, name: str) -> list | None:
        for n, p in self.header:
            if n == name:
                return p
        return None

    @property
    def schemas(self) -> list[str]:
        p = self.header_record("FILE_SCHEMA")
        if not p or not isinstance(p[0], list):
            return []
        return [str(s) for s in p[0]]

    # --- graph --------------------------------------------------------------------------
    def __getitem__(self, ref: int) -> Instance:
        if not isinstance(ref, int):
            raise self.error(self.holder_of(ref), f"{_kind(ref)} where a reference #n is "
                             "expected", StepError)
        return self.instances[int(ref)]

    def holder_of(self, value: Any) -> Instance | None:
        """The instance whose parameters hold the object ``value`` (for messages)."""
        for inst in self.instances.values():
            stack: list = [p for _, p in inst.records]
            while stack:
                v = stack.pop()
                if v is value:
                    return inst
                if isinstance(v, list):
                    stack.extend(v)
                elif isinstance(v, Typed):
                    stack.append(v.value)
        return None

    def __len__(self) -> int:
        return len(self.instances)

    def __iter__(self) -> Iterator[Instance]:
        return iter(self.instances.values())

    def by_type(self, name: str) -> list[Instance]:
        """Instances having a record ``name`` (simple or within a complex instance)."""
        if self._by_type is None:
            idx: dict[str, list[int]] = {}
            for inst in self.instances.values():
                for rn, _ in inst.records:
                    idx.setdefault(rn, []).append(inst.id)
            self._by_type = idx
        return [self.instances[i] for i in self._by_type.get(name.upper(), ())]

    def inverse(self, ref: int) -> list[Instance]:
        """Instances whose parameters reference ``#ref`` (each once, in file order)."""
        if self._inverse is None and self._pairs is not None:
            inv2: dict[int, list[int]] = {}
            for tgt, src in zip(*self._pairs):
                if src >= 0:
                    inv2.setdefault(tgt, []).append(src)
            self._inverse = {k: (v if len(v) == 1 else list(dict.fromkeys(v)))
                             for k, v in inv2.items()}
        if self._inverse is None:
            inv: dict[int, list[int]] = {}
            for inst in self.instances.values():
                seen = set()
                for r in _refs(inst):
                    if r not in seen:
                        seen.add(r)
                        inv.setdefault(r, []).append(inst.id)
            self._inverse = inv
        return [self.instances[i] for i in self._inverse.get(int(ref), ())]

    def users(self, ref: int, name: str, attr: int | None = None) -> list[Instance]:
        """Instances with a record ``name`` referencing ``#ref`` (at parameter ``attr``
        of that record when given): the EXPRESS ``USEDIN`` query."""
        out = []
        for inst in self.inverse(ref):
            p = inst.get(name)
            if p is None:
                continue
            if attr is None or (attr < len(p) and isinstance(p[attr], Ref)
                                and int(p[attr]) == int(ref)):
                out.append(inst)
        return out

    def check_tree(self) -> None:
        """Raise :class:`StepError` naming the entity when an instance refers to itself,
        or when geometric or topological instances (points, curves, surfaces, edges,
        loops, faces, shells, solids) refer to each other in a cycle: they must form a
        tree, and OpenCASCADE follows them without a guard (a native stack overflow).
        Dangling references were refused by the parser."""
        targets, sources = self._pairs if self._pairs is not None else self._ref_pairs()
        for tgt, src in zip(targets, sources):
            if tgt == src:
                raise self.error(src, f"{self[src].type} refers to itself", StepError)
        cycle = self._geometric_cycle(targets, sources)
        if cycle:
            path = " -> ".join(f"#{i}" for i in cycle + cycle[:1])
            raise self.error(cycle[0], f"{self[cycle[0]].type} is part of a reference "
                             f"cycle ({path}): geometry and topology must form a tree",
                             StepError)

    def _ref_pairs(self) -> tuple[list[int], list[int]]:
        targets: list[int] = []
        sources: list[int] = []
        for inst in self.instances.values():
            for r in _refs(inst):
                targets.append(r)
                sources.append(inst.id)
        return targets, sources

    def _geometric_cycle(self, targets: list[int], sources: list[int]) -> list[int]:
        """Instance ids along one reference cycle through a geometric or topological
        instance (empty when there is none): a depth-first walk without recursion, each
        instance and reference visited once."""
        adj: dict[int, list[int]] = {}
        for tgt, src in zip(targets, sources):
            if src >= 0:
                adj.setdefault(src, []).append(tgt)
        done: set[int] = set()
        for root in adj:
            if root in done:
                continue
            path = [root]
            pos = {root: 0}
            its = [iter(adj[root])]
            while its:
                nxt = next(its[-1], None)
                if nxt is None:
                    node = path.pop()
                    del pos[node]
                    done.add(node)
                    its.pop()
                elif nxt in pos:
                    cycle = path[pos[nxt]:]
                    if any(_TREE.search(name) for i in cycle for name in self[i].names()):
                        return cycle
                elif nxt not in done:
                    pos[nxt] = len(path)
                    path.append(nxt)
                    its.append(iter(adj.get(nxt, ())))
        return []

    def line_of(self, inst_or_offset: Instance | int) -> int:
        """1-based line number of an instance (or text offset)."""
        if isinstance(inst_or_offset, Instance):
            off = inst_or_offset.offset
            if off < 0:
                off = self.offset_of(inst_or_offset.id)
        else:
            off = inst_or_offset
        if self._lines is None:
            self._lines = [m.start() for m in re.finditer("\n", self.text)]
        return bisect.bisect_left(self._lines, off) + 1

    def offset_of(self, iid: int) -> int:
        """Text offset of the definition ``#iid=`` (found by one scan, then cached)."""
        if self._offsets is None:
            offs: dict[int, int] = {}
            for m in _DEF.finditer(self.text):
                offs.setdefault(int(m.group(1)), m.start())
            self._offsets = offs
        return self._offsets.get(int(iid), 0)

    def error(self, inst: Instance | int | None, message: str,
              cls: type[MillpathError] = MillpathError) -> MillpathError:
        """A user-facing error about instance ``inst`` (line and ``#id`` filled in)."""
        if isinstance(inst, int) and not isinstance(inst, Instance):
            inst = self.instances.get(int(inst))
        if inst is None:
            return cls(message, self.file)
        line = self.line_of(inst) if self.text else None
        return cls(message, self.file, line, f"#{inst.id}")

    def graph(self) -> tuple:
        """The comparable content: header and ``{id: records}`` with every value tagged
        by its kind, so ``1`` and ``1.0``, ``#1`` and ``1``, ``.T.`` and ``'T'`` differ."""
        return (canonical(self.header),
                {i: canonical(inst.records) for i, inst in self.instances.items()})


def _kind(v: Any) -> str:
    """How a parameter value is named in messages."""
    if isinstance(v, list):
        return "a list (...)"
    if v is None:
        return "'$'"
    if isinstance(v, Typed):
        return f"a typed value {v.name}(...)"
    text = repr(v)
    return f"{text[:20]}..." if len(text) > 20 else text


def canonical(v: Any) -> Any:
    """A hashable, kind-tagged copy of a value (lists of records included)."""
    if isinstance(v, (list, tuple)):
        return tuple(canonical(x) for x in v)
    if isinstance(v, Typed):
        return ("typed", v.name, canonical(v.value))
    if v is None or v is DERIVED:
        return repr(v)
    return (type(v).__name__, v)


def _refs(inst: Instance) -> Iterator[int]:
    stack: list = [p for _, p in inst.records]
    while stack:
        v = stack.pop()
        if isinstance(v, Ref):
            yield int(v)
        elif isinstance(v, list):
            stack.extend(v)
        elif isinstance(v, Typed):
            stack.append(v.value)


# --- tokenizer -------------------------------------------------------------------------
_TOKEN = re.compile(r"""
    (?P<ws>[ \t\r\n]+|/\*.*?\*/)
  | (?P<str>'(?:[^']|'')*')
  | (?P<ref>\#[0-9]+)
  | (?P<enum>\.[A-Za-z_][A-Za-z0-9_]*\.)
  | (?P<num>[+-]?\.?[0-9][0-9A-Za-z.+-]*)
  | (?P<kw>!?[A-Za-z_][A-Za-z0-9_]*(?:-[0-9A-Za-z]+)*)
  | (?P<bin>"[0-9A-Fa-f]*")
  | (?P<p>[=();,*$])
  | (?P<bad>/\*|'|"|.)
""", re.VERBOSE | re.DOTALL)

_INT = re.compile(r"[+-]?[0-9]+\Z")
#: Part 21 integers are machine integers: beyond 64 bits a literal is not a number a
#: reader can use (and not one a float can hold past 309 digits)
_INT_RANGE = 2 ** 63
_REAL = re.compile(r"[+-]?[0-9]+\.[0-9]*(?:[eE][+-]?[0-9]+)?\Z")

_ESC = re.compile(r"\\X2\\((?:[0-9A-Fa-f]{4})*)\\X0\\|\\X4\\((?:[0-9A-Fa-f]{8})*)\\X0\\"
                  r"|\\X\\([0-9A-Fa-f]{2})|\\S\\(.)|\\P[A-I]\\|\\\\")


def _unescape_match(m: re.Match) -> str:
    if m.group(1) is not None:
        h = m.group(1)
        return "".join(chr(int(h[i:i + 4], 16)) for i in range(0, len(h), 4))
    if m.group(2) is not None:
        h = m.group(2)
        return "".join(chr(int(h[i:i + 8], 16)) for i in range(0, len(h), 8))
    if m.group(3) is not None:
        return chr(int(m.group(3), 16))
    if m.group(4) is not None:
        return chr(ord(m.group(4)) + 128)
    if m.group(0) == "\\\\":
        return "\\"
    return ""            # \PA\ .. \PI\ code page directives


def decode_string(body: str) -> str:
    """Decode the inside of a Part 21 string literal (without the quotes)."""
    if "\n" in body or "\r" in body:     # a string broken across lines: breaks are not data
        body = body.replace("\r", "").replace("\n", "")
    if "''" in body:
        body = body.replace("''", "'")
    if "\\" in body:
        body = _ESC.sub(_unescape_match, body)
    return body


_FAST = re.compile(r"""[ \t\r\n]*('(?:[^']|'')*'|\#[0-9]+|\.[A-Za-z_][A-Za-z0-9_]*\.
    |[+-]?\.?[0-9][0-9A-Za-z.+-]*|!?[A-Za-z_][A-Za-z0-9_]*(?:-[0-9A-Za-z]+)*
    |"[0-9A-Fa-f]*"|/\*.*?\*/|[^ \t\r\n])""", re.VERBOSE | re.DOTALL)
_DEF = re.compile(r"#([0-9]+)[ \t\r\n]*=")


class _Fail(Exception):
    """Internal: an error at token index ``i`` (converted to a StepError with a line)."""

    def __init__(self, i: int, msg: str, inst: int | None):
        self.i, self.msg, self.inst = i, msg, inst


class _Parser:
    """Fast path: ``re.findall`` gives the token strings at C speed and one loop builds
    the values, dispatching on the first character. Positions are recovered only for
    errors, by the slower positional tokenizer."""

    def __init__(self, text: str, file: str | None):
        self.text = text
        self.file = file
        self._lines: list[int] | None = None

    def line(self, pos: int) -> int:
        if self._lines is None:
            self._lines = [m.start() for m in re.finditer("\n", self.text)]
        return bisect.bisect_left(self._lines, pos) + 1

    def fail_at(self, pos: int, msg: str, inst: int | None = None) -> StepError:
        return StepError(msg, self.file, self.line(pos), f"#{inst}" if inst is not None else None)

    def position(self, index: int) -> int:
        """Text offset of token ``index`` (of the comment-free token list)."""
        k = 0
        for m in _TOKEN.finditer(self.text):
            g = m.lastgroup
            if g == "ws":
                continue
            if k == index:
                return m.start()
            k += 1
        return len(self.text)

    def parse(self) -> StepFile:
        text = self.text
        toks = _FAST.findall(text)
        if "/*" in text:
            toks = [t for t in toks if not t.startswith("/*")]
        gc_was = gc.isenabled()
        gc.disable()              # the graph is acyclic lists: skip collector passes
        try:
            return self._parse(toks)
        except _Fail as e:
            if e.i >= len(toks):
                raise self.fail_at(len(text), e.msg, e.inst) from None
            t = toks[e.i]
            # a quote left open swallows text up to the next quote: find that "string"
            for j in range(e.i - 1, max(e.i - 60, 0) - 1, -1):
                if toks[j][0] == "'" and "\n" in toks[j] and ";" in toks[j]:
                    e.i, e.msg, t = j, "unterminated string", toks[j]
                    break
            if t == "'":
                e.msg = "unterminated string"
            elif t == "/" and e.i + 1 < len(toks) and toks[e.i + 1] == "*":
                e.msg = "unterminated comment"
            raise self.fail_at(self.position(e.i), e.msg, e.inst) from None
        finally:
            if gc_was:
                gc.enable()

    def _parse(self, toks: list[str]) -> StepFile:
        sf = StepFile(file=self.file, text=self.text)
        n = len(toks)

        def expect(i: int, word: str, inst: int | None = None) -> int:
            if i >= n:
                raise _Fail(i, f"truncated file: expected {word!r}", inst)
            if toks[i] != word:
                raise _Fail(i, f"expected {word!r}, found {toks[i]!r}", inst)
            return i + 1

        if n == 0 or toks[0] != "ISO-10303-21":
            raise _Fail(0, "not an ISO 10303-21 file (no 'ISO-10303-21;' at the start)", None)
        i = expect(1, ";")
        i = expect(i, "HEADER")
        i = expect(i, ";")
        targets: list[int] = []
        sources: list[int] = []
        while i < n and toks[i] != "ENDSEC":
            t = toks[i]
            if not (t[0].isalpha() or t[0] == "!"):
                raise _Fail(i, f"expected a header entity, found {t!r}", None)
            i = expect(i + 1, "(")
            params, i = self.params(toks, i, None, targets, sources)
            i = expect(i, ";")
            sf.header.append((t.upper(), params))
        i = expect(i, "ENDSEC")
        i = expect(i, ";")
        insts = sf.instances
        last = None
        while i < n and toks[i] == "DATA":
            i += 1
            if i < n and toks[i] == "(":
                _, i = self.params(toks, i + 1, None, targets, sources)
            i = expect(i, ";")
            while i < n and toks[i][0] == "#":
                if len(toks[i]) == 1:
                    raise _Fail(i, "'#' without an instance number", last)
                iid = int(toks[i][1:])
                last = iid
                if i + 2 >= n:
                    raise _Fail(n, "truncated file: instance has no value", iid)
                if toks[i + 1] != "=":
                    raise _Fail(i + 1, f"expected '=', found {toks[i + 1]!r}", iid)
                i += 2
                t = toks[i]
                records: list[Record] = []
                if t == "(":
                    i += 1
                    while i < n and (toks[i][0].isalpha() or toks[i][0] == "!"):
                        name = toks[i].upper()
                        i = expect(i + 1, "(", iid)
                        params, i = self.params(toks, i, iid, targets, sources)
                        records.append((name, params))
                    if not records:
                        raise _Fail(i, "complex instance without records", iid)
                    i = expect(i, ")", iid)
                elif t[0].isalpha() or t[0] == "!":
                    i = expect(i + 1, "(", iid)
                    params, i = self.params(toks, i, iid, targets, sources)
                    records.append((t.upper(), params))
                else:
                    raise _Fail(i, f"expected an entity name, found {t!r}", iid)
                if i >= n:
                    raise _Fail(n, "truncated file: expected ';'", iid)
                if toks[i] != ";":
                    raise _Fail(i, f"expected ';', found {toks[i]!r}", iid)
                i += 1
                if iid in insts:
                    raise _Fail(i - 1, f"instance #{iid} is defined twice", iid)
                insts[iid] = Instance(iid, records, -1)
            if i >= n:
                raise _Fail(n, "truncated file: DATA section has no ENDSEC", last)
            if toks[i] != "ENDSEC":
                raise _Fail(i, f"expected an instance '#n=' or ENDSEC, found {toks[i]!r}", last)
            i = expect(i + 1, ";")
        if i >= n:
            raise _Fail(n, "truncated file: no 'END-ISO-10303-21;'", last)
        i = expect(i, "END-ISO-10303-21")
        i = expect(i, ";")
        if i < n:
            raise _Fail(i, f"text after 'END-ISO-10303-21;': {toks[i]!r}", None)
        missing = set(targets).difference(insts)
        missing.discard(-1)
        if missing:
            for tgt, src in zip(targets, sources):
                if tgt in missing:
                    raise sf.error(src, f"dangling reference #{tgt}", StepError)
        sf._pairs = (targets, sources)
        return sf

    def params(self, toks: list[str], i: int, iid: int | None, targets: list[int],
               sources: list[int]) -> tuple[list, int]:
        """Parse a parameter list after its opening ``(``; return (list, next index)."""
        stack: list[list] = []
        typed: list[str | None] = []
        name: str | None = None
        cur: list = []
        expect_value = True      # at the start of a list or after a comma
        src = iid if iid is not None else -1
        try:
            while True:
                t = toks[i]
                i += 1
                c = t[0]
                if c == ",":
                    if expect_value:
                        raise _Fail(i - 1, "missing value before ','", iid)
                    expect_value = True
                    continue
                if c == ")":
                    if expect_value and cur:
                        raise _Fail(i - 1, "missing value before ')'", iid)
                    if not stack:
                        return cur, i
                    done = cur
                    cur = stack.pop()
                    if name is not None:
                        if len(done) != 1:
                            raise _Fail(i - 1, f"typed value {name} needs one value", iid)
                        cur.append(Typed(name, done[0]))
                    else:
                        cur.append(done)
                    name = typed.pop()
                    expect_value = False
                    continue
                if not expect_value:
                    raise _Fail(i - 1, f"expected ',' or ')', found {t!r}", iid)
                expect_value = False
                if c == "#":
                    if len(t) == 1:
                        raise _Fail(i - 1, "'#' without an instance number", iid)
                    r = int(t[1:])
                    cur.append(Ref(r))
                    targets.append(r)
                    sources.append(src)
                elif c in "0123456789+-" or (c == "." and len(t) > 1 and t[1].isdigit()):
                    try:
                        v = float(t) if "." in t else int(t)
                    except ValueError:
                        raise _Fail(i - 1, f"bad number {t[:30]!r}", iid) from None
                    if type(v) is int and not -_INT_RANGE <= v < _INT_RANGE:
                        shown = t if len(t) <= 30 else t[:30] + "..."
                        raise _Fail(i - 1, f"integer {shown} out of range (a 64-bit "
                                    "integer)", iid)
                    cur.append(v)
                elif c == "'":
                    if len(t) < 2:
                        raise _Fail(i - 1, "unterminated string", iid)
                    body = t[1:-1]
                    cur.append(decode_string(body) if ("'" in body or "\\" in body
                                                       or "\n" in body) else body)
                elif c == "(":
                    if len(stack) >= MAX_NESTING:
                        raise _Fail(i - 1, f"parameters nested more than {MAX_NESTING} "
                                    "deep", iid)
                    stack.append(cur)
                    typed.append(name)
                    name = None
                    cur = []
                    expect_value = True
                elif c == "$":
                    cur.append(None)
                elif c == "*":
                    cur.append(DERIVED)
                elif c == ".":
                    if len(t) < 3 or t[-1] != ".":
                        raise _Fail(i - 1, f"unexpected {t!r}", iid)
                    cur.append(Enum(t[1:-1].upper()))
                elif c.isalpha() or c == "!":
                    if toks[i] != "(":
                        raise _Fail(i, f"expected '(' after {t}", iid)
                    i += 1
                    if len(stack) >= MAX_NESTING:
                        raise _Fail(i - 1, f"parameters nested more than {MAX_NESTING} "
                                    "deep", iid)
                    stack.append(cur)
                    typed.append(name)
                    name = t.upper()
                    cur = []
                    expect_value = True
                elif c == '"':
                    if len(t) < 2 or t[-1] != '"':
                        raise _Fail(i - 1, "bad binary value", iid)
                    cur.append(Binary(t[1:-1]))
                else:
                    raise _Fail(i - 1, f"unexpected {t!r} in a parameter list", iid)
        except IndexError:
            raise _Fail(len(toks), "truncated file: unclosed parameter list", iid) from None


def parse(text: str, file: str | Path | None = None) -> StepFile:
    """Parse Part 21 text into a :class:`StepFile` (raises :class:`StepError`)."""
    return _Parser(text, str(file) if file is not None else None).parse()


def read(path: str | Path) -> StepFile:
    """Read and parse a Part 21 file (ISO 8859-1 tolerated; the format is 7-bit ASCII)."""
    p = Path(path)
    try:
        data = p.read_bytes()
    except FileNotFoundError:
        raise StepError("no such STEP file", p) from None
    except IsADirectoryError:
        raise StepError("is a directory, not a STEP file", p) from None
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError:
        text = data.decode("latin-1")
    return parse(text, p)
