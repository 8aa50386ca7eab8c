"""Closed-form ball-cutter depths (millpath.geometry.distance) against the GJK bisection
of millpath.geometry.convex and against dense point sampling (fixed seed)."""

import numpy as np
import pytest

from millpath.geometry.convex import depth, meets, shape_rings
from millpath.geometry.cutter import BALL, FLAT
from millpath.geometry.distance import (ball_core, core_point_dist2, core_segment_dist2,
                                        core_triangle_dist2, point_triangle_dist2,
                                        segment_triangle_dist2, triangle_triangle_dist2)


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


def test_core_distance_below_the_ball_centres_is_the_whole_cores():
    """A triangle, segment or point at or below the ball centres' edge of the core (a
    ball swept along a sloped chord, the core the vertical quad above it) is measured
    from that edge alone: the same distance as to the quad's two triangles."""
    rng = np.random.default_rng(1519)
    R, L = 3.0, 20.0
    Q1, Q2 = np.empty((3, 3)), np.empty((3, 3))
    below = 0
    for _ in range(500):
        P0 = rng.uniform(-2, 2, 3)
        P1 = P0 + rng.uniform(-3, 3, 3)
        T = rng.uniform(-4, 4, (3, 3)) + np.array([0, 0, 1.0])
        assert ball_core(P0, P1, R, L, Q1, Q2)
        below += T[:, 2].max() <= min(P0[2], P1[2]) + R
        whole = min(triangle_triangle_dist2(T, Q1), triangle_triangle_dist2(T, Q2))
        assert core_triangle_dist2(T, True, Q1, Q2) == pytest.approx(whole, rel=1e-12,
                                                                       abs=1e-12)
        p, q = T[0], T[1]
        whole = min(segment_triangle_dist2(*p, *q, Q1), segment_triangle_dist2(*p, *q, Q2))
        assert core_segment_dist2(*p, *q, True, Q1, Q2) == pytest.approx(whole, rel=1e-12,
                                                                          abs=1e-12)
        whole = min(point_triangle_dist2(*p, Q1), point_triangle_dist2(*p, Q2))
        assert core_point_dist2(*p, True, Q1, Q2) == pytest.approx(whole, rel=1e-12,
                                                                    abs=1e-12)
    assert below > 100


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
            assert abs(g - exact) < 1e-5      # bisection to 1e-7; accuracy is 1e-3
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


def _flat_depth_by_sampling(T, P0, P1, R, L, n=201, m=501):
    """Deepest point of triangle T inside a flat end mill (radius R, flutes L) swept
    from tip P0 to P1: points of T and tool positions sampled densely."""
    u, v = np.meshgrid(np.linspace(0, 1, n), np.linspace(0, 1, n))
    keep = u + v <= 1
    pts = T[0] + u[keep, None] * (T[1] - T[0]) + v[keep, None] * (T[2] - T[0])
    best = -1.0
    for t in np.linspace(0, 1, m):
        C = P0 + (P1 - P0) * t
        d = np.minimum(np.minimum(R - np.hypot(pts[:, 0] - C[0], pts[:, 1] - C[1]),
                                  pts[:, 2] - C[2]), C[2] + L - pts[:, 2])
        best = max(best, float(d.max()))
    return best


def test_flat_depth_of_a_sliver_near_the_rim():
    # pocket-thesis-arc (inch): a 1/4 in flat end mill on a chord of a G18 arc over a
    # gently sloped floor triangle that reaches 0.0029 in inside its rim. The old GJK
    # cycled on this pair for some inner bodies and, out of iterations, said "meets":
    # the bisection reported 0.000385 in for a depth of 0.000056
    T = np.array([[0.798438, 1.26699, -0.280994], [0.809375, 1.277913, -0.281512],
                  [0.798438, 1.277913, -0.281423]])
    P0 = np.array([0.804425, 1.4, -0.281311])
    P1 = np.array([0.833849, 1.4, -0.281551])
    R, L = 0.125, 0.75
    rr, rh = np.empty(3), np.empty(3)
    truth = _flat_depth_by_sampling(T, P0, P1, R, L)
    g = depth(T, P0, P1, FLAT, R, 0.0, 0.0, 0.0, L, 2e-5, 4e-9, rr, rh)
    assert abs(g - truth) < 1e-6                # sampling is within ~3e-8 here
    # and "meets" is monotonic in the depth e of the inner body
    for e in np.linspace(2e-5, 0.002, 100):
        nr, rho = shape_rings(FLAT, R, 0.0, 0.0, 0.0, L, e, rr, rh)
        assert meets(T, P0, P1, nr, rr, rh, rho, 0.0) == (e <= g)


