"""``rest = true`` for ``grid-pocket`` and ``features``: after a 12 mm end mill, a 6 mm
one cuts only the corners the bigger tool could not reach, on the real in-process
stock, Z included.

Truth, built here from the geometry (shapely buffers), not from the planner: the
corners left by a tool of radius r in a polygon P are ``P - open(P, r)`` with
``open(P, r) = buffer(buffer(P, -r), r)``; the simulator's Z-map of the planned moves
gives what was cut."""

from __future__ import annotations

import math

import numpy as np
import shapely
from shapely.geometry import Polygon, box

from millpath.job.jobfile import load_job
from millpath.model.toolpath import sample_move
from millpath.pipeline import plan_job
from millpath.simulate import simulate_toolpath

TOOLS = """units = "mm"
[stock]
box = [-5, -5, -10, 45, 35, 0]
[[tools]]
number = 1
type = "flat"
diameter = 12.0
flute_length = 20
stickout = 30
[[tools]]
number = 2
type = "flat"
diameter = 6.0
flute_length = 20
stickout = 30
"""

GRID = """[[operations]]
type = "grid-pocket"
tool = {tool}
polygon = [[0, 0], [40, 0], [40, 30], [0, 30]]
bottom = {{bezier = [[{z}, {z}], [{z}, {z}]]}}
feed = 1000
spindle = 8000
rest = {rest}
"""

POCKET = Polygon([[0, 0], [40, 0], [40, 30], [0, 30]])


def opened(poly, r):
    return poly.buffer(-r).buffer(r)


def _plan(tmp_path, text, name):
    d = tmp_path / name
    d.mkdir()
    (d / "job.toml").write_text(text)
    job = load_job(d / "job.toml")
    return job, plan_job(job)


def _cut_points(tp, ops, z, step=0.5):
    """Tool-centre points of the feed moves of operations ``ops`` at height ``z``."""
    pts, pos = [], None
    for m in tp.moves:
        if pos is not None and m.op in ops and m.kind in ("line", "arc", "cubic") \
                and abs(m.end[2] - z) < 1e-6 and abs(pos[2] - z) < 1e-6:
            pts.append(sample_move(pos, m, step))
        pos = m.end
    return np.vstack(pts) if pts else np.zeros((0, 3))


def _feed_length(tp, ops):
    total, pos = 0.0, None
    for m in tp.moves:
        if pos is not None and m.op in ops and m.kind in ("line", "arc", "cubic"):
            P = sample_move(pos, m, 0.2)
            total += float(np.linalg.norm(np.diff(P, axis=0), axis=1).sum())
        pos = m.end
    return total


def _check_corners(tp, job, stock, rest_ops, z_floor, pocket=POCKET, big_r=6.0, small_r=3.0):
    # 1. every rest cutting point's tool disk meets the leftover of the big tool
    left = pocket.difference(opened(pocket, big_r))
    P = _cut_points(tp, rest_ops, z_floor)
    assert len(P)
    d = shapely.distance(left, shapely.points(P[:, :2]))
    # the kept stretches are grown by one tool radius at each end (so they start and
    # end in air): within 2 R of a corner, never along the middle of a wall
    assert d.max() <= 2 * small_r + 0.5, d.max()
    # 2. the simulated result: the floor is cleared wherever the 6 mm tool reaches,
    # the corners included; nothing outside the pocket is cut
    zm = simulate_toolpath(tp, job.tools, stock, resolution=0.2).zmap
    X, Y = np.meshgrid(zm.xs(), zm.ys())
    cell = math.hypot(zm.dx, zm.dy)
    reach = shapely.contains_xy(opened(pocket, small_r).buffer(-cell), X, Y)
    assert np.abs(zm.heights[reach] - z_floor).max() <= 1e-6
    corners = shapely.contains_xy(left.intersection(opened(pocket, small_r)).buffer(-cell),
                                  X, Y)
    assert corners.sum() > 100                 # the corners are in the checked area
    assert np.all(zm.heights[~shapely.contains_xy(pocket.buffer(cell), X, Y)] == stock.zmax)


