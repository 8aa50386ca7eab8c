"""The exact gouge check must not take a cutter outside the part for one inside it.

A raised letter stroke (a slanted bar, like the textbox's letters) stands on a slab. A
flat or bull cutter runs beside the bar's slanted wall, with its tip between the bar's
top and the slab. The cutter's far side lies behind the plane of the bar's end wall,
with its foot on that wall, yet outside the part (the slanted wall is between them).
The truth is analytic: the cutter's side is ``clearance`` from the slanted wall and
nothing else is near, so the gouge is ``-clearance`` when negative, else none.
(Before the fix this configuration reported the cutter point's distance to the slab,
1 mm, as a gouge: issue 25's textbox false alarm.)
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from millpath.model import Stock, Tool
from millpath.model.motion import Motion
from millpath.simulate.exact import Reference, verify_exact

TOL = 0.002
TOOLS = {"flat": Tool(1, "flat", 6.0, flute_length=20, stickout=30),
         "bull": Tool(1, "bull", 6.0, corner_radius=1.0, flute_length=20, stickout=30)}


def _prism(xy, z0, z1):
    """A closed prism over the counter-clockwise polygon ``xy``, outward normals."""
    n = len(xy)
    lo = [(x, y, z0) for x, y in xy]
    hi = [(x, y, z1) for x, y in xy]
    tri = []
    for i in range(1, n - 1):
        tri.append([lo[0], lo[i + 1], lo[i]])          # bottom, facing down
        tri.append([hi[0], hi[i], hi[i + 1]])          # top, facing up
    for i in range(n):
        j = (i + 1) % n
        tri.append([lo[i], lo[j], hi[j]])
        tri.append([lo[i], hi[j], hi[i]])
    return np.array(tri, float)


BAR = [(15.0, 17.0), (18.4, 17.0), (25.2, 32.0), (21.8, 32.0)]


def _part() -> np.ndarray:
    slab = _prism([(0.0, 0.0), (40.0, 0.0), (40.0, 40.0), (0.0, 40.0)], -10.0, -5.0)
    return np.concatenate([slab, _prism(BAR, -5.0, -2.0)])


def _beside(s: float, clearance: float) -> tuple[float, float]:
    """Tool axis ``s`` along the bar's left (slanted) wall from (15, 17), 3 + clearance
    out from it."""
    d = np.array([6.8, 15.0]) / math.hypot(6.8, 15.0)
    n = np.array([-d[1], d[0]])
    c = np.array(BAR[0]) + s * d + (3.0 + clearance) * n
    return float(c[0]), float(c[1])


@pytest.mark.parametrize("kind", ["flat", "bull"])
@pytest.mark.parametrize("clearance", [0.02, -0.05])
def test_cutter_beside_a_wall_behind_another_face(kind, clearance):
    z = -4.0
    a, b = _beside(12.0, clearance), _beside(1.0, clearance)
    # at a the cutter's far side (+Y) projects onto the bar's end wall y = 17, and the
    # swept cutter reaches past that wall's plane at b
    assert 15.0 < a[0] < 18.4 and b[1] - 3.0 < 17.0
    moves = [Motion("feed", 1, (a[0], a[1], 20.0), (a[0], a[1], z), feed=500, tool=1),
             Motion("feed", 2, (a[0], a[1], z), (b[0], b[1], z), feed=500, tool=1),
             Motion("feed", 3, (b[0], b[1], z), (b[0], b[1], 20.0), feed=500, tool=1)]
    stock = Stock(0, 0, -10, 40, 40, 0)
    r = verify_exact(moves, {1: TOOLS[kind]}, stock, [Reference(_part(), "bar on slab")])
    if clearance > 0:
        assert r.max_gouge == 0.0 and r.gouging_moves == 0
    else:
        assert r.max_gouge == pytest.approx(-clearance, abs=TOL)
        assert r.gouging_moves == 3           # the plunge and the retract too
