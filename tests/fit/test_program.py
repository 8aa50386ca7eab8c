"""fit_program: rewrite G1 runs of a program text, leave every other line as written."""

from __future__ import annotations

import math

import pytest

from millpath.errors import MillpathError
from millpath.fit import fit_program


def circle_blocks(r=10.0, n=120, z=None, fmt="{:.4f}", sweep=2 * math.pi, first_g1=True,
                  plane="XY", feed=None):
    out = []
    for k in range(1, n + 1):
        a = sweep * k / n
        u, v = fmt.format(r * math.cos(a)), fmt.format(r * math.sin(a))
        if plane == "XY":
            words = f"X{u} Y{v}" + (f" Z{z}" if z is not None else "")
        else:                                   # XZ profile: X = r cos, Z = r sin
            words = f"X{u} Z{v}"
        if k == 1 and first_g1:
            words = "G1 " + words + (f" F{feed}" if feed else "")
        out.append(words)
    return out


HEAD = ["%", "(a test program)", "G21 G90 G17 G94", "T1 M6", "G43 H1", "S8000 M3"]


def program(*parts):
    return "\n".join(HEAD + [l for p in parts for l in p] + ["G0 Z5", "M2", "%"]) + "\n"


def test_other_lines_are_copied_exactly_and_runs_shrink():
    src = program(["G0 X10 Y0 Z2", "G1 Z-1 F200"], circle_blocks(), ["G0 Z5 (lift)"])
    out = fit_program(src, 0.005)
    lines = out.splitlines()
    assert lines[:len(HEAD)] == HEAD
    assert "G0 X10 Y0 Z2" in lines and "G1 Z-1 F200" in lines and "G0 Z5 (lift)" in lines
    assert lines[-3:] == ["G0 Z5", "M2", "%"]
    assert len(lines) < len(src.splitlines()) - 100
    assert any(l.startswith("G3 ") for l in lines)


def test_incremental_compensated_and_commented_runs_are_kept():
    inc = ["G91"] + [f"G1 X{0.1 * math.cos(k / 10):.4f} Y{0.1 * math.sin(k / 10):.4f}"
                     for k in range(60)] + ["G90"]
    comp = ["G41 D1", "G1 X10 Y0"] + circle_blocks(first_g1=False) + ["G40", "G1 X12 Y0"]
    dyn = ["G42.1 D6", "G1 X10 Y0"] + circle_blocks(first_g1=False) + ["G40", "G1 X12 Y0"]
    lathe = ["G7", "G1 X10 Y0"] + circle_blocks(first_g1=False) + ["G8", "G1 X12 Y0"]
    commented = [f"X{10 * math.cos(k / 20):.4f} Y{10 * math.sin(k / 20):.4f} (pt {k})"
                 for k in range(40)]
    src = program(["G0 X10 Y0 Z2", "G1 Z-1 F200"], inc, comp, dyn, lathe, commented)
    assert fit_program(src, 0.01) == src


def test_unknown_position_is_never_used_as_a_start():
    # after an expression, a G92 or a G28 the start of the next G1 is not known
    for barrier in ["#1=3", "G92 X0 Y0", "G28", "G1 X[10*cos[0]] Y0", "o100 if [1]"]:
        src = program(["G0 X10 Y0 Z2", "G1 Z-1 F200", barrier], circle_blocks(first_g1=False))
        out = fit_program(src, 0.005).splitlines()
        k = out.index(barrier)
        assert out[k + 1] == circle_blocks(first_g1=False)[0]


def test_vertical_profile_gets_g18_and_the_plane_and_g1_come_back():
    src = program(["G0 X10 Y0 Z2", "G1 Z0 F200"], circle_blocks(plane="XZ", n=90,
                                                                sweep=math.pi,
                                                                first_g1=False),
                  ["X-12 Z0 A1"])
    out = fit_program(src, 0.005)
    lines = out.splitlines()
    assert any(l.startswith("G18 G3") or l.startswith("G18 G2") for l in lines)
    # the block after the run relied on G17 and G1: the plane comes back on a line of
    # its own (no motion), G1 as a prefix of the block (no zero-length move)
    k = lines.index("G1 X-12 Z0 A1")
    assert lines[k - 1] == "G17"


