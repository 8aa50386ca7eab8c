"""The reference the exact verification measures a STEP solid against: the B-rep meshed
within a quarter of the accuracy, its chord error measured against the true faces.

The truth is an analytic solid built here with OpenCASCADE's primitives (a 40 x 30 x 20
block, a blind 6 mm hole with a 118 degree cone at its bottom, a 3 mm through hole):
facet distances and gouge depths are computed from its formulas, never from the
planner or the mesh under test."""

from __future__ import annotations

import math
import sys
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("OCP", reason="the B-rep reference needs OpenCASCADE: pip install 'millpath[step-brep]'")
sys.path.insert(0, str(Path(__file__).parent))
import builder  # noqa: E402

from millpath.model import Stock, Tool  # noqa: E402
from millpath.model.motion import Motion  # noqa: E402
from millpath.part.brep.mesh import chord_error, meshed_faces, reference_mesh  # noqa: E402
from millpath.plan.features.solid import SolidDesign  # noqa: E402
from millpath.simulate.exact import Reference, design_triangles, verify_exact  # noqa: E402

ACC = 0.001                       # the verification's accuracy (mm)
HALF = math.radians(59.0)         # half the drill point's angle
BLIND = (10.0, 15.0, 3.0)         # axis x, y and radius of the blind hole
THROUGH = (30.0, 15.0, 1.5)
Z_WALL = 10.0                     # where the blind hole's wall meets its cone
APEX = Z_WALL - BLIND[2] / math.tan(HALF)
BOX = (0.0, 0.0, 0.0, 40.0, 30.0, 20.0)


@pytest.fixture(scope="module")
def solid():
    x, y, r = BLIND
    drill = builder.fuse(builder.cylinder(x, y, Z_WALL, r, 11.0),
                         builder.cone(x, y, APEX, 0.0, r, Z_WALL - APEX))
    return builder.unify(builder.cut(builder.box(*BOX), drill,
                                     builder.cylinder(THROUGH[0], THROUGH[1], -1.0,
                                                      THROUGH[2], 22.0)))


def _wall(p):
    return np.abs(np.hypot(p[..., 0] - BLIND[0], p[..., 1] - BLIND[1]) - BLIND[2])


def _cone(p):
    """Distance from the cone's generator in the (r, z) half-plane through the axis."""
    r = np.hypot(p[..., 0] - BLIND[0], p[..., 1] - BLIND[1])
    return np.abs(r * math.cos(HALF) - (p[..., 2] - APEX) * math.sin(HALF))


def _through(p):
    return np.abs(np.hypot(p[..., 0] - THROUGH[0], p[..., 1] - THROUGH[1]) - THROUGH[2])


def analytic_distance(tri: np.ndarray, pts: np.ndarray) -> np.ndarray:
    """Distance of the points ``pts`` (m, k, 3) of triangles ``tri`` (m, 3, 3) from the
    curved face whose formula the triangle's vertices satisfy (nan for triangles of
    the planes: all three vertices on a rim lie in the plane, their normal vertical)."""
    n = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    steep = np.abs(n[:, 2]) < 0.999 * np.linalg.norm(n, axis=1)
    out = np.full(pts.shape[:2], np.nan)
    for f, extra in ((_wall, tri[:, :, 2].min(axis=1) >= Z_WALL - 1e-9),
                     (_cone, tri[:, :, 2].max(axis=1) <= Z_WALL + 1e-9),
                     (_through, np.ones(len(tri), bool))):
        on = (f(tri).max(axis=1) < 1e-6) & steep & extra
        out[on] = f(pts[on])
    return out


def test_reference_mesh_stays_within_its_bound_of_the_analytic_solid(solid):
    bound = ACC / 4
    v, t, err = reference_mesh(solid, bound)
    assert err <= bound
    tri = v[t]
    # every triangle, sampled on a fine barycentric grid, against the faces' formulas
    k = 8
    bary = np.array([(i / k, j / k, 1 - (i + j) / k) for i in range(k + 1)
                     for j in range(k + 1 - i)])
    d = analytic_distance(tri, np.einsum("kj,mjc->mkc", bary, tri))
    curved = ~np.isnan(d)
    assert curved.sum() > 1000
    assert np.max(d[curved]) <= bound + 1e-9
    # closed and the right solid: its volume is the analytic one within the chord error
    # times the curved area
    vol = np.einsum("ij,ij->i", tri[:, 0], np.cross(tri[:, 1], tri[:, 2])).sum() / 6.0
    x, y, r = BLIND
    truth = (40 * 30 * 20 - math.pi * r * r * (20 - Z_WALL)
             - math.pi * r * r * (Z_WALL - APEX) / 3 - math.pi * THROUGH[2] ** 2 * 20)
    area = (2 * math.pi * r * (20 - Z_WALL) + math.pi * r * r / math.sin(HALF)
            + 2 * math.pi * THROUGH[2] * 20)
    assert abs(vol - truth) <= bound * area


