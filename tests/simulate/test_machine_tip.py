"""The proof follows the tool tip as the machine moves it.

Truths: LinuxCNC's rs274 for where the controlled point goes (its canonical calls with
the G5x, G92, XY-rotation and tool length offsets they carry, combined as LinuxCNC's
emccanon does), and analytic depths on box-shaped designs for what the tip then cuts:
the tip is the controlled point minus the table length of the tool really in the
spindle, whatever H word the program gave.
"""

from __future__ import annotations

import importlib.util
import sys

import pytest

from millpath.interpret import interpret
from millpath.io.tooltable import ToolEntry
from millpath.model import Machine, Stock, Tool
from millpath.simulate import BoxDesign, simulate_motions
from millpath.simulate.approach import approach_from_above
from millpath.simulate.tip import tip_motions

ACC = 0.001                     # the exact check's accuracy (mm)
# real lengths: T1 50 mm, T2 50.54 mm, T3 49.46 mm
TABLE = [ToolEntry(1, 1, 6.0, {"Z": 50.0}), ToolEntry(2, 2, 6.0, {"Z": 50.54}),
         ToolEntry(3, 3, 6.0, {"Z": 49.46})]
SHAPES = {n: Tool(n, "flat", 6.0, flute_length=20, stickout=40) for n in (1, 2, 3)}
STOCK = Stock(0, 0, -10, 60, 40, 0)
# a pocket 40 x 20 x 5 deep, walls at x 10 and 50, y 10 and 30
POCKET = BoxDesign(0.0, [(10, 10, 50, 30, -5)])


def _gouge(program: str, design=POCKET, units: str = "mm") -> float:
    motions = interpret(program, TABLE, machine_units="mm")
    tips = approach_from_above(tip_motions(motions, units), STOCK.zmax)
    res = simulate_motions(tips, SHAPES, STOCK, resolution=0.25, design=design,
                           machine=Machine(), accuracy=ACC)
    return res.exact.max_gouge


# the pocket's wall pass: the tool 3 mm from the wall at y 10, floor depth
WALL = """G1 Z-5 F200
G1 X47 F600
G1 Y27
G1 X13
G1 Y13
G0 Z5
"""
START = "G21 G17 G90\nT1 M6\nG43 H1\nG0 X13 Y13 Z5\n"


def test_clean_program_reads_no_gouge():
    assert _gouge(START + WALL + "M2\n") <= ACC


@pytest.mark.parametrize("head, depth", [
    ("T1 M6\nG43 H3\n", 0.54),          # G43 with another tool's H: 0.54 mm longer in truth
    ("T2 M6\nG43 H1\n", 0.54),          # M6 of a longer tool, G43 left from the last one
    ("T3 M6\nG43 H3\nT2 M6\n", 1.08),   # M6 with no G43 after it
])
def test_the_tool_really_in_the_spindle_sets_the_depth(head, depth):
    prog = "G21 G17 G90\n" + head + "G0 X13 Y13 Z5\n" + WALL + "M2\n"
    assert _gouge(prog) == pytest.approx(depth, abs=ACC)


def test_first_move_after_a_tool_change_starts_where_the_machine_is():
    """T1 stops on the floor beside a 10 mm wide wall (a boss from x 20 to 30, 5 mm
    high); after the change the first move crosses the boss at the floor's depth: the
    tool's underside passes 5 mm below the boss top and 5 mm in from its sides.
    Taken as a drop from above at its end, it read 0."""
    boss = BoxDesign(-5.0, [(20, -100, 30, 100, 0.0)])
    prog = ("G21 G17 G90\nT1 M6\nG43 H1\nG0 X10 Y20 Z5\nG1 Z-5 F200\n"
            "T1 M6\nG43 H1\nG1 X40 F300\nG0 Z5\nM2\n")
    assert _gouge(prog, boss) == pytest.approx(5.0, abs=ACC)
    # the same motion without the tool change: the same figure
    plain = "G21 G17 G90\nT1 M6\nG43 H1\nG0 X10 Y20 Z5\nG1 Z-5 F200\nG1 X40 F300\nG0 Z5\nM2\n"
    assert _gouge(plain, boss) == pytest.approx(5.0, abs=ACC)


@pytest.mark.parametrize("frame", ["G92 X1", "G52 X-1", "G10 L2 P1 X-1", "G10 L20 P1 X1"])
def test_frames_shift_the_cut(frame):
    """Each shift moves the wall pass 1 mm towards the wall at x 10: 1 mm deep."""
    prog = "G21 G17 G90\nT1 M6\nG43 H1\n" + frame + "\nG0 X13 Y13 Z5\n" + WALL + "M2\n"
    assert _gouge(prog) == pytest.approx(1.0, abs=ACC)


