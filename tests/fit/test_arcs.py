"""Arc fitting of Toolpath runs: planes, helices, radius limits, corners, LinuxCNC radii."""

from __future__ import annotations

import math

import numpy as np
import pytest

from millpath.fit import fit_toolpath
from millpath.fit.arcs import LINUXCNC_ARC_ABS_MM, LINUXCNC_ARC_REL
from millpath.model.toolpath import PLANE_AXES

TOL = 0.005


def circle(r, n, plane="XY", z=-1.0, pitch=0.0, turns=1.0, c=(0.0, 0.0)):
    """Points on a circle (or helix) of radius r in ``plane``, n points per turn."""
    a1, a2, an = PLANE_AXES[plane]
    t = np.linspace(0, 2 * math.pi * turns, int(n * turns) + 1)
    P = np.zeros((len(t), 3))
    P[:, a1] = c[0] + r * np.cos(t)
    P[:, a2] = c[1] + r * np.sin(t)
    P[:, an] = z + pitch * t / (2 * math.pi)
    return [tuple(p) for p in P]


def written_radii_ok(tp, decimals=4):
    """Every arc, with its numbers rounded as written, has start and end radii that
    agree far within LinuxCNC's limits; returns the worst |r1 - r2|."""
    worst = 0.0
    prev = None
    for m in tp.moves:
        if m.kind == "arc":
            a1, a2, _ = PLANE_AXES[m.plane]
            s = [round(v, decimals) for v in prev]
            e = [round(v, decimals) for v in m.end]
            c = [round(v, decimals) for v in m.center]
            r1 = math.hypot(s[a1] - c[a1], s[a2] - c[a2])
            r2 = math.hypot(e[a1] - c[a1], e[a2] - c[a2])
            lim = min(LINUXCNC_ARC_ABS_MM, LINUXCNC_ARC_REL * max(r1, r2))
            assert abs(r1 - r2) <= 0.1 * lim, (r1, r2)
            worst = max(worst, abs(r1 - r2))
        prev = m.end
    return worst


def test_circle_polyline_becomes_a_few_arcs_within_tolerance(fitkit):
    pts = circle(10.0, 360)
    tp = fitkit.toolpath(pts)
    out = fit_toolpath(tp, TOL, "arcs")
    c = out.counts()
    assert c["arc"] <= 3 and c["line"] == 0
    assert fitkit.hausdorff(pts[0], tp.moves[1:], out.moves[1:], TOL / 4) <= TOL
    prev = None
    for m in out.moves:
        if m.kind == "arc":
            assert m.plane == "XY" and not m.clockwise
            if math.dist(prev, m.end) > 10.0:            # long arcs: the radius is exact
                assert abs(math.dist(m.end[:2], m.center[:2]) - 10.0) < 1e-3
        prev = m.end
    written_radii_ok(out)


def test_clockwise_contour_gives_clockwise_arcs(fitkit):
    pts = circle(5.0, 200)[::-1]
    out = fit_toolpath(fitkit.toolpath(pts), TOL)
    arcs = [m for m in out.moves if m.kind == "arc"]
    assert arcs and all(m.clockwise for m in arcs)


@pytest.mark.parametrize("plane", ["XZ", "YZ"])
def test_profiles_in_vertical_planes_become_arcs_in_that_plane(fitkit, plane):
    pts = circle(8.0, 180, plane=plane, z=3.0, turns=0.5)
    tp = fitkit.toolpath(pts)
    out = fit_toolpath(tp, TOL)
    arcs = [m for m in out.moves if m.kind == "arc"]
    assert arcs and all(m.plane == plane for m in arcs)
    assert len(out.moves) <= 4
    assert fitkit.hausdorff(pts[0], tp.moves[1:], out.moves[1:], TOL / 4) <= TOL
    written_radii_ok(out)


def test_helix_becomes_helical_xy_arcs_with_linear_z(fitkit):
    pts = circle(6.0, 120, pitch=-1.0, turns=3.0, z=0.0)
    tp = fitkit.toolpath(pts)
    out = fit_toolpath(tp, TOL)
    arcs = [m for m in out.moves if m.kind == "arc"]
    assert len(arcs) <= 8 and len(out.moves) - 1 == len(arcs)
    assert all(m.plane == "XY" for m in arcs)
    assert out.moves[-1].end[2] == pytest.approx(-3.0, abs=1e-4)
    assert fitkit.hausdorff(pts[0], tp.moves[1:], out.moves[1:], TOL / 4) <= TOL


def test_collinear_points_merge_into_one_line(fitkit):
    pts = [(x, 2.0 * x, -0.5 * x) for x in np.linspace(0, 10, 101)]
    out = fit_toolpath(fitkit.toolpath(pts), TOL)
    assert [m.kind for m in out.moves] == ["rapid", "line"]
    assert out.moves[-1].end == pts[-1]          # line ends keep the original numbers


