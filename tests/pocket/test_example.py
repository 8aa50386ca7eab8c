"""The pocket-dxf-adaptive example: adaptive 12 mm at 15 %, then rest with 6 mm.

Truth: the pocket and its islands built here with shapely from the drawing's numbers
(make_dxf.py), the simulator's Z-map of the planned moves."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
import shapely
from shapely.geometry import LineString, Point, box

import millpath
from millpath.job.jobfile import load_job
from millpath.pipeline import plan_job
from millpath.plan.base import PlanContext
from millpath.plan.pocket import operation as pocket
from millpath.simulate import simulate_toolpath

EXAMPLE = Path(millpath.__file__).parent / "examples" / "pocket-dxf-adaptive"


def _part():
    half = Point(120, 40).buffer(20, quad_segs=256).intersection(box(120, 0, 200, 80))
    outer = box(0, 0, 120, 80).difference(box(52, 62, 70, 80.1)).union(half)
    islands = Point(30, 40).buffer(12, quad_segs=256).union(
        LineString([(80, 30), (95, 30)]).buffer(6, quad_segs=256))
    return outer.difference(islands)


def _feed_length(tp, op=None) -> float:
    from millpath.model.toolpath import arc_geometry
    total, pos = 0.0, None
    for m in tp.moves:
        if pos is not None and m.kind in ("line", "arc") and (op is None or m.op == op):
            if m.kind == "line":
                total += math.dist(pos, m.end)
            else:
                r, _, sw, dn = arc_geometry(pos, m)
                total += math.hypot(abs(sw) * r, dn)
        pos = m.end
    return total


@pytest.fixture(scope="module")
def planned():
    job = load_job(EXAMPLE / "job.toml")
    tp, results, stock = plan_job(job)
    return job, tp, results, stock


def test_drawing_in_the_example_is_written_by_its_script(tmp_path):
    import importlib.util
    spec = importlib.util.spec_from_file_location("make_dxf", EXAMPLE / "make_dxf.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    from millpath.part.drawing import read_dxf, regions_from_loops
    for p in (mod.make(tmp_path / "part.dxf"), EXAMPLE / "part.dxf"):
        regs = regions_from_loops(read_dxf(p, "mm", 0.01, layer="POCKET"))
        assert len(regs) == 1 and len(regs[0].polygon.interiors) == 2
        assert abs(regs[0].polygon.area - _part().area) < 0.5


def test_floor_cleared_nothing_cut_outside_or_in_islands(planned):
    job, tp, results, stock = planned
    sim = simulate_toolpath(tp, job.tools, stock, resolution=0.2)
    zm = sim.zmap
    X, Y = np.meshgrid(zm.xs(), zm.ys())
    part = _part()
    d = math.hypot(zm.dx, zm.dy)
    reach = part.buffer(-3.0).buffer(3.0 - d)          # where the 6 mm tool reaches
    inside = shapely.contains_xy(reach, X, Y)
    assert np.abs(zm.heights[inside] - (-8.0)).max() <= 1e-9
    untouched = ~shapely.contains_xy(part.buffer(d), X, Y)
    assert np.all(zm.heights[untouched] == 0.0)
    assert sim.rapids_through_material == 0


def test_rest_cuts_a_small_fraction_and_report_measures(planned):
    job, tp, results, stock = planned
    rough, rest = tp.ops[0], tp.ops[1]
    assert rest.name == "pocket adaptive rest"
    # the rest operation alone on a full block (no earlier operation)
    ctx = PlanContext(job.units, stock, job.machine, job.tools, job.base_dir, job.path)
    alone = pocket.plan(ctx, job.operations[1][1])
    L_rest = _feed_length(tp, op=1)
    L_alone = _feed_length(alone.toolpath)
    assert L_rest < 0.15 * L_alone, (L_rest, L_alone)
    ip0, ip1 = rough.info["in_process"], rest.info["in_process"]
    assert ip0["engagement"]["max"] <= 0.15 + 0.001
    assert 0 < ip0["engagement"]["mean"] <= ip0["engagement"]["max"]
    assert 0 < ip1["engagement"]["mean"] <= ip1["engagement"]["max"]
    for ip in (ip0, ip1):
        assert 0 <= ip["air_cut_length"] <= ip["feed_length"]
        assert 0 <= ip["air_cut_share"] < 1


def test_example_program_accepted_by_rs274(planned, rs274):
    from millpath.post.writer import post
    from support.rs274 import run_rs274
    job, tp, _, _ = planned
    r = run_rs274(post(tp, job.tools), job.tools)
    assert r.ok, (r.error, r.error_line)
    assert len(r.motions) > 1000


@pytest.mark.xfail(strict=True, reason="planner defect, open: since the drawn contours "
                   "follow the DXF on the air side, the rest pass's last clean-up ring "
                   "enters the pocket's sharp corner at (117, 77) at a measured engagement "
                   "of 0.18 against the job's 0.15")
def test_rest_engagement_within_the_jobs(planned):
    _, tp, _, _ = planned
    assert tp.ops[1].info["in_process"]["engagement"]["max"] <= 0.15 + 0.001
