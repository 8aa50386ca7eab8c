"""Property tests: fitted paths stay within the tolerance of random originals.

The two-sided (Hausdorff) distance is measured by sampling both paths every
``tol / 4`` and taking exact distances from each sample to the other path's sampled
polyline. That never overestimates by more than the arcs' chord error (below 0.2 % of
the tolerance here); it can miss a maximum between samples by up to ``tol / 8``, which is
why the fitter's own check is exact and these tests are a second line.
"""

from __future__ import annotations

import math

import numpy as np
from hypothesis import HealthCheck, given, settings, strategies as st

from millpath.fit import fit_toolpath

SETTINGS = settings(max_examples=30, deadline=None, derandomize=True,
                    suppress_health_check=[HealthCheck.too_slow])


def smooth_path(rng, n, step, kind):
    """Random smooth polylines: wavy XY curves, XZ profiles, helices, arc chains."""
    t = np.cumsum(rng.uniform(0.3, 1.0, n)) * step
    if kind == "wave":
        y = sum(rng.uniform(0.5, 5) * np.sin(t / rng.uniform(1, 20) + rng.uniform(0, 6))
                for _ in range(3))
        return np.column_stack([t, y, np.full(n, -1.0)])
    if kind == "profile":
        z = sum(rng.uniform(0.2, 3) * np.cos(t / rng.uniform(2, 15) + rng.uniform(0, 6))
                for _ in range(2))
        return np.column_stack([t, np.full(n, 4.0), z])
    if kind == "helix":
        r = rng.uniform(1, 20)
        a = t / r
        return np.column_stack([r * np.cos(a), r * np.sin(a), -rng.uniform(0, 2) * a])
    # a chain of circular arcs of random radius and direction, joined tangentially
    pts = [np.zeros(2)]
    heading = 0.0
    k = 0
    while k < n:
        r = rng.uniform(0.5, 40)
        sgn = rng.choice([-1.0, 1.0])
        m = int(rng.integers(3, 60))
        for _ in range(m):
            heading += sgn * step / r
            pts.append(pts[-1] + step * np.array([math.cos(heading), math.sin(heading)]))
            k += 1
        if rng.uniform() < 0.3:
            heading += rng.uniform(-2.5, 2.5)             # a corner
    P = np.array(pts[:n])
    return np.column_stack([P, np.zeros(len(P))])


def check(fitkit, P, tol, mode, min_radius=0.0):
    pts = [tuple(p) for p in P]
    tp = fitkit.toolpath(pts)
    out = fit_toolpath(tp, tol, mode, min_radius=min_radius)
    h = fitkit.hausdorff(pts[0], tp.moves[1:], out.moves[1:], tol / 4)
    assert h <= tol * 1.002, (h, tol)
    prev = None
    for m in out.moves:
        if m.kind == "arc":
            assert math.dist([prev[i] for i in range(3)], m.center) >= 0   # finite
            assert m.plane in ("XY", "XZ", "YZ")
        prev = m.end
    return tp, out


@SETTINGS
@given(seed=st.integers(0, 2**32 - 1), kind=st.sampled_from(["wave", "profile", "helix",
                                                              "arcs"]),
       tol=st.floats(0.001, 0.05), step=st.floats(0.02, 1.0),
       mode=st.sampled_from(["arcs", "arcs+cubics"]))
def test_smooth_paths_stay_within_tolerance(fitkit, seed, kind, tol, step, mode):
    rng = np.random.default_rng(seed)
    check(fitkit, smooth_path(rng, 200, step, kind), tol, mode)


@SETTINGS
@given(seed=st.integers(0, 2**32 - 1), kind=st.sampled_from(["wave", "profile", "helix",
                                                              "arcs"]),
       tol=st.floats(0.002, 0.05), noise=st.floats(0.0, 3.0),
       mode=st.sampled_from(["arcs", "arcs+cubics"]))
def test_noisy_paths_stay_within_tolerance(fitkit, seed, kind, tol, noise, mode):
    rng = np.random.default_rng(seed)
    P = smooth_path(rng, 200, 0.2, kind)
    P = P + rng.uniform(-1, 1, P.shape) * noise * tol
    check(fitkit, P, tol, mode)


@SETTINGS
@given(seed=st.integers(0, 2**32 - 1), rmin=st.floats(0.0, 10.0))
def test_min_radius_holds_on_random_arc_chains(fitkit, seed, rmin):
    rng = np.random.default_rng(seed)
    _, out = check(fitkit, smooth_path(rng, 200, 0.1, "arcs"), 0.005, "arcs", rmin)
    prev = None
    for m in out.moves:
        if m.kind == "arc":
            assert math.dist(prev[:2], m.center[:2]) > rmin
        prev = m.end


def test_random_zigzag_surface_paths_stay_within_tolerance(fitkit):
    rng = np.random.default_rng(7)
    x = np.arange(0, 40, 0.1)
    for row in range(4):
        y = row * 0.5
        z = 2 * np.sin(x / 7 + row) + 0.5 * np.cos(x / 3) + rng.uniform(-1e-3, 1e-3, len(x))
        P = np.column_stack([x, np.full(len(x), y), z])
        check(fitkit, P if row % 2 == 0 else P[::-1], 0.005, "arcs")
