"""A tiny strategy registered for the foundation tests: a square contour with arcs,
a helix and drilled holes, so the pipeline can be tested without the real strategies."""

import sys
import types

import numpy as np
import pytest

from millpath.io.schema import Param
from millpath.model import Operation, Toolpath
from millpath.plan import registry
from millpath.plan.base import PlanResult


class FlatDesign:
    """Part top at z_top except a square pocket floor at z_floor (job units)."""

    def __init__(self, z_top, z_floor, box):
        self.z_top, self.z_floor, self.box = z_top, z_floor, box

    def height(self, x, y):
        x0, y0, x1, y1 = self.box
        inside = (x >= x0) & (x <= x1) & (y >= y0) & (y <= y1)
        return np.where(inside, self.z_floor, self.z_top)


def _plan(ctx, params):
    tp = Toolpath(ctx.units)
    d = params["depth"]
    tp.begin(Operation("test-square", "square pocket outline", params["tool"], 10000))
    tp.rapid(20, 20, 5)
    tp.line(20, 20, -d, 200)
    tp.line(40, 20, -d, 400)
    tp.arc((45, 25, -d), (40, 25, -d), False, 400)
    tp.line(45, 40, -d, 400)
    tp.line(20, 40, -d, 400)
    tp.line(20, 20, -d, 400)
    tp.rapid(20, 20, 5)
    if params["fail"]:
        tp.line(float("nan"), 0, 0, 100)
    r = ctx.tools[params["tool"]].radius
    design = FlatDesign(0.0, -d, (20 - r, 20 - r, 45 + r, 40 + r))
    return PlanResult(tp, design=design, report={"test": {"planned": len(tp.moves)}})


@pytest.fixture
def test_strategy(monkeypatch):
    mod = types.ModuleType("millpath_test_strategy")
    mod.PARAMS = {"tool": Param("int", positive=True), "depth": Param("float", 1.0),
                  "fail": Param("bool", False)}
    mod.plan = _plan
    monkeypatch.setitem(sys.modules, "millpath_test_strategy", mod)
    monkeypatch.setitem(registry.STRATEGIES, "test-square", "millpath_test_strategy")
    return mod


JOB = """
units = "mm"
[stock]
box = [0, 0, -10, 60, 60, 0]
[[tools]]
number = 1
type = "flat"
diameter = 6
stickout = 30
holder = [[20, 40]]
[[operations]]
type = "test-square"
tool = 1
depth = 2
"""


@pytest.fixture
def job_file(tmp_path, test_strategy):
    p = tmp_path / "job.toml"
    p.write_text(JOB)
    return p
