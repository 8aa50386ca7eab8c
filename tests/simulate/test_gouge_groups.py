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
