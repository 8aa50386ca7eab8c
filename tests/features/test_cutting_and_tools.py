"""Cutting data, tool selection and path building blocks of the features planner."""

from __future__ import annotations

import math

import pytest

from millpath.model import Tool, Toolpath, Operation
from millpath.part.step.shapes import HoleShape, PocketShape, SlotShape
from millpath.plan.features import paths
from millpath.plan.features.cutting import MATERIALS, material_class, speeds
from millpath.plan.features.select import hole_tool, pocket_tool, slot_tool


@pytest.mark.parametrize("text, cls", [
    ("phosphor bronze to BS 2874 PB 102", "brass-bronze"),
    ("aluminium 6061-T6", "aluminium"),
    ("Aluminum 7075", "aluminium"),
    ("SAE 1020", "steel"),
    ("mild steel S235", "steel"),
    ("AISI 4140", "alloy-steel"),
    ("stainless steel 316L", "stainless"),
    ("Delrin (POM)", "plastic"),
    ("Ti-6Al-4V", "titanium"),
    ("unobtainium", "steel"),
])
def test_material_classes(text, cls):
    assert material_class(text) == cls


def test_spindle_and_feed_formulas_mm():
    t = Tool(1, "flat", 10.0, flutes=3)
    s = speeds(t, "aluminium", "mm")
    data = MATERIALS["aluminium"]
    rpm = 1000 * data.vc_mill / (math.pi * 10.0)
    assert s.rpm == round(rpm)
    assert s.feed == pytest.approx(data.fz_mill * 3 * rpm, abs=0.5)
    assert s.plunge == pytest.approx(0.3 * s.feed, abs=1.0)


def test_drill_feed_is_per_revolution_and_inch_jobs_get_inch_per_minute():
    d = Tool(1, "drill", 0.25, flute_length=1.0, stickout=1.5)
    s = speeds(d, "steel", "inch")
    d_mm = 0.25 * 25.4
    rpm = 1000 * MATERIALS["steel"].vc_drill / (math.pi * d_mm)
    assert s.rpm == round(rpm)
    fr = MATERIALS["steel"].fr_drill * d_mm / 10.0
    assert s.feed == pytest.approx(fr * rpm / 25.4, abs=0.06)


def test_spindle_limit_and_hss_speed():
    small = Tool(1, "flat", 1.0, flutes=2)
    assert speeds(small, "aluminium", "mm", max_rpm=20000).rpm == 20000
    hss = Tool(2, "flat", 10.0, flutes=2, material="HSS")
    carbide = Tool(3, "flat", 10.0, flutes=2)
    assert speeds(hss, "steel", "mm").rpm == pytest.approx(
        0.35 * speeds(carbide, "steel", "mm").rpm, abs=1)


LIB = [Tool(1, "flat", 20.0, flute_length=40, stickout=60),
       Tool(2, "flat", 10.0, flute_length=30, stickout=45),
       Tool(3, "flat", 6.0, flute_length=20, stickout=35),
       Tool(4, "drill", 16.6, flute_length=60, stickout=80),
       Tool(5, "drill", 8.0, flute_length=40, stickout=60, point_angle=118.0),
       Tool(6, "ball", 10.0, flute_length=20, stickout=40),
       Tool(7, "bull", 12.0, corner_radius=1.0, flute_length=25, stickout=40)]


def hole(d, bottom="through", depth=10.0, **kw):
    return HoleShape(1, 0.0, 0.0, 10.0, d, depth, bottom, **kw)


def test_hole_with_matching_drill_is_drilled_else_helical():
    assert hole_tool(hole(16.6), LIB, 0.01)[:2] == ("drill", LIB[3])
    strat, tool, _ = hole_tool(hole(16.0), LIB, 0.01)
    assert strat == "helical" and tool.number == 2          # largest flat <= 0.9 D
    strat, tool, _ = hole_tool(hole(75.0), LIB, 0.01)
    assert strat == "helical" and tool.number == 1


def test_hole_bottom_kinds_choose_their_tools():
    assert hole_tool(hole(8.0, "conical", tip_angle=118.0), LIB, 0.01)[1].number == 5
    assert hole_tool(hole(8.0, "conical", tip_angle=90.0), LIB, 0.01)[1] is None
    assert hole_tool(hole(10.0, "spherical", bottom_radius=5.0), LIB, 0.01)[:2] == (
        "plunge", LIB[5])
    assert hole_tool(hole(16.0, "flat with radius", bottom_radius=1.0), LIB, 0.01)[1].number == 7
    assert hole_tool(hole(16.0, "flat"), LIB, 0.01)[1].number == 2
    strat, tool, note = hole_tool(hole(8.0, "flat"), [LIB[4]], 0.01)
    assert strat == "drill" and "cone" in note


