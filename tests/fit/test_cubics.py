"""G5 cubic fitting: XY at constant Z, tangent joins, two-sided polyline check."""

from __future__ import annotations

import math

import numpy as np

from millpath.fit import fit_toolpath
from millpath.fit.cubics import polyline_within

TOL = 0.005


def ellipse(n=2000, z=-1.0):
    t = np.linspace(0, 2 * math.pi, n + 1)
    return [(30 * math.cos(a), 10 * math.sin(a), z) for a in t]


def spiral(n=1500):
    t = np.linspace(0.5, 6 * math.pi, n)
    return [(a * math.cos(a), a * math.sin(a) * 0.5, 0.0) for a in t]


def tangent_angle(u, v):
    return abs(math.atan2(u[0] * v[1] - u[1] * v[0], u[0] * v[0] + u[1] * v[1]))


def test_curves_of_changing_curvature_get_cubics_within_tolerance(fitkit):
    for pts in (ellipse(), spiral()):
        tp = fitkit.toolpath(pts)
        arcs = fit_toolpath(tp, TOL, "arcs")
        both = fit_toolpath(tp, TOL, "arcs+cubics")
        assert both.counts()["cubic"] > 0
        assert len(both.moves) < len(arcs.moves)
        assert fitkit.hausdorff(pts[0], tp.moves[1:], both.moves[1:], TOL / 4) <= TOL * 1.002


def test_consecutive_cubics_join_with_one_tangent_on_smooth_paths(fitkit):
    out = fit_toolpath(fitkit.toolpath(spiral()), TOL, "arcs+cubics")
    joins = 0
    for a, b in zip(out.moves, out.moves[1:]):
        if a.kind == "cubic" and b.kind == "cubic":
            t_in = (a.end[0] - a.c2[0], a.end[1] - a.c2[1])
            t_out = (b.c1[0] - a.end[0], b.c1[1] - a.end[1])
            # control points are rounded to 1e-4 mm; arms are millimetres long
            assert tangent_angle(t_in, t_out) < 1e-3
            joins += 1
    assert joins >= 3


def test_cubics_keep_a_sharp_corner(fitkit):
    # two smooth curves meeting at a right angle: no move may round the corner
    t = np.linspace(0, 1, 400)
    a = [(20 * s, 3 * math.sin(math.pi * s), 0.0) for s in t]
    b = [(20 + 3 * math.sin(math.pi * s), -20 * s, 0.0) for s in t[1:]]
    pts = a + b
    tp = fitkit.toolpath(pts)
    out = fit_toolpath(tp, TOL, "arcs+cubics")
    assert any(np.allclose(m.end, (20, 0, 0), atol=1e-4) for m in out.moves)
    assert fitkit.hausdorff(pts[0], tp.moves[1:], out.moves[1:], TOL / 4) <= TOL * 1.002


def test_cubics_only_at_constant_z(fitkit):
    t = np.linspace(0, 4 * math.pi, 800)
    helix = [(10 * math.cos(a), 5 * math.sin(a), -0.1 * a) for a in t]
    out = fit_toolpath(fitkit.toolpath(helix), TOL, "arcs+cubics")
    assert out.counts()["cubic"] == 0
    prof = [(x, 0.0, math.sin(x)) for x in np.linspace(0, 10, 500)]
    assert fit_toolpath(fitkit.toolpath(prof), TOL, "arcs+cubics").counts()["cubic"] == 0


def test_polyline_within_is_two_sided_and_exact_at_vertices():
    Y = np.array([[0.0, 0.0], [10.0, 0.0]])
    assert polyline_within(np.array([[0.0, 0.004], [5.0, -0.004], [10.0, 0.0]]), Y, 0.005)
    assert not polyline_within(np.array([[0.0, 0.0], [5.0, 0.006], [10.0, 0.0]]), Y, 0.005)
    # a detour beyond the end of Y
    assert not polyline_within(np.array([[0.0, 0.0], [10.01, 0.0]]), Y, 0.005)
    # X along a corner of Y: the chord cuts the corner by 0.0071 > 0.005
    Yc = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0]])
    assert not polyline_within(np.array([[0.99, 0.0], [1.0, 0.01]]), Yc, 0.005)
    assert polyline_within(np.array([[0.995, 0.0], [1.0, 0.005]]), Yc, 0.004)
