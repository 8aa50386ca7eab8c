"""Sampling the tip Z along a move: a crest of the bottom narrower than the sample
spacing is still found (checked against an analytic bump)."""

from __future__ import annotations

import numpy as np

from millpath.plan.gridpocket.zfield import sample_chain

H, SIGMA, X0 = 0.05, 0.15, 3.43          # a bump of the required Z between samples


def _z(x, y):
    return H * np.exp(-0.5 * ((np.asarray(x) - X0) / SIGMA) ** 2) + 0.0 * np.asarray(y)


def test_a_crest_between_samples_is_followed_within_the_tolerance():
    xy = np.array([[0.0, 0.0], [6.0, 0.0]])
    spacing, tol = 1.0, 0.005
    pts, pos, checks, cpos = sample_chain(xy, _z, spacing, tol)
    x = np.linspace(0.0, 6.0, 60001)
    below = _z(x, 0.0) - np.interp(x, pts[:, 0], pts[:, 2])
    # the samples alone (every spacing / 6 ... here 1 mm) miss the bump: 0.05 below
    coarse = np.linspace(0.0, 6.0, 7)
    assert (_z(x, 0.0) - np.interp(x, coarse, _z(coarse, 0.0))).max() > 0.04
    # the dense check holds the line within the tolerance between its points, up to
    # the bump's slope times half the dense step (max slope H / (SIGMA sqrt(e)))
    slack = H / (SIGMA * np.sqrt(np.e)) * (spacing / 16) / 2
    assert below.max() <= tol + slack
    assert below.max() <= 0.01
    # the inserted points are check points for the fitter (the move must not dip below)
    assert np.all(np.isin(pts[:, 0], checks[:, 0]))
