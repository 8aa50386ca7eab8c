"""Feed step and side step of surface finishing with a ball (or bull) cutter.

Conventions (job units, mm or inch):

- ``r`` is the cutter (ball) radius; ``rho`` the signed radius of curvature of the
  *part surface* in the plane considered: **positive where the surface is convex**
  (centre of curvature below the surface, a bump), **negative where concave** (a
  valley); ``inf`` for a plane. The cutter-location (CL) curve is the offset at
  distance r, so its radius is ``r + rho`` (convex) and ``|r + rho| = |rho| - r``
  (concave, which needs ``|rho| > r``).
- ``tau`` is the chord tolerance between consecutive CL points, ``h`` the scallop
  height, both measured along the normal.

Feed step: a chord of length delta on a circle of radius R deviates from it by
``tau`` when ``delta = 2 sqrt(2 tau R - tau^2)``, with ``R = |r + rho|``.

Side step (the published formula, derived here with the law of cosines): the centres
of two neighbouring balls lie on the offset circle of radius ``|rho + r|`` around the
centre of curvature O, the cusp between them at ``|rho + h|`` from O and ``r`` from
each ball centre. The CL chord between the passes is then

    epsilon = sqrt((r^2 - (r - h)^2) ((2 rho + r + h)^2 - r^2)) / |rho + h|
            = sqrt(4 (r+rho)^2 (rho+h)^2 - ((r+rho)^2 + (rho+h)^2 - r^2)^2) / |rho + h|,

which tends to ``2 sqrt(2 r h - h^2)`` on a plane.

Misprint (Wright et al., seeds/004, eq. (2), citing Choi and Jerard): the paper prints

    epsilon = sqrt(4 (r+rho)^2 (r+h)^2 - [r^2 + 2 r rho + (rho+h)^2]^2) / |r + h|,

with ``r + h`` where ``rho + h`` belongs and ``r^2`` where ``rho^2`` belongs. Its
radicand is negative (NaN) on a plane and for every radius of curvature outside about
(-3 r, r): for every surface of the paper's own examples (0.125 in and 0.25 in balls);
where it is finite it does not give the scallop h. tests/surface/test_side_step_misprint.py
shows both against the scallop computed from the two ball circles directly. Projected on the XY plane the step
shrinks by the cosine of the CL slope across the passes.
"""

from __future__ import annotations

import numpy as np


def feed_step(r: float, rho, tau: float, max_step: float) -> np.ndarray:
    """Largest CL step (job units) keeping the chord within ``tau`` of the CL curve."""
    rho = np.asarray(rho, float)
    with np.errstate(invalid="ignore", over="ignore"):
        R = np.abs(r + rho)
        arg = 2.0 * tau * R - tau * tau
        d = np.where(arg > 0, 2.0 * np.sqrt(np.maximum(arg, 0.0)), 2.0 * tau)
    d = np.where(np.isfinite(d), d, max_step)
    return np.minimum(d, max_step)


def flat_side_step(r: float, h: float) -> float:
    """Side step on a plane: ``2 sqrt(2 r h - h^2)``."""
    return float(2.0 * np.sqrt(max(2.0 * r * h - h * h, 0.0)))


def side_step(r: float, rho, h: float) -> np.ndarray:
    """Published CL side step across passes for scallop ``h`` (see module docstring);
    ``rho`` and ``h`` may be arrays (elementwise).

    Where the formula has no solution (a concave radius at or below the cutter radius,
    where the CL surface has a crease) the step falls back to a quarter of the flat step.
    """
    rho = np.asarray(rho, float)
    h = np.asarray(h, float)
    flat = 2.0 * np.sqrt(np.maximum(2.0 * r * h - h * h, 0.0))
    with np.errstate(invalid="ignore", divide="ignore", over="ignore"):
        a = r * r - (r - h) ** 2
        b = (2.0 * rho + r + h) ** 2 - r * r
        eps = np.sqrt(a * b) / np.abs(rho + h)
    ok = np.isfinite(eps) & (b > 0) & ((rho > 0) | (-rho > r))
    eps = np.where(np.isinf(rho), flat, eps)
    ok |= np.isinf(rho)
    return np.where(ok, np.clip(eps, 0.25 * flat, 2.0 * r), 0.25 * flat)


def curvature_radius(z_minus, z0, z_plus, step: float) -> tuple[np.ndarray, np.ndarray]:
    """Signed radius of curvature (positive convex) and slope of a sampled curve
    ``z(s)`` from three samples ``step`` apart (central differences)."""
    z_minus, z0, z_plus = (np.asarray(a, float) for a in (z_minus, z0, z_plus))
    d1 = (z_plus - z_minus) / (2.0 * step)
    d2 = (z_plus - 2.0 * z0 + z_minus) / (step * step)
    with np.errstate(divide="ignore", invalid="ignore"):
        rho = -(1.0 + d1 * d1) ** 1.5 / d2
    rho = np.where(np.abs(d2) < 1e-12, np.inf, rho)
    return rho, d1