def test_rotation_of_the_work_system_turns_the_cut():
    """G10 L2 R turns the pass about the origin: the corner at (47, 27) turned by 1
    degree lands at x 46.52, y 27.82: 0.82 mm into the wall at y 30 (with the tool's 3 mm
    radius, the tool reaches y 30.82)."""
    prog = "G21 G17 G90\nT1 M6\nG43 H1\nG10 L2 P1 R1\nG0 X13 Y13 Z5\n" + WALL + "M2\n"
    import math
    t = math.radians(1.0)
    depth = max(47 * math.sin(t) + 27 * math.cos(t), 13 * math.sin(t) + 27 * math.cos(t)) + 3 - 30
    assert _gouge(prog) == pytest.approx(depth, abs=ACC)


def test_units_switch_mid_program():
    """After a G20 block X1.8 means 45.72 mm: the tool's edge reaches 48.72 mm, short
    of the wall at x 50; X1.9 (48.26 mm, edge at 51.26) cuts 1.26 mm into it."""
    body = "G1 Z-5 F200\nG20\nG1 X{x} F20\nG21\nG0 Z5\nM2\n"
    assert _gouge(START + body.format(x=1.8)) <= ACC
    assert _gouge(START + body.format(x=1.9)) == pytest.approx(1.9 * 25.4 + 3 - 50, abs=ACC)


def test_preamble_shift_in_a_job_is_refused(tmp_path):
    """A bundled features job with a one-line preamble that shifts the frame by 1 mm is
    refused by the proof (its hole walls are cut 1 mm oversize)."""
    from pathlib import Path

    from millpath.pipeline import run_job
    from millpath.verify.gate import UnsafeProgramError
    src = Path(__file__).resolve().parents[2] / "millpath" / "examples" / "features-holes-slot"
    job = next(src.glob("*.toml"))
    text = job.read_text()
    assert "[post]" not in text
    for f in src.iterdir():
        if f.is_file():
            (tmp_path / f.name).write_text(f.read_text()) if f.suffix != ".stp" else \
                (tmp_path / f.name).write_bytes(f.read_bytes())
    (tmp_path / job.name).write_text(text + '\n[post]\npreamble = "G92 X1"\n')
    with pytest.raises(UnsafeProgramError) as e:
        run_job(tmp_path / job.name, tmp_path / "out", pictures=False)
    assert "gouge" in str(e.value)


# --------------------------------------------------------------------- against rs274
FRAMES = """G21 G90
T1 M6
G43 H1
G0 X10 Y5 Z20
G92 X1
G1 X20 F300
G52 X-3 Y2
G1 Y10
G10 L2 P1 X5 Y-2 R30
G1 X30 Y12
G2 X40 Y12 I5 J0
G18 G3 X50 Z20 I5 K0
G17
G92.1
G52 X0 Y0
G10 L2 P1 X0 Y0 R0
G20
G1 X1 Y1 Z0.5
G21
T2 M6
G1 X5 Y5
G43 H3
G1 X6
G43 H2
G1 X7
G55
G10 L2 P2 X2 Y3 Z-1
G1 X8
G49
G1 X9
M2
"""


def _oracle(shared_dir):
    path = shared_dir / "tools" / "rs274_oracle.py"
    if not path.is_file():
        pytest.skip("shared/tools/rs274_oracle.py missing")
    spec = importlib.util.spec_from_file_location("rs274_oracle", path)
    mod = importlib.util.module_from_spec(spec)
    sys.modules["rs274_oracle"] = mod          # its dataclasses look themselves up there
    spec.loader.exec_module(mod)
    return mod


def test_controlled_point_matches_rs274(rs274, shared_dir, tmp_path):
    """Each block's end, as rs274 puts the controlled point (G5x + G92 + rotation +
    tool length offset, its 4 decimals), equals millpath's tip plus the table offsets of
    the tool in the spindle, through G92, G52, G10 L2 with R, G55, a G20 block, M6 with
    and without G43, and G43 with another tool's H."""
    oracle = _oracle(shared_dir)
    tbl = tmp_path / "t.tbl"
    tbl.write_text("T1 P1 D0.25 Z1.0\nT2 P2 D0.25 Z2.5\nT3 P3 D0.25 Z1.75\n")   # inches
    ngc = tmp_path / "p.ngc"
    ngc.write_text(FRAMES)
    ref = oracle.run_rs274(str(ngc), str(tbl))
    assert ref.ok, ref.error
    ours = list(interpret(FRAMES, str(tbl), machine_units="inch"))
    tips = tip_motions(ours, "mm")
    last, frame, lines = {}, {}, []
    for m in ours:
        frame[m.line] = m.frame
        if not lines or lines[-1] != m.line:
            lines.append(m.line)
    for t in tips:
        last[t.line] = t
    theirs = [m for m in ref.motions if m.kind in ("traverse", "feed", "arc")]
    assert len(theirs) == len(lines) >= 12
    worst = 0.0
    for o, line in zip(theirs, lines):
        k = 25.4 if o.units == "in" else 1.0
        want = [v * k for v in o.machine_end]
        f = frame[line]
        got = [last[line].end[i] + f.tool_mm[i] for i in range(3)]
        worst = max(worst, max(abs(a - b) for a, b in zip(want, got)))
    assert worst <= 0.0001 * 25.4 / 2 + 1e-9      # rs274 prints 4 decimals (inch)


