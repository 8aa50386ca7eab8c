"""Bezier patches and measured grids: evaluation, inversion, interpolation, meshes."""

from __future__ import annotations

import numpy as np
import pytest

from millpath.errors import GeometryError
from millpath.part.surface import BezierPatch, MeasuredGrid


def _de_casteljau(net: np.ndarray, u: float, v: float) -> np.ndarray:
    """Reference evaluation by repeated linear interpolation."""
    rows = []
    for i in range(net.shape[0]):
        pts = net[i].copy()
        while len(pts) > 1:
            pts = (1 - v) * pts[:-1] + v * pts[1:]
        rows.append(pts[0])
    pts = np.array(rows)
    while len(pts) > 1:
        pts = (1 - u) * pts[:-1] + u * pts[1:]
    return pts[0]


def _random_net(m, n, seed=1):
    rng = np.random.default_rng(seed)
    xs, ys = np.linspace(0, 3, m + 1), np.linspace(0, 2, n + 1)
    X, Y = np.meshgrid(xs, ys, indexing="ij")
    net = np.stack([X + 0.1 * rng.standard_normal(X.shape), Y + 0.1 * rng.standard_normal(X.shape),
                    rng.standard_normal(X.shape)], -1)
    return net


@pytest.mark.parametrize("m,n", [(1, 1), (3, 3), (2, 5), (6, 4)])
def test_bezier_evaluate_matches_de_casteljau_for_any_degree(m, n):
    net = _random_net(m, n)
    patch = BezierPatch(net)
    for u, v in [(0, 0), (1, 1), (0.3, 0.7), (0.9, 0.15)]:
        assert np.allclose(patch.evaluate(u, v), _de_casteljau(net, u, v), atol=1e-12)


def test_bezier_corners_interpolate_control_corners():
    net = _random_net(3, 2)
    patch = BezierPatch(net)
    assert np.allclose(patch.evaluate([0, 1, 0, 1], [0, 0, 1, 1]),
                       net[[0, -1, 0, -1], [0, 0, -1, -1]])


def test_bezier_derivatives_match_finite_differences():
    patch = BezierPatch(_random_net(3, 4))
    u, v, h = 0.37, 0.61, 1e-6
    su, sv = patch.derivatives(u, v)
    fu = (patch.evaluate(u + h, v) - patch.evaluate(u - h, v)) / (2 * h)
    fv = (patch.evaluate(u, v + h) - patch.evaluate(u, v - h)) / (2 * h)
    assert np.allclose(su, fu, atol=1e-6) and np.allclose(sv, fv, atol=1e-6)
    suu = patch.evaluate(u, v, 2, 0)
    fuu = (patch.evaluate(u + 1e-4, v) - 2 * patch.evaluate(u, v) + patch.evaluate(u - 1e-4, v)) / 1e-8
    assert np.allclose(suu, fuu, atol=1e-3)


def test_bezier_from_heights_maps_xy_to_the_box():
    z = np.array([[-0.3, -0.4, -0.3], [-0.45, -0.5, -0.4], [-0.3, -0.35, -0.28]])
    patch = BezierPatch.from_heights(z, (0.0, 0.0, 3.0, 2.0))
    u, v = np.array([0.2, 0.5, 0.8]), np.array([0.1, 0.6, 0.9])
    p = patch.evaluate(u, v)
    assert np.allclose(p[:, 0], 3 * u) and np.allclose(p[:, 1], 2 * v)
    assert np.allclose(patch.height(p[:, 0], p[:, 1]), p[:, 2])


def test_bezier_height_inverts_a_curved_xy_mapping():
    patch = BezierPatch(_random_net(3, 3, seed=4))
    uu, vv = np.meshgrid(np.linspace(0.05, 0.95, 7), np.linspace(0.05, 0.95, 5), indexing="ij")
    p = patch.evaluate(uu, vv)
    z = patch.height(p[..., 0], p[..., 1])
    assert z.shape == uu.shape
    assert np.allclose(z, p[..., 2], atol=1e-9)


def test_bezier_height_outside_is_nan_on_request():
    patch = BezierPatch.from_heights(np.zeros((2, 2)), (0, 0, 1, 1))
    assert np.isnan(patch.height(np.array([2.0]), np.array([0.5]), outside="nan"))[0]
    assert patch.height(np.array([2.0]), np.array([0.5]))[0] == 0.0


