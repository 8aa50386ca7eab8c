"""Fit the linear runs of an existing RS274NGC (LinuxCNC) program.

The program is read line by line by the interpreter's lexer (:mod:`millpath.gcode.lexer`,
one grammar for both: any word order, case, spacing, comments), with just enough of the
interpreter's modal state to
know where the tool is: units (G20/G21), distance mode (G90/G91, G90.1/G91.1), plane,
motion mode, feed mode, cutter compensation. A *fittable* block is a straight feed in
absolute coordinates (G90, G94, no compensation) that holds only ``N``, ``G1``, ``X``,
``Y``, ``Z`` and ``F`` words with literal numbers and no comment. Maximal runs of
consecutive fittable blocks with one feed, whose start point is known, are rewritten by
:func:`millpath.fit.fit_points`; every other line is copied as written. Anything the
reader does not follow (parameters, expressions, O-words, G28/G30/G53/G92, work offsets,
tool changes, tool length offsets, probing, other axes) makes the position unknown until
the axes are given again, so no run starts from a guessed point.

Written numbers use the program's own decimals where it writes more than the post
would (4 in mm, 5 in inch), up to 6; programs that never say G20 or G21 are read with
inch settings (5 decimals, LinuxCNC's inch arc-radius limit, the smaller one). After a
rewritten run the plane comes back on a block of its own (``G17``), and ``G1`` in the
first later block that relies on the motion mode, after its block delete and line
number (``N150 G1 X...``), or on a block of its own before an expression or O-word
block. Runs whose blocks do not move (zero length after
rounding) disappear, but their ``F`` word stays.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass, field

import numpy as np

from millpath.errors import MillpathError
from millpath.gcode.errors import GCodeError
from millpath.gcode.lexer import MAX_PARAM, normalize, read_block
from millpath.fit import FitSettings, fit_points
from millpath.fit.segment import PLANE_NAMES, PLANES
from millpath.model.numbers import plain
from millpath.model.units import default

_OWORD = re.compile(r"(?:/)?(?:n[\d.]*)?o")     # normalized text of an O-word line
# what must stay first on a line: block delete and the line number (N word)
_LEAD = re.compile(r"\s*(?:/\s*)?(?:[nN](?:\s*[0-9.])+)?\s*")
_PLANE_CODE = {"XY": "G17", "XZ": "G18", "YZ": "G19"}
_IJK = "IJK"
# G codes that change neither the position nor how a G1 run is read
_NEUTRAL_G = {4.0, 17.0, 18.0, 19.0, 40.0, 41.0, 42.0, 61.0, 61.1, 64.0, 90.0, 91.0, 90.1,
              91.1, 93.0, 94.0, 95.0, 96.0, 97.0, 98.0, 99.0, 80.0, 0.0, 1.0, 2.0, 3.0,
              5.0, 81.0, 82.0, 83.0, 84.0, 85.0, 86.0, 87.0, 88.0, 89.0, 73.0, 74.0,
              20.0, 21.0, 64.0, 49.0, 43.0, 43.1, 43.2, 44.0}
_MOTION_G = {0.0, 1.0, 2.0, 3.0, 5.0, 73.0, 74.0, 80.0, 81.0, 82.0, 83.0, 84.0, 85.0, 86.0,
             87.0, 88.0, 89.0, 5.1, 5.2, 5.3, 33.0, 33.1, 38.2, 38.3, 38.4, 38.5, 76.0}


def with_code(code: str, raw: str) -> str:
    """Line ``raw`` with the word ``code`` (e.g. "G1") after its block delete and line
    number, which RS274NGC wants first on the line: "N150 X1" -> "N150 G1 X1"."""
    body = raw.strip()
    lead = _LEAD.match(body).group(0)
    rest = body[len(lead):]
    return f"{lead.rstrip()} {code} {rest}".strip() if lead.strip() else f"{code} {rest}"


def _decimals(s: str) -> int:
    return len(s.split(".", 1)[1]) if "." in s else 0


@dataclass
class FitStats:
    """What :func:`fit_program` did, to say why it changed nothing.

    ``moves``: G1 moves with a coordinate; ``rewritten``/``kept``: moves in runs it
    rewrote / could not fit within the tolerance; ``skipped``: moves it may not touch,
    by reason; ``merge_min``/``merge_max`` (program units): over the runs kept, the
    smallest and the largest of each run's smallest deviation that would merge two of
    its neighbouring moves into one line (a tolerance above ``merge_min`` changes some
    run, above ``merge_max`` every run; 0 when no run was kept)."""

    moves: int = 0
    rewritten: int = 0
    kept: int = 0
    skipped: dict[str, int] = field(default_factory=dict)
    merge_min: float = 0.0
    merge_max: float = 0.0
    _sags: list[float] = field(default_factory=list, repr=False)

    def skip(self, why: str, n: int = 1) -> None:
        self.skipped[why] = self.skipped.get(why, 0) + n


def _merge_sag(points: list[list[float]]) -> float:
    """The smallest distance of an inner point of ``points`` from the segment joining
    its neighbours: the least deviation that merges two neighbouring moves."""
    P = np.asarray(points, dtype=float)
    a, b, c = P[:-2], P[1:-1], P[2:]
    d = c - a
    l2 = np.einsum("ij,ij->i", d, d)
    t = np.clip(np.einsum("ij,ij->i", b - a, d) / np.where(l2 > 0, l2, 1.0), 0.0, 1.0)
    dist = np.linalg.norm(b - (a + t[:, None] * d), axis=1)
    return float(dist.min()) if len(dist) else 0.0


def _why_not(st: "_State", b: "_Block") -> str | None:
    """Why the G1 move ``b`` cannot join a run (None: it is not a G1 move)."""
    motion = 1.0 if 1.0 in b.g else (st.motion if not b.g else None)
    if motion != 1.0 or b.opaque or not any(a in b.words for a in "XYZ"):
        return None
    if not st.known():
        return "before the position is known"
    if st.comp or st.comp_exit:
        return "under cutter radius compensation"
    if not st.absolute:
        return "in incremental distance mode (G91)"
    if st.feed_mode != 94.0:
        return "not in units-per-minute feed mode (G94)"
    if st.diameter:
        return "in diameter mode (G7)"
    return "with other words or G codes on the line"


class _State:
    def __init__(self) -> None:
        self.units: str | None = None
        self.absolute = True
        self.arc_absolute = False
        self.plane = "XY"
        self.motion: float | None = None
        self.feed_mode = 94.0
        self.comp = False
        self.diameter = False        # G7 (lathe diameter mode) in force
        self.comp_exit = False       # the move after G40 is the compensation exit move
        self.feed: float | None = None
        self.pos: list[float | None] = [None, None, None]

    def known(self) -> bool:
        return all(p is not None for p in self.pos)


class _AnyName(dict):
    """Named parameters for reading a block's codes only: every name reads as 0."""

    def __contains__(self, key) -> bool:
        return True

    def __missing__(self, key) -> float:
        return 0.0


