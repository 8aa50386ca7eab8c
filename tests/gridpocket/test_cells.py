"""Pocket outline validation, inward offset by the tool radius, and the grid check."""

from __future__ import annotations

import math

import numpy as np
import pytest
import shapely

from millpath.errors import GeometryError, PlanningError
from millpath.plan.gridpocket.cells import (build_grid, check_grid, inward_offset,
                                            pocket_polygon, polygon_problem)

L_SHAPE = [[0, 0], [3, 0], [3, 1], [1, 1], [1, 2], [0, 2]]


def test_self_intersecting_outline_is_rejected_with_file_and_key():
    bow = [[0, 0], [2, 2], [2, 0], [0, 2]]
    assert "intersects itself" in polygon_problem(bow)
    with pytest.raises(GeometryError) as e:
        pocket_polygon(bow, "job.toml", "operations[0].polygon")
    assert str(e.value).startswith("job.toml: operations[0].polygon:")


@pytest.mark.parametrize("pts,why", [
    ([[0, 0], [1, float("nan")], [1, 1]], "NaN"),
    ([[0, 0], [1, 1]], "at least 3"),
    ([[0, 0], [1, 1], [2, 2]], "no area"),
    ([[0, 0, 1], [1, 0, 1], [1, 1, 1]], "[x, y]"),
])
def test_degenerate_outlines_are_rejected(pts, why):
    assert why in polygon_problem(pts)


def test_closed_and_clockwise_outlines_are_accepted_and_oriented_ccw():
    poly = pocket_polygon([[0, 0], [0, 1], [1, 1], [1, 0], [0, 0]])
    assert poly.exterior.is_ccw and poly.area == pytest.approx(1.0)


def test_inward_offset_keeps_exactly_one_radius_from_every_wall_concave_corner_included():
    poly = pocket_polygon(L_SHAPE)
    r = 0.2
    off = inward_offset(poly, r)
    b = np.asarray(off.exterior.coords)
    d = shapely.distance(poly.exterior, shapely.points(b))
    assert np.allclose(d, r, atol=1e-6)
    # the concave corner (1, 1) is rounded: offset points around it at distance r
    near = b[np.hypot(b[:, 0] - 1, b[:, 1] - 1) < r + 1e-6]
    assert len(near) >= 5


def test_grid_cells_inside_the_offset_only():
    poly = pocket_polygon(L_SHAPE)
    g = build_grid(poly, 0.125, 0.125, 0.0625)
    assert g.shape == (24, 32)
    i, j = np.nonzero(g.inside)
    x, y = g.centre(i, j)
    d = shapely.distance(poly.exterior, shapely.points(x, y))
    assert d.min() >= 0.125 - 1e-7
    assert shapely.contains_xy(poly, x, y).all()
    # every cell centre that is at least R inside is used
    ii, jj = np.nonzero(~g.inside)
    x2, y2 = g.centre(ii, jj)
    inside_poly = shapely.contains_xy(poly, x2, y2)
    d2 = shapely.distance(poly.exterior, shapely.points(x2, y2))
    assert not np.any(inside_poly & (d2 > 0.125 + 1e-7))


def test_tool_too_big_for_the_pocket_is_a_planning_error():
    poly = pocket_polygon([[0, 0], [0.2, 0], [0.2, 3], [0, 3]])
    with pytest.raises(PlanningError, match="too big"):
        build_grid(poly, 0.125, 0.1, 0.1, "job.toml")


def test_cells_larger_than_d_over_sqrt2_are_rejected_unless_forced():
    d = 0.25
    check_grid(d / math.sqrt(2), 0.0625, d)
    with pytest.raises(PlanningError, match="D/sqrt"):
        check_grid(0.18, 0.0625, d, file="job.toml")
    check_grid(0.18, 0.0625, d, force=True)


def test_segment_inside_respects_concave_walls():
    poly = pocket_polygon(L_SHAPE)
    g = build_grid(poly, 0.2, 0.1, 0.1)
    assert g.segment_inside((0.5, 0.5), (2.5, 0.5))
    assert not g.segment_inside((0.5, 1.7), (2.5, 0.5))     # cuts across the inner corner
