"""Every bundled example: LinuxCNC's rs274 runs its program
with the tool table written for each [machine] units setting, its compensated motion
equals millpath's interpretation; after each tool change the first motion rises
straight to the safe height before any XY move, and no end mill goes straight down
into material (Z-map simulation of the motion before each vertical feed); its program
written for each other control is read as that control runs it and proven."""

from __future__ import annotations

import dataclasses
import sys
from pathlib import Path

import pytest

from millpath.interpret import interpret
from support.difftest import compare_motions
from millpath.io.tooltable import parse_tool_table, table_units, tool_table_text
from millpath.job.jobfile import load_job
from millpath.model.units import default, length_scale
from millpath.pipeline import fit_job, for_control, plan_job, post_job, run_job
from millpath.simulate.tip import tip_motions
from millpath.verify.roundtrip import compare_toolpath
from support.gcodetoolpath import compare, our_moves, their_moves

sys.path.insert(0, str(Path(__file__).parent))
from scan import approach_violations, plunge_violations  # noqa: E402

EXAMPLES = Path(__file__).resolve().parents[2] / "millpath" / "examples"
NAMES = sorted(p.parent.name for p in EXAMPLES.glob("*/job.toml"))


@pytest.fixture(scope="module", params=NAMES)
def example(request):
    job = load_job(EXAMPLES / request.param / "job.toml")
    tp, _, stock = plan_job(job)
    tp = fit_job(job, tp)
    program = post_job(job, tp, stock).text
    return request.param, job, stock, program, tp


@pytest.mark.slow
@pytest.mark.parametrize("machine_units", ["mm", "inch"])
def test_rs274_runs_the_program_with_the_table_as_written(example, machine_units, rs274):
    from support.rs274 import run_rs274
    name, job, stock, program, _ = example
    job = dataclasses.replace(job, machine_units=machine_units)
    text = tool_table_text(job.tools, job.units, job.table_units)
    assert table_units(text) == machine_units
    ours = interpret(program, parse_tool_table(text), machine_units=machine_units)
    # the standalone rs274 reads tables as inches: an mm table is converted for it
    theirs = run_rs274(program, parse_tool_table(text), table_units=machine_units)
    assert theirs.ok, f"{name}: rs274 rejected line {theirs.error_line}: {theirs.error}"
    tol = 1.5e-4
    assert compare_motions(ours, theirs.motions, tol) == [], name


@pytest.mark.slow
def test_safe_approach_and_no_straight_plunge_into_material(example):
    name, job, stock, program, _ = example
    text = tool_table_text(job.tools, job.units, job.table_units)
    motions = interpret(program, parse_tool_table(text), machine_units=job.table_units)
    assert approach_violations(program, motions, stock.zmax) == []
    res = job.simulation.get("resolution") or (0.01 if job.units == "inch" else 0.25)
    assert plunge_violations(motions, job.tools, stock, res) == []


@pytest.mark.slow
@pytest.mark.parametrize("dialect", ["grbl", "fanuc", "haas", "mach3"])
def test_program_for_each_control_is_read_as_it_runs_and_proven(example, dialect, request,
                                                                 tmp_path):
    """Each example written for each control: for GRBL the npm reader gcode-toolpath and
    millpath's GRBL reader see the same motion (0.0002 mm); the motion millpath reads
    gives back the tool path as written; and the program is proven: where nothing was
    rewritten for the control, its tip moves as in the LinuxCNC program (checked against
    rs274 above, proven by the examples' runs); else the whole run with ``--post`` is
    proven and written (GRBL and Fanuc; a Haas program is the Fanuc one under another
    title, and Mach3 rewrites what Fanuc rewrites, the same way)."""
    name, job, stock, program, tp = example
    cjob, replanned = for_control(dataclasses.replace(job, post={**job.post,
                                                                 "dialect": dialect}))
    entries = parse_tool_table(tool_table_text(job.tools, job.units, job.table_units))
    if replanned:                       # planned again by the run: proven there
        res = run_job(EXAMPLES / name / "job.toml", tmp_path / "out", dialect=dialect,
                      pictures=False)
        assert res.report["safety"]["status"] == "ok", name
        text = (tmp_path / "out" / res.report["program"]).read_text()
        if dialect == "grbl":
            ours = interpret(text, entries, machine_units=job.table_units, dialect=dialect)
            home = request.getfixturevalue("gcode_toolpath")
            assert compare(our_moves(ours), their_moves(home, text), 2e-4) == [], name
        return
    prog = post_job(cjob, tp, stock)
    if dialect == "haas":
        fanuc = post_job(dataclasses.replace(cjob, post={**cjob.post, "dialect": "fanuc"}),
                         tp, stock)
        differ = [(a, b) for a, b in zip(fanuc.text.splitlines(), prog.text.splitlines())
                  if a != b]
        assert differ == [("(millpath post: Fanuc 0i, units " + job.units + ")",
                           "(millpath post: Haas [Fanuc-style], units " + job.units + ")")]
        return
    ours = interpret(prog.text, entries, machine_units=job.table_units, dialect=dialect)
    if dialect == "grbl":
        home = request.getfixturevalue("gcode_toolpath")
        assert compare(our_moves(ours), their_moves(home, prog.text), 2e-4) == [], name
    scale = length_scale(job.table_units, job.units)
    radii = {e.number: e.diameter / 2 * scale for e in entries}
    assert compare_toolpath(prog.toolpath, prog.move_lines, ours,
                            default("roundtrip", job.units), radii) == [], name
    if prog.toolpath is tp:
        lc = interpret(program, entries, machine_units=job.table_units)
        a = [m for m in tip_motions(lc, job.units) if m.kind != "dwell"]
        b = [m for m in tip_motions(ours, job.units) if m.kind != "dwell"]
        assert len(a) == len(b), name
        assert max((max(abs(p - q) for p, q in zip(x.end, y.end)) for x, y in zip(a, b)),
                   default=0.0) < 1e-9, name
    elif dialect == "mach3":
        fanuc = post_job(dataclasses.replace(cjob, post={**cjob.post, "dialect": "fanuc"}),
                         tp, stock)
        assert fanuc.toolpath.moves == prog.toolpath.moves, name
    else:
        res = run_job(EXAMPLES / name / "job.toml", tmp_path / "out", dialect=dialect,
                      pictures=False)
        assert res.report["safety"]["status"] == "ok", name
        assert (tmp_path / "out" / res.report["program"]).exists()
