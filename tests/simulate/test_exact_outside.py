"""The exact gouge check must not take a cutter outside the part for one inside it.

A raised letter stroke (a slanted bar, like the textbox's letters) stands on a slab. A
flat or bull cutter runs beside the bar's slanted wall, with its tip between the bar's
top and the slab. The cutter's far side lies behind the plane of the bar's end wall,
with its foot on that wall, yet outside the part (the slanted wall is between them).
The truth is analytic: the cutter's side is ``clearance`` from the slanted wall and
nothing else is near, so the gouge is ``-clearance`` when negative, else none.
(Before the fix this configuration reported the cutter point's distance to the slab,
1 mm, as a gouge: issue 25's textbox false alarm.)
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from millpath.model import Stock, Tool
from millpath.model.motion import Motion
from millpath.simulate.exact import Reference, verify_exact

TOL = 0.002
TOOLS = {"flat": Tool(1, "flat", 6.0, flute_length=20, stickout=30),
         "bull": Tool(1, "bull", 6.0, corner_radius=1.0, flute_length=20, stickout=30)}


def _prism(xy, z0, z1):
    """A closed prism over the counter-clockwise polygon ``xy``, outward normals."""
    n = len(xy)
    lo = [(x, y, z0) for x, y in xy]
    hi = [(x, y, z1) for x, y in xy]
    tri = []
    for i in range(1, n - 1):
        tri.append([lo[0], lo[i + 1], lo[i]])          # bottom, facing down
        tri.append([hi[0], hi[i], hi[i + 1]])          # top, facing up
    for i in range(n):
        j = (i + 1) % n
        tri.append([lo[i], lo[j], hi[j]])
        tri.append([lo[i], hi[j], hi[i]])
    return np.array(tri, float)


BAR = [(15.0, 17.0), (18.4, 17.0), (25.2, 32.0), (21.8, 32.0)]


def _part() -> np.ndarray:
    slab = _prism([(0.0, 0.0), (40.0, 0.0), (40.0, 40.0), (0.0, 40.0)], -10.0, -5.0)
    return np.concatenate([slab, _prism(BAR, -5.0, -2.0)])


def _beside(s: float, clearance: float) -> tuple[float, float]:
    """Tool axis ``s`` along the bar's left (slanted) wall from (15, 17), 3 + clearance
    out from it."""
    d = np.array([6.8, 15.0]) / math.hypot(6.8, 15.0)
    n = np.array([-d[1], d[0]])
    c = np.array(BAR[0]) + s * d + (3.0 + clearance) * n
    return float(c[0]), float(c[1])


@pytest.mark.parametrize("kind", ["flat", "bull"])
@pytest.mark.parametrize("clearance", [0.02, -0.05])
def test_cutter_beside_a_wall_behind_another_face(kind, clearance):
    z = -4.0
    a, b = _beside(12.0, clearance), _beside(1.0, clearance)
    # at a the cutter's far side (+Y) projects onto the bar's end wall y = 17, and the
    # swept cutter reaches past that wall's plane at b
    assert 15.0 < a[0] < 18.4 and b[1] - 3.0 < 17.0
    moves = [Motion("feed", 1, (a[0], a[1], 20.0), (a[0], a[1], z), feed=500, tool=1),
             Motion("feed", 2, (a[0], a[1], z), (b[0], b[1], z), feed=500, tool=1),
             Motion("feed", 3, (b[0], b[1], z), (b[0], b[1], 20.0), feed=500, tool=1)]
    stock = Stock(0, 0, -10, 40, 40, 0)
    r = verify_exact(moves, {1: TOOLS[kind]}, stock, [Reference(_part(), "bar on slab")])
    if clearance > 0:
        assert r.max_gouge == 0.0 and r.gouging_moves == 0
    else:
        assert r.max_gouge == pytest.approx(-clearance, abs=TOL)
        assert r.gouging_moves == 3           # the plunge and the retract too


@pytest.mark.parametrize("depth", [0.0, 0.05])
def test_cutter_beyond_the_edge_of_a_height_field(depth):
    # a step (28 for x >= 10, 25 below) meshed as a height field over the stock box, an
    # open sheet with no wall at the box's sides; a flat cutter runs along the step
    # 2.2 mm inside the box's edges, its far side beyond them: behind the plane of the
    # step's wall x = 10, with its foot on it, yet outside the part (solid-hole-model's
    # false 2.2 mm). Truth: the cutter's bottom ``depth`` below the 28 level.
    from millpath.simulate.design import BoxDesign
    from millpath.simulate.exact import design_triangles
    stock = Stock(0, 0, 0, 50, 25, 31)
    tri = design_triangles(BoxDesign(28.0, [(0.0, 0.0, 10.0, 25.0, 25.0)]), stock, 0.001, 1.0)
    z = 28.0 - depth
    moves = [Motion("feed", 1, (47.2, 2.8, z), (47.2, 22.2, z), feed=500, tool=1),
             Motion("feed", 2, (47.2, 22.2, z), (13.2, 22.2, z), feed=500, tool=1)]
    tool = Tool(1, "flat", 10.0, flute_length=30, stickout=45, holder=[(32.0, 50.0)])
    r = verify_exact(moves, {1: tool}, stock, [Reference(tri, "step")])
    if depth == 0.0:
        assert r.max_gouge == 0.0 and r.gouging_moves == 0
    else:
        assert r.max_gouge == pytest.approx(depth, abs=TOL)
        assert r.gouging_moves == 2


def test_a_job_operation_design_covers_all_its_tool_path_operations():
    # a job operation that plans one tool path operation per tool (features, ...) and a
    # second job operation: each design is the reference of the tool path operations
    # its job operation planned (the motion's operation numbers are the tool path's).
    # Before, job operation 0's design was applied to tool path operation 0 only: the
    # gouge of tool path operation 1 (job operation 0's second tool) went unchecked.
    from types import SimpleNamespace

    from millpath.model import Operation, Toolpath
    from millpath.plan.base import PlanResult
    from millpath.pipeline import _references
    from millpath.simulate.design import PlaneDesign

    def planned(ops):
        tp = Toolpath("mm")
        for tool, z in ops:
            tp.begin(Operation("t", f"T{tool}", tool))
            tp.rapid(5.0, 20.0, 5.0)
            tp.line(5.0, 20.0, z, 100.0)
            tp.line(35.0, 20.0, z, 100.0)
        return tp

    tools = {1: Tool(1, "flat", 6.0, flute_length=20, stickout=30),
             2: Tool(2, "flat", 3.0, flute_length=20, stickout=30)}
    stock = Stock(0, 0, -5, 40, 40, 0)
    # job operation 0: tool 1 on its floor, then tool 2 0.05 below it; operation 1: above
    results = [PlanResult(planned([(1, -2.0), (2, -2.05)]), PlaneDesign(-2.0)),
               PlanResult(planned([(1, -1.0)]), PlaneDesign(-3.0))]
    tp = Toolpath("mm")
    for r in results:
        tp.extend(r.toolpath)
    job = SimpleNamespace(simulation={"exact": True}, tools=tools, units="mm")
    refs = _references(job, results, stock, tp)
    assert [r.ops for r in refs] == [[0, 1], [2]]
    motions, mop, pos = [], [], (5.0, 20.0, 5.0)
    for m in tp.moves:
        if m.kind == "line":
            motions.append(Motion("feed", len(motions) + 1, pos, m.end, feed=100,
                                  tool=tp.ops[m.op].tool))
            mop.append(m.op)
        pos = m.end
    r = verify_exact(motions, tools, stock, refs, motion_op=np.array(mop))
    assert r.max_gouge == pytest.approx(0.05, abs=TOL)
    assert r.gouge_at["operation"] == 1
    assert r.op_gouge[0] == 0.0 and r.op_gouge[2] == 0.0


def test_a_drill_through_an_opening_of_a_height_field_cuts_nothing():
    # a through opening (no part: -inf) in a 31 mm plate; the height-field reference
    # closes the opening with a floor under the stock. A 10 mm drill goes through it,
    # its point 3.5 mm below the stock (solid-hole-model's drills): no part there, so
    # no gouge (the floor was 3.1 mm under the stock: a false 0.4 mm).
    from millpath.simulate.design import BoxDesign
    from millpath.simulate.exact import design_triangles
    stock = Stock(-20, -20, 0, 20, 20, 31)
    tri = design_triangles(BoxDesign(31.0, [(-6.0, -6.0, 6.0, 6.0, -np.inf)]), stock,
                           0.001, 1.0)
    drill = Tool(1, "drill", 10.0, flute_length=40, stickout=55)
    moves = [Motion("feed", 1, (0.0, 0.0, 33.0), (0.0, 0.0, -3.5), feed=300, tool=1)]
    r = verify_exact(moves, {1: drill}, stock, [Reference(tri, "plate")])
    assert r.max_gouge == 0.0 and r.gouging_moves == 0