_ZEROS = [0.0] * MAX_PARAM


class _Block:
    """One line read by the interpreter's lexer (:mod:`millpath.gcode.lexer`): G codes,
    M codes, other words with their written numbers, and whether it can join a run.

    Lines with parameters, expressions, O-words or block delete are *opaque*: their
    codes are read (parameters as 0) to follow the motion mode, their position is not.
    """

    def __init__(self, raw: str):
        self.raw = raw
        self.g: list[float] = []
        self.m: list[int] = []
        self.words: dict[str, float] = {}
        self.text: dict[str, str] = {}
        self.comment = False
        self.opaque = False
        self.unknown = False            # codes unread (an O-word, a line rs274 refuses)
        body = raw.strip()
        self.empty = body == "" or body == "%"
        if self.empty:
            return
        try:
            norm, _ = normalize(raw)
        except GCodeError:
            self.opaque = self.unknown = True
            return
        self.comment = "(" in norm or ";" in raw
        core = norm.replace("(", "")
        self.empty = core == ""
        if self.empty:
            return
        if core.startswith("/") or "#" in core or "[" in core:
            self.opaque = True
        if _OWORD.match(core):
            self.opaque = self.unknown = True
            return
        try:
            blk = read_block(raw, 0, _ZEROS, _AnyName())
        except GCodeError:
            self.opaque = self.unknown = True
            return
        self.g = [round(code / 10.0, 1) for code in blk.g.values()]
        self.m = list(blk.m.values())
        self.words = {k.upper(): v for k, v in blk.words.items()}
        self.text = {k.upper(): v for k, v in blk.literal.items()}