def test_tool_library_units(tmp_path):
    """A TOML library in inches read for a mm program: a 1/4 in tool is 6.35 mm."""
    from millpath.io.toollib import read_tool_library
    p = tmp_path / "lib.toml"
    p.write_text('units = "inch"\n[[tools]]\nnumber = 1\ntype = "bull"\ndiameter = 0.25\n'
                 'corner_radius = 0.03\nflute_length = 0.75\nstickout = 1.25\n'
                 'holder = [[1.0, 2.0]]\n')
    t = read_tool_library(p, units="mm")[1]
    assert t.diameter == pytest.approx(6.35)
    assert t.corner_radius == pytest.approx(0.762)
    assert t.gauge_length == pytest.approx(3.25 * 25.4)
    assert t.holder == [pytest.approx((25.4, 50.8))]
    back = read_tool_library(p, units="inch")[1]
    assert back.diameter == pytest.approx(0.25)


# ------------------------------------------- rs274's motion against OpenCASCADE solids
MOVES = ("STRAIGHT_TRAVERSE", "STRAIGHT_FEED", "STRAIGHT_PROBE", "ARC_FEED", "RIGID_TAP",
         "DWELL")
INCH_TABLE = {1: 2.0, 2: 2.02, 3: 1.98}           # tool lengths (inch), D 6 mm


def _oracle_depth(oracle, ngc, tbl, design_solid) -> float:
    """The deepest cut of the program's moves after its first, from rs274's controlled
    points minus the length of the tool in the spindle (its CHANGE_TOOL calls; a move
    after a change starts from the last controlled point with the new tool), each
    move's sweep measured against the design solid by OpenCASCADE."""
    from support.occ_oracle import move_depth
    ref = oracle.run_rs274(str(ngc), str(tbl))
    assert ref.ok, ref.error
    motions = iter(ref.motions)
    tool, prev, worst = 0, None, 0.0
    for name, args in ref.canon:
        if name == "CHANGE_TOOL":
            tool = int(float(args))
        elif name in MOVES:
            m = next(motions)
            if m.kind == "dwell":
                continue
            k = 25.4 if m.units == "in" else 1.0
            L = INCH_TABLE.get(tool, 0.0) * 25.4     # the tool in the spindle now
            ctrl = (m.machine_end[0] * k, m.machine_end[1] * k, m.machine_end[2] * k)
            if prev is not None:                  # a tool change happens in place
                worst = max(worst, move_depth(design_solid, (prev[0], prev[1], prev[2] - L),
                                              (ctrl[0], ctrl[1], ctrl[2] - L), 3.0, 20.0))
            prev = ctrl
    return worst


OCC_CASES = {
    "clean": START + WALL,
    "wrong H": "G21 G17 G90\nT1 M6\nG43 H3\nG0 X13 Y13 Z5\n" + WALL,
    "longer tool, old G43": "G21 G17 G90\nT2 M6\nG43 H1\nG0 X13 Y13 Z5\n" + WALL,
    "M6 without G43": "G21 G17 G90\nT3 M6\nG43 H3\nT2 M6\nG0 X13 Y13 Z5\n" + WALL,
    "G92": START.replace("G0 X13", "G92 X1\nG0 X13") + WALL,
    "G52": START.replace("G0 X13", "G52 X-1.5\nG0 X13") + WALL,
    "G10 L2": START.replace("G0 X13", "G10 L2 P1 X-0.7\nG0 X13") + WALL,
    "G10 L2 R": START.replace("G0 X13", "G10 L2 P1 R1\nG0 X13") + WALL,
    # inch numbers rs274 prints exactly (4 decimals): the pass 0.08 mm below the floor
    "G20 block": START.replace("X13 Y13", "X15.24 Y15.24")
    + "G1 Z-5 F200\nG20\nG1 Z-0.2 F20\nG1 X1.9\nG21\nG0 Z5\n",
}


