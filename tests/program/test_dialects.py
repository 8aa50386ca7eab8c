"""Programs for GRBL 1.1: what the post rewrites, what the reader refuses, and the motion
against independent readers (the npm package gcode-toolpath for the GRBL program,
LinuxCNC's rs274 for the LinuxCNC program of the same tool path).

GRBL rules covered, from GRBL 1.1's documented command list (gnea/grbl wiki, "Grbl v1.1
Commands"; the G-code list of its parser): no G5, no canned cycles (G73, G81-G89), no
cutter compensation (only G40), tool length only as G43.1 (no G43 H), no M6 (error 20),
no M7 in the default build, no parameters, expressions or O-words, no P word on G2/G3
(error 36), a line buffer of 80 characters with blanks and comments stripped (error
11), G0 motion mode at start, T words accepted and ignored, no program end required.
Not covered: GRBL's own arc end-point tolerance (looser than LinuxCNC's, which the reader
applies), G38 probing, soft limits, $ settings and real-time commands.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from millpath.interpret import InterpreterError, interpret
from millpath.model import Operation, Tool, Toolpath
from millpath.post.writer import PostOptions
from millpath.program import make_program
from millpath.simulate.tip import tip_motions
from support.gcodetoolpath import compare, our_moves, their_moves

TOOLS = {1: Tool(1, "flat", 6.0, length=40.0), 2: Tool(2, "drill", 5.0, length=65.0)}
TOL = 0.0002            # mm: the agreement with gcode-toolpath


def _job() -> Toolpath:
    """Lines, a quarter arc, a three-turn helix, a cubic, an XZ arc, then a tool change
    to a drill for a run of G83 and G81 holes with mist coolant."""
    tp = Toolpath("mm")
    tp.begin(Operation("pocket", "pocket", 1, 9000))
    tp.rapid(10, 10, 5)
    tp.line(10, 10, -1, 200)
    tp.line(30, 10, -1, 600)
    tp.arc((40, 20, -1), (30, 20, 0), False, 600)
    tp.arc((40, 20, -4), (35, 20, 0), True, 400, turns=3)
    tp.cubic((45, 30), (55, 10), (60, 25, -4), 600)
    tp.arc((70, 25, -4), (65, 25, -4), True, 600, plane="XZ")
    tp.rapid(70, 25, 5)
    tp.begin(Operation("drill", "holes", 2, 3000, coolant="mist"))
    tp.rapid(20, 40, 5)
    tp.drill(20, 40, -12, 2, 120, cycle="G83", peck=3)
    tp.drill(35, 40, -12, 2, 120, cycle="G83", peck=3)
    tp.drill(50, 40, -6, 2, 150, cycle="G81", retract_initial=True)
    tp.drill(65, 40, -2, 2, 150, cycle="G82", dwell=0.5)
    tp.rapid(65, 40, 10)
    return tp


def _grbl(tp: Toolpath, **kw):
    return make_program(tp, TOOLS, tolerance=0.001,
                        options=PostOptions(dialect="grbl", safe_z=5.0, **kw))


def test_grbl_program_holds_only_what_grbl_accepts_and_names_each_rewrite():
    prog = _grbl(_job())
    text = prog.text
    for word in ("G5 ", "G83", "G81", "M6", "G43 ", "M7", "P3"):
        assert word not in text, word
    assert "T2 M0" in text and "(MSG, load T2 drill D5" in text
    assert "G4 P0.5" in text                    # G82's dwell at the bottom
    assert any("G5 splines written as lines" in f for f in prog.fallbacks)
    assert any("G83 cycles written as moves" in f for f in prog.fallbacks)
    assert any("one turn per arc" in f for f in prog.fallbacks)
    assert any("mist coolant written as flood" in f for f in prog.fallbacks)
    # every block within GRBL's 80-character buffer, blanks and comments left out
    for ln in text.splitlines():
        if not ln.startswith("("):
            assert len(ln.replace(" ", "")) <= 79
    # and the reader, as GRBL, accepts it
    interpret(text, TOOLS, machine_units="mm", dialect="grbl")


def test_grbl_motion_equals_gcode_toolpath(gcode_toolpath):
    prog = _grbl(_job())
    ours = our_moves(interpret(prog.text, TOOLS, machine_units="mm", dialect="grbl"))
    theirs = their_moves(gcode_toolpath, prog.text)
    assert compare(ours, theirs, TOL) == []
    assert len(ours) > 40


def test_grbl_tool_change_runs_each_tool_at_its_tip():
    """The operator sets Z zero at each new tool's tip: the tip follows the program
    whatever the tools' lengths (40 and 65 mm here)."""
    prog = _grbl(_job())
    motions = interpret(prog.text, TOOLS, machine_units="mm", dialect="grbl")
    tips = tip_motions(motions, "mm")
    assert {m.tool for m in tips} >= {1, 2}
    for m, t in zip(motions, tips):
        assert np.allclose(m.end, t.end, atol=1e-9)