def test_slot_tool_is_no_wider_than_the_slot():
    s = SlotShape(1, (0, 0), (1, 0), 50.0, 12.0, 3.0, 10.0, ("open", "open"))
    assert slot_tool(s, LIB, 0.01)[1].number == 2
    s.width = 25.0
    assert slot_tool(s, LIB, 0.01)[1].number == 1
    s.width = 5.0
    assert slot_tool(s, LIB, 0.01)[1] is None


def test_pocket_tool_radius_is_no_larger_than_the_corner_radius():
    p = PocketShape(1, (0, 0), 0.0, "rectangular", 5.0, 10.0, length=60, width=40,
                    corner_radius=5.0)
    assert pocket_tool(p, LIB, 0.01)[1].number == 2
    p.corner_radius = 3.0
    assert pocket_tool(p, LIB, 0.01)[1].number == 3
    p.corner_radius = 0.0
    strat, tool, note = pocket_tool(p, LIB, 0.01)
    assert tool.number == 3 and "corners are left" in note


def test_levels_are_equal_and_reach_the_floor():
    assert paths.levels(10.0, 0.0, 4.0) == pytest.approx([10 - 10 / 3, 10 - 20 / 3, 0.0])
    assert paths.levels(10.0, 7.0, 5.0) == [7.0]


def test_bore_covers_the_centre_and_ends_on_the_wall_radius():
    tp = Toolpath()
    tp.begin(Operation("features", "t", 1))
    h = paths.Heights(15.0, 11.0)
    paths.bore(tp, 50.0, 20.0, 20.0, 5.0, 10.0, 0.0, h, step_down=5.0, stepover=4.0,
               allowance=0.2, feed=500.0, plunge_feed=150.0)
    arcs = [m for m in tp.moves if m.kind == "arc"]
    radii = sorted({round(m.end[0] - 50.0, 6) for m in arcs})
    assert radii[0] <= 2.5 + 1e-9            # innermost ring within half the tool radius
    assert radii[-1] == pytest.approx(15.0)  # finishing radius = hole radius - tool radius
    assert max(b - a for a, b in zip(radii, radii[1:])) <= 4.0 + 1e-9
    assert min(m.end[2] for m in tp.moves) == pytest.approx(0.0)
    assert tp.moves[-1].kind == "rapid" and tp.moves[-1].end[2] == 15.0


@pytest.mark.parametrize("region", ["line", "box"])
def test_entries_into_material_ramp_no_steeper_than_the_ramp_angle(region):
    from shapely.geometry import LineString, box
    geom = LineString([(0.0, 0.0), (40.0, 0.0)]) if region == "line" else box(0, 0, 20, 10)
    tp = Toolpath()
    tp.begin(Operation("features", "t", 1))
    paths.clear_region(tp, geom, None, 10.0, 4.0, paths.Heights(15.0, 11.0), step_down=3.0,
                       stepover=4.0, feed=500.0, plunge_feed=150.0)
    tan = math.tan(math.radians(paths.RAMP_ANGLE))
    prev = None
    descents = 0
    for m in tp.moves:
        if prev is not None and m.kind == "line" and prev[2] <= 10.0 + 1e-9 \
                and m.end[2] < prev[2] - 1e-9:
            horiz = math.hypot(m.end[0] - prev[0], m.end[1] - prev[1])
            assert prev[2] - m.end[2] <= horiz * tan + 1e-9
            descents += 1
        prev = m.end
    assert descents > 0
    assert min(m.end[2] for m in tp.moves) == pytest.approx(4.0)


def test_speed_and_feed_scales():
    t = Tool(1, "flat", 10.0, flutes=3)
    base = speeds(t, "steel", "mm")
    scaled = speeds(t, "steel", "mm", speed_scale=0.5, feed_scale=2.0)
    assert scaled.rpm == pytest.approx(base.rpm / 2, abs=1)
    assert scaled.feed == pytest.approx(base.feed, abs=2)     # half rpm, double chip
