"""Every bundled example: LinuxCNC's rs274 runs its program
with the tool table written for each [machine] units setting, its compensated motion
equals millpath's interpretation; after each tool change the first motion rises
straight to the safe height before any XY move, and no end mill goes straight down
into material (Z-map simulation of the motion before each vertical feed)."""

from __future__ import annotations

import dataclasses
import sys
from pathlib import Path

import pytest

from millpath.interpret import interpret
from support.difftest import compare_motions
from millpath.io.tooltable import parse_tool_table, table_units, tool_table_text
from millpath.job.jobfile import load_job
from millpath.pipeline import fit_job, plan_job, post_job

sys.path.insert(0, str(Path(__file__).parent))
from scan import approach_violations, plunge_violations  # noqa: E402

EXAMPLES = Path(__file__).resolve().parents[2] / "millpath" / "examples"
NAMES = sorted(p.parent.name for p in EXAMPLES.glob("*/job.toml"))


@pytest.fixture(scope="module", params=NAMES)
def example(request):
    job = load_job(EXAMPLES / request.param / "job.toml")
    tp, _, stock = plan_job(job)
    tp = fit_job(job, tp)
    program, _ = post_job(job, tp, stock)
    return request.param, job, stock, program


@pytest.mark.slow
@pytest.mark.parametrize("machine_units", ["mm", "inch"])
def test_rs274_runs_the_program_with_the_table_as_written(example, machine_units, rs274):
    from millpath.verify.rs274 import run_rs274
    name, job, stock, program = example
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
    name, job, stock, program = example
    text = tool_table_text(job.tools, job.units, job.table_units)
    motions = interpret(program, parse_tool_table(text), machine_units=job.table_units)
    assert approach_violations(program, motions, stock.zmax) == []
    res = job.simulation.get("resolution") or (0.01 if job.units == "inch" else 0.25)
    assert plunge_violations(motions, job.tools, stock, res) == []