def _apply(st: _State, b: _Block) -> None:
    """Update the modal state and position for block ``b`` (what LinuxCNC would do, as
    far as the fitter needs it)."""
    if b.opaque:
        st.pos = [None, None, None]
        if b.unknown or any(g in _MOTION_G for g in b.g):
            st.motion = None
        return
    w = b.words
    lost = False
    for g in b.g:
        if g == 20.0:
            lost = lost or st.units not in (None, "inch")
            st.units = "inch"
        elif g == 21.0:
            lost = lost or st.units not in (None, "mm")
            st.units = "mm"
        elif g == 90.0:
            st.absolute = True
        elif g == 91.0:
            st.absolute = False
        elif g == 90.1:
            st.arc_absolute = True
        elif g == 91.1:
            st.arc_absolute = False
        elif g in (17.0, 18.0, 19.0):
            st.plane = {17.0: "XY", 18.0: "XZ", 19.0: "YZ"}[g]
        elif g in (93.0, 94.0, 95.0):
            st.feed_mode = g
        elif g == 40.0:
            st.comp_exit = st.comp
            st.comp = False
        elif g in (41.0, 42.0, 41.1, 42.1):
            st.comp = True
        elif g in (7.0, 8.0):
            st.diameter = g == 7.0           # lathe diameter mode: X is not a length
            lost = True
        elif g in (43.0, 43.1, 43.2, 44.0, 49.0):
            lost = True                      # the program Z of the tool tip changes
        elif g in _MOTION_G:
            st.motion = g
        elif g not in _NEUTRAL_G:
            lost = True                      # G10, G28, G30, G52, G53, G54.., G92, ...
    if "F" in w:
        st.feed = w["F"]
    if 6 in b.m or 61 in b.m:
        lost = True                          # a tool change may move the tool
    axes = [a for a in "XYZ" if a in w]
    moved = bool(axes) and not any(g in (4.0, 10.0, 28.0, 30.0, 52.0, 92.0) for g in b.g)
    if lost or any(g in (28.0, 30.0, 53.0, 92.0, 10.0, 52.0) for g in b.g):
        st.pos = [None, None, None]
        if axes and st.absolute and not any(g in (28.0, 30.0, 53.0, 92.0, 10.0, 52.0)
                                            for g in b.g):
            for a in axes:
                st.pos["XYZ".index(a)] = w[a]
        return
    if moved and st.motion is not None:
        cycle = st.motion in (73.0, 74.0, 81.0, 82.0, 83.0, 84.0, 85.0, 86.0, 87.0, 88.0,
                              89.0)
        if st.motion in (5.1, 5.2, 5.3, 33.0, 33.1, 38.2, 38.3, 38.4, 38.5, 76.0):
            st.pos = [None, None, None]
            return
        for a in axes:
            k = "XYZ".index(a)
            if st.absolute:
                st.pos[k] = w[a]
            else:
                p = st.pos[k]
                st.pos[k] = None if p is None else p + w[a]
        if cycle:
            st.pos[2] = None                 # back at the R plane or the initial Z
        if st.comp_exit:
            st.comp_exit = False
    elif moved:
        st.pos = [None, None, None]          # axis words with no motion mode in force


def _fittable(st: _State, b: _Block) -> bool:
    """Can block ``b`` (given the state before it) join a run of G1 moves?"""
    if b.opaque or b.comment or b.empty or b.m:
        return False
    if any(l not in "XYZF" for l in b.words) or not any(a in b.words for a in "XYZ"):
        return False
    if any(g != 1.0 for g in b.g):
        return False
    motion = 1.0 if b.g else st.motion
    return (motion == 1.0 and st.absolute and st.feed_mode == 94.0 and not st.comp
            and not st.comp_exit and not st.diameter)


