"""Bezier + line motion (Choi 1999, seeds/000 §4.3): G5 wherever the curve lies in the
XY plane, arcs where LinuxCNC's XY-only G5 cannot follow, and the thesis's uniform
parameters u1 = 1/(n-1) beside chord-length ones."""

from __future__ import annotations

import numpy as np
import shapely

from millpath.model.toolpath import sample_move
from millpath.plan.gridpocket.cells import inward_offset, pocket_polygon
from millpath.plan.gridpocket.fitmotion import _cubic_points, fit_cubic

POLY = [[0.0, 0.0], [1.6, 0.0], [1.6, 0.7], [0.9, 0.7], [0.9, 1.4], [0.0, 1.4]]


def test_uniform_parameters_recover_a_cubic_sampled_at_even_parameters():
    # a cubic whose speed varies along it, sampled at u = k/(n-1): the thesis's
    # parameters give back its control points; chord-length parameters do not
    p0, c1, c2, p3 = (np.array(v, float) for v in ([0, 0], [0.1, 1.0], [2.0, 1.2], [3, 0]))
    for n in (4, 6, 9):
        Q = _cubic_points(p0, c1, c2, p3, n)
        u1, u2 = fit_cubic(Q, "uniform")
        assert np.abs(u1 - c1).max() < 1e-9 and np.abs(u2 - c2).max() < 1e-9
        h1, h2 = fit_cubic(Q, "chord")
        assert np.abs(h1 - c1).max() > 1e-3


def test_flat_bottom_wall_pass_is_written_as_g5_within_the_tolerance(gp, tmp_path, rs274):
    from millpath.post.writer import post
    from support.rs274 import run_rs274
    net = "[[-0.3, -0.3], [-0.3, -0.3]]"
    op = (f"tool = 1\npolygon = {POLY}\nbottom = {{ bezier = {net} }}\ngrid = [0.125, 0.125]\n"
          "motion = \"bezier\"\ntolerance = 0.0005\nfeed = 10.0\nz_mode = \"tool\"\n")
    job, res = gp.plan_file(gp.write_job(tmp_path, op))
    tp = res.toolpath
    rep = res.report["pocket"]["bezier"]
    cubics = [(k, m) for k, m in enumerate(tp.moves) if m.kind == "cubic"]
    assert rep["cubics_written_as_g5"] == len(cubics) > 0
    # every G5 is at constant Z and stays within the tolerance of the tool-centre outline
    # (the walls offset by the radius: the concave corner's quarter circle)
    ring = inward_offset(pocket_polygon(POLY), 0.125).exterior
    for k, m in cubics:
        prev = tp.moves[k - 1].end
        pts = sample_move(prev, m, 0.002)
        assert np.ptp(pts[:, 2]) < 1e-12
        d = shapely.distance(ring, shapely.points(pts[:, :2]))
        assert d.max() <= 0.0005 + 1e-6
    r = run_rs274(post(tp, job.tools), job.tools, table_units="inch")
    assert r.ok, (r.error, r.error_line)


def test_sloped_bottom_cubics_become_arcs_and_both_deviations_are_reported(gp, tmp_path):
    net = "[[-0.2, -0.5, -0.3], [-0.4, -0.6, -0.2], [-0.3, -0.2, -0.5]]"
    for params in ("chord", "uniform"):
        op = (f"tool = 1\npolygon = {POLY}\nbottom = {{ bezier = {net} }}\ngrid = [0.125, 0.0625]\n"
              f"motion = \"bezier\"\nbezier_parameters = \"{params}\"\n"
              "tolerance = 0.0005\nfeed = 10.0\nz_mode = \"surface\"\n")
        job, res = gp.plan_file(gp.write_job(tmp_path, op))
        rep = res.report["pocket"]["bezier"]
        assert rep["parameters"] == params
        assert rep["cubics_written_as_g5"] == res.toolpath.counts()["cubic"] == 0
        assert rep["cubics_written_as_arcs"] > 0 and rep["arcs_from_cubics"] > 0
        dev = rep["max_deviation"]
        assert 0 < dev[params] <= 0.0005 / 2 + 1e-9          # XZ/YZ cubics: half the tolerance
        assert dev["chord" if params == "uniform" else "uniform"] > 0
