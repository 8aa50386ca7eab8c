"""Error messages and blocks: each program fails (or not) exactly as rs274 does, with
rs274's wording."""

from __future__ import annotations

import pytest

from millpath.interpret.difftest import differential
from millpath.io.tooltable import ToolEntry

TOOLS = [ToolEntry(1, 1, 0.25, {"Z": 1.0}), ToolEntry(2, 2, -0.1, {"Z": 0.5, "X": 0.1})]

PROGRAMS = [
 "G21\nG0 X[1 +]\nM2", "G21\nG0 X[1 foo 2]\nM2", "G21\nG0 X[1\nM2", "G21\nG0 X#\nM2", "G21\nG0 X#0\nM2",
 "G21\nG0 X#6000\nM2", "G21\n#1 2\nM2", "G21\nG0 X#<nope>\nM2", "G21\nG0 X[sqrt[-1]]\nM2", "G21\nG0 X[ln[0]]\nM2",
 "G21\nG0 X[acos[2]]\nM2", "G21\nG0 X[asin[2]]\nM2", "G21\nG0 X[[-8]**0.5]\nM2", "G21\nG0 X[atan[1]]\nM2",
 "G21\nG0 X[atan[1]/2]\nM2", "G21\nG0 X[bogus[1]]\nM2", "G21\nG0 X[sin 1]\nM2", "G21\nG-1\nM2", "G21\nG1000\nM2",
 "G21\nG1.55\nM2", "G21\nM-1\nM2", "G21\nM1.5\nM2", "G21\nM3 M5\nM2", "G21\nM1 M2 M3 M7 M48\nM2",
 "G21\nF-1\nM2", "G21\nS-1\nM2", "G21\nT-1\nM2", "G21\nG43 H-1\nM2", "G21\nG81 L-1\nM2", "G21\nT1.5\nM2",
 "G21\nG0 X1 $1\nM2", "G21\nG0 X1 &\nM2", "G21\nN5 G0 X1 N6\nM2", "G21\nG0 X1 (a (b) c)\nM2",
 "G21\nG4\nM2", "G21\nG4 P1 G2 X1 R1 F1\nM2", "G21\nG10 L3 P1\nM2", "G21\nG10 L2 P10 X1\nM2", "G21\nG10 L2 P1.5 X1\nM2",
 "G21\nG10 L1 P1\nM2", "G21\nG53 G2 X1\nM2", "G21\nG91 G53 G0 X1\nM2", "G21\nG0 D1\nM2", "G21\nG0 E1\nM2",
 "G21\nG0 H1\nM2", "G21\nG0 I1\nM2", "G21\nG0 J1\nM2", "G21\nG0 K1\nM2", "G21\nG0 L1\nM2", "G21\nG0 P1\nM2",
 "G21\nG0 R1\nM2", "G21\nG2 X1 Y1 R1 F1 P0\nM2", "G21\nG92\nM2", "G21\nG52\nM2", "G21 F1\nG2 X1 Y1 I1 J0 K1\nM2",
 "G21 F1\nG18 G2 X1 Z1 J1\nM2", "G21 F1\nG19 G2 Y1 Z1 I1\nM2", "G21 F1\nG18 G2 Y1 R1\nM2", "G21 F1\nG19 G2 X1 R1\nM2",
 "G21 F1\nG90.1 G2 X1 Y1 I1\nM2", "G21 F1\nG90.1 G2 X1 Y1 J1\nM2", "G21 F1\nG0 X0\nG2 X0 Y0 R1\nM2",
 "G21 F1\nG93 G2 X1 Y1 R1\nM2", "G21\nG1 X1 G93\nM2", "G21 F1\nG81 X1 Z-1 R1 G93\nM2", "G21 F1\nG18 G81 X1 Z-1 R1\nM2",
 "G21 F1\nG19 G81 X1 Z-1 R1\nM2", "G21 F1\nG18 G81 Y-1 R-2\nM2", "G21 F1\nG19 G81 X-1 R-2\nM2",
 "G21 F1\nG82 Z-1 R1\nM2", "G21 F1\nG89 Z-1 R1\nM2", "G21 F1\nG73 Z-1 R1\nM2", "G21 F1\nG83 Z-1 R1 Q-1\nM2",
 "G21 F1\nG81 Z-1 R1 A1\nM2", "G21 F1\nG5 X1 Y1 I1 J1\nM2", "G21 F1\nG5 X1 Y1 Z1 P1 Q1\nM2", "G21 F1\nG18 G5 X1 Y1 P1 Q1\nM2",
 "G21 F1\nG5.1 X1 Y1 I1\nM2", "G21 F1\nG41 D1\nG5 X1 Y1 I1 J1 P1 Q1\nM2", "G21\nG41.1\nM2", "G21\nG41 D-1\nM2",
 "G21\nG41 D1\nG17\nG54\nM2", "G21\nG41 D1\nG61\nM2", "G21\nG41 D1\nG98\nM2", "G21\nG41 D1\nG28\nM2",
 "G21\nG41 D1\nM48\nM2", "G21\nG41 D1\nM49\nM2", "G21\nG41 D1\nG10 L2 P1 X1\nM2", "G21\nG41 D1\nG10 L2 P2 X1\nM2",
 "G21\nG41 D1\nG28.1\nM2", "G21 F1\nG0 X0 Y0\nG41 D1\nG1 X0.1\nM2", "G21 F1\nG0 X0 Y0\nG41 D1\nG2 X0.1 Y0 R0.05\nM2",
 "G21\nM61\nM2", "G21\nM61 Q9\nM2", "G21\nG43.2\nM2", "G21\nG96\nM2", "G21\n%\nM2",
 "G21\nG0 X1\nM2\nG0 X2", "%\nG21\nG0 X1\n%\nG0 X2\n", "%\nG21\nG0 X1\n", "G21\nG0 X1 Y2 Z3 X4\nM2",
 "G21\nG17 G18\nM2", "G21\nG20 G21\nM2", "G21\nG90 G91\nM2", "G21\nG54 G55\nM2", "G21\nM7 M8\nM2", "G21\nM6 M61 Q1\nM2",
 "G21\nG0 X1 G1 Y1\nM2", "G21\nG10 G92 X1\nM2", "G21\nG4 P1 G92 X1\nM2",
]


@pytest.mark.parametrize("program", PROGRAMS)
def test_error_same_block_and_message_as_rs274(rs274, program):
    c = differential(program + "\n", TOOLS, machine_units="inch")
    assert c.same, f"{program!r}\n{c}"
    assert (c.ours_error is None) == (c.their_error is None)
    if c.ours_error:
        assert c.ours_error[1] == c.their_error[1]
