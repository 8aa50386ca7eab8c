"""Fast path for the commonest block shapes:
``[N..] [G0-3] [X] [Y] [Z] [I] [J] [K] [R] [F] [(comment) | ;comment]``.

A regular expression recognizes such a line (plain numbers, no parameters or
expressions; one tried first for the words in this order, a second for any order and
case) and hands its values straight to the machine's motion code,
skipping the general reader and the block checks, which cannot fail for these words
when the motion is G0-G3. Any other line goes to the general reader, so behaviour and
errors are the same either way; only the time differs.
"""

from __future__ import annotations

import re

from millpath.interpret.compfast import comp_run
from millpath.interpret.cycles import CYCLES
from millpath.interpret.errors import GCodeError
from millpath.interpret.arcs import (RADIUS_TOLERANCE, SPIRAL_TOLERANCE, arc_center_r,
                                     check_arc)
from millpath.gcode.lexer import Block
from millpath.interpret.store import PACK, PLANE_CODE

# at most nine digits before the point: a larger number (over the reader's MAX_COORDINATE
# bound) goes to the general reader, which refuses it
_NUM = r"([-+]?+(?:\d{1,9}+(?!\d)\.?+\d*+|\.\d++))"
# possessive quantifiers (Python 3.11) keep the regex engine from backtracking
_FAST = re.compile(r"[ \t]*+(?:[Nn][ \t]*+\d++(?:\.\d*+)?+[ \t]*+)?+"
                   r"(?:[Gg]0*([0-3])(?![\d.])[ \t]*+)?+"
                   + "".join(rf"(?:[{u}{u.lower()}][ \t]*+{_NUM}[ \t]*+)?+" for u in "XYZIJKRF")
                   + r"(?:\([^()]*+\)[ \t]*+|;.*+)?+\r?")
# The same words in any order and case (``G`` with spaces before its digits too): each
# alternative refuses a second word of its letter later on the line (before a comment),
# so a duplicate goes to the general reader, which reports it. Groups come out in the
# order of ``_FAST``'s.
_W = r"[ \t]*+"
_FREE = re.compile(
    rf"{_W}(?:[Nn]{_W}\d++(?:\.\d*+)?+{_W})?+(?:(?:"
    + "|".join([rf"[Gg]{_W}0*+([0-3])(?![\d.])(?![^(;]*[Gg])"]
               + [rf"[{u}{u.lower()}]{_W}{_NUM}(?![^(;]*[{u}{u.lower()}])" for u in "XYZIJKRF"])
    + rf"){_W})*+(?:\([^()]*+\){_W}|;.*+)?+\r?")
# ``_FREE`` without its look-aheads (each scans the rest of the line: more than half
# the time of a match): a duplicate is found by counting letters instead (match_free)
_FREE_WORDS = re.compile(
    rf"{_W}(?:[Nn]{_W}\d++(?:\.\d*+)?+{_W})?+(?:(?:"
    + "|".join([rf"[Gg]{_W}0*+([0-3])(?![\d.])"]
               + [rf"[{u}{u.lower()}]{_W}{_NUM}" for u in "XYZIJKRF"])
    + rf"){_W})*+(?:\([^()]*+\){_W}|;.*+)?+\r?")
#: all a line matched by ``_FREE_WORDS`` without a comment may hold but word letters
_NOT_WORD_LETTERS = b"0123456789.+- \t\rNn"
_LETTERS = "xyzijkrf"
#: G40, G41/G42 with an optional whole D word, then the rest of the line (a simple move)
_COMP_SWITCH = re.compile(r"[ \t]*+[Gg]0*4([012])(?![\d.])[ \t]*+"
                          r"(?:[Dd][ \t]*+(\d++)(?![\d.])[ \t]*+)?+(.*+)")


def match_free(line: str):
    """``_FREE.fullmatch(line)``, sooner: the words in any order without the look-aheads,
    then, on an ASCII line without a comment, as many word letters as words found (a
    letter given twice leaves fewer words than letters); other lines go to ``_FREE``."""
    mt = _FREE_WORDS.fullmatch(line)
    if mt is None:
        return None
    if "(" in line or ";" in line or not line.isascii():
        return _FREE.fullmatch(line)
    if len(line.encode().translate(None, _NOT_WORD_LETTERS)) != 9 - mt.groups().count(None):
        return None                # a word twice: the general reader reports it
    return mt