def test_level_cylinder_prism_against_sampling_and_gjk():
    """A cylinder swept along a level chord (flat end mill, shank) is tested as a prism:
    its answer agrees with dense sampling of the triangle wherever the sampled distance
    is clear of the radius, and with the GJK iteration on the same solid (fixed seed);
    vertical triangles (walls) and triangles cut by the slab's faces included."""
    from millpath.geometry.convex import meets_prism
    rng = np.random.default_rng(1523)
    u, v = np.meshgrid(np.linspace(0, 1, 201), np.linspace(0, 1, 201))
    keep = u + v <= 1
    rr, rh = np.empty(3), np.empty(3)
    checked = [0, 0]
    for n in range(600):
        T = rng.uniform(-2, 2, (3, 3))
        if n % 4 == 0:                      # a wall: vertical triangle
            T[:, 1] = T[0, 1] + (T[:, 0] - T[0, 0]) * rng.uniform(-2, 2)
        P0 = rng.uniform(-1.5, 1.5, 3)
        P1 = P0 + np.append(rng.uniform(-1.5, 1.5, 2), 0.0)
        r = rng.uniform(0.2, 1.5)
        za, zb = P0[2] + 0.1, P0[2] + rng.uniform(0.3, 2.0)
        got = meets_prism(T, P0[0], P0[1], P1[0], P1[1], r, za, zb)
        pts = T[0] + u[keep, None] * (T[1] - T[0]) + v[keep, None] * (T[2] - T[0])
        pts = pts[(pts[:, 2] >= za) & (pts[:, 2] <= zb)]
        if len(pts):
            d = np.array([np.sqrt(segment_triangle_dist2(*p[:2], 0.0, *p[:2], 0.0,
                                                         np.array([[P0[0], P0[1], 0.0],
                                                                   [P1[0], P1[1], 0.0],
                                                                   [P1[0], P1[1], 0.0]])))
                          for p in pts[::7]])
            ds = d.min()
            if ds <= r - 1e-9:
                assert got, n
                checked[0] += 1
            elif ds > r + 0.05:
                assert not got, n
                checked[1] += 1
        # the same solid through meets(): the prism (tol 0) and GJK (a tiny tol) agree
        rr[:2] = r
        rh[0], rh[1] = za - P0[2], zb - P0[2]
        assert meets(T, P0, P1, 2, rr, rh, 0.0, 0.0) == got
        if got != meets(T, P0, P1, 2, rr, rh, 0.0, 1e-12):
            # only at a touch: the GJK answer within its 1e-10 of the boundary
            assert meets(T, P0, P1, 2, rr - 1e-7, rh, 0.0, 0.0) != \
                meets(T, P0, P1, 2, rr + 1e-7, rh, 0.0, 0.0)
    assert checked[0] > 100 and checked[1] > 100


def test_may_meet_holds_every_meeting():
    """The pre-test's grown prism (level cylinder) never misses what GJK finds within
    the grow distance (fixed seed)."""
    from millpath.geometry.convex import may_meet
    rng = np.random.default_rng(1529)
    rr, rh = np.empty(3), np.empty(3)
    hits = 0
    for _ in range(800):
        T = rng.uniform(-2, 2, (3, 3))
        P0 = rng.uniform(-1.5, 1.5, 3)
        P1 = P0 + np.append(rng.uniform(-1.5, 1.5, 2), 0.0)
        rr[:2] = rng.uniform(0.2, 1.5)
        rh[0], rh[1] = 0.1, rng.uniform(0.3, 2.0)
        g = rng.uniform(0.0, 0.3)
        if meets(T, P0, P1, 2, rr, rh, 0.0, g):
            hits += 1
            assert may_meet(T, P0, P1, 2, rr, rh, 0.0, g)
    assert hits > 100