def test_cycles_as_moves_make_rs274s_motion(gcode_toolpath, rs274):
    """The G83/G81 run written as moves for GRBL (read by gcode-toolpath) moves as
    LinuxCNC's rs274 runs the canned cycles of the LinuxCNC program."""
    from support.rs274 import run_rs274
    tp = Toolpath("mm")
    tp.begin(Operation("drill", "holes", 2, 3000))
    tp.rapid(20, 40, 5)
    tp.drill(20, 40, -12.3, 2, 120, cycle="G83", peck=2.5)
    tp.drill(35, 40, -12.3, 2, 120, cycle="G83", peck=2.5)
    tp.drill(50, 45, -4, 1, 120, cycle="G73", peck=1.5, retract_initial=True)
    tp.drill(60, 45, -6, 3, 150, cycle="G85")
    tp.drill(70, 45, -6, 3, 150, cycle="G81", retract_initial=True)
    tp.rapid(70, 45, 10)
    linuxcnc = make_program(tp, TOOLS, options=PostOptions(safe_z=5.0))
    assert "G83" in linuxcnc.text
    theirs_lc = run_rs274(linuxcnc.text, TOOLS, table_units="mm")
    assert theirs_lc.ok, theirs_lc.error
    rs = [("G0" if m.kind == "traverse" else "G1",
           tuple(v for v in m.end), "G17", None)
          for m in theirs_lc.motions if m.kind in ("traverse", "feed")]
    grbl = _grbl(tp)
    assert "G83" not in grbl.text
    assert compare(rs, their_moves(gcode_toolpath, grbl.text), TOL) == []


def test_helix_turns_split_by_angle():
    """Three turns of a helix from Z -1 to -4 about (35, 20) from (40, 20): three
    full circles ending at Z -2, -3, -4 (equal angles, equal rise)."""
    tp = Toolpath("mm")
    tp.begin(Operation("pocket", "p", 1, 9000))
    tp.rapid(40, 20, 5)
    tp.line(40, 20, -1, 200)
    tp.arc((40, 20, -4), (35, 20, 0), True, 400, turns=3)
    arcs = [m for m in _grbl(tp).toolpath.moves if m.kind == "arc"]
    assert [round(m.end[2], 9) for m in arcs] == [-2.0, -3.0, -4.0]
    assert all(m.turns == 1 and m.end[:2] == (40, 20) for m in arcs)


