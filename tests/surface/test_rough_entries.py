"""Surface roughing enters material only where there is material: beside the stock the
tool goes straight down, a start whose tool overlaps the stock from outside is entered
from the side at its own Z, and helices are left to starts over the stock.

Truth: the stock box of the job (the tool's distance from its footprint, computed here)
and the proof of the written program (no gouge, no rapid through material)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from millpath import run_job
from millpath.model import Stock

JOB = """units = "mm"
[stock]
box = [0.0, 0.0, 0.0, 40.0, 30.0, 16.0]
[[tools]]
number = 10
type = "bull"
diameter = 10.0
corner_radius = 1.0
flute_length = 25.0
stickout = 35.0
[[operations]]
type = "surface-rough"
tool = 10
stepdown = 3.0
stepover = 6.0
allowance = 0.3
feed = 2000.0
surface = { box = [0.0, 0.0, 40.0, 30.0], heights = [
  [8.0, 9.0, 11.0, 9.0],
  [9.0, 13.0, 14.0, 10.0],
  [8.0, 10.0, 9.0, 7.0],
] }
"""
R = 5.0
CLEARANCE = 1.0          # surface-rough's approach clearance in mm


def _outside(stock: Stock, x: float, y: float) -> float:
    dx = max(stock.xmin - x, 0.0, x - stock.xmax)
    dy = max(stock.ymin - y, 0.0, y - stock.ymax)
    return math.hypot(dx, dy)


@pytest.fixture(scope="module")
def rough(tmp_path_factory):
    d = tmp_path_factory.mktemp("rough")
    (d / "job.toml").write_text(JOB)
    return run_job(d / "job.toml", d / "out")


def test_the_program_is_proven(rough):
    rep = rough.report
    assert rep["safety"]["status"] == "ok"
    assert rep["verification"]["rapids_through_material"] == 0


def test_no_helix_starts_outside_the_stock_and_side_entries_go_in_level(rough):
    tp = rough.toolpath
    stock = Stock(0.0, 0.0, 0.0, 40.0, 30.0, 16.0)
    pos = None
    helices = side = straight = 0
    for m in tp.moves:
        if pos is not None and m.kind == "arc" and abs(m.end[2] - pos[2]) > 1e-9:
            assert _outside(stock, pos[0], pos[1]) == 0.0, f"helix from {pos} beside the stock"
            helices += 1
        if pos is not None and m.kind == "line" and m.end[2] < pos[2] - 1e-9 \
                and math.hypot(m.end[0] - pos[0], m.end[1] - pos[1]) < 1e-9 \
                and _outside(stock, pos[0], pos[1]) > 0.0:
            # a descent beside the stock (straight down, or a side entry's first leg):
            # fed from the clearance above the start only, the tool wholly beside it
            assert pos[2] - m.end[2] <= CLEARANCE + 1e-9
            assert _outside(stock, pos[0], pos[1]) >= R - 1e-9
            straight += 1
        if pos is not None and m.kind == "line" and abs(m.end[2] - pos[2]) < 1e-9 \
                and _outside(stock, pos[0], pos[1]) >= R - 1e-9 \
                and _outside(stock, m.end[0], m.end[1]) < R:
            side += 1
        pos = m.end
    assert straight > 0 and side > 0
    t = rough.report["operations"][0]["time"]
    assert t["entries"] >= 1


def test_nearest_point_of_a_box_and_a_bar_footprint():
    box = Stock(0.0, 0.0, 0.0, 40.0, 30.0, 16.0)
    assert box.nearest_xy(-3.0, 10.0) == (0.0, 10.0)
    assert box.nearest_xy(45.0, 34.0) == (40.0, 30.0)
    assert box.nearest_xy(20.0, 10.0) == (20.0, 10.0)
    bar = Stock.from_cylinder(0.0, 0.0, 10.0, -5.0, 0.0)
    assert bar.nearest_xy(20.0, 0.0) == pytest.approx((10.0, 0.0))
    assert bar.nearest_xy(-6.0, 8.0) == pytest.approx((-6.0, 8.0))
    x, y = bar.nearest_xy(10.0, 10.0)
    assert math.hypot(x, y) == pytest.approx(10.0) and x == pytest.approx(y)