def match_simple(line: str):
    """Regex match of a simple motion line (words G0-G3 X Y Z I J K R F, plain numbers,
    any order and case), or None; ``groups()`` are (g, x, y, z, i, j, k, r, f)."""
    return _FAST.fullmatch(line) or match_free(line)


class FastPath:
    """Executes simple motion lines directly on ``machine``."""

    def __init__(self, machine) -> None:
        self.m = machine
        self.match = match_simple
        self.sampled = None
        self.first, self.second = _FAST.fullmatch, match_free
        self.blk = Block(0, "")
        self.k = 0

    def order(self, lines: list[str]):
        """The two regexes, the one most of ``lines`` match in full tried first (from a
        sample of 200 lines; both accept every line of the ordered shape)."""
        if self.sampled is not lines:
            self.sampled = lines
            step = max(len(lines) // 200, 1)
            sample = lines[::step]
            hits = sum(1 for s in sample if _FAST.fullmatch(s))
            if hits >= 0.7 * len(sample):
                self.first, self.second = _FAST.fullmatch, match_free
            else:
                self.first, self.second = match_free, _FAST.fullmatch
        return self.first, self.second

    def run(self, lines: list[str], k: int, base: int = 0, stop: int | None = None) -> int:
        """Execute ``lines[k:]`` (line ``k`` is source line ``base + k + 1``) while they
        have the simple shape; return the index of the first line the general reader must
        handle (or ``len(lines)``)."""
        match = self.match
        m = self.m
        one = self.groups
        end_k = len(lines) if stop is None else stop
        try:
            return self._loop(lines, k, end_k, match, m, one, base)
        except GCodeError as e:
            e.line = base + self.k + 1
            raise

    def comp_end(self, f, x, y, z) -> list:
        """Before a compensated move (the machine's position and feed are current): set
        the line's F word, if any; return the programmed end point (X Y Z words, the
        others from the programmed position)."""
        m = self.m
        if f is not None:
            m.feed_rate = float(f)
        prog = m.comp.prog
        return [prog[0] if x is None else float(x), prog[1] if y is None else float(y),
                prog[2] if z is None else float(z)]

    def comp_move(self, buf: list, k: int, move, *args) -> tuple:
        """Call the machine's compensated ``move(*args)`` for line index ``k``; on an
        error drop what it stored and re-raise. Returns the new (current, output)
        position as six numbers."""
        self.k = k
        mark = len(buf)
        try:
            move(*args)
        except GCodeError:
            del buf[mark:]
            raise
        c, o = self.m.cur, self.m.out
        return c[0], c[1], c[2], o[0], o[1], o[2]

    def _loop(self, lines, k, end_k, match, m, one, base) -> int:
        buf = m.store.buf
        pack = PACK
        # Machine state lives in locals inside the loop; it is written back before any
        # call into the machine (``one``) and on leaving, and read again after. Arcs
        # outside G17 go through the machine's own code.
        comp_line = comp_arcs = False

        def load():
            simple = (not m.comp.side and m.dist_abs and m.feed_mode == 0)
            arcs_ok = (simple and not m.ijk_abs and not m.comp.arc_not_allowed
                       and m.plane == "XY")
            units = m.units
            c, o = m.cur, m.out
            nonlocal comp_line, comp_arcs
            comp_line = (m.comp.side and m.comp.radius > 0.0 and not m.comp.first
                         and m.dist_abs and m.feed_mode == 0)
            comp_arcs = (comp_line and m.plane == "XY" and not m.ijk_abs
                         and not m.comp.arc_not_allowed)
            return (c[0], c[1], c[2], o[0], o[1], o[2], m.feed_rate, m.motion_mode, simple,
                    arcs_ok, PLANE_CODE[m.plane], m.state_index, RADIUS_TOLERANCE[units],
                    SPIRAL_TOLERANCE[units], units)

        (cx, cy, cz, ox, oy, oz, feed, mode, simple, arcs_ok, pcode, state, rtol,
         stol, units) = load()
        moved = False
        straight = False
        try:
            first, second = self.order(lines)
            while k < end_k:
                if comp_line:
                    # compensated G0-G3 in G17: a run of them with the state in locals
                    k2 = comp_run(m, lines, k, end_k, first, second, base)
                    if k2 != k:
                        k = k2
                        (cx, cy, cz, ox, oy, oz, feed, mode, simple, arcs_ok, pcode, state,
                         rtol, stol, units) = load()
                        continue
                line = lines[k]
                mt = first(line)
                if mt is None:
                    mt = second(line)
                    if mt is None:
                        sw = _COMP_SWITCH.fullmatch(line)
                        if sw is None:
                            return k
                        # G40 / G41 Dn / G42 Dn, G40 with a G0/G1 move: the machine's own
                        # executors, without the general reader
                        self.put_back(cx, cy, cz, ox, oy, oz, feed, mode, moved, straight)
                        moved = straight = False
                        self.k = k
                        ok = self.comp_switch(sw, base + k + 1)
                        (cx, cy, cz, ox, oy, oz, feed, mode, simple, arcs_ok, pcode, state,
                         rtol, stol, units) = load()
                        if not ok:
                            return k
                        k += 1
                        continue
                g, x, y, z, i, j, kk, r, f = mt.groups()
                if g is None:
                    code = mode if (x is not None or y is not None or z is not None) else -1
                else:
                    code = (ord(g) - 48) * 10
                if (comp_line and code in (0, 10) and i is None and j is None and kk is None
                        and r is None and (f is None or f[0] != "-")):
                    # G0/G1 with compensation on (not the entry move): comp.straight2.
                    # With compensation on, every line goes through the machine, so its
                    # position and feed are the locals' already.
                    end = self.comp_end(f, x, y, z)
                    if code == 10 and m.feed_rate == 0.0:
                        return k
                    m.motion_mode = code
                    m.comp.arc_not_allowed = False
                    m.cycles.il_flag = False
                    # comp.straight2 changes only the position (and the feed set above)
                    cx, cy, cz, ox, oy, oz = self.comp_move(
                        buf, k, m.comp.straight2, code, base + k + 1, end,
                        m.feed_rate if code == 10 else 0.0)
                    feed, mode = m.feed_rate, code
                    k += 1
                    continue
                if (comp_arcs and code >= 20 and kk is None and (f is None or f[0] != "-")
                        and ((r is None) != (i is None and j is None))
                        and (r is None or x is not None or y is not None)):
                    # G2/G3 in G17 with compensation on (not the entry move): comp.arc2
                    end = self.comp_end(f, x, y, z)
                    if m.feed_rate == 0.0:
                        return k
                    m.motion_mode = code
                    m.cycles.il_flag = False
                    cx, cy, cz, ox, oy, oz = self.comp_move(
                        buf, k, m.comp.arc2, code, base + k + 1,
                        None if r is None else float(r), end,
                        0.0 if i is None else float(i), 0.0 if j is None else float(j),
                        -1 if code == 20 else 1, m.feed_rate)
                    feed, mode = m.feed_rate, code
                    k += 1
                    continue
                if (not simple or code < 0 or code > 30
                        or (code >= 20 and not arcs_ok)):
                    self.put_back(cx, cy, cz, ox, oy, oz, feed, mode, moved, straight)
                    moved = straight = False
                    self.k = k
                    ok = one(g, x, y, z, i, j, kk, r, f, base + k + 1)
                    (cx, cy, cz, ox, oy, oz, feed, mode, simple, arcs_ok, pcode, state, rtol,
                     stol, units) = load()
                    if not ok:
                        return k
                    k += 1
                    continue
                if f is not None:
                    if f[0] == "-":
                        return k
                    feed = float(f)
                ex = cx if x is None else float(x)
                ey = cy if y is None else float(y)
                ez = cz if z is None else float(z)
                if code <= 10:
                    # G0/G1 without compensation: LinuxCNC's convert_straight, inlined
                    if i is not None or j is not None or kk is not None or r is not None:
                        return k
                    if code == 10:
                        if feed == 0.0:
                            return k
                        buf += pack(ox, oy, oz, ex, ey, ez, feed, 0.0, 0.0, 0.0,
                                    1, base + k + 1, 0, pcode, state)
                    else:
                        buf += pack(ox, oy, oz, ex, ey, ez, 0.0, 0.0, 0.0, 0.0,
                                    0, base + k + 1, 0, pcode, state)
                    straight = True
                else:
                    if r is not None:
                        # G2/G3 in G17 with R: convert_arc2 with arc_center_r
                        if (kk is not None or i is not None or j is not None or feed == 0.0
                                or (x is None and y is None)):
                            return k
                        self.k = k                      # the line of an error
                        c1, c2 = arc_center_r(code == 20, units, cx, cy, ex, ey, float(r))
                    else:
                        # G2/G3 in G17 with incremental I/J: convert_arc2, inlined
                        if kk is not None or (i is None and j is None) or feed == 0.0:
                            return k
                        c1 = cx if i is None else cx + float(i)
                        c2 = cy if j is None else cy + float(j)
                        try:
                            check_arc("XY", cx, cy, c1, c2, ex, ey, rtol, stol)
                        except GCodeError:
                            return k                    # the machine's error
                    buf += pack(ox, oy, oz, ex, ey, ez, feed, c1, c2, cz,
                                2, base + k + 1, -1 if code == 20 else 1, pcode, state)
                ox = cx = ex
                oy = cy = ey
                oz = cz = ez
                mode = code
                moved = True
                k += 1
            return k
        finally:
            self.put_back(cx, cy, cz, ox, oy, oz, feed, mode, moved, straight)

    def put_back(self, cx: float, cy: float, cz: float, ox: float, oy: float, oz: float,
                 feed: float, mode: int, moved: bool, straight: bool) -> None:
        """Write the loop's locals back to the machine: position, output point, feed,
        motion mode, and the flags a move (``moved``) or a straight move clears."""
        m = self.m
        m.cur, m.out = [cx, cy, cz], [ox, oy, oz]
        m.feed_rate, m.motion_mode = feed, mode
        if moved:
            m.cycles.il_flag = False
        if straight:
            m.comp.arc_not_allowed = False

    def comp_switch(self, sw, n: int) -> bool:
        """Execute a line matched by ``_COMP_SWITCH`` (G40, G41/G42 with an optional
        whole D, or G40 followed by a simple G0/G1 move) as the general path would:
        compensation switched, then the move; on an error, nothing of the line is kept.
        False (nothing done) to use the general reader."""
        m = self.m
        code = 400 + 10 * int(sw.group(1))
        d, rest = sw.group(2), sw.group(3)
        mt = None
        if rest:
            if code != 400 or d is not None:
                return False
            mt = self.match(rest)
            if mt is None:
                return False
            g, x, y, z, i, j, k, r, f = mt.groups()
            if (g not in ("0", "1") or i is not None or j is not None or k is not None
                    or r is not None or (f is not None and f[0] == "-")):
                return False
        elif code == 400 and d is not None:
            return False                      # D with G40: the reader's error
        store = m.store
        mark = len(store)
        try:
            m.comp.on_off(code, {} if d is None else {"d": float(d)})
            if mt is not None:
                self.groups(g, x, y, z, i, j, k, r, f, n)
        except GCodeError:
            store.truncate(mark)
            raise
        return True

    def try_line(self, raw: str, n: int) -> bool:
        """Execute ``raw`` if it has the simple shape; False to use the general reader."""
        mt = self.match(raw)
        if mt is None:
            return False
        return self.groups(*mt.groups(), n)

    def cycle_line(self, code: int, x, y, z, r, f, n: int) -> bool:
        """A line of modal X Y Z R (F) words under canned cycle ``code``."""
        if f is not None and f[0] == "-":
            return False
        return self.motion_words(code, (x, y, z, None, None, None, r), f, n)

    def motion_words(self, code: int, values: tuple, f, n: int) -> bool:
        """Set the line's F word, then run motion ``code`` on the words ``values``
        (X Y Z I J K R, None when absent), as the general path would."""
        m = self.m
        w = {c: float(v) for c, v in zip("xyzijkr", values) if v is not None}
        if f is not None:
            fv = float(f)
            w["f"] = fv
            if m.feed_mode != 1:
                m.feed_rate = fv
        blk = self.blk
        blk.line = n
        blk.words = w
        store = m.store
        mark = len(store)
        try:
            m.motion(code, blk)
        except GCodeError:
            store.truncate(mark)
            raise
        return True

    def groups(self, g, x, y, z, i, j, k, r, f, n: int) -> bool:
        """Execute a simple line from its regex groups; False to use the general reader."""
        m = self.m
        if g is not None:
            code = int(g) * 10
        elif x is None and y is None and z is None:
            if i is not None or j is not None or k is not None or r is not None:
                return False
            if f is not None:
                if f[0] == "-":
                    return False
                if m.feed_mode != 1:
                    m.feed_rate = float(f)
            return True                       # empty line or a lone F word
        else:
            code = m.motion_mode
            if code not in (0, 10, 20, 30):
                if code not in CYCLES or i is not None or j is not None or k is not None:
                    return False
                # X Y Z R of a canned cycle in force: the block's checks cannot fail for
                # these words, so only the motion remains (the cycle's own errors)
                return self.cycle_line(code, x, y, z, r, f, n)
        if code < 20 and (i is not None or j is not None or k is not None or r is not None):
            return False
        if f is not None and f[0] == "-":
            return False
        if code < 20 and m.dist_abs and not (m.comp.side and m.comp.radius > 0.0) and (
                code == 0 or m.feed_mode == 0):
            # straight move without compensation: LinuxCNC's convert_straight, inlined
            if f is not None:
                m.feed_rate = float(f)
            if code == 10 and m.feed_rate == 0.0:
                return False                  # the general path raises the error
            cur = m.cur
            end = [cur[0] if x is None else float(x), cur[1] if y is None else float(y),
                   cur[2] if z is None else float(z)]
            o = m.out
            store = m.store
            feed = m.feed_rate if code == 10 else 0.0
            store.buf += PACK(o[0], o[1], o[2], end[0], end[1], end[2], feed, 0.0, 0.0, 0.0,
                              1 if code == 10 else 0, n, 0, PLANE_CODE[m.plane], m.state_index)
            m.out = end
            m.cur = end
            m.motion_mode = code
            m.comp.arc_not_allowed = False
            m.cycles.il_flag = False
            return True
        if code >= 20 and m.dist_abs and not m.comp.side and m.feed_mode == 0 \
                and not m.ijk_abs and not m.comp.arc_not_allowed and r is None:
            # arc with incremental I/J/K and no compensation: convert_arc2, inlined
            if f is not None:
                m.feed_rate = float(f)
            plane = m.plane
            if plane == "XY":
                o1, o2, bad = i, j, k
            elif plane == "XZ":
                o1, o2, bad = k, i, j
            else:
                o1, o2, bad = j, k, i
            if bad is not None or (o1 is None and o2 is None) or m.feed_rate == 0.0:
                return False
            cur = m.cur
            end = [cur[0] if x is None else float(x), cur[1] if y is None else float(y),
                   cur[2] if z is None else float(z)]
            a1, a2, an = m.axes
            s1, s2 = cur[a1], cur[a2]
            c1 = s1 + (0.0 if o1 is None else float(o1))
            c2 = s2 + (0.0 if o2 is None else float(o2))
            try:
                check_arc(plane, s1, s2, c1, c2, end[a1], end[a2], RADIUS_TOLERANCE[m.units],
                          SPIRAL_TOLERANCE[m.units])
            except GCodeError:
                return False                  # the general path raises the error
            center = [0.0, 0.0, 0.0]
            center[a1] = c1
            center[a2] = c2
            center[an] = cur[an]
            o = m.out
            store = m.store
            store.buf += PACK(o[0], o[1], o[2], end[0], end[1], end[2], m.feed_rate,
                              center[0], center[1], center[2], 2, n, -1 if code == 20 else 1,
                              PLANE_CODE[plane], m.state_index)
            m.out = end
            m.cur = end
            m.motion_mode = code
            m.cycles.il_flag = False
            return True
        # the words the motion reads: X Y Z, and I J K R for arcs
        values = (x, y, z, i, j, k, r) if code >= 20 else (x, y, z, None, None, None, None)
        return self.motion_words(code, values, f, n)
