"""pocket: floors cleared, walls and islands untouched, safe entries, measured engagement.

Truth: polygons built here with shapely (independently of the drawing reader and the
planner), the simulator's Z-map swept by the test itself (helpers.measure)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import shapely
from shapely.geometry import Polygon, box

from millpath.io.schema import validate
from millpath.model import Machine, Stock, Tool
from millpath.plan.base import PlanContext
from millpath.plan.pocket import operation as pocket


TOP, DEPTH = 0.0, 3.0
SQUARE = [[0, 0], [40, 0], [40, 30], [0, 30]]
ISLAND = [[15, 10], [22, 10], [22, 18], [15, 18]]
# two rooms joined by a neck 8 mm wide (tool 6 mm)
NECK = [[0, 0], [18, 0], [18, 11], [26, 11], [26, 0], [44, 0], [44, 27], [26, 27],
        [26, 19], [18, 19], [18, 27], [0, 27]]


def _plan(polygon, islands, strategy, D=6.0, **extra):
    tools = {1: Tool(1, "flat", D)}
    stock = Stock(-8, -8, -10, 52, 38, TOP)
    ctx = PlanContext("mm", stock, Machine(), tools, Path("."))
    keys = {"tool": 1, "polygon": polygon, "depth": DEPTH, "stepdown": 3.0,
            "strategy": strategy, "feed": 1000.0, **extra}
    if islands:
        keys["islands"] = islands
    res = pocket.plan(ctx, validate(keys, pocket.PARAMS, "op", None))
    return res, tools, stock


def cell_centres(zm):
    return np.meshgrid(zm.xs(), zm.ys())


def _check_cut(zm, part: Polygon, R: float, floor: float):
    """Every cell the tool can reach is at the floor; nothing outside ``part`` is cut."""
    X, Y = cell_centres(zm)
    diag = np.hypot(zm.dx, zm.dy)
    reach = part.buffer(-R).buffer(R - diag)          # reachable, one cell in
    inside = shapely.contains_xy(reach, X, Y)
    assert inside.sum() > 100
    assert np.abs(zm.heights[inside] - floor).max() <= 1e-9
    outside = ~shapely.contains_xy(part.buffer(diag), X, Y)
    assert np.all(zm.heights[outside] == TOP)


@pytest.mark.parametrize("strategy", ["offset", "zigzag", "adaptive"])
def test_floor_cleared_walls_and_island_untouched_no_plunge(strategy, sweep_measure):
    res, tools, stock = _plan(SQUARE, [ISLAND], strategy)
    zm, samples, plunge = sweep_measure(res.toolpath, tools, stock, 0.1)
    part = Polygon(SQUARE, [ISLAND])
    _check_cut(zm, part, 3.0, TOP - DEPTH)
    assert plunge <= 1e-9                      # no straight feed down into material
    rapids = [m for m in res.toolpath.moves if m.kind == "rapid"]
    assert min(m.end[2] for m in rapids) >= TOP   # rapids never go below the stock top


def test_finish_allowance_leaves_stock_then_finish_cuts_to_size(sweep_measure):
    res, tools, stock = _plan(SQUARE, [ISLAND], "offset", allowance=0.5)
    ops = res.toolpath.ops
    assert [o.name for o in ops] == ["pocket offset", "pocket finish"]
    tp_rough = type(res.toolpath)("mm")
    tp_rough.begin(ops[0])
    for m in res.toolpath.moves:
        if m.op == 0:
            tp_rough.moves.append(m)
    zm, _, _ = sweep_measure(tp_rough, tools, stock, 0.1)
    X, Y = cell_centres(zm)
    core = shapely.contains_xy(Polygon(SQUARE, [ISLAND]).buffer(-3.5).buffer(3.0 - 0.15), X, Y)
    assert np.abs(zm.heights[core] - (TOP - DEPTH + 0.5)).max() <= 1e-9   # floor allowance
    wall = shapely.contains_xy(box(0, 0, 40, 30).buffer(-0.05), X, Y) & ~shapely.contains_xy(
        box(0, 0, 40, 30).buffer(-0.45), X, Y) & ~shapely.contains_xy(
        Polygon(ISLAND).buffer(2), X, Y) & (np.abs(X - 20) < 10)
    assert wall.any() and np.all(zm.heights[wall] == TOP)               # wall allowance
    zm2, _, plunge = sweep_measure(res.toolpath, tools, stock, 0.1)
    _check_cut(zm2, Polygon(SQUARE, [ISLAND]), 3.0, TOP - DEPTH)
    assert plunge <= 1e-9


@pytest.mark.parametrize("name,polygon,islands", [
    ("sharp corners and an island", SQUARE, [ISLAND]),
    ("narrow neck", NECK, []),
])
def test_adaptive_engagement_never_exceeds_target(name, polygon, islands, sweep_measure):
    target = 0.15
    res, tools, stock = _plan(polygon, islands, "adaptive", engagement=target)
    zm, s, plunge = sweep_measure(res.toolpath, tools, stock, 0.05)
    assert len(s) > 100
    assert s[:, 2].max() <= target + 0.001, s[np.argmax(s[:, 2])]
    assert s[:, 2].mean() > 0.3 * target            # it does cut, not only graze
    _check_cut(zm, Polygon(polygon, islands), 3.0, TOP - DEPTH)
    assert plunge <= 1e-9


def test_tool_too_big_and_neck_errors_name_the_place():
    from millpath.errors import PlanningError
    with pytest.raises(PlanningError, match=r"does not fit in the pocket polygon: its widest place, round \(\d+\.\d+, 15\.000\), is 30 wide"):
        _plan(SQUARE, [], "offset", D=32.0)
    with pytest.raises(PlanningError, match=r"neck of the pocket polygon at \(22\.000, 15\.000\)"):
        _plan(NECK, [], "offset", D=9.0)
