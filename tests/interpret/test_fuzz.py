"""Bad input never crashes: random and mutated programs give motion or a clean
InterpreterError, never another exception, and never infinite or NaN coordinates.

Seeds are fixed (``derandomize``); the loop limits lowered for speed are restored after
each example. Numbers include huge, tiny and non-finite spellings and expressions that
overflow."""

from __future__ import annotations

import contextlib
import math
import os

from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import millpath.interpret.cycles as cycles
import millpath.interpret.oword as oword

from millpath.interpret import InterpreterError, interpret
from millpath.io.tooltable import ToolEntry

TOOLS = [ToolEntry(1, 1, 0.25, {"Z": 1.0}), ToolEntry(2, 2, -0.1, {"Z": 0.5}),
         ToolEntry(3, 3, 0.0, {})]

SEEDS = [
    "G21 F100\nG0 X-10 Y-10 Z5\nT1 M6 G43\nG41 D1\nG1 X0 Y0\nG1 Z-1\nG1 X20\nG3 X20 Y20 R10\n"
    "G1 X0 Y20\nG2 X0 Y0 I0 J-10\nG40 G1 X-10 Y-10\nM2\n",
    "G20 F10\nG0 X0 Y0 Z1\nG98 G81 X1 Y1 Z-0.5 R0.1\nX2\nG99 G83 X3 Z-1 R0.2 Q0.3\nG73 X4 "
    "Z-1 R0.2 Q0.2 L2\nG85 X5 Z-1 R.1\nG89 X6 Z-1 R.1 P1\nG80\nM2\n",
    "G21 F100\n#1=2 #<a>=[#1*3]\nG18 G2 X1 Z1 I0.5 K0.5\nG19 G3 Y1 Z0 J0.5 K-0.5\nG17 G5 X2 "
    "Y2 I1 J0 P0 Q1\nG10 L2 P2 X1\nG55 G92 X0\nG91 G1 X[sin[#<a>]] Y1\nG90 G53 G0 X0\nM30\n",
    "G21 F10\n#1=0\no1 while [#1 lt 3]\n#1=[#1+1]\no2 if [#1 eq 2]\nG1 X#1\no2 else\n"
    "G1 Y#1\no2 endif\no1 endwhile\no<s> sub\nG0 Z#1\no<s> endsub [2]\no<s> call [5]\nM2\n",
    "%\nG21 F100 S1000 M3 M8\nG42.1 D4\nG1 X10 Y0\nG1 Y10\nG2 X0 Y10 R5\nG40 G0 X-5\nG4 P1\n%\n",
]

FUZZ = int(os.environ.get("MILLPATH_FUZZ_EXAMPLES", "400"))
ALPHABET = "GMXYZIJKRPQFSTDHLNOABCUVWE0123456789.-+[]#=<>() ;/%*@^$\n\t" + "abcdefgmnoqrstxyz"


@contextlib.contextmanager
def small_limits():
    """Lower the endless-loop and cycle limits for one example, then restore them."""
    saved = (oword.MAX_IDLE_ITERATIONS, oword.MAX_LOOP_ITERATIONS, cycles.MAX_CYCLE_STEPS)
    oword.MAX_IDLE_ITERATIONS, oword.MAX_LOOP_ITERATIONS = 2_000, 20_000
    cycles.MAX_CYCLE_STEPS = 20_000
    try:
        yield
    finally:
        oword.MAX_IDLE_ITERATIONS, oword.MAX_LOOP_ITERATIONS, cycles.MAX_CYCLE_STEPS = saved


def check(program: str) -> None:
    with small_limits():
        try:
            ms = interpret(program, TOOLS)
        except InterpreterError as e:
            assert isinstance(e.line, int) and e.line >= 1
            assert isinstance(e.message, str) and e.message and "\n" not in e.message
            ms = e.motions
    a = ms.arrays()
    for key in ("start", "end", "center", "feed"):
        assert all(math.isfinite(v) for v in a[key].ravel()), key
    for m in ms:
        assert m.kind in ("traverse", "feed", "arc", "cubic", "dwell")
        assert len(m.end) == 3 and len(m.start) == 3


def test_limits_are_restored():
    before = (oword.MAX_IDLE_ITERATIONS, oword.MAX_LOOP_ITERATIONS, cycles.MAX_CYCLE_STEPS)
    check("G21\no1 while [1]\no1 endwhile\nM2\n")
    assert (oword.MAX_IDLE_ITERATIONS, oword.MAX_LOOP_ITERATIONS,
            cycles.MAX_CYCLE_STEPS) == before


@settings(max_examples=FUZZ, deadline=None, derandomize=True,
          suppress_health_check=[HealthCheck.too_slow])
@given(st.text(alphabet=ALPHABET, max_size=200))
def test_random_text(text):
    check(text)


