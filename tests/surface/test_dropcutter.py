"""Drop-cutter: exact contacts for flat, ball and bull cutters, against OpenCAMLib."""

from __future__ import annotations

import math

import numpy as np
import pytest

from millpath.part.surface.mesh import Mesh, function_mesh, grid_triangles, random_mesh
from millpath.geometry.cutter import Cutter
from millpath.plan.surface.dropcutter import MeshHeight, build_index, drop

CUTTERS = {"ball": Cutter(3.0, 3.0), "flat": Cutter(3.0, 0.0), "bull": Cutter(3.0, 1.0)}


def _ocl_z(mesh: Mesh, kind: str, xy: np.ndarray) -> np.ndarray:
    ocl = pytest.importorskip("opencamlib")
    s = ocl.STLSurf()
    for t in mesh.triangles:
        s.addTriangle(ocl.Triangle(*[ocl.Point(float(p[0]), float(p[1]), float(p[2]))
                                     for p in t]))
    cutter = {"ball": ocl.BallCutter(6.0, 40.0), "flat": ocl.CylCutter(6.0, 40.0),
              "bull": ocl.BullCutter(6.0, 1.0, 40.0)}[kind]
    b = ocl.BatchDropCutter()
    b.setSTL(s)
    b.setCutter(cutter)
    zmin = float(mesh.bounds[0][2]) - 50.0
    for x, y in xy:
        b.appendPoint(ocl.CLPoint(float(x), float(y), zmin))
    b.run()
    return np.array([p.z for p in b.getCLPoints()])


def _step_mesh() -> Mesh:
    """A block with exactly vertical walls on a floor, plus a slanted roof."""
    x = np.array([0.0, 10.0, 10.0, 20.0, 25.0, 25.0, 40.0])
    y = np.array([0.0, 12.0, 12.0, 28.0, 28.0, 40.0])
    X, Y = np.meshgrid(x, y)
    inside = (np.arange(7)[None, :] >= 2) & (np.arange(7)[None, :] <= 4) \
        & (np.arange(6)[:, None] >= 2) & (np.arange(6)[:, None] <= 3)
    Z = np.where(inside, 8.0 + 0.2 * X - 0.1 * Y, 0.0)
    return Mesh(grid_triangles(x, y, Z), "step")


MESHES = {
    "random": lambda: random_mesh(3000, seed=7, size=50.0, zrange=12.0),
    "waves": lambda: function_mesh(lambda x, y: 4 * np.sin(x / 3.0) * np.cos(y / 4.0),
                                   (0, 40), (0, 40), 41, 37, "waves"),
    "step": _step_mesh,
}


@pytest.mark.parametrize("mesh_name", sorted(MESHES))
@pytest.mark.parametrize("kind", sorted(CUTTERS))
def test_drop_agrees_with_opencamlib_within_1e6(mesh_name, kind):
    mesh = MESHES[mesh_name]()
    lo, hi = mesh.bounds
    rng = np.random.default_rng(11)
    xy = rng.uniform(lo[:2] + 3.5, hi[:2] - 3.5, size=(600, 2))
    r = drop(build_index(mesh), CUTTERS[kind], xy)
    z_ocl = _ocl_z(mesh, kind, xy)
    assert np.all(np.isfinite(r.z))
    np.testing.assert_allclose(r.z, z_ocl, atol=1e-6, rtol=0)


@pytest.mark.parametrize("kind", sorted(CUTTERS))
def test_passes_of_close_points_agree_with_opencamlib_within_1e6(kind):
    """Points in pass order (each query starts from the previous contact, a triangle
    listed in several cells is tested once per query), serial and parallel batches and
    repeated calls on one index."""
    mesh = MESHES["waves"]()
    idx = build_index(mesh, cell=0.8)
    xs = np.arange(3.5, 36.5, 0.07)
    ys = np.arange(4.0, 36.0, 2.3)
    X, Y = np.meshgrid(xs, ys)
    X[1::2] = X[1::2, ::-1]                                   # zigzag order
    xy = np.column_stack([X.ravel(), Y.ravel()])
    assert len(xy) >= 4000 > len(xs)
    z_ocl = _ocl_z(mesh, kind, xy)
    whole = drop(idx, CUTTERS[kind], xy).z                    # parallel batch
    rows = np.concatenate([drop(idx, CUTTERS[kind], xy[i:i + len(xs)]).z
                           for i in range(0, len(xy), len(xs))])   # serial calls
    np.testing.assert_allclose(whole, z_ocl, atol=1e-6, rtol=0)
    np.testing.assert_allclose(rows, z_ocl, atol=1e-6, rtol=0)


