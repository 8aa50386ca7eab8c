"""The LinuxCNC post-processor: golden output per move kind and plane, and rs274
accepts what it writes."""

import math

import pytest

from millpath.model import Operation, Tool, Toolpath
from millpath.post.writer import post, post_with_lines
from support.rs274 import run_rs274

TOOLS = {1: Tool(1, "flat", 6.0, stickout=30, flute_length=18),
         2: Tool(2, "drill", 5.0, stickout=60, flute_length=40)}


def body(text):
    """Program lines after the preamble and tool change, without the trailer."""
    lines = text.splitlines()
    start = lines.index("M8") + 1
    return lines[start:-3]


def base(units="mm"):
    tp = Toolpath(units)
    tp.begin(Operation("test", "golden", 1, 10000))
    tp.rapid(0, 0, 5)
    tp.line(0, 0, -1, 100)
    return tp


def test_preamble_tool_change_and_trailer():
    text = post(base(), TOOLS, title="golden")
    assert text.splitlines() == [
        "(golden)", "(millpath post: LinuxCNC 2.9, units mm)", "(T1 flat D6)",
        "G17 G90 G94 G40 G49 G80", "G91.1", "G21", "G54",
        "(operation 1: test - golden)", "T1 M6", "G43 H1", "S10000 M3", "M8",
        "G0 Z5", "X0 Y0", "G1 Z-1 F100", "M5", "M9", "M2"]


def test_inch_program_uses_g20_and_five_decimals():
    tp = Toolpath("inch")
    tp.begin(Operation("test", "inch", 1, 8000))
    tp.rapid(0.123456, -0.0000004, 0.1)
    text = post(tp, TOOLS)
    assert "G20" in text.splitlines()
    assert "X0.12346 Y0" in text.splitlines()


def test_lines_are_modal_and_write_only_changed_axes():
    tp = base()
    tp.line(10, 0, -1, 100)
    tp.line(10, 5.00004, -1, 250)
    tp.line(10.00001, 5.00004, -1, 250)     # rounds to the same point: nothing written
    tp.rapid(10, 5, 5)
    assert body(post(tp, TOOLS)) == ["G0 Z5", "X0 Y0", "G1 Z-1 F100", "X10", "Y5 F250",
                                    "G0 Z5"]


def test_xy_arcs_clockwise_counterclockwise_and_full_turns():
    tp = base()
    tp.arc((10, 0, -1), (5, 0, -1), True, 200)
    tp.arc((10, 0, -1), (5, 0, -1), False, 200, turns=2)
    tp.arc((0, 0, -3), (5, 0, -1), False, 200)            # helical half turn
    assert body(post(tp, TOOLS))[3:] == ["G2 X10 Y0 I5 J0 F200", "G3 I-5 J0 P2",
                                         "G3 X0 Y0 Z-3 I-5 J0"]


def test_xz_and_yz_arcs_select_their_plane_and_use_ik_jk():
    tp = base()
    tp.arc((10, 0, -1), (5, 0, -1), False, 200, plane="XZ")
    tp.arc((10, 10, -1), (10, 5, -1), True, 200, plane="YZ")
    tp.line(20, 10, -1, 200)
    tp.compensation("left", 1)
    assert body(post(tp, TOOLS))[3:] == ["G18", "G3 Z-1 X10 K0 I5 F200", "G19",
                                         "G2 Y10 Z-1 J5 K0", "G1 X20", "G17", "G41 D1",
                                         "G40"]


def test_cubic_is_written_as_g5_with_offsets_from_its_ends():
    tp = base()
    tp.cubic((2, 3), (8, 3), (10, 0, -1), 300)
    assert body(post(tp, TOOLS))[3:] == ["G5 X10 Y0 I2 J3 P-2 Q3 F300"]


def test_drill_cycles_are_modal_and_closed_by_g80():
    tp = Toolpath("mm")
    tp.begin(Operation("drill", "holes", 2, 2000))
    tp.rapid(10, 10, 10)
    tp.drill(10, 10, -12, 2, 80, "G83", peck=3)
    tp.drill(20, 10, -12, 2, 80, "G83", peck=3)
    tp.drill(30, 10, -5, 2, 60, "G82", dwell=0.5, retract_initial=True)
    tp.rapid(30, 10, 20)
    assert body(post(tp, TOOLS)) == [
        "G0 Z20", "X10 Y10", "Z10", "G99 G83 X10 Y10 Z-12 R2 Q3 F80", "X20 Y10", "G80",
        "G98 G82 X30 Y10 Z-5 R2 P0.5 F60", "G80", "G0 Z20"]


def test_compensation_moves_write_g41_d_and_g40():
    tp = base()
    tp.compensation("left", 1)
    tp.line(10, 0, -1, 100)
    tp.compensation("off")
    tp.line(12, -2, -1, 100)
    assert body(post(tp, TOOLS))[3:] == ["G41 D1", "X10", "G40", "X12 Y-2"]


def test_arc_centre_is_fitted_to_the_written_end_points():
    tp = base()
    # end point and centre that round badly: the written centre must keep r1 == r2
    a = 0.7
    tp.line(10.00004, 0.00004, -1, 100)
    c = (0.00004, 0.00004, -1)
    end = (c[0] + 10 * math.cos(a), c[1] + 10 * math.sin(a), -1)
    tp.arc(end, c, False, 100)
    line = body(post(tp, TOOLS))[-1]
    w = dict((t[0], float(t[1:])) for t in line.split()[1:])
    sx, sy = 10.0, 0.0
    cx, cy = sx + w["I"], sy + w["J"]
    r1 = math.hypot(sx - cx, sy - cy)
    r2 = math.hypot(w["X"] - cx, w["Y"] - cy)
    assert abs(r1 - r2) < 1.5e-4