def test_spline_lines_stay_within_the_tolerance():
    """Every point of the cubic lies within the tolerance of the lines written for it
    (the curve sampled at 2001 parameters, distance to the polyline)."""
    tp = Toolpath("mm")
    tp.begin(Operation("pocket", "p", 1, 9000))
    tp.rapid(0, 0, 1)
    tp.line(0, 0, -1, 200)
    P = [(0.0, 0.0), (10.0, 40.0), (50.0, -30.0), (60.0, 10.0)]
    tp.cubic(P[1], P[2], (P[3][0], P[3][1], -1), 500)
    lines = [m.end[:2] for m in _grbl(tp).toolpath.moves[2:]]
    poly = np.array([(0.0, 0.0)] + lines)
    t = np.linspace(0, 1, 2001)[:, None]
    B = ((1 - t) ** 3 * P[0] + 3 * (1 - t) ** 2 * t * P[1] + 3 * (1 - t) * t ** 2 * P[2]
         + t ** 3 * P[3])
    a, b = poly[:-1], poly[1:]
    ab = b - a
    u = np.clip(np.einsum("kij,ij->ki", B[:, None, :] - a[None], ab) / (ab ** 2).sum(1), 0, 1)
    near = a[None] + u[..., None] * ab[None]
    dist = np.sqrt(((B[:, None, :] - near) ** 2).sum(-1)).min(1)
    assert dist.max() <= 0.001 + 1e-9
    # and not many more lines than chords of the curve's own curvature need: a chord of
    # length h on radius r strays h^2 / (8 r), so about the integral of
    # sqrt(k / (8 tol)) ds chords suffice
    t = t[:, 0]
    d1 = (3 * (1 - t) ** 2)[:, None] * np.subtract(P[1], P[0]) + \
        (6 * (1 - t) * t)[:, None] * np.subtract(P[2], P[1]) + \
        (3 * t ** 2)[:, None] * np.subtract(P[3], P[2])
    d2 = (6 * (1 - t))[:, None] * (np.add(P[2], P[0]) - 2 * np.array(P[1])) + \
        (6 * t)[:, None] * (np.add(P[3], P[1]) - 2 * np.array(P[2]))
    speed = np.hypot(d1[:, 0], d1[:, 1])
    k = np.abs(d1[:, 0] * d2[:, 1] - d1[:, 1] * d2[:, 0]) / speed ** 3
    need = np.trapezoid(np.sqrt(k / (8 * 0.001)) * speed, t[:])
    assert len(lines) <= 2 * need + 4, (len(lines), need)


@pytest.mark.parametrize("block, why", [
    ("G5 X1 Y1 I1 J1 P1 Q1", "G5"),
    ("G81 X1 Y1 Z-1 R1 F10", "G81"),
    ("T1 M6", "M6"),
    ("M7", "M7"),
    ("G43 H1", "G43"),
    ("G41 D1", "G41"),
    ("#1 = 2", "no parameters"),
    ("o100 sub", "O-words"),
    ("G1 X1 F10\nG2 X1 Y0 I1 J0 P2", "a P word on an arc"),
    ("G1 X1000.00001 Y1000.00001 Z1000.00001 (comments do not count) F10000.00001 "
     "S100000.00001 T1234567890123456789012", "83 characters, more than its 79"),
])
def test_grbl_reader_refuses_what_grbl_refuses(block, why):
    with pytest.raises(InterpreterError, match=why) as e:
        interpret(block, dialect="grbl")
    assert e.value.line == block.count("\n") + 1


def test_grbl_reader_reads_what_linuxcnc_does_not():
    """GRBL starts in G0 and needs no program end; a T word is no tool change."""
    ms = interpret("G21\nX10 Y5\nT3\nG1 Z-1 F100\n", dialect="grbl")
    assert [(m.kind, m.end) for m in ms] == [("traverse", (10.0, 5.0, 0.0)),
                                            ("feed", (10.0, 5.0, -1.0))]
    with pytest.raises(InterpreterError):
        interpret("G21\nX10 Y5\n")                 # LinuxCNC: no motion mode, no end


