"""``rest = true`` for ``surface-rough``: a 4 mm ball roughs only where a 10 mm bull
nose left more than the ball's own target (surface + allowance), on the real stock,
Z included: a skin left thick (large allowance of the first rougher) is roughed again.

Truth: the simulator's Z-maps of the same job with the second rougher run with and
without ``rest`` (what rest skipped must already be within its threshold)."""

from __future__ import annotations

import shutil
from pathlib import Path

import numpy as np
import pytest

import millpath
from millpath.job.jobfile import load_job
from millpath.model.toolpath import sample_move
from millpath.pipeline import plan_job
from millpath.simulate import simulate_toolpath

CAVITY = Path(millpath.__file__).parent / "examples" / "surface-cavity" / "cavity.stl"

JOB = """units = "mm"
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
allowance = {first}
feed = 1500.0
[[operations]]
type = "surface-rough"
surface = "cavity.stl"
tool = 2
stepdown = 3.0
stepover = 2.4
allowance = 0.3
feed = 1500.0
rest = {rest}
"""


def _plan(tmp_path, first: float, rest: bool):
    d = tmp_path / f"{first}-{rest}"
    d.mkdir()
    shutil.copy(CAVITY, d / "cavity.stl")
    (d / "job.toml").write_text(JOB.format(first=first, rest="true" if rest else "false"))
    job = load_job(d / "job.toml")
    return job, *plan_job(job)


def _feed_length(tp, op):
    """Length of the feed moves (lines, arcs: helix entries included) of ``op``."""
    total, pos = 0.0, None
    for m in tp.moves:
        if pos is not None and m.op == op and m.kind in ("line", "arc"):
            P = sample_move(pos, m, 0.2)
            total += float(np.linalg.norm(np.diff(P, axis=0), axis=1).sum())
        pos = m.end
    return total


@pytest.mark.slow
def test_rest_rough_cuts_only_what_the_bigger_rougher_left(tmp_path):
    job, tp_r, res_r, stock = _plan(tmp_path, 0.0, True)
    _, tp_f, res_f, _ = _plan(tmp_path, 0.0, False)
    sec = res_r[1].report["surface_rough"][0]["rest"]
    thr = sec["threshold"]
    L_r, L_f = _feed_length(tp_r, 1), _feed_length(tp_f, 1)
    print("rest rough", sec, "length", L_r, "full", L_f, tp_r.ops[1].info["in_process"])
    # rest feeds less than the full rougher, entries included; most of what it keeps is
    # the staircase the bull's 3 mm layers leave on the cavity's walls (measured: 5,862 mm
    # against 7,182, the passes alone 4,549 against 6,562; entries descend from the
    # material under the tool, so neither spends its length on helices from the top)
    assert 0 < L_r < L_f
    zr = simulate_toolpath(tp_r, job.tools, stock, resolution=0.2).zmap.heights
    zf = simulate_toolpath(tp_f, job.tools, stock, resolution=0.2).zmap.heights
    # what the rest rougher skipped was within its threshold of what the full one leaves
    assert float(np.max(zr - zf)) <= thr + 0.011
    ip = tp_r.ops[1].info["in_process"]
    assert ip["removed_volume"] > 0 and 0 <= ip["air_cut_share"] < 1
    # Z counts: a first rougher that leaves a 3 mm skin leaves the ball nearly all of
    # its path to cut
    _, _, res_t, _ = _plan(tmp_path, 3.0, True)
    thick = res_t[1].report["surface_rough"][0]["rest"]
    print("after a 3 mm skin", thick, "after a 0 mm skin", sec)
    assert thick["points_kept"] > 0.8 * thick["points"]
    assert sec["points_kept"] < 0.6 * sec["points"]
