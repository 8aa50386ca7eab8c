"""Four-point segments, C1 blends, fewest-chord linearization, points files."""

from __future__ import annotations

import math

import numpy as np
import pytest

from millpath.errors import GeometryError, JobError
from millpath.part.curve.blend import build_curve
from millpath.part.curve.fourpoint import BASIS, DBASIS, FourPointSegment, basis, dbasis
from millpath.part.curve.linearize import chord_deviation, linearize_curve
from millpath.part.curve.points import points_from_params, read_points_csv

PUBLISHED = [(1, 15), (3, 14), (5, 12.5), (7, 10), (15, 8), (11, 17), (5, 16.5), (1, 15)]


def dense_chord_deviation(seg, a, b, n=400):
    """Largest distance of curve samples on [a, b] from the chord segment."""
    u = a[:, None] + (b - a)[:, None] * np.linspace(0, 1, n + 1)[None, :]
    p = seg.at(u)
    pa, pb = seg.at(a)[:, None, :], seg.at(b)[:, None, :]
    d = pb - pa
    t = np.clip(((p - pa) * d).sum(-1) / (d * d).sum(-1), 0, 1)
    return np.hypot(*np.moveaxis(p - (pa + t[..., None] * d), -1, 0)).max(axis=1)


def test_basis_interpolates_its_nodes_and_sums_to_one():
    nodes = np.array([0, 1 / 3, 2 / 3, 1])
    assert np.allclose(basis(nodes), np.eye(4), atol=1e-14)
    u = np.linspace(0, 1, 11)
    assert np.allclose(basis(u).sum(axis=1), 1.0)
    assert np.allclose(dbasis(u).sum(axis=1), 0.0)


def test_derivative_coefficients_are_derived_not_misprinted():
    # L2'(u) = 40.5 u^2 - 45 u + 9 (the published table prints 41.5)
    assert DBASIS[1].tolist() == [40.5, -45.0, 9.0]
    assert DBASIS[2].tolist() == [-40.5, 36.0, -4.5]
    u = np.linspace(0.05, 0.95, 7)
    h = 1e-6
    fd = (basis(u + h) - basis(u - h)) / (2 * h)
    assert np.allclose(dbasis(u), fd, atol=1e-7)
    assert BASIS.shape == (4, 4)


def test_bezier_form_is_the_same_cubic():
    seg = FourPointSegment(np.array(PUBLISHED[:4], float))
    b = seg.bezier()
    u = np.linspace(0, 1, 9)[:, None]
    bz = ((1 - u) ** 3 * b[0] + 3 * (1 - u) ** 2 * u * b[1] + 3 * (1 - u) * u ** 2 * b[2]
          + u ** 3 * b[3])
    assert np.allclose(bz, seg.at(u[:, 0]), atol=1e-12)


def test_published_blend_inner_points_to_printed_precision():
    curve = build_curve(PUBLISHED)
    kinds = [s.kind for s in curve.segments]
    assert kinds == ["given", "blend", "given"]
    inner = curve.segments[1].points[1:3]
    # printed with two decimals, truncated: (10.33, 4.38) and (14.11, 0.44)
    printed = np.floor(inner * 100) / 100
    assert printed.tolist() == [[10.33, 4.38], [14.11, 0.44]]
    assert np.allclose(inner, [[10.3333, 4.3889], [14.1111, 0.4444]], atol=1e-4)


def test_blends_are_c1_at_both_junctions_and_the_curve_closes():
    pts = [(0, 0), (10, -1), (20, 1), (30, 0), (40, 10), (38, 20), (30, 30), (20, 32),
           (5, 25), (0, 20), (-3, 12), (-2, 6)]
    curve = build_curve(pts)
    assert curve.closed
    assert [s.kind for s in curve.segments] == ["given", "blend", "given", "blend",
                                                "given", "blend"]
    for j in curve.junctions():
        assert j["position_gap"] <= 1e-9
        assert j["derivative_gap"] <= 1e-9, j