class _Emitter:
    """Writes the fitted primitives of one run as blocks."""

    def __init__(self, st: _State, d: int):
        self.d = d
        self.plane = st.plane
        self.motion = st.motion
        self.arc_absolute = st.arc_absolute
        self.pos = [plain(v, d) for v in st.pos]   # type: ignore[arg-type]
        self.lines: list[str] = []
        self.feed = ""                  # F word of the run, until a block carries it

    def _emit(self, words: list[str]) -> None:
        self.lines.append(" ".join(words) + self.feed)
        self.feed = ""

    def finish(self) -> list[str]:
        """The blocks; a lone F word if no block could carry the run's feed."""
        if self.feed:
            self.lines.append(self.feed.strip())
            self.feed = ""
        return self.lines

    def _axes(self, end, skip: tuple[int, ...] = ()) -> list[str]:
        words = []
        for k in range(3):
            s = plain(end[k], self.d)
            if s != self.pos[k] and k not in skip:
                words.append("XYZ"[k] + s)
            self.pos[k] = s
        return words

    def _head(self, code: str, plane: str | None = None) -> list[str]:
        words = []
        if plane is not None and plane != self.plane:
            words.append(_PLANE_CODE[plane])
            self.plane = plane
        # LinuxCNC wants the G5 word on every cubic block (I J P Q are not modal)
        if code == "G5" or self.motion != {"G1": 1.0, "G2": 2.0, "G3": 3.0, "G5": 5.0}[code]:
            words.append(code)
            self.motion = {"G1": 1.0, "G2": 2.0, "G3": 3.0, "G5": 5.0}[code]
        return words

    def line(self, end) -> None:
        words = self._head("G1") + self._axes(end)
        if words:
            self._emit(words)

    def verbatim(self, block: "_Block", end) -> None:
        """Copy an original G1 block, prefixed by G1 when the motion mode changed."""
        if "F" in block.words:
            self.feed = ""                       # the block sets the feed itself
        if block.g:                              # the block names G1 itself
            self.motion = 1.0
            self.lines.append(block.raw)
        else:
            prefix = " ".join(self._head("G1"))
            self.lines.append(with_code(prefix, block.raw) if prefix else block.raw)
        for k in range(3):
            self.pos[k] = plain(end[k], self.d)

    def arc(self, start, end, plane: str, c1: float, c2: float, cw: bool) -> None:
        a1, a2, _ = PLANES[PLANE_NAMES.index(plane)]
        words = self._head("G2" if cw else "G3", plane) + self._axes(end)
        if self.arc_absolute:
            words += [_IJK[a1] + plain(c1, self.d), _IJK[a2] + plain(c2, self.d)]
        else:
            words += [_IJK[a1] + plain(c1 - start[a1], self.d),
                      _IJK[a2] + plain(c2 - start[a2], self.d)]
        self._emit(words)

    def cubic(self, start, end, ctrl) -> None:
        words = self._head("G5", "XY")
        words += [f"X{plain(end[0], self.d)}", f"Y{plain(end[1], self.d)}",
                  f"I{plain(ctrl[0] - start[0], self.d)}", f"J{plain(ctrl[1] - start[1], self.d)}",
                  f"P{plain(ctrl[2] - end[0], self.d)}", f"Q{plain(ctrl[3] - end[1], self.d)}"]
        self.pos[0], self.pos[1] = plain(end[0], self.d), plain(end[1], self.d)
        self._emit(words)


def _run_points(start: list[float], run: list[_Block]) -> list[list[float]]:
    """The positions a run of moves passes through: ``start``, then the end of each
    block (axes a block does not name keep their value)."""
    pts = [list(start)]
    for b in run:
        p = list(pts[-1])
        for a in "XYZ":
            if a in b.words:
                p["XYZ".index(a)] = b.words[a]
        pts.append(p)
    return pts


