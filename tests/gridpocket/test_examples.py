"""The bundled grid-pocket examples, end to end: plan, post, LinuxCNC's rs274 and our
interpreter against the plan, and the Z-map simulation against the design."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from millpath.interpret import interpret
from millpath.post.writer import post_with_lines
from millpath.simulate import simulate_toolpath
from millpath.verify.roundtrip import compare_toolpath

EXAMPLES = Path(__file__).resolve().parents[2] / "millpath" / "examples"
NAMES = ["pocket-casestudy-line", "pocket-casestudy-arc", "pocket-casestudy-bezier",
         "pocket-deep-layers", "pocket-measured"]
GOUGE_LIMIT = 0.0005      # inch, the limit in tool Z mode


@pytest.fixture(scope="module", params=NAMES)
def example(request, gp):
    job, res = gp.plan_file(EXAMPLES / request.param / "job.toml")
    program, lines = post_with_lines(res.toolpath, job.tools, title=request.param)
    sim = simulate_toolpath(res.toolpath, job.tools, job.stock,
                            resolution=job.simulation["resolution"], design=res.design,
                            machine=job.machine)
    return request.param, job, res, program, lines, sim


def test_every_example_is_a_tool_mode_inch_grid_pocket():
    for name in NAMES:
        text = (EXAMPLES / name / "job.toml").read_text()
        assert 'type = "grid-pocket"' in text and 'units = "inch"' in text
        assert 'z_mode = "tool"' in text


def test_interpreter_motion_matches_the_plan(example):
    name, job, res, program, lines, sim = example
    motions = interpret(program, job.tools, machine_units="inch")
    assert compare_toolpath(res.toolpath, lines, motions, 2e-5) == []


def test_rs274_accepts_the_program_and_moves_as_planned(example, rs274):
    from support.rs274 import run_rs274
    name, job, res, program, lines, sim = example
    r = run_rs274(program, job.tools, table_units="inch")
    assert r.ok, f"{name}: rs274 rejected line {r.error_line}: {r.error}"
    kinds = {m.kind for m in r.motions}
    if res.toolpath.counts()["cubic"]:
        assert "nurbs" in kinds or "cubic" in kinds
    # rs274 prints 4 decimals: compare lines and arcs (its G5 output has no controls)
    plain = [m if m.kind != "cubic" else None for m in res.toolpath.moves]
    if None not in plain:
        assert compare_toolpath(res.toolpath, lines, r.motions, 1.5e-4) == []


def test_no_gouge_no_rapid_through_material_no_holder_contact(example):
    name, job, res, program, lines, sim = example
    assert sim.max_gouge <= GOUGE_LIMIT, name
    assert sim.rapids_through_material == 0
    assert sim.holder_contacts == 0


def test_walls_are_never_cut_and_the_reachable_bottom_is_cleared(example, gp):
    name, job, res, program, lines, sim = example
    tool = job.tools[job.operations[0][1]["tool"]]
    left, wall_cut = gp.plan_view(sim.zmap, res.design, res.design.polygon, tool)
    assert wall_cut == 0.0, f"{name}: cut {wall_cut} outside the walls"
    bottom = res.design.surface
    flat = np.ptp(bottom.control[..., 2]) == 0 if hasattr(bottom, "control") else False
    if flat:
        # flat bottom: nothing above it in plan view wherever the tool can reach
        assert left <= 1e-6, f"{name}: {left} left above the flat bottom"
    else:
        # sculptured bottom: the left-over height is measured. With the zigzag runs the
        # tool has moved along every cell edge, so no point is farther than half a cell
        # from a pass: a ball leaves at most its cusp there (plus the surface's own
        # curvature), a flat end mill a step on the slope.
        dx, dy = res.report["pocket"]["grid"]["dx"], res.report["pocket"]["grid"]["dy"]
        half = max(dx, dy) / 2.0
        if tool.type == "ball":
            bound = 1.5 * (tool.radius - (tool.radius ** 2 - half ** 2) ** 0.5)
        else:
            # a flat bottom on a slope: at most the slope times half a cell diagonal
            X, Y = np.meshgrid(np.linspace(*res.design.polygon.bounds[::2], 200),
                               np.linspace(*res.design.polygon.bounds[1::2], 200))
            gy, gx = np.gradient(bottom.height(X, Y), Y[:, 0], X[0])
            slope = float(np.hypot(gx, gy).max())
            bound = 1.2 * slope * np.hypot(dx, dy) / 2.0
        assert left < bound, f"{name}: {left} left above the bottom (bound {bound})"
    print(f"{name}: max left-over above the bottom in the reachable area {left:.6f} in, "
          f"max gouge {sim.max_gouge:.6f} in")


def test_the_three_motion_modes_cut_the_same_pocket(gp):
    vols, blocks = {}, {}
    for mode in ("line", "arc", "bezier"):
        job, res = gp.plan_file(EXAMPLES / f"pocket-casestudy-{mode}" / "job.toml")
        program, _ = post_with_lines(res.toolpath, job.tools)
        blocks[mode] = program.count("\n")
        sim = simulate_toolpath(res.toolpath, job.tools, job.stock, resolution=0.01,
                                design=res.design, machine=job.machine)
        vols[mode] = sim.removed_volume
    assert blocks["arc"] < blocks["line"] / 2 and blocks["bezier"] < blocks["line"] / 2
    assert max(vols.values()) - min(vols.values()) < 0.005 * vols["line"]


@pytest.mark.parametrize("seed", [3, 11, 29])
def test_random_concave_pockets_are_cleared_without_touching_the_walls(tmp_path, gp, seed):
    rng = np.random.default_rng(seed)
    n = 11
    ang = np.sort(rng.uniform(0, 2 * np.pi, n))
    rad = rng.uniform(0.45, 1.0, n)
    pts = np.column_stack([1.5 + 1.4 * rad * np.cos(ang), 1.0 + 0.95 * rad * np.sin(ang)])
    poly = "polygon = [" + ", ".join(f"[{x:.4f}, {y:.4f}]" for x, y in pts) + "]\n"
    p = gp.write_job(tmp_path, "tool = 1\n" + poly + 'bottom = { bezier = [[-0.25, -0.25], '
                     '[-0.25, -0.25]] }\nfeed = 10\nstepdown = 0.15\nzigzag = false\n'
                     'grid = [0.15, 0.15]\nmotion = "arc"\n')
    job, res = gp.plan_file(p)
    sim = simulate_toolpath(res.toolpath, job.tools, job.stock, resolution=0.01,
                            design=res.design, machine=job.machine)
    assert sim.max_gouge <= 1e-6 and sim.rapids_through_material == 0
    left, wall_cut = gp.plan_view(sim.zmap, res.design, res.design.polygon, job.tools[1])
    assert wall_cut == 0.0 and left <= 1e-6
