"""Compensated runs (interpret/compfast.py: G0-G3 under G41/G42 in G17 with the state
in locals) against LinuxCNC's rs274: the shapes the run takes (G0 corners, modal lines,
F changes, R and I/J arcs, concave corners between lines and arcs, arc-to-arc joins)
and the lines it hands back to the machine's code (a zero-length move queued behind
another, a dwell in the queue, an arc of two turns, gouges and bad arcs in the middle
of a run): same motion (1e-4) or an error on the same block with the same message."""

from __future__ import annotations

import pytest

from support.difftest import differential
from millpath.io.tooltable import ToolEntry

# inches (rs274's machine units): T1 D0.25 (6.35 mm)
TOOLS = [ToolEntry(1, 1, 0.25, {"Z": 1.0}), ToolEntry(3, 3, 1.0, {"Z": 2.0})]

P = {}
P["mixed_run"] = """G21 F100
G0 X-10 Y-10
G41 D1
G1 X0 Y0
X20
Y5 F150
G0 X25 Y10
G1 X30 Y30
G3 X20 Y40 R10
G2 X10 Y50 I-10 J0
G1 X0 Y40
G1 X0 Y40
G1 X-5 Y20
G4 P0.5
G1 X-5 Y10
G3 X0 Y0 R8
G40 G1 X-10 Y-10
M2
"""
P["right_side_arcs_and_concave_lines"] = """G21 F300
G0 X-20 Y-20 Z1
G42 D1
G1 X0 Y0
G1 Z-1
G1 X40 Y0
G1 X40 Y30
G1 X30 Y20
G1 X20 Y30
G2 X10 Y30 R5
G3 X0 Y30 R5
G1 X0 Y0
G40 G0 X-20 Y-20
M2
"""
P["arc_to_arc_concave"] = """G21 F200
G0 X-10 Y0
G41 D1
G1 X0 Y0
G3 X20 Y0 I10 J0
G2 X40 Y0 I10 J0
G3 X60 Y0 R10
G1 X60 Y-20
G40 G1 X70 Y-30
M2
"""
P["two_turn_arc_in_run"] = """G21 F200
G0 X-10 Y0
G41 D1
G1 X0 Y0
G1 X10 Y0
G3 X20 Y0 I5 J0 P2
G1 X30 Y0
G40 G1 X40 Y-10
M2
"""
P["gouge_in_run"] = """G21 F100
G0 X-10 Y-10
G42 D3
G1 X0 Y0
G1 X30 Y0
G1 X30 Y5
G1 X29 Y5
G1 X29 Y30
G40 G1 X70 Y-10
M2
"""
P["arc_radius_under_tool_in_run"] = """G21 F100
G0 X-10 Y-10
G41 D3
G1 X0 Y0
G1 X30 Y0
G3 X30 Y2 R1
G1 X0 Y2
M2
"""
P["bad_arc_in_run"] = """G21 F100
G0 X-10 Y-10
G41 D1
G1 X0 Y0
G1 X20 Y0
G3 X40 Y0 R5
G1 X50 Y0
M2
"""
P["spiral_arc_in_run"] = """G21 F100
G0 X-10 Y-10
G41 D1
G1 X0 Y0
G1 X20 Y0
G3 X30 Y10 I5 J0
M2
"""
# the compensation switches the fast path executes itself (G40, G41/G42 with a whole D
# or none, G40 with a G0/G1 move)
P["switches"] = """G21 F100
G0 X-10 Y-10
g41 d1
G1 X0 Y0
G1 X20 Y0
G40 G0 X30 Y-10
G42
G1 X40 Y0
G1 X40 Y20
G40
G1 X50 Y30 F200
G41 D0
G1 X60 Y40
G40 g1 x70 y30
M2
"""
P["switch_on_when_on"] = "G21 F10\nG0 X-10\nG41 D1\nG1 X0 Y0\nG42 D1\nM2\n"
P["switch_missing_tool"] = "G21 F10\nG41 D7\nM2\n"
P["switch_d_with_g40"] = "G21 F10\nG40 D1\nM2\n"
P["switch_exit_gouges"] = """G21 F100
G0 X-10 Y-10
G41 D3
G1 X0 Y0
G1 X30 Y0
G1 X30 Y5
G40 G1 X29 Y5
M2
"""
P["inch_run"] = """G20 F10
G0 X-1 Y-1
G42 D1
G1 X0 Y0
G1 Y2
G2 X2 Y2 R1
G1 Y0
G3 X0 Y0 I-1 J0
G40 G1 X-1 Y-1
M2
"""


@pytest.mark.parametrize("name", sorted(P))
def test_same_as_rs274(rs274, name):
    c = differential(P[name], TOOLS, machine_units="inch")
    assert c.same, f"{name}:\n{c}"
    if c.ours_error:
        assert c.ours_error[1] == c.their_error[1]


def test_most_programs_run_and_some_fail():
    """The set holds runs that complete and runs that stop at an error."""
    from millpath.interpret import run
    errors = {name: run(text, TOOLS).error for name, text in P.items()}
    assert sum(e is None for e in errors.values()) >= 4
    assert errors["switches"] is None
    for name in ("bad_arc_in_run", "spiral_arc_in_run", "gouge_in_run",
                 "arc_radius_under_tool_in_run", "switch_on_when_on", "switch_missing_tool",
                 "switch_d_with_g40", "switch_exit_gouges"):
        assert errors[name] is not None, name
