"""A two-operation 3D job: surface-rough with a 10 mm bull nose, then surface-finish
with a 4 mm ball, ``rest = true``: the finisher works only where the rougher left
material, and what it skips was already within its rest allowance.

Truth: the simulator's Z-maps of the same job finished with and without ``rest``."""

from __future__ import annotations

import shutil
from pathlib import Path

import numpy as np
import pytest

import millpath
from millpath.job.jobfile import load_job
from millpath.pipeline import plan_job
from millpath.simulate import simulate_toolpath

CAVITY = Path(millpath.__file__).parent / "examples" / "surface-cavity" / "cavity.stl"

JOB = """units = "mm"
name = "rough then rest finish"
[stock]
box = [0.0, 0.0, -20.0, 50.0, 40.0, 0.5]
[[tools]]
number = 1
type = "bull"
diameter = 10.0
corner_radius = 2.0
flute_length = 25.0
stickout = 40.0
[[tools]]
number = 2
type = "ball"
diameter = 4.0
flute_length = 25.0
stickout = 40.0
[[operations]]
type = "surface-rough"
surface = "cavity.stl"
tool = 1
stepdown = 3.0
stepover = 5.0
allowance = 0.0
feed = 1500.0
[[operations]]
type = "surface-finish"
surface = "cavity.stl"
tool = 2
scallop = 0.02
tolerance = 0.01
feed = 1200.0
compare = false
rest = {rest}
rest_allowance = 0.1
"""


def _plan(tmp_path, rest: bool):
    d = tmp_path / ("rest" if rest else "full")
    d.mkdir()
    shutil.copy(CAVITY, d / "cavity.stl")
    (d / "job.toml").write_text(JOB.replace("{rest}", "true" if rest else "false"))
    job = load_job(d / "job.toml")
    return job, *plan_job(job)


@pytest.mark.slow
def test_rest_finish_works_only_where_the_rougher_left_material(tmp_path):
    job, tp_r, res_r, stock = _plan(tmp_path, True)
    _, tp_f, res_f, _ = _plan(tmp_path, False)
    sec = res_r[1].report["surface_finish"][0]["rest"]
    # a 10 mm bull nose in 3 mm layers leaves terraces on every slope: the ball still
    # has most of the cavity to finish, but not the floor and the flat top
    assert 0 < sec["points_kept"] < 0.95 * sec["points"]
    L_full = res_f[1].report["surface_finish"][0]["cutting_length"]
    assert sec["cutting_length"] < 0.95 * L_full
    print("rest figures", sec, "full cutting length", L_full)
    ip = tp_r.ops[1].info["in_process"]            # measured on the carried stock
    assert ip["removed_volume"] > 0 and 0 <= ip["air_cut_share"] < 1
    assert "in_process" in tp_r.ops[0].info
    # what the rest finisher skipped was within its allowance (0.1) of what the full
    # finisher leaves; cells one tool footprint sampled: 0.1 + 0.01 numerical slack
    zr = simulate_toolpath(tp_r, job.tools, stock, resolution=0.2).zmap.heights
    zf = simulate_toolpath(tp_f, job.tools, stock, resolution=0.2).zmap.heights
    print("largest extra stock left by rest", float(np.max(zr - zf)))
    assert float(np.max(zr - zf)) <= 0.1 + 0.011
