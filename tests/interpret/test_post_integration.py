"""Programs written by millpath's LinuxCNC post interpret cleanly, and as rs274 does."""

from __future__ import annotations

import math

import pytest

from millpath.interpret import interpret
from support.difftest import differential
from millpath.model import Tool, Toolpath
from millpath.model.toolpath import Operation
from millpath.post.writer import post


def sample_toolpath(units: str) -> tuple[Toolpath, dict[int, Tool]]:
    s = 1.0 if units == "mm" else 1 / 25.4
    tools = {1: Tool(1, diameter=6.0 * s, length=50.0 * s),
             2: Tool(2, "drill", diameter=5.0 * s, length=60.0 * s)}
    tp = Toolpath(units=units)
    tp.begin(Operation("profile", "outside profile", 1, spindle=8000))
    tp.rapid(-20 * s, -20 * s, 5 * s)
    tp.compensation("left", 1)
    tp.line(0, 0, 5 * s, 300 * s)
    tp.line(0, 0, -2 * s, 100 * s)
    tp.line(40 * s, 0, -2 * s, 300 * s)
    tp.arc((50 * s, 10 * s, -2 * s), (40 * s, 10 * s, 0), False, 300 * s)
    tp.line(50 * s, 30 * s, -2 * s, 300 * s)
    tp.line(0, 30 * s, -2 * s, 300 * s)
    tp.line(0, 0, -2 * s, 300 * s)
    tp.compensation("off")
    tp.line(-20 * s, -20 * s, -2 * s, 300 * s)
    tp.cubic((-15 * s, -30 * s), (-5 * s, -30 * s), (0, -20 * s, -2 * s), 300 * s)
    tp.rapid(-20 * s, -20 * s, 5 * s)
    tp.arc((-10 * s, -20 * s, 5 * s), (-15 * s, -20 * s, 5 * s), True, 200 * s, plane="XZ")
    tp.arc((-10 * s, -10 * s, 5 * s), (-10 * s, -15 * s, 5 * s), False, 200 * s, plane="YZ",
           turns=2)
    tp.begin(Operation("drilling", "holes", 2, spindle=2000, coolant="mist"))
    tp.rapid(0, 50 * s, 10 * s)
    for k, cyc in enumerate(("G81", "G82", "G83", "G73", "G85", "G89")):
        x = 10 * s * k
        tp.drill(x, 50 * s, -10 * s, 2 * s, 120 * s, cycle=cyc, peck=3 * s if cyc in
                 ("G83", "G73") else 0.0, dwell=0.5 if cyc in ("G82", "G89") else 0.0,
                 retract_initial=k % 2 == 0)
    tp.rapid(0, 0, 20 * s)
    return tp, tools


@pytest.mark.parametrize("units", ["mm", "inch"])
def test_posted_program_interprets_cleanly(units):
    tp, tools = sample_toolpath(units)
    program = post(tp, tools, title="integration")
    ms = interpret(program, tools, machine_units=units)
    kinds = {m.kind for m in ms}
    assert {"traverse", "feed", "arc", "cubic", "dwell"} <= kinds
    assert all(math.isfinite(v) for m in ms for v in m.end)


@pytest.mark.parametrize("units", ["mm", "inch"])
def test_posted_program_same_as_rs274(rs274, units):
    tp, tools = sample_toolpath(units)
    program = post(tp, tools, title="integration")
    c = differential(program, tools, machine_units=units)
    assert c.same, f"{program}\n{c}"
