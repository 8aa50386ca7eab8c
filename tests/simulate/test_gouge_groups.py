"""The exact gouge check run group by group (a run of chords looked at whole first)
gives every chord the penetration it has checked alone, and both equal the analytic
gouge of a ball rolling round a sphere (fixed, deterministic data)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from millpath.geometry.index import BoxIndex
from millpath.model import Tool
from millpath.simulate.gouge import ToolShapes, gouge_chords
from millpath.simulate.groups import chord_groups

RS, R = 10.0, 3.0          # sphere radius, ball radius (mm)


def _sphere(nt: int = 90, nphi: int = 360) -> np.ndarray:
    """Upper hemisphere of radius RS about the origin, vertices on the sphere."""
    th = np.linspace(0.0, math.pi / 2, nt + 1)
    ph = np.linspace(0.0, 2 * math.pi, nphi + 1)
    T, P = np.meshgrid(th, ph, indexing="ij")
    V = RS * np.stack([np.sin(T) * np.cos(P), np.sin(T) * np.sin(P), np.cos(T)], axis=-1)
    a, b, c, d = V[:-1, :-1], V[1:, :-1], V[1:, 1:], V[:-1, 1:]
    tri = np.concatenate([np.stack([a, b, c], 2).reshape(-1, 3, 3),
                          np.stack([a, c, d], 2).reshape(-1, 3, 3)])
    keep = np.linalg.norm(np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0]), axis=1) > 0
    return np.ascontiguousarray(tri[keep])


def _path(n: int = 3000):
    """Ball centres round the sphere at polar angle 40 degrees, at RS + R - delta from
    its centre: the ball goes delta deep into the sphere along its normal."""
    phi = np.linspace(0.0, 2 * math.pi, n + 1)
    delta = 0.004 * np.sin(3 * phi) ** 2 - 0.001
    rho = RS + R - delta
    th = math.radians(40)
    C = np.stack([rho * math.sin(th) * np.cos(phi), rho * math.sin(th) * np.sin(phi),
                  rho * math.cos(th) * np.ones_like(phi)], axis=1)
    tips = C - np.array([0.0, 0.0, R])
    return tips[:-1], tips[1:], delta


def test_groups_give_each_chord_its_own_gouge():
    tri = _sphere()
    idx = BoxIndex.build(tri.min(axis=1), tri.max(axis=1))
    S, E, delta = _path()
    slot = np.zeros(len(S), np.int64)
    shapes = ToolShapes.of([Tool(1, "ball", 2 * R, flute_length=20, stickout=30)])
    grp = chord_groups(S, E, slot, np.zeros(len(S), np.int64), 0.01, 2 * R)
    assert grp.count.max() > 4                     # real runs, not single chords
    alone = gouge_chords(S, E, slot, shapes, tri, idx, 0.001)
    runs = (grp.start, grp.S, grp.E, grp.dev + 1e-9)
    whole = gouge_chords(S, E, slot, shapes, tri, idx, 0.001, groups=runs)
    assert np.array_equal(alone.gouge >= 0, whole.gouge >= 0)
    np.testing.assert_allclose(whole.gouge, alone.gouge, rtol=0, atol=1e-12)
    # the analytic truth: the chord's deepest point within the mesh's sagitta (the
    # facets lie inside the sphere by at most RS (1 - cos(half the facet's angle)))
    sag = RS * (1 - math.cos(math.radians(1.0) / math.sqrt(2)))
    truth = np.maximum(delta[:-1], delta[1:])
    hit = whole.gouge >= 0
    assert hit.any() and (~hit).any()
    assert np.all(whole.gouge[hit] <= truth[hit] + 0.001)
    assert np.all(whole.gouge[hit] >= truth[hit] - sag - 0.001)
    assert whole.gouge.max() == pytest.approx(0.003, abs=sag + 0.001)


def _trough(rc: float = 20.0, n: int = 400, half: float = 0.6, y0: float = -5.0,
            y1: float = 25.0) -> np.ndarray:
    """A concave cylindrical floor z = rc - sqrt(rc^2 - x^2) over |x| <= rc sin(half),
    along Y from y0 to y1, vertices on the cylinder (material below)."""
    a = np.linspace(-half, half, n + 1)
    x, z = rc * np.sin(a), rc - rc * np.cos(a)
    tri = []
    for i in range(n):
        p, q = (x[i], y0, z[i]), (x[i + 1], y0, z[i + 1])
        r, s = (x[i + 1], y1, z[i + 1]), (x[i], y1, z[i])
        tri += [[p, q, r], [p, r, s]]
    return np.asarray(tri, float)


def test_groups_of_a_flat_end_mill_find_its_rim_gouges():
    """A flat end mill along the bottom of a concave trough: its rim goes into the floor
    by sqrt(r^2 + (rc - tip)^2) - rc (normal to the floor). Run by run the check finds
    each chord's gouge as chord by chord (the rim test's rings are not overwritten by
    the depth search of an earlier triangle)."""
    rc, r = 20.0, 3.0
    # and a wall 0.01 inside the tool's side (x = r - 0.01, material beyond): the depth
    # search on its triangles runs before the floor's rim tests
    xw, zw = r - 0.01, rc - math.sqrt(rc * rc - (r - 0.01) ** 2)
    ys_w = np.arange(-5, 25, 0.5)
    wall = [[(xw, y, zw), (xw, y + 0.5, zw), (xw, y + 0.5, 10.0)] for y in ys_w]
    wall += [[(xw, y, zw), (xw, y + 0.5, 10.0), (xw, y, 10.0)] for y in ys_w]
    tri = np.concatenate([np.asarray(wall, float), _trough(rc)])
    idx = BoxIndex.build(tri.min(axis=1), tri.max(axis=1))
    ys = np.linspace(0.0, 20.0, 801)
    tip = 0.05 * np.sin(ys / 3.0) ** 2           # 0 .. 0.05 above the trough's bottom
    P = np.stack([np.zeros_like(ys), ys, tip], axis=1)
    S, E = P[:-1], P[1:]
    slot = np.zeros(len(S), np.int64)
    shapes = ToolShapes.of([Tool(1, "flat", 2 * r, flute_length=20, stickout=30)])
    grp = chord_groups(S, E, slot, np.zeros(len(S), np.int64), 0.01, 2 * r)
    assert grp.count.max() > 4
    alone = gouge_chords(S, E, slot, shapes, tri, idx, 0.001)
    whole = gouge_chords(S, E, slot, shapes, tri, idx, 0.001,
                         groups=(grp.start, grp.S, grp.E, grp.dev + 1e-9))
    np.testing.assert_allclose(whole.gouge, alone.gouge, rtol=0, atol=1e-9)
    # analytic: the rim's depth at the chord's lower end, within the facets' sagitta
    low = np.minimum(S[:, 2], E[:, 2])
    truth = np.sqrt(r * r + (rc - low) ** 2) - rc
    sag = rc * (1 - math.cos(1.2 / 400 / 2))
    assert np.all(whole.gouge >= truth - sag - 0.001)
    assert np.all(whole.gouge <= truth + 0.001)
