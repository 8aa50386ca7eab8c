"""The bundled free-form surface examples end to end: planned, simulated against the
design (gouge, scallop, rapids, holder), posted, interpreted back and accepted by
LinuxCNC's rs274. Lengths in mm."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import millpath
from millpath.interpret import interpret
from millpath.job.jobfile import load_job
from millpath.pipeline import plan_job
from millpath.post.writer import post_with_lines
from millpath.simulate import simulate_toolpath
from millpath.verify.roundtrip import compare_toolpath

EXAMPLES = Path(millpath.__file__).parent / "examples"


def _run(name: str):
    job = load_job(EXAMPLES / name / "job.toml")
    tp, results, stock = plan_job(job)
    design = results[-1].design
    res = job.simulation["resolution"]
    sim = simulate_toolpath(tp, job.tools, stock, resolution=res, design=design,
                            machine=job.machine)
    program, lines = post_with_lines(tp, job.tools, title=name)
    return job, tp, results, sim, program, lines


@pytest.fixture(scope="module")
def mould():
    return _run("surface-mould")


@pytest.fixture(scope="module")
def cavity():
    return _run("surface-cavity")


@pytest.fixture(scope="module")
def sideways():
    return _run("surface-sideways")


def _left_inside(sim, design, box, margin):
    zm = sim.zmap
    X, Y = np.meshgrid(zm.xs(), zm.ys())
    dev = zm.heights - design.height(X.ravel(), Y.ravel()).reshape(X.shape)
    x0, y0, x1, y1 = box
    m = (X > x0 + margin) & (X < x1 - margin) & (Y > y0 + margin) & (Y < y1 - margin)
    return dev[m]


def test_mould_is_finished_to_the_scallop_without_gouge(mould):
    job, tp, results, sim, program, lines = mould
    res = job.simulation["resolution"]
    assert sim.max_gouge <= 0.001 + res
    assert sim.rapids_through_material == 0 and sim.holder_contacts == 0
    finish = results[-1].report["surface_finish"][0]
    assert finish["side_step"] == "variable"
    cmp = finish["compare"]
    assert cmp["variable"]["pass_lines"] < cmp["published"]["pass_lines"]
    dev = _left_inside(sim, results[-1].design, (0.0, 0.0, 60.0, 40.0), 2 * res)
    # measured scallop (vertical) on the finished surface, away from the stock's sides
    assert dev.max() <= finish["scallop"]
    assert dev.min() >= -finish["tolerance"]


def test_cavity_short_tool_is_lifted_and_the_chosen_tool_reaches_the_floor(cavity):
    job, tp, results, sim, program, lines = cavity
    res = job.simulation["resolution"]
    assert sim.max_gouge <= 0.001 + res
    assert sim.rapids_through_material == 0 and sim.holder_contacts == 0
    short = results[1].report["surface_finish"][0]
    assert short["tool"] == 1 and short["holder"]["lifted_points"] > 0
    chosen = results[2].report["surface_finish"][0]
    assert chosen["tool"] == 2
    why = {c["tool"]: c for c in chosen["tool_choice"]["candidates"]}
    assert "concave radius" in why[3]["rejected"] and "holder" in why[1]["rejected"]
    # the long tool finishes the cavity floor (z = -18) to the scallop
    floor = _left_inside(sim, results[-1].design, (21.0, 17.0, 29.0, 23.0), 0.0)
    assert floor.max() <= chosen["scallop"] and floor.min() >= -chosen["tolerance"]


def test_sideways_cavity_is_turned_up_placed_and_finished_without_gouge(sideways):
    """Issue 23: a mould cavity STL that opens towards -Y, turned up with ``rotate`` and
    put on the stock top with ``place``; finished within its tolerance."""
    from millpath.part.surface.mesh import read_stl
    job, tp, results, sim, program, lines = sideways
    raw = read_stl(EXAMPLES / "surface-sideways" / "cavity-sideways.stl")
    lo, hi = raw.bounds
    # as exported: 60 (X) x 20 (Y, the depth) x 40 (Z), the cavity face at Y = 0, and
    # the cavity bottom 10 mm into the block
    np.testing.assert_allclose([*lo, *hi], [-30, 0, -20, 30, 20, 20], atol=1e-9)
    t = raw.triangles.reshape(-1, 3)
    assert np.all(t[np.abs(t[:, 0]) < 1.0, 1][(np.abs(t[np.abs(t[:, 0]) < 1.0, 2]) < 1.0)]
                  <= 10.0 + 1e-9)
    design = results[-1].design
    # turned and placed: the block fills the stock's XY (60 x 40), its top at Z 0 and
    # the bowl's centre (the stock's centre) 10 mm down
    assert design.height(np.array([30.0]), np.array([20.0]))[0] == pytest.approx(-10.0)
    assert design.height(np.array([1.0, 59.0]), np.array([1.0, 39.0])) == \
        pytest.approx([0.0, 0.0])
    finish = results[-1].report["surface_finish"][0]
    assert finish["strategy"] == "steep-shallow" and finish["waterline"]["levels"] > 1
    assert sim.max_gouge <= finish["tolerance"] + 0.001
    assert sim.rapids_through_material == 0 and sim.holder_contacts == 0
    # the zigzag side of the bowl (slopes under 40 degrees) is finished to the scallop
    floor = _left_inside(sim, design, (24.0, 17.0, 36.0, 23.0), 0.0)
    assert floor.max() <= finish["scallop"] and floor.min() >= -finish["tolerance"]


@pytest.mark.parametrize("example", ["mould", "cavity", "sideways"])
def test_program_round_trips_and_rs274_accepts_it(example, request, rs274):
    from support.rs274 import run_rs274
    job, tp, results, sim, program, lines = request.getfixturevalue(example)
    motions = interpret(program, job.tools, machine_units="mm")
    assert compare_toolpath(tp, lines, motions, 1e-3) == []
    r = run_rs274(program, job.tools, table_units="mm")
    assert r.ok, f"rs274 rejected line {r.error_line}: {r.error}"
