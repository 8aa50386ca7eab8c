"""Simulated removed volume against closed forms, at a resolution of D/50.

Paths are placed at generic positions (not aligned with the grid) so the cell-centre
sampling error averages out, as it does in real programs.
"""

from __future__ import annotations

import math

import pytest

from millpath.model import Operation, Stock, Tool, Toolpath
from millpath.simulate import simulate_toolpath

REL = 0.005          # the 0.5 %


def _tp(tool: int = 1) -> Toolpath:
    tp = Toolpath()
    tp.begin(Operation("test", "test", tool))
    return tp


def _sim(tp, tool: Tool, stock: Stock, **kw):
    return simulate_toolpath(tp, {tool.number: tool}, stock, resolution=tool.diameter / 50, **kw)


def test_flat_slot_volume_matches_slot_plus_end_circles():
    tool = Tool(1, "flat", 6.0)
    tp = _tp()
    a, b, depth = (3.3, 7.1), (41.7, 22.9), 2.0
    tp.rapid(a[0], a[1], 5.0)
    tp.line(a[0], a[1], -depth, 100)
    tp.line(b[0], b[1], -depth, 300)
    tp.rapid(b[0], b[1], 5.0)
    r = _sim(tp, tool, Stock(-10, -10, -10, 60, 40, 0))
    L = math.dist(a, b)
    expected = (L * 6.0 + math.pi * 9.0) * depth
    assert r.removed_volume == pytest.approx(expected, rel=REL)
    assert r.rapids_through_material == 0 and r.holder_contacts == 0


@pytest.mark.parametrize("depth", [3.0, 5.0])
def test_ball_groove_volume_matches_half_disc_section_and_hemisphere(depth):
    R = 3.0
    tool = Tool(1, "ball", 2 * R)
    tp = _tp()
    a, b = (2.17, 3.61), (37.9, 19.3)
    tp.rapid(a[0], a[1], 5.0)
    tp.line(a[0], a[1], -depth, 100)
    tp.line(b[0], b[1], -depth, 300)
    tp.rapid(b[0], b[1], 5.0)
    r = _sim(tp, tool, Stock(-5, -5, -10, 45, 25, 0))
    L = math.dist(a, b)
    extra = depth - R          # cylinder part above the ball centre
    section = math.pi * R * R / 2 + 2 * R * extra
    ends = 2.0 / 3.0 * math.pi * R ** 3 + math.pi * R * R * extra
    assert r.removed_volume == pytest.approx(L * section + ends, rel=REL)


@pytest.mark.parametrize("cycle,peck", [("G81", 0.0), ("G83", 2.5), ("G73", 1.5)])
def test_drilled_hole_volume_is_cylinder_plus_118_degree_cone(cycle, peck):
    tool = Tool(3, "drill", 6.0, point_angle=118.0, flute_length=40, stickout=50)
    tp = _tp(3)
    tp.rapid(10.37, 9.71, 10.0)
    tp.drill(10.37, 9.71, -12.0, 2.0, 100, cycle=cycle, peck=peck)
    r = _sim(tp, tool, Stock(0, 0, -20, 20, 20, 0))
    R = 3.0
    p = R / math.tan(math.radians(59.0))
    expected = math.pi * R * R * (12.0 - p) + math.pi * R * R * p / 3.0
    assert r.removed_volume == pytest.approx(expected, rel=REL)
    assert r.rapids_through_material == 0


def test_helical_bore_volume_is_cylinder_of_helix_plus_tool_radius():
    R, rh, depth = 3.0, 2.0, 6.0
    tool = Tool(1, "flat", 2 * R)
    tp = _tp()
    cx, cy = 20.13, 19.87
    tp.rapid(cx + rh, cy, 2.0)
    tp.line(cx + rh, cy, 0.0, 200)
    tp.arc((cx + rh, cy, -depth), (cx, cy, 0.0), clockwise=False, feed=300, turns=3)
    tp.arc((cx + rh, cy, -depth), (cx, cy, 0.0), clockwise=False, feed=300)
    tp.line(cx, cy, -depth, 300)
    tp.rapid(cx, cy, 5.0)
    r = _sim(tp, tool, Stock(0, 0, -10, 40, 40, 0))
    assert r.removed_volume == pytest.approx(math.pi * (rh + R) ** 2 * depth, rel=REL)


def test_circular_pocket_of_concentric_arcs_has_the_pocket_volume():
    R, Rp, depth = 3.0, 12.0, 4.0
    tool = Tool(1, "flat", 2 * R)
    tp = _tp()
    cx, cy = 15.07, 14.93
    tp.rapid(cx, cy, 2.0)
    tp.line(cx, cy, -depth, 100)
    for rr in (2.5, 5.0, 7.5, Rp - R):
        tp.line(cx + rr, cy, -depth, 300)
        tp.arc((cx + rr, cy, -depth), (cx, cy, -depth), clockwise=True, feed=300)
    tp.rapid(cx + Rp - R, cy, 5.0)
    r = _sim(tp, tool, Stock(0, 0, -10, 30, 30, 0))
    assert r.removed_volume == pytest.approx(math.pi * Rp * Rp * depth, rel=REL)


def test_bull_nose_cut_volume_accounts_for_corner_radii():
    R, rc, depth = 5.0, 2.0, 3.0
    a_ = R - rc
    tool = Tool(1, "bull", 2 * R, corner_radius=rc)
    tp = _tp()
    a, b = (8.21, 10.43), (52.6, 31.7)
    tp.rapid(a[0], a[1], 5.0)
    tp.line(a[0], a[1], -depth, 100)
    tp.line(b[0], b[1], -depth, 300)
    tp.rapid(b[0], b[1], 5.0)
    r = _sim(tp, tool, Stock(0, 0, -10, 60, 45, 0))
    L = math.dist(a, b)
    section = 2 * R * depth - 2 * (1 - math.pi / 4) * rc * rc
    tool_vol = math.pi * R * R * depth - 2 * math.pi * (a_ * (1 - math.pi / 4) * rc * rc
                                                        + rc ** 3 / 6)
    assert r.removed_volume == pytest.approx(L * section + tool_vol, rel=REL)


def test_cut_below_stock_bottom_removes_only_the_stock():
    tool = Tool(1, "flat", 6.0)
    tp = _tp()
    tp.rapid(10.3, 10.1, 5)
    tp.line(10.3, 10.1, -50, 100)
    r = _sim(tp, tool, Stock(0, 0, -5, 20, 20, 0))
    assert r.removed_volume == pytest.approx(math.pi * 9 * 5, rel=REL)
    assert r.zmap.heights.min() == -5.0