def test_published_curve_junctions_report_the_closing_corner():
    j = build_curve(PUBLISHED).junctions()
    assert all(x["derivative_gap"] <= 1e-9 for x in j[:2])      # blend junctions C1
    assert j[2]["point"] == [1.0, 15.0] and abs(j[2]["tangent_turn_deg"]) > 170


def test_bad_point_counts_are_errors():
    with pytest.raises(GeometryError, match="four per segment"):
        build_curve(PUBLISHED[:6])
    with pytest.raises(GeometryError, match="coincide"):
        build_curve([(0, 0), (0, 0), (1, 1), (2, 2)])


@pytest.mark.parametrize("scale,tol", [(1.0, 0.00004), (20.0, 0.00004), (20.0, 0.01)])
def test_every_chord_meets_the_tolerance_by_dense_sampling(scale, tol):
    curve = build_curve(PUBLISHED).transformed(scale, (40.0, 40.0))
    lin = linearize_curve(curve, tol)
    for seg, sl in zip(curve.segments, lin.segments):
        dense = dense_chord_deviation(seg, sl.u[:-1], sl.u[1:])
        assert dense.max() <= tol
        assert np.allclose(dense, sl.deviation, atol=tol * 1e-3)
        # the search uses the tolerance: chords are long, not tiny steps
        assert np.median(sl.deviation) > 0.9 * tol
        assert sl.chords <= sl.uniform_chords
        u = np.linspace(0, 1, sl.uniform_chords + 1)
        assert chord_deviation(seg, u[:-1], u[1:]).max() <= tol
        if sl.uniform_chords > 1:
            u = np.linspace(0, 1, sl.uniform_chords)
            assert chord_deviation(seg, u[:-1], u[1:]).max() > tol


def test_linearization_report_has_the_published_table_columns():
    lin = linearize_curve(build_curve(PUBLISHED), 0.00004)
    rep = lin.report()
    assert rep["chords"] == sum(s["chords"] for s in rep["segments"])
    assert rep["chords"] < rep["uniform_chords"]
    s0 = rep["segments"][0]
    assert len(s0["steps"]) == len(s0["deviations"]) == s0["chords"]
    assert math.isclose(sum(s0["steps"]), 1.0, abs_tol=1e-9)
    assert max(s0["deviations"]) <= 0.00004


def test_fewer_chords_than_uniform_steps_on_the_published_curve():
    lin = linearize_curve(build_curve(PUBLISHED), 0.00004)
    assert all(s.chords < s.uniform_chords for s in lin.segments)


def test_points_csv_reads_header_comments_and_names_bad_lines(tmp_path):
    f = tmp_path / "pts.csv"
    f.write_text("# outline\nx,y\n" + "\n".join(f"{x},{y}" for x, y in PUBLISHED) + "\n")
    assert read_points_csv(f).shape == (8, 2)
    f.write_text("x,y\n1,2\n3,4\n5;6\n7 8\n1,2,3\n")
    with pytest.raises(GeometryError) as e:
        read_points_csv(f)
    assert str(e.value).startswith(f"{f}:6:")
    f.write_text("1,2\n3,abc\n")
    with pytest.raises(GeometryError) as e:
        read_points_csv(f)
    assert str(e.value).startswith(f"{f}:2:")
    with pytest.raises(JobError, match="exactly one"):
        points_from_params(None, None, "job.toml", "op")


def test_each_chord_reaches_as_far_as_the_tolerance_allows():
    """Greedy fewest chords: every chord's far end is the last parameter within T."""
    tol = 0.0005
    curve = build_curve(PUBLISHED)
    lin = linearize_curve(curve, tol)
    for seg, sl in zip(curve.segments, lin.segments):
        a, b = sl.u[:-2], sl.u[1:-1]                      # all chords but the last
        longer = np.minimum(b + 1e-6 * (b - a), 1.0)
        assert np.all(chord_deviation(seg, a, longer) > tol)
        assert np.all(sl.deviation <= tol)