@pytest.mark.parametrize("kind", sorted(CUTTERS))
def test_contact_point_is_on_the_cutter_surface_and_on_the_mesh(kind):
    mesh = random_mesh(1500, seed=2, size=40.0)
    idx = build_index(mesh)
    c = CUTTERS[kind]
    rng = np.random.default_rng(5)
    xy = rng.uniform(5, 35, size=(300, 2))
    r = drop(idx, c, xy)
    d = np.hypot(r.cc[:, 0] - xy[:, 0], r.cc[:, 1] - xy[:, 1])
    assert np.all(d <= c.radius + 1e-9)
    prof = np.array([c.height(v) for v in d])
    np.testing.assert_allclose(r.cc[:, 2], r.z + prof, atol=1e-9)
    surf = MeshHeight(idx).height(r.cc[:, 0], r.cc[:, 1])
    assert np.all(r.cc[:, 2] <= surf + 1e-9)     # contact lies on (the top of) the mesh


def test_ball_on_a_plane_touches_under_the_axis_offset_by_the_normal():
    # plane z = 0.5 x: ball centre sits R / cos(theta) above the plane, tip R below that
    mesh = function_mesh(lambda x, y: 0.5 * x, (0, 30), (0, 30), 7, 7, "slope")
    R = 3.0
    z = drop(build_index(mesh), Cutter(R, R), [[15.0, 15.0]]).z[0]
    expected = 7.5 + R * math.sqrt(1 + 0.25) - R
    assert z == pytest.approx(expected, abs=1e-12)


def test_flat_cutter_on_a_plane_rests_on_its_rim():
    mesh = function_mesh(lambda x, y: 0.5 * x, (0, 30), (0, 30), 7, 7, "slope")
    z = drop(build_index(mesh), Cutter(3.0, 0.0), [[15.0, 15.0]]).z[0]
    assert z == pytest.approx(0.5 * 18.0, abs=1e-12)


def test_ball_over_a_spherical_dent_matches_the_closed_form():
    # fine mesh of a sphere cap of radius 20: ball centre at distance 20 - R from centre
    Rs, R = 20.0, 3.0
    mesh = function_mesh(lambda x, y: 30.0 - np.sqrt(np.maximum(Rs**2 - x**2 - y**2, 0.0)),
                         (-12, 12), (-12, 12), 241, 241, "dent")
    xy = np.array([[0.0, 0.0], [3.0, -2.0], [-4.0, 5.0]])
    z = drop(build_index(mesh), Cutter(R, R), xy).z
    rho = np.hypot(xy[:, 0], xy[:, 1])
    exact = 30.0 - np.sqrt((Rs - R) ** 2 - rho**2) - R
    # vertices lie on the sphere and the chords of a concave surface lie above it: the
    # tool sits slightly higher than on the true sphere, by at most the chord error
    assert np.all(z >= exact - 1e-9)
    assert np.all(z <= exact + 0.001)


def test_points_off_the_mesh_get_minus_infinity_or_the_floor():
    mesh = random_mesh(200, seed=0, size=10.0)
    idx = build_index(mesh)
    r = drop(idx, CUTTERS["ball"], [[100.0, 100.0], [5.0, 5.0]])
    assert r.z[0] == -np.inf and np.isfinite(r.z[1])
    assert np.isnan(r.cc[0]).all()
    r2 = drop(idx, CUTTERS["ball"], [[100.0, 100.0]], z_floor=-7.0)
    assert r2.z[0] == -7.0


def test_mesh_height_interpolates_triangles():
    mesh = function_mesh(lambda x, y: 2.0 * x - y + 1.0, (0, 10), (0, 10), 5, 5, "plane")
    h = MeshHeight(build_index(mesh))
    x = np.array([0.3, 5.0, 9.9, 20.0])
    y = np.array([0.1, 7.5, 9.9, 1.0])
    z = h.height(x, y)
    np.testing.assert_allclose(z[:3], 2 * x[:3] - y[:3] + 1.0, atol=1e-12)
    assert z[3] == -np.inf


def test_cutter_parse_and_profile():
    assert Cutter.parse("ball:6") == Cutter(3.0, 3.0)
    assert Cutter.parse("flat:6") == Cutter(3.0, 0.0)
    assert Cutter.parse("bull:6:1") == Cutter(3.0, 1.0)
    with pytest.raises(ValueError):
        Cutter.parse("bull:6")
    with pytest.raises(ValueError):
        Cutter.parse("cone:6")
    c = Cutter(3.0, 1.0)
    assert c.height(1.5) == 0.0 and c.height(3.0) == pytest.approx(1.0)
