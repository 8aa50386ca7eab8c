"""The side-step formula of Wright et al. (seeds/004, eq. (2)) as printed, and as
millpath uses it, against the scallop of two balls computed directly.

Independent truth: two balls of radius r whose centres lie on the CL circle (radius
|rho + r| about the centre of curvature O) a chord ``eps`` apart; the cusp is where
their circles cross nearer to O (convex) or farther from O (concave), and the scallop is its distance from the surface circle of radius |rho|.
"""

from __future__ import annotations

import math

import numpy as np

from millpath.plan.surface.steps import flat_side_step, side_step


def printed_side_step(r, rho, h):
    """eq. (2) exactly as printed."""
    with np.errstate(invalid="ignore"):
        return np.sqrt(4 * (r + rho) ** 2 * (r + h) ** 2
                       - (r * r + 2 * r * rho + (rho + h) ** 2) ** 2) / abs(r + h)


def scallop(r: float, rho: float, eps: float) -> float:
    """Scallop height between two balls ``eps`` apart along the CL circle."""
    if math.isinf(rho):
        return r - math.sqrt(r * r - (eps / 2) ** 2)
    R = abs(rho + r) if rho > 0 else abs(rho) - r        # CL circle radius about O
    if eps > 2 * R:
        return math.inf
    half = math.asin(eps / (2 * R))
    # ball centres at angles +-half; the crossing of their circles on the symmetry axis
    cx = R * math.sin(half)
    cy = R * math.cos(half)
    if cx > r:
        return math.inf                                  # the balls do not even overlap
    w = math.sqrt(r * r - cx * cx)
    if rho > 0:
        return (cy - w) - rho          # convex: the cusp tip is the crossing nearer to O
    return abs(rho) - (cy + w)         # concave: the crossing farther from O


# the paper's cases: 0.125 in ball (scallop 0.0015 in and 0.0012 in), 0.25 in ball
# (25 micro-inch); radii of curvature from tight to flat, convex and concave
CASES = [(0.0625, 0.0015), (0.0625, 0.0012), (0.125, 25e-6)]
RHOS = [0.25, 0.5, 1.0, 2.0, 5.0, 20.0, math.inf, -0.5, -1.0, -2.0, -5.0, -20.0]


def test_printed_formula_gives_nan_for_every_case_of_the_paper():
    for r, h in CASES:
        for rho in RHOS:
            assert math.isnan(float(printed_side_step(r, rho, h))), (r, h, rho)


def test_printed_formula_where_finite_does_not_hold_the_scallop():
    r, h = 0.0625, 0.0015
    for rho in (0.03, 0.05):
        eps = float(printed_side_step(r, rho, h))
        assert math.isfinite(eps)
        assert abs(scallop(r, rho, eps) - h) > 0.5 * h


def test_millpath_side_step_gives_exactly_the_scallop():
    for r, h in CASES:
        for rho in RHOS:
            eps = float(side_step(r, np.array([rho]), h)[0])
            flat = flat_side_step(r, h)
            assert 0.25 * flat < eps < 2 * r                 # no fallback, no clip
            assert abs(scallop(r, rho, eps) - h) <= 1e-9 * max(1.0, abs(rho)), (r, h, rho)