HUGE = st.one_of(
    st.integers(10, 400).map(lambda n: "9" * n),                   # up to 1e400 as digits
    st.integers(-400, 400).map(lambda e: f"[10**{e}]"),
    st.integers(0, 2000).map(lambda e: f"[EXP[{e}]]"),
    st.integers(1, 320).map(lambda n: f"[{'9' * n}*{'9' * n}]"),
    st.sampled_from(["[1/0]", "[0/0]", "[1 MOD 0]", "[-2**2001]", "[0**-1]", "[LN[0]]",
                     "[SQRT[-1]]", "[ACOS[2]]", "[TAN[90]]", "[SIN[" + "9" * 300 + "]]",
                     "[COS[[10**300]]]", "[ATAN[1]/[0]]", "[FIX[[10**308]]]",
                     "[ROUND[-[10**308]]]", "#[10**300]", "#-1", "#5401", "inf", "nan",
                     "1e400", "-1e-400", "[" * 130 + "1" + "]" * 130]))
NUM = st.one_of(st.integers(-1000, 1000).map(str),
                st.floats(allow_nan=False, allow_infinity=False, width=32).map(
                    lambda v: f"{v:.6f}"),
                st.floats(allow_nan=False, allow_infinity=False).map(lambda v: f"{v:.20f}"),
                HUGE,
                st.sampled_from(["0", "-0", ".5", "1.", "1e5", "[1/3]", "#1", "#<x>", "[2**40]",
                                 "[-1]", "[1e308]", "99999999999999999999999", "sqrt[-1]"]))
WORD = st.tuples(st.sampled_from(list("GMXYZIJKRPQFSTDHL")), NUM).map(lambda t: t[0] + t[1])
GWORD = st.sampled_from(["G0", "G1", "G2", "G3", "G4", "G5", "G5.1", "G10 L2 P1", "G10 L20 P2",
                         "G17", "G18", "G19", "G20", "G21", "G28", "G30", "G40", "G41", "G42",
                         "G41.1", "G42.1", "G43", "G43.1", "G49", "G53", "G54", "G55", "G73",
                         "G80", "G81", "G82", "G83", "G85", "G89", "G90", "G91", "G90.1",
                         "G91.1", "G92", "G92.1", "G92.2", "G92.3", "G93", "G94", "G98", "G99",
                         "M2", "M3", "M5", "M6", "T1", "T2", "D1", "D2", "D3", "H1"])
# words whose value becomes a count (turns, repeats, pecks, loop iterations)
COUNTED = st.tuples(st.sampled_from(["G2 X1 I1 P", "G81 Z-1 R1 L", "G83 Z-1 R1 Q",
                                     "G73 Z-1 R[10**200] Q", "G64 P", "G4 P", "G10 L2 P1 R",
                                     "o1 repeat [", "o1 while [", "o<s> call [", "o1 if ["]),
                    NUM).map(lambda t: t[0] + t[1] + ("]" if t[0].endswith("[") else ""))
FLOW = st.sampled_from(["o1 endrepeat", "o1 endwhile", "o1 endif", "o<s> sub", "o<s> endsub",
                        "o1 do", "o1 continue", "o1 break"])
BLOCK = st.one_of(st.lists(st.one_of(WORD, GWORD), min_size=0, max_size=6).map(" ".join),
                  COUNTED, FLOW)


@settings(max_examples=FUZZ, deadline=None, derandomize=True,
          suppress_health_check=[HealthCheck.too_slow])
@given(st.lists(BLOCK, max_size=25))
def test_random_blocks(blocks):
    check("G21 F100\n" + "\n".join(blocks) + "\nM2\n")


@settings(max_examples=FUZZ, deadline=None, derandomize=True,
          suppress_health_check=[HealthCheck.too_slow])
@given(st.sampled_from(SEEDS), st.lists(st.tuples(st.integers(0, 10**6), st.integers(0, 3),
                                                  st.text(alphabet=ALPHABET, max_size=4)),
                                        min_size=1, max_size=6))
def test_mutated_programs(seed, edits):
    text = seed
    for pos, op, s in edits:
        i = pos % (len(text) + 1)
        if op == 0:
            text = text[:i] + text[i + 1:]
        elif op == 1:
            text = text[:i] + s + text[i:]
        elif op == 2:
            text = text[:i] + s + text[i + len(s):]
        else:
            lines = text.split("\n")
            j = pos % len(lines)
            lines.insert((pos // 7) % len(lines), lines[j])
            text = "\n".join(lines)
    check(text)


def test_seeds_run_cleanly():
    for s in SEEDS:
        ms = interpret(s, TOOLS)
        assert len(ms) > 0
        assert all(math.isfinite(v) for m in ms for v in m.end)
