"""Rest machining of pockets uses the real stock, Z included: a pocket cleared only to
half depth is not treated as cleared.

Truth: the simulator's Z-map of the planned moves and the polygon built here."""

from __future__ import annotations

import math

import numpy as np
import shapely
from shapely.geometry import Polygon

from millpath.job.jobfile import load_job
from millpath.pipeline import plan_job
from millpath.simulate import simulate_toolpath

JOB = """units = "mm"
[stock]
box = [-5, -5, -12, 45, 35, 0]
[[tools]]
number = 1
type = "flat"
diameter = 6.0
[[operations]]
type = "pocket"
tool = 1
polygon = [[0, 0], [40, 0], [40, 30], [0, 30]]
depth = 4.0
stepdown = 4.0
feed = 1000.0
[[operations]]
type = "pocket"
tool = 1
polygon = [[0, 0], [40, 0], [40, 30], [0, 30]]
depth = 8.0
stepdown = 4.0
rest = true
feed = 1000.0
"""


def _length_at(tp, op: int, z: float) -> float:
    total, pos = 0.0, None
    for m in tp.moves:
        if (pos is not None and m.op == op and m.kind == "line"
                and abs(m.end[2] - z) < 1e-9 and abs(pos[2] - z) < 1e-9):
            total += math.dist(pos, m.end)
        pos = m.end
    return total


def test_half_depth_is_not_cleared_and_cleared_level_is_skipped(tmp_path):
    (tmp_path / "job.toml").write_text(JOB)
    job = load_job(tmp_path / "job.toml")
    tp, results, stock = plan_job(job)
    first = _length_at(tp, 0, -4.0)
    assert first > 300
    assert _length_at(tp, 1, -4.0) == 0.0           # level -4 was cleared: skipped
    assert _length_at(tp, 1, -8.0) > 0.8 * first     # level -8 was not: cut in full
    ip = tp.ops[1].info["in_process"]
    assert ip["air_cut_share"] < 0.1
    zm = simulate_toolpath(tp, job.tools, stock, resolution=0.2).zmap
    X, Y = np.meshgrid(zm.xs(), zm.ys())
    part = Polygon([[0, 0], [40, 0], [40, 30], [0, 30]])
    d = math.hypot(zm.dx, zm.dy)
    inside = shapely.contains_xy(part.buffer(-3).buffer(3 - d), X, Y)
    assert np.abs(zm.heights[inside] + 8.0).max() <= 1e-9
    assert np.all(zm.heights[~shapely.contains_xy(part.buffer(d), X, Y)] == 0.0)


def test_rest_without_an_earlier_operation_warns_and_plans_it_all(tmp_path):
    """``rest = true`` on the first operation: nothing has cut the stock yet, so the whole
    pocket is planned, and the user is told so in one warning line naming the job."""
    import warnings

    from millpath.errors import MillpathWarning
    first_only = JOB.split("[[operations]]")
    text = first_only[0] + "[[operations]]" + first_only[2]        # the rest operation alone
    (tmp_path / "job.toml").write_text(text)
    job = load_job(tmp_path / "job.toml")
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        tp, _, _ = plan_job(job)
    ours = [str(w.message) for w in caught if issubclass(w.category, MillpathWarning)]
    assert len(ours) == 1 and "operations[0]: rest = true" in ours[0]
    assert str(tmp_path / "job.toml") in ours[0]
    assert min(m.end[2] for m in tp.moves) <= -8.0 + 1e-9       # cut to the full depth
