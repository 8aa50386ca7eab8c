"""Round trip under cutter compensation and of G5 control points.

Truth: the programs are planned by millpath's profile and die-cavity planners (whose
compensated motion LinuxCNC's rs274 reproduces: tests/interpret) and must come back
clean; then the program text is changed by a known amount (a coordinate moved normal to
the contour, the tool table's diameter, a G5 control point) and the round trip must
see exactly those changes, and not changes below its tolerance."""

from __future__ import annotations

import math
import re
from pathlib import Path

import pytest

from millpath.interpret import interpret
from millpath.interpret.errors import InterpreterError
from millpath.io.schema import validate
from millpath.model import Machine, Stock, Tool, Toolpath
from millpath.model.toolpath import Operation
from millpath.plan.base import PlanContext
from millpath.plan.profile import operation as profile
from millpath.post.writer import post_with_lines
from millpath.verify.roundtrip import compare_toolpath
from support.rs274 import run_rs274

TOL = 2e-4              # mm: the round trip's tolerance (post rounds to 0.0001)
L_SHAPE = [[0, 0], [60, 0], [60, 40], [30, 40], [30, 25], [0, 25]]
TOOLS = {3: Tool(3, "flat", 6.0)}
STOCK = Stock(-20, -20, -12, 80, 60, 0)


def _profile(side: str, **keys):
    ctx = PlanContext("mm", STOCK, Machine(), TOOLS, Path("."))
    base = {"tool": 3, "polygon": L_SHAPE, "depth": 10.0, "stepdown": 4.0, "feed": 800.0,
            "side": side, "compensation": "control"}
    tp = profile.plan(ctx, validate({**base, **keys}, profile.PARAMS, "op", None)).toolpath
    prog, lines = post_with_lines(tp, TOOLS)
    return tp, prog, lines


def _check(tp, prog, lines, diameter=6.0, radius=3.0):
    motions = interpret(prog, {3: Tool(3, "flat", diameter)}, machine_units="mm")
    return compare_toolpath(tp, lines, motions, TOL, {3: radius})


@pytest.mark.parametrize("side,keys", [("outside", {}), ("inside", {}),
                                       ("outside", {"tabs": 3, "tab_height": 2.0})])
def test_compensated_profiles_come_back_clean(side, keys):
    tp, prog, lines = _profile(side, **keys)
    assert re.search(r"G4[12] D3", prog)
    assert _check(tp, prog, lines) == []


def test_a_wrong_tool_diameter_is_seen():
    tp, prog, lines = _profile("outside")
    assert _check(tp, prog, lines, diameter=6.0 + 2 * 0.0003) != []     # 0.0003 off
    assert _check(tp, prog, lines, diameter=6.0 + 2 * 0.0001) == []     # within 0.0002
    diffs = _check(tp, prog, lines, diameter=5.8)
    assert diffs and ("G41 D3" in diffs[0] or "G42 D3" in diffs[0])


def test_a_tool_wider_than_the_wear_margin_is_refused_as_linuxcnc_refuses_it(rs274):
    """The concave corner is rounded to the tool radius plus the wear margin (0.1 mm):
    a tool 0.2 mm wider than the program's cannot follow it; LinuxCNC refuses the
    program and so does the interpreter, at the same line."""
    tp, prog, lines = _profile("outside")
    wide = {3: Tool(3, "flat", 6.4, flute_length=20, stickout=30)}
    ref = run_rs274(prog, wide)
    assert not ref.ok and "concave corner cannot be reached" in ref.error
    with pytest.raises(InterpreterError) as e:
        interpret(prog, wide, machine_units="mm")
    assert "concave corner cannot be reached" in str(e.value)
    assert e.value.line == ref.error_line
    assert _check(tp, prog, lines, diameter=6.0 + 2 * 0.09) != []      # within the margin


def _move_line(prog: str, lineno: int, axis: str, by: float, modal: float = 0.0) -> str:
    """``prog`` with the ``axis`` word of line ``lineno`` changed by ``by`` (``modal``:
    the axis's value when the line does not write it)."""
    rows = prog.splitlines()
    m = re.search(axis + r"(-?[0-9.]+)", rows[lineno - 1])
    if m:
        rows[lineno - 1] = rows[lineno - 1].replace(m.group(0), f"{axis}{float(m.group(1)) + by:.4f}")
    else:
        rows[lineno - 1] += f" {axis}{modal + by:.4f}"
    return "\n".join(rows) + "\n"


def test_a_contour_point_moved_normal_to_the_contour_is_seen():
    tp, prog, lines = _profile("outside")
    # the L's bottom edge (0,0)-(60,0): a compensated move along it at the first level
    on, prev, target = False, None, None
    for m, ln in zip(tp.moves, lines):
        if m.kind == "comp":
            on = m.comp != "off"
        elif on and m.kind == "line" and prev is not None and abs(prev[1]) < 1e-5 \
                and abs(m.end[1]) < 1e-5 and abs(m.end[0] - prev[0]) > 1.0:
            target, x_end = ln, m.end[0]
            break
        if m.kind != "comp":
            prev = m.end
    assert target is not None
    assert _check(tp, _move_line(prog, target, "Y", 0.0005), lines) != []
    assert _check(tp, _move_line(prog, target, "Y", -0.0005), lines) != []
    assert _check(tp, _move_line(prog, target, "Y", 0.0001), lines) == []
    # along the edge (X): the offset path is the same line, only its end moves
    assert _check(tp, _move_line(prog, target, "X", 0.1, x_end), lines) != []


def test_compensation_without_radii_is_not_compared():
    tp, prog, lines = _profile("outside")
    motions = interpret(prog, {3: Tool(3, "flat", 5.8)}, machine_units="mm")
    assert compare_toolpath(tp, lines, motions, TOL) == []