def test_tiny_circles_keep_their_points(fitkit):
    pts = circle(0.01, 24)
    tp = fitkit.toolpath(pts)
    out = fit_toolpath(tp, 0.0005)
    assert out.counts()["arc"] == 0


def test_huge_radius_arcs_are_written_as_lines(fitkit):
    r = 5000.0
    t = np.linspace(0, 200.0 / r, 201)
    pts = [(r * math.sin(a), r - r * math.cos(a), 0.0) for a in t]
    tp = fitkit.toolpath(pts)
    out = fit_toolpath(tp, TOL)
    c = out.counts()
    assert c["arc"] == 0 and c["line"] < 50
    assert fitkit.hausdorff(pts[0], tp.moves[1:], out.moves[1:], TOL / 4) <= TOL


def test_arcs_stay_larger_than_min_radius(fitkit):
    pts = circle(3.0, 360)
    assert fit_toolpath(fitkit.toolpath(pts), TOL, min_radius=2.9).counts()["arc"] > 0
    for rmin in (3.0, 3.5):
        tp = fitkit.toolpath(pts)
        out = fit_toolpath(tp, TOL, min_radius=rmin)
        prev = None
        for m in out.moves:
            if m.kind == "arc":
                assert math.dist(prev[:2], m.center[:2]) > rmin
                assert math.dist(m.end[:2], m.center[:2]) > rmin
            prev = m.end
        assert fitkit.hausdorff(pts[0], tp.moves[1:], out.moves[1:], TOL / 4) <= TOL
    # the arcs that fit a 3 mm circle within 5 um cover far less of it above 3.5 mm
    assert fit_toolpath(fitkit.toolpath(pts), TOL, min_radius=3.5).counts()["arc"] == 0 or \
        len(fit_toolpath(fitkit.toolpath(pts), TOL, min_radius=3.5).moves) > 20


def test_arc_never_turns_against_a_corner_of_the_original(fitkit):
    # a gentle counter-clockwise arc with a dent whose first vertex turns clockwise by
    # 11 degrees, shallower than the tolerance: an arc over that vertex would be within
    # tolerance but turn the wrong way through the corner
    r = 50.0
    t = np.linspace(0, 0.4, 41)
    pts = [(r * math.sin(a), r - r * math.cos(a), 0.0) for a in t]
    a, b = np.array(pts[20]), np.array(pts[21])
    d = (b - a) / np.linalg.norm(b - a)
    dent = a + 0.02 * d + 0.004 * np.array([d[1], -d[0], 0.0])   # right of travel
    pts.insert(21, tuple(dent))
    P = np.array(pts)
    u = np.diff(P[:, :2], axis=0)
    turn = np.arctan2(u[:-1, 0] * u[1:, 1] - u[:-1, 1] * u[1:, 0], (u[:-1] * u[1:]).sum(1))
    corners = [k + 1 for k in np.flatnonzero(turn < -math.radians(5))]
    assert corners == [20]
    out = fit_toolpath(fitkit.toolpath(pts), TOL)
    assert out.counts()["arc"] >= 2
    # original vertex index of each move end, then: no arc has a corner strictly inside
    index = [int(np.argmin(np.linalg.norm(P - np.array(m.end), axis=1))) for m in out.moves]
    for k in range(1, len(out.moves)):
        if out.moves[k].kind == "arc":
            assert not any(index[k - 1] < c < index[k] for c in corners)
            assert not out.moves[k].clockwise


def test_noisy_straight_path_does_not_become_arcs(fitkit):
    rng = np.random.default_rng(1)
    x = np.linspace(0, 20, 201)
    pts = [(xi, 0.002 * rng.uniform(-1, 1), 0.0) for xi in x]
    tp = fitkit.toolpath(pts)
    out = fit_toolpath(tp, TOL)
    assert out.counts()["arc"] == 0 and out.counts()["line"] <= 3
    assert fitkit.hausdorff(pts[0], tp.moves[1:], out.moves[1:], TOL / 4) <= TOL


def test_inch_toolpath_uses_five_decimals(fitkit):
    pts = circle(0.5, 360)
    tp = fitkit.toolpath(pts, units="inch")
    out = fit_toolpath(tp, 0.0002)
    assert out.counts()["arc"] >= 1
    for m in out.moves:
        if m.kind == "arc":
            assert all(abs(v * 1e5 - round(v * 1e5)) < 1e-6 for v in m.center[:2])
    written_radii_ok(out, decimals=5)
    assert fitkit.hausdorff(pts[0], tp.moves[1:], out.moves[1:], 0.0002 / 4) <= 0.0002
