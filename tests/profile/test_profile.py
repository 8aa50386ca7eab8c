"""profile: walls where the contour says, tabs, leads, CAM = control compensation.

Truth: the contour polygon built here with shapely; the control variant is offset by
millpath's interpreter (and LinuxCNC's rs274 accepts both programs)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import shapely
from scipy import ndimage
from shapely.geometry import Polygon

from millpath.interpret import interpret
from millpath.io.schema import validate
from millpath.model import Machine, Stock, Tool
from millpath.plan.base import PlanContext
from millpath.plan.profile import operation as profile
from millpath.post.writer import post
from millpath.simulate import simulate_motions

L_SHAPE = [[0, 0], [60, 0], [60, 40], [30, 40], [30, 25], [0, 25]]
TOOLS = {3: Tool(3, "flat", 6.0)}
STOCK = Stock(-20, -20, -12, 80, 60, 0)


def _plan(**keys):
    ctx = PlanContext("mm", STOCK, Machine(), TOOLS, Path("."))
    base = {"tool": 3, "polygon": L_SHAPE, "depth": 10.0, "stepdown": 4.0, "feed": 800.0}
    return profile.plan(ctx, validate({**base, **keys}, profile.PARAMS, "op", None))


def _stock(tp, res=0.1):
    prog = post(tp, TOOLS)
    motions = interpret(prog, TOOLS, machine_units="mm")
    return prog, simulate_motions(motions, TOOLS, STOCK, resolution=res).zmap


@pytest.mark.parametrize("comp", ["cam", "control"])
def test_outside_profile_wall_and_tabs(comp):
    res = _plan(side="outside", compensation=comp, tabs=3, tab_height=2.0)
    prog, zm = _stock(res.toolpath)
    assert ("G41 D3" in prog) == (comp == "control")
    X, Y = np.meshgrid(zm.xs(), zm.ys())
    part = Polygon(L_SHAPE)
    d = np.hypot(zm.dx, zm.dy)
    inside = shapely.contains_xy(part.buffer(-d), X, Y)
    assert np.all(zm.heights[inside] == 0.0)                    # the part is untouched
    # the slot round the part, one cell off both sides of the tool's sweep
    band = shapely.contains_xy(part.buffer(6.0 - d), X, Y) & ~shapely.contains_xy(
        part.buffer(d), X, Y)
    # the inner corner of the L (30, 25) cannot be reached by a round tool from outside
    band &= np.hypot(X - 30, Y - 25) > 6.0
    hb = zm.heights[band]
    assert hb.min() >= -10.0 - 1e-9 and hb.max() <= -8.0 + 1e-9   # tabs 2 high, 45 deg ends
    tab = np.zeros_like(zm.heights, bool)
    tab[band] = zm.heights[band] > -10.0 + 1e-9
    # the tab zones are contiguous stretches of the slot: 3 of them
    labels, n = ndimage.label(ndimage.binary_closing(tab, iterations=3))
    sizes = ndimage.sum(tab, labels, range(1, n + 1))
    big = sizes > 200                    # a tab: 12 mm x 6 mm = 7200 cells at 0.1
    assert big.sum() == 3, sorted(sizes)
    assert sizes[~big].sum() < 50        # cells on the sweep's edge at round corners
    assert (np.isclose(hb, -10.0)).mean() > 0.7


def test_inside_profile_stays_inside_and_cam_equals_control():
    walls = {}
    for comp in ("cam", "control"):
        res = _plan(side="inside", compensation=comp, polygon=[[0, 0], [40, 0], [40, 30], [0, 30]],
                    depth=5.0, stepdown=5.0)
        _, zm = _stock(res.toolpath, 0.2)
        X, Y = np.meshgrid(zm.xs(), zm.ys())
        outside = ~shapely.contains_xy(Polygon([[0, 0], [40, 0], [40, 30], [0, 30]]).buffer(0.3), X, Y)
        assert np.all(zm.heights[outside] == 0.0)
        walls[comp] = zm.heights
    # control compensation cuts what the CAM offset cuts (cells differ only at the
    # corners' arcs, sampled at cell centres)
    diff = walls["cam"] != walls["control"]
    assert diff.mean() < 0.002


@pytest.mark.parametrize("comp", ["cam", "control"])
def test_profile_programs_accepted_by_rs274(rs274, comp):
    from support.rs274 import run_rs274
    res = _plan(side="outside", compensation=comp, tabs=2, tab_height=3.0)
    r = run_rs274(post(res.toolpath, TOOLS), TOOLS)
    assert r.ok, (r.error, r.error_line)
    assert len(r.motions) > 20


def test_lead_radius_and_tab_height_errors():
    from millpath.errors import JobError, PlanningError
    with pytest.raises(JobError, match="lead_radius: 2 must be larger than the tool radius 3"):
        _plan(side="outside", lead_radius=2.0)
    with pytest.raises(JobError, match="tab_height"):
        _plan(side="outside", tabs=2, tab_height=12.0)
    with pytest.raises(PlanningError, match="does not fit inside the contour"):
        _plan(side="inside", polygon=[[0, 0], [5, 0], [5, 5], [0, 5]])


def test_zmap_comparison_leaves_the_waste_out_and_still_sees_a_real_gouge():
    """A 40 x 20 plate cut from a sheet 10 deep: the design is the plate and a 4 mm slot
    around it; the sheet beyond (scrap, where leads and entries run) is not designed.
    Truth: cells set by hand. A 10 mm deep disc in the scrap is neither gouge nor left;
    the same disc in the plate is a 10 mm gouge; a stub left in the slot is left."""
    from millpath.plan.profile.design import ProfileDesign
    from millpath.simulate.designgrid import design_grid
    from millpath.simulate.simulator import compare_design, deviation
    from millpath.simulate.zmap import ZMap
    plate = Polygon([(0, 0), (40, 0), (40, 20), (0, 20)])
    band = plate.buffer(4.0, join_style="mitre").difference(plate)
    ring = np.array(plate.exterior.coords[:-1])
    design = ProfileDesign(plate, [ring], band, -10.0, 0.0, through=False)
    zmap = ZMap.from_stock(Stock(-15, -15, -12, 55, 35, 0), 0.25)
    X, Y = np.meshgrid(zmap.xs(), zmap.ys())
    zmap.heights[shapely.contains_xy(band, X, Y)] = -10.0     # the slot cut as designed

    def disc(cx, cy, r=2.0):
        return (X - cx) ** 2 + (Y - cy) ** 2 < r * r

    zmap.heights[disc(50, 30)] = -10.0                         # an entry in the scrap
    grid = design_grid(zmap, design)
    c = compare_design(zmap, grid)
    assert c.max_gouge == 0.0 and c.max_left == 0.0
    assert deviation(zmap, grid)[disc(50, 30)].tolist() == [0.0] * int(disc(50, 30).sum())
    zmap.heights[disc(20, 10)] = -10.0                         # a hole in the plate
    zmap.heights[disc(-2, 10, 1.0)] = -4.0                     # a stub in the slot
    c = compare_design(zmap, design_grid(zmap, design))
    assert c.max_gouge == pytest.approx(10.0) and c.max_left == pytest.approx(6.0)


def test_a_job_designs_nothing_only_where_every_operation_designs_nothing():
    from millpath.pipeline import MinDesign
    from millpath.plan.profile.design import ProfileDesign
    from millpath.simulate.design import PlaneDesign
    square = Polygon([(0, 0), (10, 0), (10, 10), (0, 10)])
    ring = np.array(square.exterior.coords[:-1])
    a = ProfileDesign(square, [ring], square.buffer(2.0).difference(square), -5, 0, False)
    b = ProfileDesign(square.buffer(20.0), [ring], square.buffer(1.0), -5, 0, False)
    x, y = np.array([20.0, 5.0, 11.0]), np.array([20.0, 5.0, 5.0])
    assert a.waste(x, y).tolist() == [True, False, False]
    assert MinDesign([a, b]).waste(x, y).tolist() == [False, False, False]
    assert not hasattr(MinDesign([a, PlaneDesign(0.0)]), "waste")