def test_bad_moves_are_refused():
    tp = base()
    tp.line(5, 0, -1, 0)
    with pytest.raises(ValueError, match="feed rate"):
        post(tp, TOOLS)
    tp = base()
    tp.line(math.nan, 0, -1, 100)
    with pytest.raises(ValueError, match="non-finite"):
        post(tp, TOOLS)


def test_move_lines_point_at_the_lines_that_carry_each_move():
    tp = base()
    tp.line(10, 0, -1, 100)
    tp.rapid(10, 0, -1)
    text, where = post_with_lines(tp, TOOLS)
    lines = text.splitlines()
    assert lines[where[0] - 1] == "X0 Y0"
    assert lines[where[2] - 1] == "X10"
    assert where[3] is None


def all_kinds(units):
    k = 1.0 if units == "mm" else 1 / 25.4
    tp = Toolpath(units)
    tp.begin(Operation("test", "all kinds", 1, 10000))
    tp.rapid(0, 0, 5 * k)
    tp.line(0, 0, -1 * k, 100 * k)
    tp.arc((10 * k, 0, -k), (5 * k, 0, -k), True, 200 * k)
    tp.arc((10 * k, 0, -k), (5 * k, 0, -k), False, 200 * k, turns=3)
    tp.arc((20 * k, 0, -k), (15 * k, 0, -k), False, 200 * k, plane="XZ")
    tp.arc((20 * k, 10 * k, -k), (20 * k, 5 * k, -k), True, 200 * k, plane="YZ")
    tp.arc((30 * k, 10 * k, -3 * k), (25 * k, 10 * k, -k), True, 200 * k)
    tp.cubic((32 * k, 15 * k), (38 * k, 5 * k), (40 * k, 10 * k, -3 * k), 300 * k)
    tp.rapid(40 * k, 10 * k, 5 * k)
    tp.begin(Operation("drill", "holes", 2, 3000))
    tp.rapid(50 * k, 50 * k, 10 * k)
    tp.drill(50 * k, 50 * k, -10 * k, 2 * k, 80 * k, "G83", peck=3 * k)
    tp.drill(60 * k, 50 * k, -10 * k, 2 * k, 80 * k, "G73", peck=3 * k)
    tp.drill(70 * k, 50 * k, -5 * k, 2 * k, 80 * k, "G81", retract_initial=True)
    tp.drill(80 * k, 50 * k, -5 * k, 2 * k, 80 * k, "G82", dwell=1.0)
    tp.rapid(80 * k, 50 * k, 20 * k)
    tp.begin(Operation("contour", "compensated square", 1, 10000))
    tp.rapid(-10 * k, 5 * k, 5 * k)
    tp.line(-10 * k, 5 * k, -k, 100 * k)
    tp.compensation("left", 1)
    tp.line(0, 0, -k, 100 * k)
    tp.line(20 * k, 0, -k, 100 * k)
    tp.line(20 * k, 20 * k, -k, 100 * k)
    tp.line(0, 20 * k, -k, 100 * k)
    tp.line(0, 0, -k, 100 * k)
    tp.compensation("off")
    tp.line(-10 * k, -5 * k, -k, 100 * k)
    tp.rapid(-10 * k, -5 * k, 5 * k)
    return tp


@pytest.mark.parametrize("units", ["mm", "inch"])
def test_rs274_accepts_every_move_kind_and_reproduces_the_toolpath(rs274, units):
    tp = all_kinds(units)
    tools = TOOLS if units == "mm" else {
        1: Tool(1, "flat", 0.25, stickout=1.2, flute_length=0.7),
        2: Tool(2, "drill", 0.2, stickout=2.4, flute_length=1.6)}
    text, where = post_with_lines(tp, tools)
    r = run_rs274(text, tools, table_units=units)
    assert r.ok, (r.error, r.error_block)
    assert r.units == units
    by_line = {}
    for m in r.motions:
        by_line.setdefault(m.line, []).append(m)
    k = 1.0 if units == "mm" else 1 / 25.4
    comp = False
    for m, line in zip(tp.moves, where):
        if m.kind == "comp":
            comp = m.comp != "off"
            continue
        if comp:
            continue            # LinuxCNC moves these on purpose (and one block late)
        got = by_line[line]
        if m.kind in ("rapid", "line", "arc"):
            assert len(got) == 1
            assert got[0].end == pytest.approx(m.end, abs=1e-4)
        if m.kind == "arc":
            assert got[0].rotation == (-m.turns if m.clockwise else m.turns)
        if m.kind == "drill":
            assert min(g.end[2] for g in got) == pytest.approx(m.end[2], abs=1e-4)
    # tool length offset of the gauge length, in program units
    assert r.motions[0].tool_offset[2] == pytest.approx(tools[1].gauge_length, abs=1e-4)
    # the compensated square runs tool radius inside (G41 on a CCW square is inside)
    ends = [m.end[:2] for m in r.motions if m.kind == "feed"]
    r = tools[1].radius
    for corner in ((20 * k - r, r), (20 * k - r, 20 * k - r), (r, 20 * k - r)):
        assert any(math.dist(e, corner) < 1e-4 for e in ends)