def test_chord_error_is_the_sagitta_of_the_coarse_mesh(solid):
    """At the design's own 0.01 mm the measured chord error of the blind hole's wall is
    the largest sagitta R (1 - cos(dtheta / 2)) of its facets' edges (computed here from
    the vertex angles); it is far above the accuracy, which is why the reference is
    meshed anew."""
    from OCP.BRepBuilderAPI import BRepBuilderAPI_Copy
    shape = BRepBuilderAPI_Copy(solid, True, False).Shape()
    x, y, r = BLIND
    found = False
    for face, nodes, idx in meshed_faces(shape, 0.01, 0.2, None, None):
        rad = np.hypot(nodes[:, 0] - x, nodes[:, 1] - y)
        if not (np.allclose(rad, r, atol=1e-7) and nodes[:, 2].min() >= Z_WALL - 1e-7):
            continue
        found = True
        th = np.arctan2(nodes[:, 1] - y, nodes[:, 0] - x)
        e = idx[:, [0, 1, 1, 2, 2, 0]].reshape(-1, 2)
        dth = np.abs(np.angle(np.exp(1j * (th[e[:, 0]] - th[e[:, 1]]))))
        sagitta = float(np.max(r * (1 - np.cos(dth / 2))))
        assert ACC < sagitta <= 0.01 + 1e-9
        assert chord_error(face, nodes, idx) == pytest.approx(sagitta, abs=1e-9)
    assert found


def _plunge(x, y, z, tool, line):
    return [Motion("feed", line, (x, y, 25.0), (x, y, z), 300, tool=tool),
            Motion("feed", line, (x, y, z), (x, y, 25.0), 300, tool=tool)]


@pytest.mark.parametrize("tool, x, depth_below, truth", [
    (Tool(1, "drill", 6.0, point_angle=118.0, flute_length=30, stickout=40), BLIND[0],
     0.0, 0.0),                                       # the drill that made the hole
    (Tool(1, "drill", 6.0, point_angle=118.0, flute_length=30, stickout=40), BLIND[0],
     0.02, 0.02 * math.sin(HALF)),                    # 0.02 deeper: normal to the cone
    (Tool(1, "drill", 6.04, point_angle=118.0, flute_length=30, stickout=40), BLIND[0],
     0.0, 0.02),                                      # 0.02 wider: into the wall
    (Tool(1, "drill", 3.0, point_angle=118.0, flute_length=30, stickout=40), THROUGH[0],
     1.0, 0.0),                                       # through, the hole's own size
])
def test_exact_gouge_of_a_drill_against_the_solid_is_the_analytic_one(
        solid, tool, x, depth_below, truth):
    design = SolidDesign(solid, 0.01)
    stock = Stock.from_box(BOX)
    tri = design_triangles(design, stock, ACC, 1.0)
    assert design.chord_error is not None and design.chord_error <= ACC / 4
    apex = APEX if x == BLIND[0] else 0.0
    mo = _plunge(x, BLIND[1], apex - depth_below, 1, 7)
    res = verify_exact(mo, {1: tool}, stock, [Reference(tri, "solid")], accuracy=ACC)
    assert abs(res.max_gouge - truth) <= ACC + 1e-3
    if truth == 0.0:
        assert res.max_gouge <= ACC


def test_a_step_file_given_as_the_design_is_meshed_within_the_accuracy(solid, tmp_path):
    """``millpath simulate --design part.stp`` (and ``[simulation] design``): the
    triangles stand within a quarter of the accuracy of the analytic faces."""
    from millpath.cli.programs import read_design
    path = builder.write_step(solid, tmp_path / "part.stp")
    _, (ref,) = read_design(path, "mm", Stock.from_box(BOX))
    tri = ref.triangles
    d = analytic_distance(tri, np.einsum("kj,mjc->mkc", np.array(
        [[.5, .5, 0], [0, .5, .5], [.5, 0, .5], [1 / 3, 1 / 3, 1 / 3]]), tri))
    curved = ~np.isnan(d)
    assert curved.sum() > 1000
    assert np.max(d[curved]) <= ACC / 4 + 1e-9
