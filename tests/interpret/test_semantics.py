"""Known-answer tests that need no rs274: expansions and geometry worked out by hand
from LinuxCNC's rules (cycles, compensation, offsets, parsing)."""

from __future__ import annotations

import math

import pytest

from millpath.interpret import interpret, run
from millpath.io.tooltable import ToolEntry

TOOLS = [ToolEntry(1, 1, 2.0, {"Z": 10.0})]          # 2 mm diameter in an mm machine


def ends(ms):
    return [tuple(round(v, 6) for v in m.end) for m in ms if m.kind != "dwell"]


def test_g81_g99_retracts_to_r_and_g98_to_initial_level():
    ms = interpret("G21 F100\nG0 X0 Y0 Z5\nG99 G81 X1 Y0 Z-2 R1\nG98 G81 X2 Z-2 R1\nM2\n")
    # the initial level (Z5) is kept while cycles follow each other: the G98 hole
    # positions and retracts at Z5
    assert ends(ms)[1:] == [(1, 0, 5), (1, 0, 1), (1, 0, -2), (1, 0, 1),
                            (2, 0, 5), (2, 0, 1), (2, 0, -2), (2, 0, 5)]


def test_g83_pecks_back_to_r_and_down_to_a_clearance_above_the_last_depth():
    ms = interpret("G21 F100\nG0 X0 Y0 Z5\nG83 X0 Z-3 R1 Q2\nM2\n")
    kinds = [m.kind for m in ms]
    assert ends(ms)[1:] == [(0, 0, 5), (0, 0, 1), (0, 0, -1), (0, 0, 1), (0, 0, -0.746),
                            (0, 0, -3), (0, 0, 1)]
    assert kinds[3] == "feed" and kinds[5] == "traverse"


def test_entry_move_ends_a_radius_left_of_the_programmed_point():
    ms = interpret("G21 F100\nG0 X-10 Y0\nG41 D1\nG1 X0 Y0\nG1 X10\nG40 G1 X20 Y-10\nM2\n",
                   TOOLS, machine_units="mm")
    # moving +X with the tool on the left: 1 mm towards +Y
    assert ms[1].end == pytest.approx((0.0, 1.0, 0.0))
    assert ms[2].end == pytest.approx((10.0, 1.0, 0.0))


def test_convex_corner_gets_an_arc_about_the_programmed_corner():
    ms = interpret("G21 F100\nG0 X-10 Y0\nG42 D1\nG1 X0 Y0\nG1 X10\nG1 Y10\nG40 G1 X20 Y20\n"
                   "M2\n", TOOLS, machine_units="mm")
    arcs = [m for m in ms if m.kind == "arc"]
    assert len(arcs) == 1
    assert arcs[0].center == pytest.approx((10.0, 0.0, 0.0))
    assert arcs[0].start == pytest.approx((10.0, -1.0, 0.0))
    assert arcs[0].end == pytest.approx((11.0, 0.0, 0.0))
    assert arcs[0].rotation == 1


def test_concave_corner_is_trimmed():
    ms = interpret("G21 F100\nG0 X-10 Y0\nG41 D1\nG1 X0 Y0\nG1 X10\nG1 Y10\nG40 G1 X0 Y20\n"
                   "M2\n", TOOLS, machine_units="mm")
    # inside corner at (10, 0) with the tool left: the lines meet at (9, 1)
    assert ms[2].end == pytest.approx((9.0, 1.0, 0.0))
    assert ms[3].start == pytest.approx((9.0, 1.0, 0.0))
    assert all(m.kind != "arc" for m in ms)


def test_gouging_corner_is_an_error_on_its_block():
    # a 0.5 mm step into a left turn: the 1 mm radius tool cannot back up that far
    r = run("G21 F100\nG0 X-10 Y0\nG41 D1\nG1 X0 Y0\nG1 X0.5\nG1 X0.5 Y5\nM2\n",
            TOOLS, machine_units="mm")
    assert r.error is not None and r.error.line == 6
    assert r.error.message == ("Straight feed in concave corner cannot be reached by the "
                               "tool without gouging")


def test_work_offsets_and_g92_shift_program_coordinates():
    ms = interpret("G21\nG0 X5 Y5\nG10 L2 P2 X10\nG55\nG0 X0\nG92 X1\nG0 X2\nM2\n")
    # in G55 the point (5, 5) is (-5, 5); G92 then makes it X1
    assert ends(ms) == [(5, 5, 0), (0, 5, 0), (2, 5, 0)]


def test_expression_precedence_and_functions():
    ms = interpret("G21\nG0 X[1 + 2 * 3 ** 2] Y[-2 ** 2] Z[10 mod 4]\n"
                   "G0 X[round[-2.5]] Y[fix[-2.5]] Z[fup[-2.5]]\nM2\n")
    assert ends(ms) == [(19, 4, 2), (-3, -3, -2)]


def test_comments_spaces_case_and_line_numbers():
    ms = interpret("g21 (mm)\nn10 g 0 x 1 . 5 ( a ) y2 ; rest\n/G0 X3\nM2\n")
    assert ends(ms) == [(1.5, 2, 0), (3, 2, 0)]
    assert [m.line for m in ms] == [2, 3]


def test_helix_and_full_turns_in_xz():
    ms = interpret("G21 F100\nG0 X0 Y0 Z0\nG18 G3 X0 Z0 Y5 I1 K0 P3\nM2\n")
    arc = ms[1]
    assert arc.plane == "XZ" and arc.rotation == 3
    assert arc.center == pytest.approx((1.0, 0.0, 0.0))
    assert arc.end == pytest.approx((0.0, 5.0, 0.0))
    assert math.isclose(arc.start[1], 0.0)