CORPUS = {
    "inch, G91 incremental, R arcs": """G20 G90 G17
G0 X1 Y1 Z0.2
G1 Z-0.05 F10
G91 G1 X0.5 F20
G2 X0.5 Y0.5 R0.5
G3 X-0.5 Y0.5 R-0.5
G90 G0 Z0.2
M30
""",
    "XZ and YZ arcs, full circle, helix": """G21 G90
G0 X0 Y0 Z5
G1 Z0 F300
G18 G2 X10 Z0 I5 K0
G19 G3 Y10 Z0 J5 K0
G17 G2 X10 Y10 I-5 J0
G3 X10 Y10 Z-3 I0 J5
G0 Z5
""",
    "work offset G55, comments of both kinds": """G21 G55 (work two)
G0 X5 Y5 ; to the start
G1 Z-1 F100
G1 X25 Y5
G2 X25 Y25 I0 J10
M2
""",
}


@pytest.mark.parametrize("name", sorted(CORPUS))
def test_grbl_corpus_equals_gcode_toolpath(name, gcode_toolpath):
    text = CORPUS[name]
    ours = our_moves(interpret(text, dialect="grbl"))
    assert compare(ours, their_moves(gcode_toolpath, text), TOL) == []


def test_full_circle_angle_for_reference():
    """The split's rise per turn follows the angle: a quarter arc plus two turns."""
    tp = Toolpath("mm")
    tp.begin(Operation("pocket", "p", 1, 9000))
    tp.rapid(10, 0, 1)
    tp.line(10, 0, 0, 100)
    tp.arc((0, 10, -9), (0, 0, 0), False, 100, turns=3)
    arcs = [m for m in _grbl(tp).toolpath.moves if m.kind == "arc"]
    total = 2 * 2 * math.pi + math.pi / 2
    assert [round(m.end[2], 9) for m in arcs] == [round(-9 * 2 * math.pi / total, 9),
                                                 round(-9 * 4 * math.pi / total, 9), -9.0]


def test_check_reads_each_dialect(tmp_path):
    """``millpath check --dialect grbl`` reads a GRBL program that LinuxCNC refuses (no
    motion mode at the first move), and refuses, naming the line, a block GRBL lacks."""
    from click.testing import CliRunner
    from millpath.cli.main import cli
    f = tmp_path / "part.nc"
    f.write_text("G21\nX10 Y5\nG1 Z-1 F100\nG2 X20 Y5 I5 J0\n")
    r = CliRunner().invoke(cli, ["check", str(f), "--dialect", "grbl"])
    assert r.exit_code == 0, r.output
    assert "4 moves" in r.output or "3 moves" in r.output
    r = CliRunner().invoke(cli, ["check", str(f)])
    assert r.exit_code == 1
    f.write_text("G21\nG0 X10 Y5\nG81 Z-3 R1 F100\n")
    r = CliRunner().invoke(cli, ["check", str(f), "--dialect", "grbl"])
    assert r.exit_code == 1
    assert f"{f}:3: GRBL 1.1 does not accept this block: G81" in r.output


# --- Fanuc 0i, Haas, Mach3/4 -----------------------------------------------------------
# Fanuc rules covered (FANUC Series 0i-MF programming manual: decimal point programming,
# dwell, canned cycles, program number): a length word without a decimal point counts
# least input increments (0.001 mm / 0.0001 in) -- the writer puts a point in every
# length, the reader scales bare numbers; dwell P (G04, G82, G89) in milliseconds; the
# program between % lines headed by O<n>; no G91.1 (I J K incremental), no G5, no P turns
# on arcs, no M7. Not covered: macro B (#) variables, G54.1 P extended offsets, G68
# rotation, G05.1 AI contour control, parameter-dependent modal defaults.

def _words_without_point(text: str) -> list[str]:
    import re
    bad = []
    for ln in text.splitlines():
        if ln.startswith(("(", "%", "O")):
            continue
        code = re.sub(r"\([^)]*\)", "", ln)
        bad += [w for w in re.findall(r"[XYZIJKRQ][-+]?[0-9.]+", code) if "." not in w]
    return bad