def _fit_run(st: _State, run: list[_Block], tol: float, mode: str,
             min_radius: float) -> "_Emitter | None":
    """The emitter holding a run's rewritten blocks (None: keep the run as written).
    ``st``: the state before the run, its motion mode the one the output is in."""
    base = int(default("decimals", "inch" if st.units != "mm" else "mm"))
    d = base
    for b in run:
        for a in "XYZ":
            if a in b.text:
                d = max(d, _decimals(b.text[a]))
    d = min(d, 6)
    pts = _run_points(st.pos, run)
    s = FitSettings("inch" if st.units != "mm" else "mm", tol, mode, min_radius, decimals=d)
    P, idx, kinds, ends, par = fit_points(np.array(pts, dtype=float), s)
    if len(kinds) >= len(run):
        return None
    em = _Emitter(st, d)
    em.feed = f" F{run[0].text['F']}" if "F" in run[0].text else ""
    prev = 0
    for k, e, p in zip(kinds.tolist(), ends.tolist(), par):
        start, end = P[prev], P[e]
        if k == 0 and e == prev + 1 and idx[e] == idx[prev] + 1:
            em.verbatim(run[idx[e] - 1], end)
        elif k == 0:
            em.line(end)
        elif k == 1:
            em.arc(start, end, PLANE_NAMES[int(p[0])], float(p[1]), float(p[2]),
                   bool(p[3] > 0.5))
        else:
            em.cubic(start, end, p[:4])
        prev = e
    em.finish()
    return em


def fit_program(text: str, tolerance: float, mode: str = "arcs", *,
                min_radius: float = 0.0, file: str | None = None,
                stats: FitStats | None = None) -> str:
    """Return ``text`` with its runs of ``G1`` moves replaced by arcs (and ``G5``
    cubics with ``mode="arcs+cubics"``) within ``tolerance`` (program units).

    No arc gets a radius at or below ``min_radius`` (program units; give the largest
    tool radius so that concave arcs stay larger than the tool). Lines that are not
    rewritten are copied exactly. ``file`` names the program in error messages;
    ``stats``, when given, is filled with what was and was not fitted (:class:`FitStats`).
    """
    fs = stats if stats is not None else FitStats()
    try:
        if not (min_radius >= 0.0 and math.isfinite(min_radius)):
            raise ValueError(f"min radius must be a length >= 0, not {min_radius!r}")
        FitSettings("mm", tolerance, mode, min_radius)
    except ValueError as e:
        raise MillpathError(str(e), file) from None
    src = text.splitlines()
    blocks = [_Block(l) for l in src]
    st = _State()
    out: list[str] = []
    out_motion: float | None = None      # output's motion mode where it differs from st's
    i = 0
    n = len(blocks)
    while i < n:
        b = blocks[i]
        if st.known() and _fittable(st, b):
            feed = b.words.get("F", st.feed)
            start_state = _State()
            start_state.__dict__.update(st.__dict__)
            start_state.pos = list(st.pos)
            j = i
            while j < n and _fittable(st, blocks[j]) and blocks[j].words.get("F", feed) == feed:
                _apply(st, blocks[j])
                j += 1
            run = blocks[i:j]
            if out_motion is not None:
                start_state.motion = out_motion
            em = (_fit_run(start_state, run, tolerance, mode, min_radius) if len(run) >= 2
                  else None)
            fs.moves += len(run)
            if len(run) < 2:
                fs.skip("single moves between other blocks")
            elif em is None:
                fs.kept += len(run)
                fs._sags.append(_merge_sag(_run_points(start_state.pos, run)))
            else:
                fs.rewritten += len(run)
            if em is None:
                if out_motion is not None and not run[0].g:
                    out.append(with_code("G1", run[0].raw))
                    out.extend(rb.raw for rb in run[1:])
                else:
                    out.extend(rb.raw for rb in run)
                out_motion = None
            else:
                out.extend(em.lines)
                if em.plane != st.plane:
                    out.append(_PLANE_CODE[st.plane])
                out_motion = em.motion if em.motion != st.motion else None
            i = j
            continue
        why = _why_not(st, b)
        if why is not None:
            fs.moves += 1
            fs.skip(why)
        if out_motion is not None:
            # the output is still in the G2/G3/G5 mode of the last rewritten run
            if any(g in _MOTION_G for g in b.g):
                out_motion = None
            elif b.opaque:
                out.append("G1")
                out_motion = None
            elif any(a in b.words for a in "XYZABCUVW"):
                out.append(with_code("G1", b.raw))
                out_motion = None
                _apply(st, b)
                i += 1
                continue
        out.append(b.raw)
        _apply(st, b)
        i += 1
    if fs._sags:
        fs.merge_min, fs.merge_max = min(fs._sags), max(fs._sags)
    nl = "\r\n" if "\r\n" in text else "\n"
    return nl.join(out) + (nl if text.endswith("\n") else "")