def test_g1_restore_is_left_out_when_the_next_block_sets_motion():
    # (and no lone G1 block: rs274 turns those into zero-length feeds)
    src = program(["G0 X10 Y0 Z2", "G1 Z-1 F200"], circle_blocks())
    lines = fit_program(src, 0.005).splitlines()
    k = lines.index("G0 Z5")
    assert lines[k - 1].startswith("X") or lines[k - 1].startswith("G3")


def test_numbers_keep_the_programs_precision():
    src = program(["G0 X10 Y0 Z2", "G1 Z-1 F200"], circle_blocks(fmt="{:.6f}", n=720))
    out = fit_program(src, 0.0005)
    arcs = [l for l in out.splitlines() if l.startswith(("G2", "G3"))]
    assert arcs
    assert max(len(w.split(".")[1]) for l in arcs for w in l.split() if "." in w) == 6


def test_inch_program_uses_five_decimals():
    src = ("G20 G90 G17\nG0 X0.5 Y0 Z0.1\nG1 Z-0.05 F20\n"
           + "\n".join(circle_blocks(r=0.5, n=360, fmt="{:.5f}", first_g1=False)) + "\nM2\n")
    out = fit_program(src, 0.0002)
    arcs = [l for l in out.splitlines() if l.startswith(("G2", "G3"))]
    assert arcs and all(len(w.split(".")[1]) <= 5 for l in arcs for w in l.split() if "." in w)


def test_feed_changes_split_runs_and_keep_their_words():
    blocks = circle_blocks()
    blocks[60] += " F300"
    src = program(["G0 X10 Y0 Z2", "G1 Z-1 F200"], blocks)
    out = fit_program(src, 0.005)
    assert out.count("F300") == 1 and out.count("F200") == 1
    k = [i for i, l in enumerate(out.splitlines()) if "F300" in l][0]
    assert out.splitlines()[k].split()[0].startswith(("X", "G"))


def test_bad_tolerance_is_a_user_error_naming_the_file():
    with pytest.raises(MillpathError) as e:
        fit_program("G1 X1\n", -1.0, file="part.ngc")
    assert "part.ngc" in str(e.value)
    with pytest.raises(MillpathError):
        fit_program("G1 X1\n", 0.01, "splines", file="part.ngc")


def test_empty_and_trailing_newline_are_preserved():
    assert fit_program("", 0.01) == ""
    assert fit_program("G0 X1", 0.01) == "G0 X1"
    assert fit_program("G0 X1\n", 0.01) == "G0 X1\n"


def test_crlf_programs_keep_their_line_ends():
    src = program(["G0 X10 Y0 Z2", "G1 Z-1 F200"], circle_blocks()).replace("\n", "\r\n")
    out = fit_program(src, 0.005)
    assert out.count("\n") == out.count("\r\n") and out.endswith("\r\n")
    assert len(out) < len(src) / 4


def test_a_run_that_does_not_move_keeps_its_feed_and_motion_mode():
    src = ("G21 G90 G17\nG0 X1 Y1 Z0\nG1 X1 Y1 F300\nX1 Y1\nX2 Y2 (move on)\nM2\n")
    out = fit_program(src, 0.01)
    lines = out.splitlines()
    assert "F300" in out
    assert "G1 X2 Y2 (move on)" in lines or "X2 Y2 (move on)" in lines


def test_next_run_and_opaque_blocks_after_an_arc_run_get_g1_back():
    blocks = circle_blocks(sweep=math.pi, n=90)
    tail = ["X-10 Y-1 F500"] + [f"X{-10 + 0.1 * k:.4f} Y{-1 - 0.1 * k:.4f}" for k in range(1, 5)]
    src = program(["G0 X10 Y0 Z2", "G1 Z-1 F200"], blocks, tail, ["X[-9] Y-2"])
    lines = fit_program(src, 0.005).splitlines()
    assert any(l.startswith("G3") for l in lines)
    after = lines[max(i for i, l in enumerate(lines) if l.startswith("G3")) + 1]
    assert after.startswith("G1 ")
    # an opaque block (expression) right after an arc run: a G1 block of its own
    src = program(["G0 X10 Y0 Z2", "G1 Z-1 F200"], blocks, ["X[-9] Y-2"])
    lines = fit_program(src, 0.005).splitlines()
    k = lines.index("X[-9] Y-2")
    assert lines[k - 1] == "G1" and lines[k - 2].startswith("G3")
