"""Basic behaviour of the interpreter without rs274: lines, arcs, tools, errors."""

from __future__ import annotations

import math

import pytest

from millpath.interpret import InterpreterError, interpret, run
from millpath.io.tooltable import ToolEntry
from millpath.model.tool import Tool

TOOLS = [ToolEntry(1, 1, diameter=0.25, offsets={"Z": 1.0}),
         ToolEntry(2, 2, diameter=-0.1, offsets={"Z": 0.5, "X": 0.1})]


def test_lines_and_arcs_in_program_coordinates():
    ms = interpret("G21 F100\nG0 X1 Y2 Z3\nG1 X4\nG2 X6 Y2 I1 J0\nM2\n")
    assert [m.kind for m in ms] == ["traverse", "feed", "arc"]
    assert ms[0].end == (1.0, 2.0, 3.0)
    assert ms[1].start == (1.0, 2.0, 3.0) and ms[1].feed == 100.0
    arc = ms[2]
    assert arc.center == (5.0, 2.0, 3.0) and arc.rotation == -1 and arc.plane == "XY"


def test_tool_table_is_read_in_machine_units():
    prog = "G21\nT1 M6\nG43\nG0 X0 Y0 Z0\nM2\n"
    inch = interpret(prog, TOOLS, machine_units="inch")
    assert inch[0].tool_offset == pytest.approx((0.0, 0.0, 25.4))
    assert inch[0].end[2] == pytest.approx(0.0) and inch[0].tool == 1
    mm = interpret(prog, TOOLS, machine_units="mm")
    assert mm[0].tool_offset == pytest.approx((0.0, 0.0, 1.0))


def test_tools_as_millpath_tool_dict_use_gauge_length():
    tools = {3: Tool(3, diameter=6.0, length=50.0)}
    ms = interpret("G21\nT3 M6 G43\nG0 Z10\nM2\n", tools, machine_units="mm")
    assert ms[0].tool_offset[2] == 50.0 and ms[0].tool == 3


def test_error_carries_line_message_and_motion_before():
    with pytest.raises(InterpreterError) as ei:
        interpret("G21\nG0 X1\nG1 X2\nM2\n")
    e = ei.value
    assert e.line == 3 and e.message == "Cannot do g1 with zero feed rate"
    assert len(e.motions) == 1


def test_run_never_raises_for_gcode_errors():
    r = run("G21\nG0 X1 X2\n")
    assert r.error is not None and r.error.line == 2
    assert r.error.message == "Multiple x words on one line"


def test_missing_program_end_is_an_error_on_the_last_line():
    r = run("G21\nG0 X1\n")
    assert r.error.line == 2 and "program end" in r.error.message


def test_expressions_and_parameters():
    ms = interpret("G21\n#1=2 #<r>=[3*2]\nG0 X[#1+1] Y#<r> Z[atan[1]/[1]]\n"
                   "G0 X[sqrt[16]] Y[2**3] Z[7 mod 3]\nM2\n")
    assert ms[0].end == pytest.approx((3.0, 6.0, 45.0))
    assert ms[1].end == pytest.approx((4.0, 8.0, 1.0))


def test_units_switch_scales_position():
    ms = interpret("G21 G0 X25.4\nG20 G0 Y1\nM2\n")
    assert ms[1].end == pytest.approx((1.0, 1.0, 0.0))


def test_cubic_spline_has_control_points():
    ms = interpret("G21 F100\nG5 X10 Y0 I2 J2 P-2 Q2\nM2\n")
    assert ms[0].kind == "cubic"
    assert ms[0].controls == ((2.0, 2.0), (8.0, 2.0))


def test_full_circle_with_p_turns():
    ms = interpret("G21 F100\nG0 X1 Y0\nG3 X1 Y0 I-1 J0 P2\nM2\n")
    assert ms[1].rotation == 2 and ms[1].center == pytest.approx((0, 0, 0))


def test_motion_to_json_shape():
    ms = interpret("G21 F100\nG2 X2 Y0 R1\nM2\n")
    d = ms[0].to_json()
    assert d["kind"] == "arc" and d["plane"] == "XY" and d["rotation"] == -1
    assert math.isclose(d["center"][0], 1.0)


def test_line_numbers_stay_right_across_chunks(monkeypatch):
    import millpath.interpret.runner as runner
    monkeypatch.setattr(runner, "CHUNK", 40)
    text = "G21 F100\n" + "".join(f"G1 X{i} Y{i % 7}\n" for i in range(30))
    r = run(text + "G2 X1 Y1\nM2\n")
    assert r.error.line == 32 and r.error.message == "R i j k words all missing for arc"
    assert [m.line for m in r.motions] == list(range(2, 32))
    monkeypatch.setattr(runner, "CHUNK", 1 << 22)
    assert [m.line for m in run(text + "M2\n").motions] == list(range(2, 32))


def test_motion_list_is_a_compact_sequence():
    ms = interpret("G21 F100\nG0 X1\nG1 X2\nG2 X4 Y0 R1\nM2\n")
    assert len(ms) == 3 and ms[-1].kind == "arc" and ms[1:2][0].kind == "feed"
    assert list(ms) == [ms[0], ms[1], ms[2]]
    a = ms.arrays()
    assert a["end"].shape == (3, 3) and list(a["kind"]) == [0, 1, 2]
    assert a["center"][2].tolist() == pytest.approx([3.0, 0.0, 0.0])