def _cubic_program():
    tp = Toolpath("mm")
    tp.begin(Operation("test", "cubic", 3, 1000.0, "off"))
    tp.rapid(0, 0, 5)
    tp.line(0, 0, -1, 300)
    tp.cubic((10.0, 20.0), (30.0, -15.0), (40.0, 5.0, -1), 600)
    tp.cubic((45.0, 10.0), (50.0, 20.0), (55.0, 30.0, -1), 600)
    tp.rapid(55, 30, 5)
    prog, lines = post_with_lines(tp, TOOLS)
    return tp, prog, lines


def test_g5_control_points_are_compared():
    tp, prog, lines = _cubic_program()
    assert _check(tp, prog, lines) == []
    g5 = [i + 1 for i, r in enumerate(prog.splitlines()) if r.startswith("G5 ")]
    assert len(g5) == 1 or len(g5) == 2
    for word in "IJPQ":
        for by, seen in ((0.001, True), (0.0001, False)):
            diffs = _check(tp, _move_line(prog, g5[0], word, by), lines)
            assert bool(diffs) == seen, (word, by, diffs)
            if seen:
                assert "control points" in diffs[0]


def test_the_check_measures_distance_normal_to_arcs():
    """A compensated contour with an arc: G41 round a 20 mm circle's quarter, the tool
    6 mm: the tool centre runs on radius 23 (the left of a clockwise arc is outside);
    with G42 on radius 17."""
    tp = Toolpath("mm")
    tp.begin(Operation("test", "arc", 3, 1000.0, "off"))
    tp.rapid(-10, 30, 5)
    tp.line(-10, 30, -1, 300)
    for side, radius in (("left", 23.0), ("right", 17.0)):
        tp = Toolpath("mm")
        tp.begin(Operation("test", "arc", 3, 1000.0, "off"))
        tp.rapid(-10, 30, 5)
        tp.line(-10, 30, -1, 300)
        tp.compensation(side, d=3)
        tp.line(0, 20, -1, 600)                                 # entry, to the arc's start
        tp.arc((20, 0, -1), (0, 0, -1), True, 600)              # clockwise quarter, r 20
        tp.line(20, -10, -1, 600)
        tp.compensation("off")
        tp.line(30, -20, -1, 600)
        prog, lines = post_with_lines(tp, TOOLS)
        motions = interpret(prog, TOOLS, machine_units="mm")
        arcs = [m for m in motions if m.kind == "arc" and m.center[:2] == (0.0, 0.0)]
        assert len(arcs) == 1
        assert math.isclose(math.hypot(*arcs[0].end[:2]), radius, abs_tol=1e-4)
        assert compare_toolpath(tp, lines, motions, TOL, {3: 3.0}) == []
        assert compare_toolpath(tp, lines, motions, TOL, {3: 3.001}) != []
        # the same distance on the other side: the side is checked too
        other = prog.replace("G41 D3" if side == "left" else "G42 D3",
                             "G42 D3" if side == "left" else "G41 D3")
        assert other != prog
        diffs = compare_toolpath(tp, lines, interpret(other, TOOLS, machine_units="mm"),
                                 TOL, {3: 3.0})
        assert diffs and "of the contour" in diffs[0], diffs


def _short_arc_program():
    """A clockwise arc of radius 3 about a grid point over a 0.17 mm chord, its start
    off the grid (as an offset path's is): the post places the centre on the written
    chord's bisector, 0.0011 from the planned one."""
    tp = Toolpath("mm")
    tp.begin(Operation("test", "short arc", 3, 1000.0, "off"))
    tp.rapid(130.0, 52.0, 5)
    tp.line(130.0, 52.0, 3.5, 300)
    tp.line(138.85229986512462, 52.59165357804554, 3.5, 600)
    tp.arc((139.01630984200406, 52.6398261469145, 3.5), (139.7794, 49.7385, 3.5), True, 600)
    tp.line(140.9584, 53.1506, 3.5, 600)
    tp.rapid(140.9584, 53.1506, 5)
    prog, lines = post_with_lines(tp, TOOLS)
    return tp, prog, lines


def test_a_short_arc_is_compared_by_where_it_runs_not_by_its_centre(rs274):
    """rs274 runs the short arc within 0.0002 of the planned one although its centre is
    0.0011 away: the round trip passes. A half circle of radius 10 with its centre
    written 0.0005 off (the arc itself moved by about that) is seen."""
    from support.rs274 import run_rs274
    tp, prog, lines = _short_arc_program()
    ref = run_rs274(prog, TOOLS)
    assert ref.ok, ref.error
    arc = [m for m in ref.motions if m.kind == "arc"][0]
    assert abs(arc.center[0] - 139.7794) > 0.001 - 1e-9
    assert compare_toolpath(tp, lines, ref.motions, TOL) == []
    assert compare_toolpath(tp, lines, interpret(prog, TOOLS, machine_units="mm"), TOL) == []

    tp = Toolpath("mm")
    tp.begin(Operation("test", "half circle", 3, 1000.0, "off"))
    tp.rapid(0, 0, 5)
    tp.line(0, 0, -1, 300)
    tp.arc((20.0, 0.0, -1), (10.0, 0.0, -1), True, 600)
    tp.rapid(20, 0, 5)
    prog, lines = post_with_lines(tp, TOOLS)
    assert compare_toolpath(tp, lines, run_rs274(prog, TOOLS).motions, TOL) == []
    row = lines[next(i for i, m in enumerate(tp.moves) if m.kind == "arc")]
    for axis in ("I", "J"):
        ref = run_rs274(_move_line(prog, row, axis, 0.0005), TOOLS)
        assert ref.ok, ref.error
        assert compare_toolpath(tp, lines, ref.motions, TOL) != [], axis