def test_bezier_mesh_has_two_triangles_per_cell_on_the_surface():
    patch = BezierPatch.from_heights([[0, 1], [1, 2]], (0, 0, 1, 1))
    tris = patch.to_mesh(4, 3)
    assert tris.shape == (24, 3, 3)
    v = tris.reshape(-1, 3)
    assert np.allclose(patch.height(v[:, 0], v[:, 1]), v[:, 2])
    # counter-clockwise seen from +Z: positive signed area
    e1, e2 = tris[:, 1] - tris[:, 0], tris[:, 2] - tris[:, 0]
    assert np.all(e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0] > 0)


def test_bezier_rejects_nan_and_bad_shapes():
    with pytest.raises(GeometryError):
        BezierPatch(np.full((2, 2, 3), np.nan))
    with pytest.raises(GeometryError):
        BezierPatch(np.zeros((2, 3)))
    with pytest.raises(GeometryError):
        BezierPatch.from_heights([[0, 1]], (0, 0, 1, 1))


def _grid_points(f, nx=6, ny=5, h=0.3, jitter=0.0, seed=0):
    rng = np.random.default_rng(seed)
    X, Y = np.meshgrid(np.arange(nx) * h, np.arange(ny) * h, indexing="ij")
    X = X + jitter * h * rng.uniform(-1, 1, X.shape)
    Y = Y + jitter * h * rng.uniform(-1, 1, Y.shape)
    pts = np.stack([X.ravel(), Y.ravel(), f(X.ravel(), Y.ravel())], 1)
    return pts[rng.permutation(len(pts))]


def test_measured_grid_reproduces_samples_and_bilinear_functions():
    f = lambda x, y: 0.1 + 0.2 * x - 0.3 * y + 0.05 * x * y  # noqa: E731
    g = MeasuredGrid(_grid_points(f))
    assert g.regular
    x = np.linspace(0, 1.5, 13)
    y = np.linspace(0, 1.2, 13)
    assert np.allclose(g.height(x, y), f(x, y), atol=1e-12)
    assert np.allclose(g.height(g.X, g.Y), g.Z)


def test_measured_grid_near_regular_passes_through_every_sample():
    f = lambda x, y: np.sin(x) * np.cos(y)  # noqa: E731
    pts = _grid_points(f, jitter=0.05)
    g = MeasuredGrid(pts)
    assert not g.regular
    assert np.allclose(g.height(pts[:, 0], pts[:, 1]), pts[:, 2], atol=1e-9)
    # between samples it stays close to the smooth function
    x, y = np.meshgrid(np.linspace(0.1, 1.4, 9), np.linspace(0.1, 1.1, 9))
    assert np.abs(g.height(x, y) - f(x, y)).max() < 0.03


def test_measured_grid_cubic_is_closer_than_linear_on_a_smooth_surface():
    f = lambda x, y: np.sin(2 * x) * np.cos(1.5 * y)  # noqa: E731
    pts = _grid_points(f, nx=9, ny=8)
    x, y = np.meshgrid(np.linspace(0.2, 2.2, 15), np.linspace(0.2, 1.9, 15))
    lin = np.abs(MeasuredGrid(pts).height(x, y) - f(x, y)).max()
    cub = np.abs(MeasuredGrid(pts, method="cubic").height(x, y) - f(x, y)).max()
    assert cub < lin / 3


def test_measured_grid_reads_csv_with_header_and_names_bad_lines(tmp_path):
    f = tmp_path / "pts.csv"
    f.write_text("x,y,z\n0,0,1\n1,0,2\n0,1,3\n1,1,4\n")
    g = MeasuredGrid.from_csv(f)
    assert g.height(np.array([0.5]), np.array([0.5]))[0] == pytest.approx(2.5)
    assert g.to_mesh().shape == (2, 3, 3)
    assert g.to_mesh(4, 4).shape == (32, 3, 3)
    bad = tmp_path / "bad.csv"
    bad.write_text("0,0,1\n1,0,2\n0,1,nan\n")
    with pytest.raises(GeometryError) as e:
        MeasuredGrid.from_csv(bad)
    assert e.value.line == 3 and "bad.csv" in str(e.value)
    bad.write_text("0,0,1\n1,0,2\n0,1,oops\n")
    with pytest.raises(GeometryError, match=":3:"):
        MeasuredGrid.from_csv(bad)


def test_measured_grid_rejects_incomplete_grids():
    pts = _grid_points(lambda x, y: x * 0, nx=4, ny=4)[:-1]
    with pytest.raises(GeometryError, match="do not fill"):
        MeasuredGrid(pts)
