"""Cycle time against hand-computed trapezoidal profiles (within 1 %)."""

from __future__ import annotations

import math

import pytest

from millpath.model.motion import Motion
from millpath.model import Machine, Operation, Toolpath
from millpath.simulate import cycle_time, operation_times

M = Machine(rapid=5000.0, max_feed=3000.0, acceleration=500.0)


def _tp() -> Toolpath:
    tp = Toolpath()
    tp.begin(Operation("t", "first", 1))
    return tp


def test_single_long_feed_move_is_cruise_plus_one_ramp():
    tp = _tp()
    tp.line(0, 0, 0, 600)
    tp.line(100, 0, 0, 600)          # 10 mm/s: accelerate 0.02 s, cruise, decelerate
    assert cycle_time(tp, M) == pytest.approx(100 / 10 + 10 / 500, rel=0.01)


def test_square_stops_at_each_corner():
    tp = _tp()
    tp.line(0, 0, 0, 1200)
    for x, y in ((50, 0), (50, 50), (0, 50), (0, 0)):
        tp.line(x, y, 0, 1200)       # 20 mm/s, full stop at each 90-degree corner
    assert cycle_time(tp, M) == pytest.approx(4 * (50 / 20 + 20 / 500), rel=0.01)


def test_rapid_runs_at_machine_rapid_rate():
    tp = _tp()
    tp.rapid(0, 0, 0)
    tp.rapid(120, 160, 0)            # 200 mm at 5000 mm/min = 83.33 mm/s
    v = 5000 / 60
    assert cycle_time(tp, M) == pytest.approx(200 / v + v / 500, rel=0.01)


def test_short_move_never_reaches_its_feed():
    tp = _tp()
    tp.line(0, 0, 0, 3000)
    tp.line(0.5, 0, 0, 3000)         # triangle profile: 2 sqrt(L / a)
    assert cycle_time(tp, M) == pytest.approx(2 * math.sqrt(0.5 / 500), rel=0.01)


def test_feed_is_capped_by_machine_max_feed():
    tp = _tp()
    tp.line(0, 0, 0, 9000)
    tp.line(300, 0, 0, 9000)         # capped at 3000 mm/min = 50 mm/s
    assert cycle_time(tp, M) == pytest.approx(300 / 50 + 50 / 500, rel=0.01)


def test_collinear_moves_do_not_stop_between_them():
    tp = _tp()
    tp.line(0, 0, 0, 600)
    for k in range(1, 11):
        tp.line(10 * k, 0, 0, 600)
    assert cycle_time(tp, M) == pytest.approx(100 / 10 + 10 / 500, rel=0.01)


def test_dwell_and_per_operation_times_add_up():
    tp = _tp()
    tp.line(0, 0, 0, 600)
    tp.line(100, 0, 0, 600)
    tp.begin(Operation("d", "second", 2))
    tp.drill(100, 0, -10, 2, 120, cycle="G82", dwell=1.5)
    ops = operation_times(tp, M)
    assert [o["name"] for o in ops] == ["first", "second"]
    assert ops[0]["cycle_time_s"] == pytest.approx(10.02, rel=0.01)
    # rapid 0 -> 2 (from z=0 up to R), feed 12 mm at 2 mm/s, dwell 1.5, rapid 12 up
    v = 5000 / 60
    feed = 12 / 2 + 2 / 500
    rap = lambda L: 2 * math.sqrt(L / 500) if L < v * v / 500 else L / v + v / 500
    expected = rap(2) + feed + 1.5 + rap(12)
    assert ops[1]["cycle_time_s"] == pytest.approx(expected, rel=0.01)
    assert sum(o["cycle_time_s"] for o in ops) == pytest.approx(cycle_time(tp, M), rel=1e-9)


def test_motion_arcs_and_inverse_time_feeds():
    # a full circle of radius 10 at 600 mm/min: 2 pi 10 / 10 s + one ramp
    arc = Motion("arc", 1, (10.0, 0.0, 0.0), (10.0, 0.0, 0.0), feed=600.0,
                 center=(0.0, 0.0, 0.0), rotation=1)
    assert cycle_time([arc], M) == pytest.approx(2 * math.pi + 10 / 500, rel=0.01)
    # inverse time: F2 = the move takes half a minute (capped feed not reached)
    inv = Motion("feed", 2, (0.0, 0.0, 0.0), (100.0, 0.0, 0.0), feed=2.0,
                 feed_mode="inverse_time")
    assert cycle_time([inv], M) == pytest.approx(30.0 + (100 / 30) / 500, rel=0.01)
