"""ISO 14649 (STEP-NC ARM) files read into the AP224 records."""

from __future__ import annotations

import pytest

from millpath.part.step.ap224 import read_part
from millpath.part.step.shapes import HoleShape, PocketShape, SlotShape, feature_shapes


@pytest.fixture(scope="module")
def final(shared_dir):
    return read_part(shared_dir / "step" / "iso14649_teste_final_unblab.p21")


def test_stock_material_and_feature_list(final):
    assert final.stock.shape == "block"
    assert final.stock.dims == {"length": 120.0, "width": 120.0, "height": 18.25}
    assert final.material == "SAE 1020 ACO SEM LIGA"
    assert [f.type for f in final.features] == (["SLOT", "SLOT", "ROUND_HOLE", "ROUND_HOLE",
                                                  "POCKET"] + ["ROUND_HOLE"] * 6)
    assert final.features[0].placement.axis == (0.0, 0.0, -1.0)   # reversed: into material


def test_shapes_of_the_arm_features(final):
    s = feature_shapes(final)
    slot = next(x for x in s.shapes if isinstance(x, SlotShape))
    assert (slot.start, slot.width, slot.depth, slot.length, slot.ends) == (
        (0.0, 83.875), 18.25, 7.0, 120.0, ("open", "open"))
    pocket = next(x for x in s.shapes if isinstance(x, PocketShape))
    assert (pocket.center, pocket.length, pocket.width, pocket.corner_radius, pocket.depth) == (
        (60.0, 35.0), 57.0, 57.0, 3.0, 4.0)
    holes = [x for x in s.shapes if isinstance(x, HoleShape)]
    assert sorted({(h.diameter, h.bottom) for h in holes}) == [
        (6.0, "through"), (10.0, "through"), (39.0, "flat")]
    floor_holes = [h for h in holes if h.z_top == 14.25]       # drilled in the pocket floor
    assert len(floor_holes) == 4 and all(h.depth == 14.25 for h in floor_holes)
    assert [(u.id, u.reason) for u in s.skipped] == [
        (81, "slot wall first angle is not 90 degrees")]


def test_other_arm_files(shared_dir):
    furo = read_part(shared_dir / "step" / "iso14649_furo.p21")
    (hole,) = feature_shapes(furo).shapes
    assert (hole.x, hole.y, hole.z_top, hole.diameter, hole.depth, hole.bottom) == (
        50.0, 50.0, 20.0, 10.0, 10.0, "conical")
    defesa = read_part(shared_dir / "step" / "iso14649_peca_defesa.p21")
    kinds = sorted(type(x).__name__ for x in feature_shapes(defesa).shapes)
    assert kinds == ["HoleShape", "PocketShape"]


def test_planning_an_arm_file_cuts_its_features(shared_dir, rs274):
    from millpath.io.schema import validate
    from millpath.model import Machine, Tool
    from millpath.plan.base import PlanContext
    from millpath.plan.features.operation import PARAMS, plan
    from millpath.post.writer import post
    from millpath.simulate import simulate_toolpath
    from support.rs274 import run_rs274

    tools = {1: Tool(1, "flat", 10.0, flutes=3, flute_length=30, stickout=45),
             2: Tool(2, "flat", 6.0, flutes=3, flute_length=20, stickout=35),
             3: Tool(3, "flat", 20.0, flutes=3, flute_length=40, stickout=60),
             4: Tool(4, "drill", 10.0, flute_length=50, stickout=70),
             5: Tool(5, "drill", 6.0, flute_length=40, stickout=60)}
    ctx = PlanContext(units="mm", stock=None, machine=Machine(), tools=tools,
                      base_dir=shared_dir)
    params = validate({"step": str(shared_dir / "step" / "iso14649_teste_final_unblab.p21")},
                      PARAMS, "op", None, shared_dir)
    r = plan(ctx, params)
    order = [op.tool for op in r.toolpath.ops]
    assert order[:2] == [1, 2]            # slot and pocket before the holes in its floor
    res = run_rs274(post(r.toolpath, tools), tools)
    assert res.ok, (res.error, res.error_line)
    st = r.stock
    sim = simulate_toolpath(r.toolpath, tools, st, resolution=0.5, design=r.design)
    expected = r.design.volume_on_grid(sim.zmap.xs(), sim.zmap.ys(), sim.zmap.cell_area,
                                          sim.zmap.zmin)
    assert sim.removed_volume == pytest.approx(expected, rel=0.01)
    assert sim.max_gouge <= 1e-6 and sim.rapids_through_material == 0
