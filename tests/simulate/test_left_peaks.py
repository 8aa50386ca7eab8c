"""Material left is read at its peaks, not only where the samples fall: a ball's
scallop cusps between parallel passes over a plane, against their analytic height
R - sqrt(R^2 - (w/2)^2) (w the stepover). Program units mm, accuracy 0.001 mm."""

from __future__ import annotations

import math

import numpy as np
import pytest

from millpath.model import Stock, Tool
from millpath.model.motion import Motion
from millpath.simulate.exact import Reference, orient_outward, verify_exact
from millpath.simulate.leftpeak import closest_on_triangles

ACC = 0.001
BALL = Tool(1, "ball", 6.0, flute_length=20, stickout=30)


def _box(lo, hi) -> np.ndarray:
    v = np.array([[x, y, z] for x in (lo[0], hi[0]) for y in (lo[1], hi[1])
                  for z in (lo[2], hi[2])], float)
    quads = [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)]
    tri = [[v[a], v[b], v[c]] for a, b, c, d in quads] + [[v[a], v[c], v[d]]
                                                          for a, b, c, d in quads]
    return orient_outward(np.array(tri))


def _passes(w: float, y0: float) -> list[Motion]:
    """Ball passes along X at tip z = 0, ``w`` apart from ``y0`` past both edges."""
    out, y = [], y0
    while y < 12.0 + w:
        out.append(Motion("feed", 1, (-16.0, y, 0.0), (16.0, y, 0.0), 500, tool=1))
        y += w
    return out


@pytest.mark.parametrize("w,y0", [(1.3, -13.0), (1.5, -12.77), (0.9, -12.31)])
def test_scallop_cusps_read_at_their_height(w, y0):
    R = BALL.radius
    cusp = R - math.sqrt(R * R - (w / 2) ** 2)
    res = verify_exact(_passes(w, y0), {1: BALL}, Stock(-10, -10, -5, 10, 10, 1),
                       [Reference(_box((-10, -10, -5), (10, 10, 0)), "plate")], accuracy=ACC)
    assert res.max_left == pytest.approx(cusp, abs=ACC)
    # on the top face, between two passes
    at = res.max_left_at if hasattr(res, "max_left_at") else res.left_at
    assert at["z"] == pytest.approx(0.0, abs=1e-9)
    k = (at["y"] - y0) / w
    assert abs(k - math.floor(k) - 0.5) * w < 0.01
    assert res.max_gouge == 0.0


def test_closest_point_of_a_triangle():
    T = np.array([[[0, 0, 0], [4, 0, 0], [0, 4, 0]]], float)
    P = np.array([[1, 1, 0], [5, -1, 0], [-1, 2, 0], [3, 3, 0], [1, 1, 2]], float)
    got = closest_on_triangles(P, np.repeat(T, len(P), axis=0))
    want = [[1, 1, 0], [4, 0, 0], [0, 2, 0], [2, 2, 0], [1, 1, 0]]
    assert np.allclose(got, want)


def test_uncut_stock_is_said_to_be_uncut_and_its_area_measured():
    """Ball passes at tip z = 0 over y <= 0 only, stock 20 mm over the plate's top:
    past y = R the stock is uncut (left at the measuring cap, twice the diameter);
    more than 0.5 mm is left where R - sqrt(R^2 - y^2) > 0.5, y > sqrt(R^2 - (R - 0.5)^2),
    an area of 20 x (10 - that) on the top face, to within a band one sample spacing
    wide along the region's edge."""
    R = BALL.radius
    passes = [Motion("feed", 1, (-16.0, y, 0.0), (16.0, y, 0.0), 500, tool=1)
              for y in np.arange(-13.0, 0.001, 1.0)]
    res = verify_exact(passes, {1: BALL}, Stock(-10, -10, -5, 10, 10, 20),
                       [Reference(_box((-10, -10, -5), (10, 10, 0)), "plate")], accuracy=ACC)
    assert res.reach == pytest.approx(2 * BALL.diameter)
    assert res.max_left == pytest.approx(res.reach) and res.left_is_uncut
    y0 = math.sqrt(R * R - (R - 0.5) ** 2)
    truth = 20.0 * (10.0 - y0)
    band = 2 * (20.0 + (10.0 - y0)) * res.spacing
    assert abs(res.left_area(0.5) - truth) <= band
