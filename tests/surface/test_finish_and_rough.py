"""Zigzag finishing and layered roughing of free-form surfaces, proven with the Z-map
simulator (gouge, scallop, rapids, holder), our interpreter and LinuxCNC's rs274.

The surface is a small bicubic Bezier net (30 x 24 mm, heights 1..7 mm) tessellated
into 2 x 60 x 60 triangles; lengths in mm."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from millpath.errors import JobError
from millpath.interpret import interpret
from millpath.io.schema import validate
from millpath.model.stock import Machine, Stock
from millpath.model.tool import Tool
from millpath.part.surface.load import load_surface
from millpath.part.surface.mesh import Mesh, function_mesh
from millpath.plan.base import PlanContext
from millpath.plan.surface import operation as finish_op
from millpath.plan.surface import rough as rough_op
from millpath.plan.surface.dropcutter import build_index, surface_cutter
from millpath.plan.surface.sampler import Sampler
from millpath.plan.surface.toolchoice import choose_tool, mesh_concave_radius
from millpath.post.writer import post_with_lines
from millpath.simulate import simulate_toolpath
from millpath.verify.roundtrip import compare_toolpath

NET = {"box": [0.0, 0.0, 30.0, 24.0],
       "heights": [[2, 3, 5, 3], [3, 7, 6, 2], [4, 6, 3, 1], [2, 3, 2, 2]]}
SCALLOP, TOL, RES = 0.02, 0.01, 0.05
TOOLS = {1: Tool(1, "ball", 6.0, flute_length=15.0, stickout=25.0, holder=[(20.0, 30.0)]),
         2: Tool(2, "flat", 6.0, flute_length=15.0, stickout=25.0),
         3: Tool(3, "bull", 8.0, corner_radius=1.0, flute_length=20.0, stickout=30.0,
                 holder=[(20.0, 30.0)])}
STOCK = Stock(-3.0, -3.0, -2.0, 33.0, 27.0, 8.0)


def _ctx(stock=STOCK, tools=TOOLS) -> PlanContext:
    return PlanContext("mm", stock, Machine.default_for("mm"), tools, Path("."), None)


def _finish(**kw):
    p = {"surface": NET, "tool": 1, "scallop": SCALLOP, "tolerance": TOL, "divisions": 60}
    p.update(kw)
    return finish_op.plan(_ctx(), validate(p, finish_op.PARAMS, "op", None))


def _deviation(sim, design, margin: float = 0.5):
    """Simulated minus design height on the Z-map cells inside the surface (less a
    margin at the surface's edges, where the design ends)."""
    zm = sim.zmap
    X, Y = np.meshgrid(zm.xs(), zm.ys())
    dev = zm.heights - design.height(X.ravel(), Y.ravel()).reshape(X.shape)
    x0, y0, x1, y1 = NET["box"]
    m = (X > x0 + margin) & (X < x1 - margin) & (Y > y0 + margin) & (Y < y1 - margin)
    return dev[m]


@pytest.fixture(scope="module")
def variable():
    res = _finish(side_step="variable", compare=True)
    sim = simulate_toolpath(res.toolpath, TOOLS, STOCK, resolution=RES, design=res.design)
    return res, sim


@pytest.fixture(scope="module")
def published():
    res = _finish(side_step="published", compare=False)
    sim = simulate_toolpath(res.toolpath, TOOLS, STOCK, resolution=RES, design=res.design)
    return res, sim


def test_variable_side_step_keeps_the_measured_scallop_under_h_without_gouge(variable):
    res, sim = variable
    dev = _deviation(sim, res.design)
    assert sim.max_gouge <= 0.001 + RES
    assert dev.min() >= -TOL                       # chords gouge at most the tolerance
    assert dev.max() <= SCALLOP                     # measured scallop, vertical
    assert sim.rapids_through_material == 0 and sim.holder_contacts == 0


def test_published_side_step_holds_h_with_more_passes_than_variable(variable, published):
    res_v, _ = variable
    res_p, sim_p = published
    dev = _deviation(sim_p, res_p.design)
    assert dev.max() <= SCALLOP and sim_p.max_gouge <= 0.001 + RES
    cmp = res_v.report["surface_finish"][0]["compare"]
    assert cmp["published"]["pass_lines"] == res_p.report["surface_finish"][0]["pass_lines"]
    assert cmp["variable"]["pass_lines"] < cmp["published"]["pass_lines"]
    assert cmp["variable"]["cutting_length"] < cmp["published"]["cutting_length"]


def test_every_cutting_point_sits_on_the_drop_cutter_surface(variable):
    res, _ = variable
    mesh = load_surface(NET, 60, Path("."))
    s = Sampler(build_index(mesh), surface_cutter(TOOLS[1]), 0.0,
                tuple(TOOLS[1].holder_cylinders()), z_floor=float(mesh.bounds[0][2]))
    ends = np.array([m.end for m in res.toolpath.moves if m.kind == "line"])
    z, _ = s.z_safe(ends[:, 0], ends[:, 1])
    # feed moves are the CL points (at or above the drop-cutter Z: links lift)
    assert np.all(ends[:, 2] >= z - 1e-9)
    assert np.mean(np.abs(ends[:, 2] - z) < 1e-9) > 0.95


def test_feed_steps_verified_at_the_midpoint_within_tolerance(variable):
    res, _ = variable
    mesh = load_surface(NET, 60, Path("."))
    s = Sampler(build_index(mesh), surface_cutter(TOOLS[1]), 0.0)
    P = np.array([m.end for m in res.toolpath.moves])
    a, b = P[:-1], P[1:]
    cut = np.array([m.kind == "line" for m in res.toolpath.moves[1:]])
    on = np.abs(s.z_cut(a[:, 0], a[:, 1]) - a[:, 2]) < 1e-9
    on &= np.abs(s.z_cut(b[:, 0], b[:, 1]) - b[:, 2]) < 1e-9
    mid = 0.5 * (a + b)[cut & on]
    dz = s.z_cut(mid[:, 0], mid[:, 1]) - mid[:, 2]
    assert len(mid) > 1000
    assert dz.max() <= TOL + 1e-9                 # never deeper than the tolerance
    assert dz.min() >= -min(TOL, 0.25 * SCALLOP) - 1e-9


def test_program_interprets_back_to_the_plan_and_rs274_accepts_it(variable, rs274):
    from support.rs274 import run_rs274
    res, _ = variable
    program, lines = post_with_lines(res.toolpath, TOOLS, title="surface test")
    motions = interpret(program, TOOLS, machine_units="mm")
    assert compare_toolpath(res.toolpath, lines, motions, 1e-3) == []
    r = run_rs274(program, TOOLS, table_units="mm")
    assert r.ok, f"rs274 rejected line {r.error_line}: {r.error}"


def test_flat_end_mill_cannot_drive_a_scallop():
    with pytest.raises(JobError, match="tool: T2 is a flat end mill.*ball or bull"):
        _finish(tool=2)


def test_roughing_leaves_the_allowance_and_never_rapids_through_material():
    p = validate({"surface": NET, "tool": 3, "stepdown": 2.0, "stepover": 4.0,
                  "allowance": 0.3, "divisions": 60}, rough_op.PARAMS, "op", None)
    res = rough_op.plan(_ctx(), p)
    sec = res.report["surface_rough"][0]
    assert sec["levels"][0] == pytest.approx(6.0) and sec["levels"][-1] < 2.0
    sim = simulate_toolpath(res.toolpath, TOOLS, STOCK, resolution=0.1, design=res.design)
    dev = _deviation(sim, res.design)
    assert dev.min() >= 0.3 - 0.25 * 0.3 - 1e-6   # allowance less the chord tolerance
    assert dev.max() <= 2.0 + 0.3 + 0.1           # a staircase no taller than a layer
    assert sim.rapids_through_material == 0 and sim.holder_contacts == 0


def _cavity_mesh() -> Mesh:
    """A flat plate (z = 0) with a narrow trench 8 mm wide, 12 deep, vertical-ish walls
    and a round bottom of radius 4 mm, along X."""
    def f(x, y):
        d = np.abs(y - 15.0)
        z = np.where(d < 4.0, -8.0 - np.sqrt(np.maximum(16.0 - d * d, 0.0)), 0.0)
        return z
    return function_mesh(f, (0.0, 40.0), (0.0, 30.0), 81, 241, "trench")


def test_roughing_reaches_the_bottom_of_a_narrow_trench_and_its_walls(tmp_path):
    from millpath.part.surface.mesh import write_stl
    write_stl(_cavity_mesh(), tmp_path / "trench.stl")
    tools = {4: Tool(4, "flat", 6.0, flute_length=20.0, stickout=30.0, holder=[(20.0, 30.0)])}
    stock = Stock(0.0, 0.0, -14.0, 40.0, 30.0, 0.5)
    ctx = PlanContext("mm", stock, Machine.default_for("mm"), tools, tmp_path, None)
    p = validate({"surface": "trench.stl", "tool": 4, "stepdown": 3.0, "stepover": 6.0,
                  "allowance": 0.2}, rough_op.PARAMS, "op", None)
    res = rough_op.plan(ctx, p)
    # the rows (6 mm apart) all miss the trench's 8 mm: the bottom layer comes from
    # the fine raster, the walls from each layer's contour pass
    # (a 6 mm flat in a 4 mm radius round bottom: -8 - sqrt(16 - 9), plus the allowance;
    # lower still at the trench's open ends, where the tool passes the mesh's edge)
    assert res.report["surface_rough"][0]["levels"][-1] <= -10.446 + 1e-3
    sim = simulate_toolpath(res.toolpath, tools, stock, resolution=0.1, design=res.design)
    zm = sim.zmap
    col = zm.heights[:, np.argmin(np.abs(zm.xs() - 20.0))]
    ys = zm.ys()
    assert col[np.argmin(np.abs(ys - 15.0))] < -10.4
    assert sim.max_gouge == 0.0 and sim.rapids_through_material == 0


JOB = """units = "mm"
[stock]
box = [0.0, 0.0, -14.0, 40.0, 30.0, 0.5]
[[tools]]
number = 4
type = "flat"
diameter = 6.0
flute_length = 20.0
stickout = 30.0
holder = [[20.0, 30.0]]
[[tools]]
number = 5
type = "ball"
diameter = 6.0
shank_diameter = 5.0
flute_length = 6.0
stickout = 8.0
holder = [[24.0, 30.0]]
[[operations]]
type = "surface-rough"
surface = "trench.stl"
tool = 4
stepdown = 3.0
allowance = 0.2
[[operations]]
type = "surface-finish"
surface = "trench.stl"
tool = 5
scallop = 0.05
tolerance = 0.02
region = [2.0, 8.0, 38.0, 22.0]
compare = false
"""


def test_short_tool_holder_lifts_points_and_never_touches_the_part(tmp_path):
    from millpath.job.jobfile import load_job
    from millpath.part.surface.mesh import write_stl
    from millpath.pipeline import plan_job
    write_stl(_cavity_mesh(), tmp_path / "trench.stl")
    (tmp_path / "job.toml").write_text(JOB)
    job = load_job(tmp_path / "job.toml")
    tp, results, stock = plan_job(job)
    holder = results[1].report["surface_finish"][0]["holder"]
    assert holder["lifted_points"] > 0 and "left" in holder["note"]
    sim = simulate_toolpath(tp, job.tools, stock, resolution=0.1, design=results[1].design)
    assert sim.holder_contacts == 0 and sim.rapids_through_material == 0
    assert sim.max_gouge <= 0.001 + 0.1
    # (a necked ball: a shank as wide as the ball rubs the allowance a near-vertical
    # wall keeps above the ball)
    # the holder (radius 12, 8 mm above the tip) keeps 1 mm over the plate: the ball
    # stops 7 mm down the 12 mm trench
    finish = [m.end[2] for m in tp.moves if m.op == 1]
    assert min(finish) == pytest.approx(-7.0, abs=0.05)


def test_concave_radius_on_the_mesh_matches_a_sphere_bowl_and_a_cylinder_trough():
    R = 10.0
    bowl = function_mesh(lambda x, y: R - np.sqrt(np.maximum(R * R - x * x - y * y, 0.0)),
                         (-6, 6), (-6, 6), 121, 121, "bowl")
    assert mesh_concave_radius(bowl) == pytest.approx(R, rel=0.03)
    trough = function_mesh(lambda x, y: -np.sqrt(np.maximum(36.0 - y * y, 0.0)),
                           (0, 20), (-4, 4), 41, 161, "trough")
    assert mesh_concave_radius(trough) == pytest.approx(6.0, rel=0.03)
    dome = function_mesh(lambda x, y: np.sqrt(np.maximum(R * R - x * x - y * y, 0.0)),
                         (-6, 6), (-6, 6), 61, 61, "dome")
    assert math.isinf(mesh_concave_radius(dome))


def test_tool_choice_takes_the_largest_ball_that_fits_and_explains_the_rest():
    trough = function_mesh(lambda x, y: -np.sqrt(np.maximum(36.0 - y * y, 0.0)),
                           (0, 20), (-5.9, 5.9), 41, 237, "trough")
    tools = {1: Tool(1, "ball", 16.0), 2: Tool(2, "ball", 10.0, flute_length=3.0,
                                                stickout=4.0, holder=[(30.0, 30.0)]),
             3: Tool(3, "ball", 10.0, flute_length=10.0, stickout=30.0,
                     holder=[(12.0, 30.0)]),
             4: Tool(4, "ball", 6.0), 5: Tool(5, "flat", 10.0)}
    index = build_index(trough)
    tool, why = choose_tool(tools, index, None, (2.0, -5.0, 18.0, 5.0), 0.5)
    assert tool is not None and tool.number == 3
    cands = {c["tool"]: c for c in why["candidates"]}
    assert "not below the smallest concave radius" in cands[1]["rejected"]
    assert "holder" in cands[2]["rejected"]
    assert cands[3]["chosen"] and 4 not in cands and 5 not in cands
    assert why["min_concave_radius"] == pytest.approx(6.0, rel=0.05)
