"""AP224 layer: units, stock, material and features found through the instance graph."""

from __future__ import annotations

import math
from pathlib import Path

import pytest

from millpath.errors import MillpathError
from millpath.part.step.ap224 import read_part
from millpath.part.step.build import Ap224Builder
from millpath.part.step.p21 import parse
from millpath.part.step.shapes import HoleShape, PocketShape, SlotShape, feature_shapes

FIXTURES = Path(__file__).parent / "fixtures"


@pytest.fixture(scope="module")
def sample(shared_dir):
    return read_part(shared_dir / "step" / "ap224_995277945.stp")


def test_sample_units_stock_material(sample):
    assert sample.units.length == "inch" and sample.units.length_mm == 25.4
    assert sample.units.angle == "degree"
    assert sample.stock.shape == "cylinder"
    assert sample.stock.dims == {"diameter": pytest.approx(2.38157), "length": 1.5}
    assert sample.material == "phosphor bronze to BS 2874 PB 102"
    assert "THREAD PIECE, UNION" in sample.product


def test_sample_all_features(sample):
    types = sorted(f.type for f in sample.features)
    assert types == sorted(["ROUND_HOLE"] * 4 + ["REVOLVED_PROFILE"] * 2 + ["OUTER_ROUND"] * 3
                           + ["OUTSIDE_PROFILE", "THREAD", "CHAMFER", "CHAMFER",
                              "COMPOSITE_HOLE"])
    by_id = {f.id: f for f in sample.features}
    hole = by_id[1918]
    assert hole.component("CIRCULAR_CLOSED_PROFILE").params["diameter"] == 1.116
    assert hole.component("PATH_FEATURE_COMPONENT").params["distance"] == pytest.approx(0.65)
    assert hole.component("HOLE_BOTTOM").description == "flat"
    assert hole.placement.axis == (0.0, 0.0, 1.0)
    through = by_id[2241]
    assert through.component("HOLE_BOTTOM").description == "through"
    assert through.component("PATH_FEATURE_COMPONENT").direction == (0.0, -1.0, 0.0)
    groove = by_id[1978].component("SQUARE_U_PROFILE")
    assert groove.params["width"] == 0.1 and groove.params["first angle"] == 135.0
    hexagon = by_id[2040].component("NGON_CLOSED_PROFILE")
    assert hexagon.params["number of sides"] == 6.0
    assert by_id[1848].children == [1918, 1864]
    assert by_id[2440].texts["form"] == "UNS" and by_id[2440].params["major diameter"] == 1.875
    chamfer = by_id[2369]
    assert sorted(k for c in chamfer.components for k in c.params) == ["chamfer angle",
                                                                      "offset amount"]


def test_sample_turned_features_are_listed_as_unmachinable(sample):
    """RAMP convention: both holes of the composite hole start at the bar's bottom face
    (origin z 0, axis +Z): the 0.77 hole runs 1.5 up, the whole bar (a through hole,
    drillable from the top); the 1.116 counterbore runs 0.65 up from the bottom face
    only (needs the part turned over)."""
    s = feature_shapes(sample)
    (hole,) = s.shapes
    assert hole.id == 1864 and hole.bottom == "through"
    assert (hole.diameter, hole.z_top, hole.depth) == (0.77, 1.5, 1.5)
    reasons = {u.id: u.reason for u in s.skipped}
    assert "not planned" in reasons[2440]
    assert "opens only at the stock bottom" in reasons[1918]
    assert "not along Z" in reasons[2241]  # a radial hole (depth along -Y)
    assert 1848 not in reasons             # composite: covered by its holes


def test_iso14649_files_are_recognised(shared_dir):
    for f in sorted((shared_dir / "step").glob("iso14649_*.p21")):
        part = read_part(f)
        assert part.step.schemas == ["COMBINED_SCHEMA"]
        assert part.features and part.stock.shape == "block"


def test_published_example_plate_with_three_holes():
    part = read_part(FIXTURES / "plate_three_holes.stp")
    assert part.units.length == "mm"
    assert part.stock.shape == "block"
    assert part.stock.box() == (0.0, 0.0, 0.0, 225.0, 100.0, 12.5)
    holes = feature_shapes(part).shapes
    assert [(h.x, h.diameter, h.bottom) for h in holes] == [
        (112.5, 75.0, "through"), (187.5, 31.2, "through"), (37.5, 31.2, "through")]
    assert all(h.z_top == 12.5 and h.depth == 12.5 for h in holes)


def test_published_example_block_with_holes_and_slot():
    shapes = feature_shapes(read_part(FIXTURES / "block_holes_slot.stp")).shapes
    holes = [s for s in shapes if isinstance(s, HoleShape)]
    slots = [s for s in shapes if isinstance(s, SlotShape)]
    assert [h.diameter for h in holes] == [16.6, 16.6]
    assert len(slots) == 1 and slots[0].width == 25.0 and slots[0].ends == ("open", "open")