def test_grid_pocket_rest_cuts_only_the_corners(tmp_path):
    body = TOOLS + GRID.format(tool=1, z=-5, rest="false")
    job, (tp, res, stock) = _plan(tmp_path, body + GRID.format(tool=2, z=-5, rest="true"),
                                  "rest")
    _, (tp_f, res_f, _) = _plan(tmp_path, body + GRID.format(tool=2, z=-5, rest="false"),
                                "full")
    first = {i for i, o in enumerate(tp.ops) if o.tool == 1}
    rest_ops = {i for i, o in enumerate(tp.ops) if o.tool == 2}
    _check_corners(tp, job, stock, rest_ops, -5.0)
    L_rest = _feed_length(tp, rest_ops)
    L_full = _feed_length(tp_f, {i for i, o in enumerate(tp_f.ops) if o.tool == 2})
    print("grid-pocket rest", L_rest, "full", L_full, res[1].report["pocket"]["rest"])
    assert L_rest < 0.25 * L_full
    air = [tp.ops[i].info["in_process"]["air_cut_share"] for i in rest_ops]
    assert all(0.0 <= a <= 1.0 for a in air)
    assert max(tp.ops[i].info["in_process"]["removed_volume"] for i in first) > 0


def test_grid_pocket_rest_sees_half_depth(tmp_path):
    """The first operation clears only to -2.5 with the big tool: the rest operation
    (floor -5) must cut the whole pocket, not only the corners."""
    body = TOOLS + GRID.format(tool=1, z=-2.5, rest="false")
    job, (tp, res, stock) = _plan(tmp_path, body + GRID.format(tool=2, z=-5, rest="true"),
                                  "half")
    rest_ops = {i for i, o in enumerate(tp.ops) if o.tool == 2}
    zm = simulate_toolpath(tp, job.tools, stock, resolution=0.2).zmap
    X, Y = np.meshgrid(zm.xs(), zm.ys())
    reach = shapely.contains_xy(opened(POCKET, 3.0).buffer(-0.3), X, Y)
    assert np.abs(zm.heights[reach] + 5.0).max() <= 1e-6
    P = _cut_points(tp, rest_ops, -5.0)
    # the rest tool went over the middle of the pocket, far from any corner
    assert shapely.contains_xy(box(12, 10, 28, 20), P[:, 0], P[:, 1]).any()


def test_features_rest_cuts_only_the_corners(tmp_path):
    from millpath.part.step.build import Ap224Builder
    b = Ap224Builder("REST", units="mm", material="aluminium")
    b.block(50.0, 40.0, 10.0)
    b.pocket((25.0, 20.0, 10.0), 5.0, "rectangular", length=40.0, width=30.0,
             corner_radius=0.5)
    (tmp_path / "part.stp").write_text(b.text())
    ops = """[[operations]]
type = "features"
step = "part.stp"
tool = {tool}
rest = {rest}
"""
    text = TOOLS.replace("box = [-5, -5, -10, 45, 35, 0]", "box = [0, 0, 0, 50, 40, 10]")
    (tmp_path / "job.toml").write_text(text + ops.format(tool=1, rest="false")
                                       + ops.format(tool=2, rest="true"))
    job = load_job(tmp_path / "job.toml")
    tp, res, stock = plan_job(job)
    (tmp_path / "job.toml").write_text(text + ops.format(tool=1, rest="false")
                                       + ops.format(tool=2, rest="false"))
    tp_f, _, _ = plan_job(load_job(tmp_path / "job.toml"))
    rest_ops = {i for i, o in enumerate(tp.ops) if o.tool == 2}
    _check_corners(tp, job, stock, rest_ops, 5.0, pocket=box(5, 5, 45, 35))
    L_rest = _feed_length(tp, rest_ops)
    L_full = _feed_length(tp_f, {i for i, o in enumerate(tp_f.ops) if o.tool == 2})
    print("features rest", L_rest, "full", L_full, res[1].report["features"]["rest"])
    assert L_rest < 0.25 * L_full
