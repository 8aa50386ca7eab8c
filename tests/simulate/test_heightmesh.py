"""The height-field reference of the exact check (millpath.geometry.heightmesh) on an
analytic pocket whose wall stands on a sloped floor: a rectangle turned by
30 degrees, floor z = -5 + 0.1 x inside, top z = 0 outside. The wall is a vertical
plane the test knows; a flat end mill run along it a known distance past (or short of)
it must gouge by exactly that, measured normal to the wall, within 0.002 mm."""

from __future__ import annotations

import math

import numpy as np
import pytest
import shapely
from shapely.geometry import Polygon

from millpath.model import Stock, Tool
from millpath.model.motion import Motion
from millpath.simulate.exact import Reference, design_triangles, verify_exact

TOL = 0.002
ANGLE = math.radians(30.0)
U = np.array([math.cos(ANGLE), math.sin(ANGLE)])     # along the wall
N = np.array([-math.sin(ANGLE), math.cos(ANGLE)])    # into the pocket from the wall
ORIGIN = np.array([5.0, 3.0])                        # a point of the wall


class SlopedPocket:
    """The rectangle ORIGIN + a U + b N, 0 <= a <= 40, 0 <= b <= 20, cut to
    z = -5 + 0.1 x; z = 0 elsewhere (mm)."""

    def __init__(self):
        c = [ORIGIN, ORIGIN + 40 * U, ORIGIN + 40 * U + 20 * N, ORIGIN + 20 * N]
        self.polygon = Polygon(c)

    def height(self, x, y):
        x, y = np.broadcast_arrays(np.asarray(x, float), np.asarray(y, float))
        inside = shapely.contains_xy(self.polygon, x, y)
        return np.where(inside, -5.0 + 0.1 * x, 0.0)


def _pass(offset: float) -> list[Motion]:
    """A flat D6 end mill from above, along the wall with its axis 3 + offset from it,
    over the middle 20 mm of the wall, tip 1 mm above the highest floor under it."""
    a = ORIGIN + 10 * U + (3.0 + offset) * N
    b = ORIGIN + 30 * U + (3.0 + offset) * N
    z = -5.0 + 0.1 * (max(a[0], b[0]) + 3.0) + 1.0
    pts = [(a[0], a[1], 5.0), (a[0], a[1], z), (b[0], b[1], z), (b[0], b[1], 5.0)]
    return [Motion("feed", i + 2, pts[i], pts[i + 1], feed=500, tool=1) for i in range(3)]


@pytest.mark.parametrize("offset", [-0.02, 0.01])
def test_wall_over_a_sloped_floor(offset):
    design = SlopedPocket()
    stock = Stock(0, -20, -10, 50, 40, 0)
    tool = Tool(1, "flat", 6.0, flute_length=20, stickout=30)
    tri = design_triangles(design, stock, 0.001, 3.0)
    r = verify_exact(_pass(offset), {1: tool}, stock, [Reference(tri, "sloped pocket")],
                     accuracy=0.001)
    if offset < 0:
        assert r.max_gouge == pytest.approx(-offset, abs=TOL)
        # the pass along the wall, or the retract at its end: beside the wall too, it
        # gouges it by as much (the tie goes to whichever chord measures a hair deeper)
        assert r.gouge_at["line"] in (3, 4)
        at = np.array([r.gouge_at["x"], r.gouge_at["y"]]) - ORIGIN
        assert abs(at @ N) < 1e-6                      # on the wall
    else:
        # 0.01 mm clear of the wall: a ramp across a wall cell (0.05 mm) would show
        # up to 0.04 of false gouge here
        assert r.max_gouge == 0.0 and r.gouging_moves == 0


def test_wall_cells_are_vertical_faces_on_the_boundary():
    design = SlopedPocket()
    stock = Stock(0, -20, -10, 50, 40, 0)
    tri = design_triangles(design, stock, 0.001, 3.0)
    n = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    n /= np.linalg.norm(n, axis=1)[:, None]
    c = tri.mean(axis=1)
    rel = c[:, :2] - ORIGIN
    along = rel @ U
    # triangles that are not horizontal-ish near the long wall's middle part
    steep = np.abs(n[:, 2]) < 0.9
    near = (np.abs(rel @ N) < 0.1) & (along > 1) & (along < 39)
    sel = steep & near
    assert sel.sum() > 100
    assert np.allclose(n[sel, 2], 0.0, atol=1e-12)              # vertical
    assert np.allclose(n[sel, :2] @ N, 1.0, atol=1e-9)          # facing the pocket
    v = tri[sel].reshape(-1, 3)
    assert np.abs((v[:, :2] - ORIGIN) @ N).max() < 1e-6         # on the wall's plane


class RoundHole:
    """A hole of radius 2.055 (z = -10 inside, 0 outside) whose rim crosses the bottom
    edge of the cell [2.25, 3] x [3, 3.75] between its corner and its midpoint, 0.004
    deep: every corner, edge midpoint and centre of that cell lies outside the hole."""

    C = (2.40, 3.004 - 2.055)
    R = 2.055

    def height(self, x, y):
        x, y = np.broadcast_arrays(np.asarray(x, float), np.asarray(y, float))
        return np.where(np.hypot(x - self.C[0], y - self.C[1]) < self.R, -10.0, 0.0)


def test_top_face_does_not_overhang_a_wall_crossing_a_cell_edge_between_samples():
    """The top face's triangles stay out of the hole (analytic circle) but for the flat
    tolerance: the rim crossing an edge between its samples splits the cell."""
    from millpath.geometry.heightmesh import height_field_mesh
    flat = 0.0005
    tri = height_field_mesh(RoundHole(), (0.0, 0.0, 6.0, 6.0), size=0.75, min_size=0.05,
                            flat_tol=flat, floor=-20.0, wall_size=0.0005)
    top = tri[np.all(np.abs(tri[:, :, 2]) < 1e-12, axis=1)]
    t = np.linspace(0.0, 1.0, 201)[:, None]
    worst = 0.0
    for a, b in ((0, 1), (1, 2), (2, 0)):
        P = top[:, None, a, :2] + t[None] * (top[:, None, b, :2] - top[:, None, a, :2])
        inside = RoundHole.R - np.hypot(P[..., 0] - RoundHole.C[0], P[..., 1] - RoundHole.C[1])
        worst = max(worst, float(inside.max()))
    assert worst <= flat + 1e-6, worst
