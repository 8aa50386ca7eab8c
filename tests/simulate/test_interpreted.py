"""Toolpath simulation agrees with simulating the interpreted posted program.

The same toolpath is simulated directly (drilling cycles expanded by the simulator)
and as the motion of its posted RS274NGC program, interpreted by millpath's
interpreter and by LinuxCNC's rs274: canned-cycle expansion, arc directions and
helices must agree.
"""

from __future__ import annotations

import numpy as np
import pytest

from millpath.model import Machine, Operation, Stock, Tool, Toolpath
from millpath.simulate import simulate_motions, simulate_toolpath
from millpath.simulate.path import toolpath_motions
from millpath.simulate.tip import tip_motions

TOOLS = {1: Tool(1, "flat", 6.0, flute_length=25, stickout=35),
         2: Tool(2, "drill", 5.0, flute_length=30, stickout=40),
         3: Tool(3, "ball", 4.0, flute_length=20, stickout=30)}
STOCK = Stock(0, 0, -20, 60, 50, 0)


def _toolpath() -> Toolpath:
    tp = Toolpath()
    # each operation starts where the post's safe approach after a tool change puts the
    # tool (straight up to the operation's highest Z, then X and Y), so that the direct
    # simulation and the posted program make the same motion
    tp.begin(Operation("mill", "slots and arcs", 1))
    tp.rapid(0, 0, 5)
    tp.rapid(10, 10, 5)
    tp.line(10, 10, -2, 200)
    tp.line(40, 12, -2, 600)
    tp.arc((40, 32, -2), (40, 22, -2), clockwise=False, feed=600)
    tp.arc((20, 32, -4), (30, 32, -2), clockwise=True, feed=600)
    tp.arc((22, 32, -7), (21, 32, -7), clockwise=False, feed=400, turns=2)  # helix
    tp.rapid(22, 32, 5)
    tp.begin(Operation("drill", "holes", 2))
    tp.rapid(22, 32, 10)
    tp.rapid(50, 5, 10)
    tp.drill(50, 5, -10, 2, 150, cycle="G81")
    tp.drill(50, 15, -12, 2, 150, cycle="G83", peck=3.0)
    tp.drill(50, 25, -9, 2, 150, cycle="G73", peck=2.0, retract_initial=True)
    tp.drill(50, 35, -6, 1, 150, cycle="G82", dwell=0.5)
    tp.drill(50, 44, -5, 1, 150, cycle="G85")
    tp.drill(5, 44, -5, 1, 150, cycle="G89", dwell=0.25, retract_initial=True)
    tp.begin(Operation("finish", "ball ramp", 3))
    tp.rapid(5, 44, 10)
    tp.rapid(5, 25, 10)
    tp.rapid(5, 25, 5)
    tp.line(5, 25, -1, 200)
    tp.line(15, 40, -3, 400)
    tp.rapid(15, 40, 10)
    return tp


def _posted():
    from millpath.post.writer import post
    return post(_toolpath(), TOOLS, title="simulate cross-check")


def _compare(motions):
    direct = simulate_toolpath(_toolpath(), TOOLS, STOCK, resolution=0.1,
                               machine=Machine())
    inter = simulate_motions(motions, TOOLS, STOCK, resolution=0.1, machine=Machine())
    # posted coordinates are rounded to 0.001 mm (rs274 prints 0.0001)
    assert np.abs(direct.zmap.heights - inter.zmap.heights).max() < 0.003
    assert inter.removed_volume == pytest.approx(direct.removed_volume, rel=1e-4)
    assert inter.cycle_time_s == pytest.approx(direct.cycle_time_s, rel=0.01)
    assert inter.rapids_through_material == direct.rapids_through_material == 0


def _path(motions):
    """End points of moving motions, without zero-length ones."""
    out = []
    for m in motions:
        if m.kind == "dwell":
            out.append(("dwell", round(m.dwell, 3)))
        elif max(abs(a - b) for a, b in zip(m.start, m.end)) > 1e-6:
            out.append((m.kind, tuple(round(v, 3) for v in m.end)))
    return out


def _expected(mine):
    """The toolpath's path as the machine moves it through its tool changes, which
    happen where the machine stands. The drill is 5 mm longer than tool 1: tool 1
    rises from 5 to 15 before M6, and the drill arrives with its tip at 10. The ball is
    10 mm shorter than the drill: its tip arrives at 20 and comes down to 10."""
    out = _path(mine)
    at = out.index(("traverse", (22.0, 32.0, 5.0))) + 1
    assert out[at] == ("traverse", (22.0, 32.0, 10.0))
    out[at] = ("traverse", (22.0, 32.0, 15.0))
    at = out.index(("traverse", (5.0, 44.0, 10.0)))
    out.insert(at, ("traverse", (5.0, 44.0, 10.0)))
    return out


def test_millpath_interpreter_motion_simulates_like_the_toolpath():
    from millpath.interpret import interpret
    motions = interpret(_posted(), TOOLS, machine_units="mm")
    _compare(motions)


def test_drilling_cycles_and_arcs_expand_like_millpath_interpreter():
    from millpath.interpret import interpret
    motions = interpret(_posted(), TOOLS, machine_units="mm")
    mine, _ = toolpath_motions(_toolpath())
    # the interpreter starts at machine zero; the toolpath at its first end point
    assert _path(tip_motions(motions, "mm"))[1:] == _expected(mine)


def test_rs274_motion_simulates_like_the_toolpath(rs274):
    from support.rs274 import run_rs274
    res = run_rs274(_posted(), TOOLS, table_units="mm")
    assert res.ok, res.error
    _compare(res.motions)
    mine, _ = toolpath_motions(_toolpath())
    assert _path(tip_motions(res.motions, "mm"))[1:] == _expected(mine)


def test_cubic_moves_simulate_like_their_interpreted_g5():
    from millpath.interpret import interpret
    from millpath.post.writer import post
    tp = Toolpath()
    tp.begin(Operation("mill", "spline", 1))
    tp.rapid(0, 0, 5)               # where the post's safe approach starts (see above)
    tp.rapid(5, 5, 5)
    tp.line(5, 5, -1.5, 200)
    tp.cubic((15, 30), (35, -10), (50, 20, -1.5), 500)
    tp.cubic((55, 30), (40, 45), (20, 40, -1.5), 500)
    tp.rapid(20, 40, 5)
    direct = simulate_toolpath(tp, TOOLS, STOCK, resolution=0.1, machine=Machine())
    motions = interpret(post(tp, TOOLS), TOOLS, machine_units="mm")
    assert sum(m.kind == "cubic" for m in motions) == 2
    inter = simulate_motions(motions, TOOLS, STOCK, resolution=0.1, machine=Machine())
    assert np.abs(direct.zmap.heights - inter.zmap.heights).max() < 0.003
    assert inter.removed_volume == pytest.approx(direct.removed_volume, rel=1e-4)
    assert inter.cycle_time_s == pytest.approx(direct.cycle_time_s, rel=0.01)
