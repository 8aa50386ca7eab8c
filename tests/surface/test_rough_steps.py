"""surface-rough beside vertical walls: no chord of a pass dips into the allowance where
the safe Z jumps (a flat cutter reaching a wall's top edge) between two checked points.

The part is a slanted bar (like the textbox's letter strokes, where the exact check
found the roughing 0.016 mm into a letter's top edge) standing on a plate, with vertical
walls. Analytic truth for a flat end mill of radius R: the lowest safe tip Z over (x, y)
is the bar's top where (x, y) is closer than R to the bar's outline (shapely's
distance; at exactly R the cutter's side only touches the wall), else the plate. Every cutting chord, sampled every 0.005 mm, must stay at least the
allowance less the operation's tolerance (a quarter of the allowance) above it.
"""

from __future__ import annotations

import numpy as np
import pytest
import shapely
from shapely.geometry import Polygon, box

from millpath.io.schema import validate
from millpath.model.stock import Machine, Stock
from millpath.model.tool import Tool
from millpath.part.surface.mesh import write_stl
from support.prism import stepped_solid
from millpath.plan.base import PlanContext
from millpath.plan.surface import rough as rough_op

BAR = Polygon([(15.0, 17.0), (18.4, 17.0), (25.2, 32.0), (21.8, 32.0)])
TOP, PLATE, R = -2.05, -5.0, 3.0


@pytest.mark.parametrize("angle", [0.0, 90.0])
def test_rough_chords_keep_the_allowance_beside_vertical_walls(tmp_path, angle):
    plate = box(0.0, 0.0, 40.0, 45.0).difference(BAR)
    write_stl(stepped_solid([(plate, PLATE), (BAR, TOP)], -10.0), tmp_path / "bar.stl")
    tools = {1: Tool(1, "flat", 2 * R, flute_length=30.0, stickout=40.0)}
    stock = Stock(0.0, 0.0, -10.0, 40.0, 45.0, 1.0)
    ctx = PlanContext("mm", stock, Machine.default_for("mm"), tools, tmp_path, None)
    allowance = 0.2
    p = validate({"surface": "bar.stl", "tool": 1, "stepdown": 1.5, "allowance": allowance,
                  "angle": angle}, rough_op.PARAMS, "op", None)
    res = rough_op.plan(ctx, p)
    tol = 0.25 * allowance
    moves = res.toolpath.moves
    worst = np.inf
    checked = 0
    for a, b in zip(moves[:-1], moves[1:]):
        if b.kind != "line":
            continue
        A, B = np.array(a.end), np.array(b.end)
        n = max(2, int(np.ceil(np.hypot(*(B - A)[:2]) / 0.005)) + 1)
        P = A + (B - A) * np.linspace(0.0, 1.0, n)[:, None]
        near = shapely.distance(shapely.points(P[:, :2]), BAR) < R - 1e-9
        safe = np.where(near, TOP, PLATE)
        worst = min(worst, float(np.min(P[:, 2] - safe)))
        checked += int(near.sum())
    assert checked > 1000                        # passes ran beside the bar
    assert worst >= allowance - tol - 1e-3, worst