@pytest.mark.parametrize("case", list(OCC_CASES))
def test_gouge_matches_rs274_motion_against_opencascade(case, rs274, shared_dir, tmp_path):
    """millpath's proof of each program equals the depth OpenCASCADE measures between
    the design solid and the flat end mill swept along rs274's motion, the tip placed
    by the length of the tool really in the spindle (within the proof's accuracy and
    rs274's 4 printed decimals)."""
    from support.occ_oracle import BoxCut
    oracle = _oracle(shared_dir)
    program = OCC_CASES[case] + "M2\n"
    ngc, tbl = tmp_path / "p.ngc", tmp_path / "t.tbl"
    ngc.write_text(program)
    tbl.write_text("".join(f"T{n} P{n} D{6 / 25.4:.6f} Z{z}\n" for n, z in INCH_TABLE.items()))
    # the part goes on below the stock's bottom: no surface there
    solid = BoxCut((0, 0, -1000, 60, 40, 0), [(10, 10, -5, 50, 30, 1)])
    truth = _oracle_depth(oracle, ngc, tbl, solid)
    motions = interpret(program, str(tbl), machine_units="inch")
    tips = approach_from_above(tip_motions(motions, "mm"), STOCK.zmax)
    shapes = {n: Tool(n, "flat", 6.0, flute_length=20, stickout=40) for n in INCH_TABLE}
    res = simulate_motions(tips, shapes, STOCK, resolution=0.25, design=POCKET,
                           machine=Machine(), accuracy=ACC)
    got = res.exact.max_gouge
    if case == "clean":
        assert truth == 0.0 and got <= ACC
    else:
        assert truth > 0.3
        assert got == pytest.approx(truth, abs=ACC + 5e-5)


def test_first_move_after_a_tool_change_against_opencascade(rs274, shared_dir, tmp_path):
    """The boss crossed right after a tool change in place: the new tool is 0.508 mm
    longer and its G43 leaves the tip where the change put it, 5.508 mm down; its
    deepest point is 5.026 mm from the boss (the foot of its wall). OpenCASCADE's depth
    of rs274's motion and millpath's proof agree."""
    from support.occ_oracle import BoxCut
    oracle = _oracle(shared_dir)
    program = ("G21 G17 G90\nT1 M6\nG43 H1\nG0 X10 Y20 Z5\nG1 Z-5 F200\n"
               "T2 M6\nG43 H2\nG1 X40 F300\nG0 Z5\nM2\n")
    ngc, tbl = tmp_path / "p.ngc", tmp_path / "t.tbl"
    ngc.write_text(program)
    tbl.write_text("".join(f"T{n} P{n} D{6 / 25.4:.6f} Z{z}\n" for n, z in INCH_TABLE.items()))
    solid = BoxCut((0, 0, -1000, 60, 40, 0),
                   [(-1, -1, -5, 20, 41, 1), (30, -1, -5, 61, 41, 1)])
    truth = _oracle_depth(oracle, ngc, tbl, solid)
    motions = interpret(program, str(tbl), machine_units="inch")
    tips = approach_from_above(tip_motions(motions, "mm"), STOCK.zmax)
    shapes = {n: Tool(n, "flat", 6.0, flute_length=20, stickout=40) for n in INCH_TABLE}
    boss = BoxDesign(-5.0, [(20, -100, 30, 100, 0.0)])
    res = simulate_motions(tips, shapes, STOCK, resolution=0.25, design=boss,
                           machine=Machine(), accuracy=ACC)
    assert truth == pytest.approx((5 ** 2 + 0.508 ** 2) ** 0.5, abs=1e-4)
    assert res.exact.max_gouge == pytest.approx(truth, abs=ACC + 5e-5)


def test_rs274_motion_carries_the_tool_number_not_its_slot(rs274, tmp_path):
    """rs274 prints CHANGE_TOOL with the tool table's slot; the motion read back carries
    the number SELECT_TOOL named, as millpath's interpreter does."""
    from support.rs274 import run_rs274
    tbl = tmp_path / "t.tbl"
    tbl.write_text("T9 P9 D6 Z40 ;\nT10 P10 D12 Z50 ;\n")
    ngc = tmp_path / "p.ngc"
    ngc.write_text("G21\nT10 M6 G43\nG0 X1 Y0 Z60\nT9 M6 G43\nG0 X2 Y0 Z60\nM2\n")
    r = run_rs274(ngc, tbl, table_units="mm")
    assert r.ok, r.error
    theirs = [m.tool for m in r.motions if m.kind == "traverse"]
    ours = [m.tool for m in interpret(ngc.read_text(), str(tbl), machine_units="mm")
            if m.kind == "traverse"]
    assert theirs[-1] == 9 and 10 in theirs
    assert theirs == ours