def test_every_hole_bottom_kind():
    part = read_part(FIXTURES / "hole_bottoms.stp")
    bottoms = [f.component("HOLE_BOTTOM").description for f in part.features]
    assert sorted(set(bottoms)) == sorted(["through", "flat", "conical", "spherical",
                                           "flat with radius", "flat with taper"])
    s = feature_shapes(part)
    kinds = {h.bottom: h for h in s.shapes}
    assert kinds["spherical"].bottom_radius == 5.0
    assert kinds["flat with radius"].bottom_radius == 1.0
    assert kinds["conical"].tip_angle == 118.0
    # the fixture's taper gives only its angle; AP224 (WR7, WR15) also needs the flat's
    # 'final diameter', without which the bottom is undefined
    assert [u.reason for u in s.skipped] == ["hole bottom has no 'final diameter'"]


def test_slots_and_pockets():
    s = feature_shapes(read_part(FIXTURES / "slots_pockets.stp")).shapes
    slots = [x for x in s if isinstance(x, SlotShape)]
    pockets = [x for x in s if isinstance(x, PocketShape)]
    assert [x.ends for x in slots] == [("open", "open"), ("radiused", "radiused"),
                                       ("flat", "open")]
    assert [p.profile for p in pockets] == ["rectangular", "circular", "ngon"]
    rect = pockets[0]
    assert (rect.length, rect.width, rect.corner_radius, rect.depth) == (40.0, 30.0, 5.0, 6.0)
    assert rect.outline().area == pytest.approx(40 * 30 - (4 - math.pi) * 25, rel=1e-3)
    assert pockets[2].sides == 6


def test_inch_units_and_measures_with_other_units():
    part = read_part(FIXTURES / "inch_plate.stp")
    assert part.units.length == "inch"
    assert part.stock.dims["length"] == 4.0
    # a measure in mm inside an inch file is converted to inches
    b = Ap224Builder("MIXED", units="inch")
    b.block(2.0, 1.0, 0.5)
    f = b.hole((1.0, 0.5, 0.5), 0.25, 0.5, bottom="through")
    sf = b.sf
    mm_unit = next(i.id for i in sf.instances.values() if i.get("SI_UNIT") is not None
                   and i.has("LENGTH_UNIT"))
    for inst in sf.instances.values():
        if inst.get("REPRESENTATION_ITEM") == ["diameter"]:
            inst.get("MEASURE_WITH_UNIT")[0] = type(inst.get("MEASURE_WITH_UNIT")[0])(
                "LENGTH_MEASURE", 6.35)
            inst.get("MEASURE_WITH_UNIT")[1] = type(inst.get("MEASURE_WITH_UNIT")[1])(mm_unit)
    hole = read_part(parse(b.text())).features[0]
    assert hole.id == f
    assert hole.component("CIRCULAR_CLOSED_PROFILE").params["diameter"] == pytest.approx(0.25)


def test_measures_are_found_by_name_not_position():
    b = Ap224Builder("ORDER", units="mm")
    b.block(100.0, 50.0, 20.0)
    b.pocket((50.0, 25.0, 20.0), 4.0, "rectangular", width=20.0, corner_radius=3.0,
             length=60.0)
    p = feature_shapes(read_part(parse(b.text()))).shapes[0]
    assert (p.length, p.width, p.corner_radius) == (60.0, 20.0, 3.0)


def test_stock_without_height_is_an_error_naming_the_instance():
    b = Ap224Builder("BAD", units="mm")
    b.block(10.0, 10.0, 5.0)
    for inst in b.sf.instances.values():
        if inst.get("REPRESENTATION_ITEM") == ["height"]:
            inst.get("REPRESENTATION_ITEM")[0] = "thickness"
    with pytest.raises(MillpathError) as e:
        read_part(parse(b.text(), "bad.stp"))
    assert "'height'" in e.value.message and e.value.entity.startswith("#")
    assert e.value.file == "bad.stp" and e.value.line is not None


