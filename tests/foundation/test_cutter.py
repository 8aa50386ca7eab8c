"""The one cutter description: its profile on the solid each shape is, its outline and
the tools it is made from."""

from __future__ import annotations

import math

import numpy as np
import pytest

from millpath.geometry.cutter import BALL, BULL, DRILL, FLAT, Cutter, height
from millpath.model import Tool
from millpath.report.viewer.toolshape import cutter_profile

R = 3.0
r = np.linspace(0.0, R, 301)


def test_flat_end_is_a_plane():
    assert Cutter(R).kind == FLAT
    assert np.all(Cutter(R).height(r) == 0.0)


def test_ball_lies_on_its_sphere():
    h = Cutter(R, R).height(r)
    assert np.abs(r ** 2 + (h - R) ** 2 - R ** 2).max() < 1e-9
    assert Cutter(R, R).kind == BALL and Cutter(R, R).tip_height == pytest.approx(R)


@pytest.mark.parametrize("rc", [0.5, 1.5, 2.9])
def test_bull_is_flat_then_on_its_torus(rc):
    c = Cutter(R, rc)
    h = c.height(r)
    a = R - rc
    assert c.kind == BULL
    assert np.all(h[r <= a] == 0.0)
    out = r > a
    assert np.abs((r[out] - a) ** 2 + (h[out] - rc) ** 2 - rc ** 2).max() < 1e-9


@pytest.mark.parametrize("angle", [60.0, 90.0, 118.0, 135.0])
def test_drill_point_is_a_cone_of_its_angle(angle):
    c = Cutter.of(Tool(1, "drill", 2 * R, point_angle=angle))
    h = c.height(r[1:])
    assert c.kind == DRILL
    assert np.degrees(2 * np.arctan2(r[1:], h)) == pytest.approx(angle, abs=1e-9)
    assert c.tip_height == pytest.approx(R / math.tan(math.radians(angle / 2)))


@pytest.mark.parametrize("c", [Cutter(R), Cutter(R, R), Cutter(R, 1.0), Cutter(R, 0.0, 1.2)],
                         ids=["flat", "ball", "bull", "drill"])
def test_scalar_array_and_compiled_profiles_agree_and_hold_beyond_the_radius(c):
    rr = np.array([0.0, 0.3, 1.9, 2.0, 2.99, 3.0])
    arr = c.height(rr)
    assert arr == pytest.approx([c.height(float(v)) for v in rr], abs=0.0)
    assert arr == pytest.approx([height(*c.row, float(v)) for v in rr], abs=0.0)
    assert c.height(R + 1.0) == pytest.approx(c.tip_height, abs=0.0)
    assert c.height(rr.reshape(2, 3)).shape == (2, 3)


def test_cutter_of_a_tool_keeps_its_numbers():
    assert Cutter.of(Tool(1, "flat", 6.0)) == Cutter(3.0)
    assert Cutter.of(Tool(2, "ball", 6.0)) == Cutter(3.0, 3.0)
    assert Cutter.of(Tool(3, "bull", 6.0, corner_radius=1.0)) == Cutter(3.0, 1.0)
    assert Cutter.of(Tool(4, "drill", 6.0, point_angle=90.0)).slope == pytest.approx(1.0)


@pytest.mark.parametrize("bad", [(0.0,), (3.0, 4.0), (3.0, -1.0), (3.0, 1.0, 1.0),
                                 (3.0, 0.0, -1.0), (math.inf,)])
def test_impossible_cutters_are_refused(bad):
    with pytest.raises(ValueError):
        Cutter(*bad)


@pytest.mark.parametrize("tool", [Tool(1, "flat", 6.0, flute_length=12.0),
                                  Tool(2, "ball", 6.0, flute_length=12.0),
                                  Tool(3, "bull", 6.0, corner_radius=1.0, flute_length=12.0),
                                  Tool(4, "drill", 6.0, flute_length=12.0)],
                         ids=lambda t: t.type)
def test_outline_runs_on_the_profile_from_the_tip_to_the_flutes(tool):
    pts = np.array(cutter_profile(tool, steps=16))
    c = Cutter.of(tool)
    assert tuple(pts[0]) == (0.0, 0.0)
    assert np.all(np.diff(pts[:, 0]) >= 0.0) and np.all(np.diff(pts[:, 1]) >= 0.0)
    body = pts[:-1]
    assert body[:, 1] == pytest.approx(c.height(body[:, 0]), abs=1e-12)
    assert tuple(pts[-1]) == pytest.approx((3.0, 12.0))
