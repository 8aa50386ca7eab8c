"""Closed-form ball-cutter depths (millpath.geometry.distance) against the GJK bisection
of millpath.geometry.convex and against dense point sampling (fixed seed)."""

import numpy as np

from millpath.geometry.convex import BALL, depth
from millpath.geometry.distance import (ball_core, core_triangle_dist2,
                                        segment_triangle_dist2)


def test_segment_triangle_distance_matches_sampling():
    rng = np.random.default_rng(15)
    for _ in range(60):
        T = rng.uniform(-1, 1, (3, 3))
        p, q = rng.uniform(-1.5, 1.5, (2, 3))
        d = np.sqrt(segment_triangle_dist2(*p, *q, T))
        u, v = np.meshgrid(np.linspace(0, 1, 81), np.linspace(0, 1, 81))
        keep = u + v <= 1
        pts = T[0] + u[keep, None] * (T[1] - T[0]) + v[keep, None] * (T[2] - T[0])
        s = np.linspace(0, 1, 161)[:, None]
        seg = p + s * (q - p)
        brute = np.sqrt(((pts[:, None, :] - seg[None]) ** 2).sum(-1).min())
        assert d <= brute + 1e-12          # exact is never above a sampled distance
        assert brute - d < 0.03            # and the sampling comes close to it


def test_ball_depth_matches_gjk():
    rng = np.random.default_rng(1515)
    R, L = 3.0, 20.0
    rr, rh = np.empty(3), np.empty(3)
    Q1, Q2 = np.empty((3, 3)), np.empty((3, 3))
    n = 0
    for _ in range(400):
        P0 = rng.uniform(-2, 2, 3)
        P1 = P0 + rng.uniform(-3, 3, 3) * (rng.random() > 0.2)
        T = rng.uniform(-4, 4, (3, 3)) + np.array([0, 0, 1.0])
        fc = ball_core(P0, P1, R, L, Q1, Q2)
        exact = R - np.sqrt(core_triangle_dist2(T, fc, Q1, Q2))
        g = depth(T, P0, P1, BALL, R, 0.0, 0.0, 0.0, L, 0.0005, 1e-7, rr, rh)
        if exact < 0.0005:
            assert g < 0 or g < 0.0005 + 1e-6
        elif exact < R - 1e-6:
            n += 1
            assert abs(g - exact) < 1e-4      # GJK meets() stops within ~5e-5; accuracy is 1e-3
    assert n > 50


def test_meets_within_tol_agrees_with_the_exact_ball_distance():
    """meets(..., tol) is "within tol of the swept solid": for a swept ball that is
    exactly "distance to the core <= radius + tol" (closed form of geometry.distance).
    It once answered "no" for triangles within tol, and even for shallow cuts, which
    let the coarse pre-test of the gouge check pass over gouging chords."""
    from millpath.geometry.convex import meets, shape_rings
    rng = np.random.default_rng(1516)
    R, L, e0 = 3.0, 20.0, 0.0005
    rr, rh = np.empty(3), np.empty(3)
    Q1, Q2 = np.empty((3, 3)), np.empty((3, 3))
    nr, rho = shape_rings(BALL, R, 0.0, 0.0, 0.0, L, e0, rr, rh)
    checked = {True: 0, False: 0}
    for _ in range(600):
        P0 = rng.uniform(-2, 2, 3)
        P1 = P0 + rng.uniform(-3, 3, 3) * (rng.random() > 0.2)
        T = rng.uniform(-4, 4, (3, 3)) + np.array([0, 0, 1.0])
        tol = float(rng.choice([0.0, 0.002, 0.02, 0.2]))
        # C_e0 of a ball is its core (axis from R to L - e0) grown by R - e0
        fc = ball_core(P0, P1, R, L - e0, Q1, Q2)
        gap = np.sqrt(core_triangle_dist2(T, fc, Q1, Q2)) - (R - e0)
        if abs(gap - tol) < 1e-6:
            continue                        # on the boundary: either answer
        want = gap <= tol
        assert meets(T, P0, P1, nr, rr, rh, rho, tol) == want, (gap, tol)
        checked[want] += 1
    assert checked[True] > 50 and checked[False] > 50