def test_fixture_files_match_their_generator():
    import importlib.util
    spec = importlib.util.spec_from_file_location("make_fixtures", FIXTURES / "make_fixtures.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    for name, make in mod.FIXTURES.items():
        assert (FIXTURES / name).read_text() == make().text(), name


def test_features_are_expressed_in_the_stock_frame():
    b = Ap224Builder("OFFSET", units="mm")
    b.block(100.0, 50.0, 20.0, origin=(10.0, 20.0, -20.0))
    b.hole((60.0, 45.0, 0.0), 8.0, 5.0, bottom="flat")
    b.pocket((40.0, 40.0, 0.0), 4.0, "rectangular", angle_ref=(0.5, 3 ** 0.5 / 2, 0.0),
             length=30.0, width=10.0, corner_radius=2.0)
    part = read_part(parse(b.text()))
    assert part.stock.box() == (0.0, 0.0, 0.0, 100.0, 50.0, 20.0)
    hole, pocket = feature_shapes(part).shapes
    assert (hole.x, hole.y, hole.z_top) == (50.0, 25.0, 20.0)
    assert pocket.center == (30.0, 20.0) and pocket.angle == pytest.approx(60.0)
    minx, miny, maxx, maxy = pocket.outline().bounds
    assert maxy - miny > maxx - minx               # long side turned towards +Y


def test_features_not_reachable_from_the_top_are_reported():
    b = Ap224Builder("SIDE", units="mm")
    b.block(50.0, 50.0, 20.0)
    f = b.hole((0.0, 25.0, 10.0), 6.0, 10.0, bottom="flat")
    sf = b.sf
    # turn the hole's depth path to +X (drilled from the side)
    for inst in sf.instances.values():
        if inst.get("DIRECTION") == ["", [0.0, 0.0, -1.0]]:
            inst.get("DIRECTION")[1] = [1.0, 0.0, 0.0]
    (u,) = feature_shapes(read_part(parse(b.text()))).skipped
    assert u.id == f and "not along Z" in u.reason


def test_generated_file_with_20000_instances_parses_and_extracts():
    import importlib.util
    bench = Path(__file__).resolve().parents[2] / "bench" / "step_parse.py"
    spec = importlib.util.spec_from_file_location("step_parse", bench)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    text, nfeat = mod.generate(20000)
    sf = parse(text, "big.stp")
    assert len(sf) >= 20000
    part = read_part(sf)
    assert len(part.features) == nfeat
    assert len(feature_shapes(part).shapes) == nfeat


def test_si_units_without_prefix_are_metres_and_plans_scale_to_the_job(tmp_path):
    from millpath.io.schema import validate
    from millpath.model import Machine, Tool
    from millpath.plan.base import PlanContext
    from millpath.plan.features.operation import PARAMS, plan
    b = Ap224Builder("METRES", units="mm")
    b.block(0.1, 0.05, 0.02)
    b.hole((0.05, 0.025, 0.02), 0.008, 0.02, bottom="through")
    for inst in b.sf.instances.values():
        si = inst.get("SI_UNIT")
        if si is not None and si[1] == "METRE":
            si[0] = None                       # (LENGTH_UNIT NAMED_UNIT SI_UNIT($,.METRE.))
    (tmp_path / "m.stp").write_text(b.text())
    part = read_part(tmp_path / "m.stp")
    assert (part.units.length, part.units.length_mm) == ("m", 1000.0)
    assert part.stock.dims["length"] == 0.1
    ctx = PlanContext(units="mm", stock=None, machine=Machine(), base_dir=tmp_path,
                      tools={1: Tool(1, "drill", 8.0, flute_length=40, stickout=60)})
    r = plan(ctx, validate({"step": "m.stp"}, PARAMS, "op", None, tmp_path))
    assert r.stock.box == pytest.approx((0.0, 0.0, 0.0, 100.0, 50.0, 20.0))
    (d,) = [m for m in r.toolpath.moves if m.kind == "drill"]
    assert d.end[:2] == pytest.approx((50.0, 25.0))


def test_step_and_planar_face_are_extracted():
    b = Ap224Builder("STEP-FACE", units="mm")
    b.block(100.0, 50.0, 20.0)
    st = b.step((0.0, 0.0, 20.0), (1.0, 0.0), 100.0)
    pf = b.planar_face((0.0, 25.0, 20.0), (1.0, 0.0), 100.0, 50.0, 0.5)
    part = read_part(parse(b.text()))
    by_id = {f.id: f for f in part.features}
    assert by_id[st].type == "STEP"
    assert by_id[st].component("VEE_PROFILE").params["profile angle"] == 90.0
    assert by_id[st].component("PATH_FEATURE_COMPONENT").params["distance"] == 100.0
    face = by_id[pf]
    assert face.type == "PLANAR_FACE" and face.params["removal depth"] == 0.5
    assert face.component("LINEAR_PROFILE").params["profile length"] == 50.0
    assert face.placement.origin == (0.0, 25.0, 20.0)
    shapes = feature_shapes(part)
    assert [u.id for u in shapes.skipped] == [st] and "width and depth" in shapes.skipped[0].reason
    (face_shape,) = shapes.shapes
    assert (face_shape.start, face_shape.length, face_shape.width, face_shape.depth) == (
        (0.0, 25.0), 100.0, 50.0, 0.5)


def test_bad_geometry_is_a_user_error_naming_the_instance():
    b = Ap224Builder("BADPOINT", units="mm")
    b.block(10.0, 10.0, 5.0)
    for inst in b.sf.instances.values():
        if inst.get("CARTESIAN_POINT") is not None:
            inst.get("CARTESIAN_POINT")[1] = ["x", 0.0, 0.0]
            bad = inst.id
            break
    with pytest.raises(MillpathError) as e:
        read_part(parse(b.text(), "p.stp"))
    assert e.value.entity == f"#{bad}" and "numbers" in e.value.message
