"""'flat with taper' hole bottoms (AP224 HOLE_BOTTOM, seeds/002 Figure 4): read, planned
with a flat end mill in cone levels, and machined to the analytic volume without gouge."""

from __future__ import annotations

import math

import pytest

from millpath.job.jobfile import load_job
from millpath.part.step.ap224 import read_part
from millpath.part.step.build import Ap224Builder
from millpath.part.step.shapes import feature_shapes
from millpath.plan.base import PlanContext
from millpath.plan.registry import strategy

D, FINAL, ANGLE, DEPTH, TOP = 20.0, 10.0, 90.0, 12.0, 20.0


def _part(tmp_path, angle_name="taper_angle"):
    b = Ap224Builder("TAPER", units="mm", material="aluminium 6061")
    b.block(60.0, 40.0, TOP)
    b.hole((20.0, 20.0, TOP), D, DEPTH, bottom="flat with taper",
           **{"final_diameter": FINAL, angle_name: ANGLE})
    (tmp_path / "part.stp").write_text(b.text())
    (tmp_path / "job.toml").write_text(
        'units = "mm"\n[simulation]\nresolution = 0.25\n[[tools]]\nnumber = 1\n'
        'type = "flat"\ndiameter = 8.0\nflute_length = 30.0\nstickout = 40.0\n'
        '[[operations]]\ntype = "features"\nstep = "part.stp"\n')
    return tmp_path / "job.toml"


@pytest.mark.parametrize("angle_name", ["taper_angle", "taper_diameter"])
def test_taper_bottom_is_read_with_either_angle_name(tmp_path, angle_name):
    _part(tmp_path, angle_name)
    (h,) = feature_shapes(read_part(tmp_path / "part.stp")).shapes
    assert (h.bottom, h.final_diameter, h.tip_angle) == ("flat with taper", FINAL, ANGLE)


def test_taper_hole_is_machined_to_the_analytic_volume(tmp_path, rs274):
    from millpath.post.writer import post
    from millpath.simulate import simulate_toolpath
    from support.rs274 import run_rs274
    job = load_job(_part(tmp_path))
    ctx = PlanContext(units=job.units, stock=None, machine=job.machine, tools=job.tools,
                      base_dir=job.base_dir, job_file=job.path)
    res = strategy("features").plan(ctx, job.operations[0][1])
    (rec,) = res.report["features"]["planned"]
    assert rec["strategy"] == "taper" and res.report["features"]["unmachinable"] == []
    sim = simulate_toolpath(res.toolpath, job.tools, res.stock, resolution=0.25,
                            design=res.design)
    # cylinder down to where the 90 degree cone meets the wall, then the frustum
    cone_h = (D - FINAL) / 2.0 / math.tan(math.radians(ANGLE / 2.0))
    R, r = D / 2.0, FINAL / 2.0
    volume = math.pi * R * R * (DEPTH - cone_h) + math.pi * cone_h / 3.0 * (R * R + R * r + r * r)
    assert sim.removed_volume == pytest.approx(volume, rel=0.01)
    assert sim.max_gouge <= 1e-6
    r274 = run_rs274(post(res.toolpath, job.tools), job.tools)
    assert r274.ok, (r274.error, r274.error_line)