@pytest.mark.parametrize("name", ["fanuc", "haas", "mach3"])
def test_program_reads_back_as_rs274_reads_the_linuxcnc_one(name, rs274):
    """The same tool path written for the control and for LinuxCNC: millpath reading
    the control's program as that control does moves as LinuxCNC's rs274 moves for the
    LinuxCNC program (lines, arcs, helices cut per turn, cycles, dwells)."""
    from support.rs274 import run_rs274
    from support.difftest import compare_motions
    tp = _job()
    tp.moves = [m for m in tp.moves if m.kind != "cubic"]       # G5: lines, compared below
    prog = make_program(tp, TOOLS, options=PostOptions(dialect=name, safe_z=5.0))
    ours = interpret(prog.text, TOOLS, machine_units="mm", dialect=name)
    lc = make_program(prog.toolpath, TOOLS, options=PostOptions(safe_z=5.0))
    theirs = run_rs274(lc.text, TOOLS, table_units="mm")
    assert theirs.ok, theirs.error
    assert compare_motions(ours, theirs.motions, 1.5e-4) == []
    assert "G83" in prog.text and "G5 " not in prog.text and " P3" not in prog.text
    if name in ("fanuc", "haas"):
        assert prog.text.startswith("%\nO0001\n") and prog.text.endswith("%\n")
        assert "G91.1" not in prog.text
        assert _words_without_point(prog.text) == []
    else:
        assert "G91.1" in prog.text and "M7" in prog.text


def test_fanuc_reads_bare_numbers_as_increments_and_dwell_in_ms():
    """X10 is 0.010 mm (0.0010 in after G20); I5000 is 5 mm; G04 P1500 and a G82's
    P1500 dwell 1.5 s; the O number line is the program's name."""
    text = ("%\nO0012 (part)\nG21 G17 G90\nG0 X10 Y5. Z5.\nG1 Z-1. F100\nG4 P1500\n"
            "G82 X20. Y5. Z-3. R1. P1500 F100\nG80\nG2 X30. Y5. I5000 J0\n"
            "G20\nG0 X10\nM30\n%\n")
    ms = interpret(text, dialect="fanuc")
    assert ms[0].end == pytest.approx((0.010, 5.0, 5.0))
    dwells = [m.dwell for m in ms if m.kind == "dwell"]
    assert dwells == [1.5, 1.5]
    arc = next(m for m in ms if m.kind == "arc")
    assert arc.center[:2] == pytest.approx((25.0, 5.0)) and arc.end[0] == pytest.approx(30.0)
    assert ms[-1].end[0] == pytest.approx(0.0010)               # inch, program units
    with pytest.raises(InterpreterError, match="G91.1"):
        interpret("%\nO1\nG91.1\nM30\n%\n", dialect="fanuc")


def test_machine_file_holds_a_shops_post_settings(tmp_path):
    """``[post] machine = "shop/haas.toml"``: that file's [post] and [machine] keys,
    under the job's own; an unknown key there is an error naming the machine file and
    its key."""
    from millpath.errors import JobErrors
    from millpath.job.jobfile import load_job
    src = Path(__file__).resolve().parents[2] / "millpath" / "examples" / "pocket-thesis"
    job = tmp_path / "job.toml"
    job.write_text((src / "job.toml").read_text()
                   + '\n[post]\nmachine = "shop/haas.toml"\nend = "M2"\n')
    (tmp_path / "shop").mkdir()
    (tmp_path / "shop" / "haas.toml").write_text(
        '[post]\ndialect = "haas"\nline_numbers = true\nend = "M30"\n'
        '[machine]\nrapid = 25400\nmax_feed = 16510\n')
    loaded = load_job(job)
    post = loaded.post
    assert (post["dialect"], post["line_numbers"], post["end"]) == ("haas", True, "M2")
    assert "machine" not in post
    assert (loaded.machine.rapid, loaded.machine.max_feed) == (25400, 16510)
    (tmp_path / "shop" / "haas.toml").write_text('[post]\ndialect = "haas"\nspeed = 3\n')
    with pytest.raises(JobErrors) as e:
        load_job(job)
    assert "haas.toml" in str(e.value) and "speed" in str(e.value)
