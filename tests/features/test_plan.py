"""The ``features`` operation on the prismatic AP224 fixtures: cycles, order, report,
design, LinuxCNC acceptance and simulated material removal."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from millpath.geometry.cutter import Cutter
from millpath.errors import MillpathError
from millpath.io.schema import validate
from millpath.model import Machine, Tool
from millpath.plan.base import PlanContext
from millpath.plan.features.operation import PARAMS, plan

FIXTURES = Path(__file__).resolve().parents[1] / "step" / "fixtures"

TOOLS_MM = {
    1: Tool(1, "flat", 20.0, flutes=3, flute_length=40, stickout=60),
    2: Tool(2, "flat", 10.0, flutes=3, flute_length=30, stickout=45),
    3: Tool(3, "flat", 6.0, flutes=3, flute_length=20, stickout=35),
    4: Tool(4, "drill", 16.6, flute_length=60, stickout=80),
    5: Tool(5, "drill", 8.0, flute_length=40, stickout=60),
    6: Tool(6, "ball", 10.0, flute_length=20, stickout=40),
    7: Tool(7, "bull", 12.0, corner_radius=1.0, flutes=3, flute_length=25, stickout=40),
    8: Tool(8, "drill", 10.0, flute_length=50, stickout=70),
    9: Tool(9, "drill", 6.0, flute_length=40, stickout=60),
}
TOOLS_IN = {
    1: Tool(1, "flat", 0.25, flutes=2, flute_length=0.75, stickout=1.25),
    2: Tool(2, "drill", 0.25, flute_length=1.2, stickout=1.75),
    3: Tool(3, "flat", 0.375, flutes=3, flute_length=1.0, stickout=1.5),
}

#: fixture -> (units, tools, simulation resolution)
PRISMATIC = {
    "plate_three_holes.stp": ("mm", TOOLS_MM, 0.5),
    "block_holes_slot.stp": ("mm", TOOLS_MM, 0.5),
    "hole_bottoms.stp": ("mm", TOOLS_MM, 0.2),
    "slots_pockets.stp": ("mm", TOOLS_MM, 0.25),
    "inch_plate.stp": ("inch", TOOLS_IN, 0.01),
}


def run_plan(name: str, **over):
    units, tools, _ = PRISMATIC[name]
    ctx = PlanContext(units=units, stock=None, machine=Machine.default_for(units),
                      tools=tools, base_dir=FIXTURES)
    params = validate({"step": name, **over}, PARAMS, "operations[0]", None, FIXTURES)
    return plan(ctx, params)


@pytest.fixture(scope="module")
def planned():
    return {name: run_plan(name) for name in PRISMATIC}


def test_plate_three_holes_uses_helical_interpolation_without_drills(planned):
    r = planned["plate_three_holes.stp"]
    rep = r.report["features"]
    assert [p["strategy"] for p in rep["planned"]] == ["helical"] * 3
    assert rep["unmachinable"] == []
    assert r.stock.box == (0.0, 0.0, 0.0, 225.0, 100.0, 12.5)
    assert rep["material_class"] == "aluminium"


def test_block_holes_slot_drills_matching_holes_and_mills_the_slot(planned):
    r = planned["block_holes_slot.stp"]
    tp = r.toolpath
    drills = [m for m in tp.moves if m.kind == "drill"]
    assert [(m.end[0], m.end[1]) for m in drills] == [(25.0, 20.0), (95.0, 20.0)]
    assert all(tp.tool_of(m) == 4 for m in drills)
    # through: the full diameter leaves the bottom face
    assert all(m.end[2] + Cutter.of(TOOLS_MM[4]).tip_height < 0.0 for m in drills)
    slot_tool = tp.ops[0].tool
    assert TOOLS_MM[slot_tool].diameter <= 25.0
    assert r.report["features"]["tool_changes"] == len(tp.ops) == 2


def test_deep_holes_are_peck_drilled():
    r = run_plan("hole_bottoms.stp")
    cycles = {(round(m.end[0]), round(m.end[1])): (m.cycle, m.peck) for m in r.toolpath.moves
              if m.kind == "drill"}
    # 6 mm conical hole 24 mm deep (4 D) in aluminium: chip-breaking pecks of one diameter
    assert cycles[(45, 42)] == ("G73", 6.0)
    # 10 mm through hole 25 mm deep (< 3 D to the shoulder): plain G81
    assert cycles[(15, 15)][0] == "G81"
    brass = run_plan("hole_bottoms.stp", material="brass-bronze")
    deep = {(round(m.end[0]), round(m.end[1])): m.cycle for m in brass.toolpath.moves
            if m.kind == "drill"}
    assert deep[(45, 42)] == "G83"          # short chips: full retract pecks
    assert deep[(15, 15)] == "G81"


def test_holes_deeper_than_six_diameters_get_full_retract_pecks(tmp_path):
    from millpath.part.step.build import Ap224Builder
    b = Ap224Builder("DEEP", units="mm", material="aluminium")
    b.block(50.0, 50.0, 45.0)
    b.hole((25.0, 25.0, 45.0), 6.0, 40.0, bottom="conical", tip_angle=118.0)
    (tmp_path / "deep.stp").write_text(b.text())
    ctx = PlanContext(units="mm", stock=None, machine=Machine(), tools=TOOLS_MM,
                      base_dir=tmp_path)
    r = plan(ctx, validate({"step": "deep.stp"}, PARAMS, "op", None, tmp_path))
    (m,) = [m for m in r.toolpath.moves if m.kind == "drill"]
    assert (m.cycle, m.peck, m.end[2]) == ("G83", 6.0, 5.0)
    assert m.r_plane > 45.0


def test_operations_are_grouped_by_tool(planned):
    for r in planned.values():
        tools = [op.tool for op in r.toolpath.ops]
        assert len(tools) == len(set(tools))


def test_unmachinable_features_are_reported():
    rep = run_plan("hole_bottoms.stp").report["features"]
    assert [(u["type"], u["reason"]) for u in rep["unmachinable"]] == [
        ("ROUND_HOLE", "hole bottom has no 'final diameter'")]      # the fixture's taper
    assert {p["strategy"] for p in rep["planned"]} == {"drill", "helical", "plunge"}


def test_restricting_tools_changes_the_strategy():
    r = run_plan("block_holes_slot.stp", tools=[1, 2, 3])
    assert {p["strategy"] for p in r.report["features"]["planned"]} == {"helical", "slot"}
    with pytest.raises(MillpathError, match="tool 42"):
        run_plan("block_holes_slot.stp", tools=[42])


def test_design_is_stock_top_minus_features(planned):
    d = planned["hole_bottoms.stp"].design
    z = d.height(np.array([15.0, 35.0, 75.0, 55.0, 90.0, 75.0]),
                 np.array([15.0, 15.0, 15.0, 15.0, 55.0, 19.9]))
    assert z[0] == -np.inf                       # through hole
    assert z[1] == pytest.approx(17.0)           # flat, 8 deep
    assert z[2] == pytest.approx(16.0)           # spherical, lowest point 9 deep
    assert z[3] == pytest.approx(15.0)           # conical tip 10 deep
    assert z[4] == 25.0                          # untouched top
    assert 16.0 < z[5] < 25.0                    # on the sphere near the wall


def test_missing_step_file_is_a_user_error(tmp_path):
    ctx = PlanContext(units="mm", stock=None, machine=Machine(), tools=TOOLS_MM,
                      base_dir=tmp_path)
    with pytest.raises(MillpathError, match="no such STEP file"):
        plan(ctx, validate({"step": "none.stp"}, PARAMS, "operations[0]", None, tmp_path))


@pytest.mark.parametrize("name", sorted(PRISMATIC))
def test_rs274_accepts_the_program(name, planned, rs274):
    from millpath.post.writer import post
    from support.rs274 import run_rs274
    units, tools, _ = PRISMATIC[name]
    r = planned[name]
    res = run_rs274(post(r.toolpath, tools, title=name), tools,
                    table_units=units)
    assert res.ok, (res.error, res.error_line)
    assert len(res.motions) > 0


@pytest.mark.parametrize("name", sorted(PRISMATIC))
def test_simulation_removes_the_feature_volumes_and_nothing_else(name, planned):
    from millpath.simulate import simulate_toolpath
    units, tools, res = PRISMATIC[name]
    r = planned[name]
    stock = r.stock
    sim = simulate_toolpath(r.toolpath, tools, stock, resolution=res, design=r.design)
    expected = r.design.volume_on_grid(sim.zmap.xs(), sim.zmap.ys(), sim.zmap.cell_area,
                                          sim.zmap.zmin)
    assert sim.removed_volume == pytest.approx(expected, rel=0.01)
    assert sim.max_gouge <= 1e-6                  # nothing below the finished part
    assert sim.rapids_through_material == 0
    assert sim.holder_contacts == 0


def nested_part(tmp_path, corner: float, inner_diameter: float) -> Path:
    from millpath.part.step.build import Ap224Builder
    b = Ap224Builder("NESTED", units="mm", material="aluminium")
    b.block(100.0, 80.0, 20.0)
    b.pocket((50.0, 40.0, 20.0), 5.0, "rectangular", length=60.0, width=40.0,
             corner_radius=corner)
    b.pocket((50.0, 40.0, 15.0), 4.0, "circular", diameter=inner_diameter)
    b.hole((50.0, 40.0, 11.0), 8.0, 11.0, bottom="through")
    (tmp_path / "nested.stp").write_text(b.text())
    return tmp_path / "nested.stp"


@pytest.mark.parametrize("corner, inner, inner_start", [
    (5.0, 20.0, 15.0),      # same tool: outer pocket first, inner starts at its floor
    (3.0, 30.0, 20.0),      # inner pocket's tool comes first: it starts at the stock top
])
def test_nested_features_start_where_material_is(tmp_path, corner, inner, inner_start):
    from millpath.simulate import simulate_toolpath
    path = nested_part(tmp_path, corner, inner)
    ctx = PlanContext(units="mm", stock=None, machine=Machine(), tools=TOOLS_MM,
                      base_dir=tmp_path)
    r = plan(ctx, validate({"step": path.name}, PARAMS, "op", None, tmp_path))
    rec = {p["type"] + str(p.get("z_start")): p for p in r.report["features"]["planned"]}
    assert f"POCKET{inner_start}" in rec
    (drill,) = [m for m in r.toolpath.moves if m.kind == "drill"]
    assert drill.cycle == "G81"                 # 8 mm hole, 11 mm deep once cleared
    st = r.stock
    sim = simulate_toolpath(r.toolpath, TOOLS_MM, st, resolution=0.25, design=r.design)
    expected = r.design.volume_on_grid(sim.zmap.xs(), sim.zmap.ys(), sim.zmap.cell_area,
                                          sim.zmap.zmin)
    assert sim.removed_volume == pytest.approx(expected, rel=0.01)
    assert sim.max_gouge <= 1e-6 and sim.rapids_through_material == 0


@pytest.mark.parametrize("name", sorted(PRISMATIC))
def test_interpreted_program_gives_back_the_toolpath(name, planned):
    from millpath.interpret import interpret
    from millpath.post.writer import post_with_lines
    from millpath.verify.roundtrip import compare_toolpath
    units, tools, _ = PRISMATIC[name]
    r = planned[name]
    program, lines = post_with_lines(r.toolpath, tools, title=name)
    motions = interpret(program, tools, machine_units=units)
    tol = 2e-4 if units == "mm" else 2e-5
    assert compare_toolpath(r.toolpath, lines, motions, tol) == []


@pytest.mark.parametrize("with_pocket", [False, True])
def test_flat_holes_are_drilled_then_flattened_when_the_drill_comes_first(tmp_path, with_pocket):
    from millpath.part.step.build import Ap224Builder
    from millpath.simulate import simulate_toolpath
    b = Ap224Builder("FLAT", units="mm", material="aluminium")
    b.block(80.0, 40.0, 20.0)
    b.hole((20.0, 20.0, 20.0), 10.0, 12.0, bottom="flat")
    if with_pocket:           # the 6 mm end mill is needed first for the pocket
        b.pocket((55.0, 20.0, 20.0), 3.0, "rectangular", length=30.0, width=20.0,
                 corner_radius=3.0)
    (tmp_path / "flat.stp").write_text(b.text())
    ctx = PlanContext(units="mm", stock=None, machine=Machine(), tools=TOOLS_MM,
                      base_dir=tmp_path)
    r = plan(ctx, validate({"step": "flat.stp"}, PARAMS, "op", None, tmp_path))
    hole = [p for p in r.report["features"]["planned"] if p["type"] == "HOLE"]
    if with_pocket:
        assert [(p["strategy"], p["tool"]) for p in hole] == [("helical", 3)]
    else:
        assert [(p["strategy"], p["tool"]) for p in hole] == [("drill", 8), ("flatten", 3)]
        flatten = hole[1]
        assert flatten["z_start"] == pytest.approx(8.0 + Cutter.of(TOOLS_MM[8]).tip_height)
    assert len(r.toolpath.ops) == len({op.tool for op in r.toolpath.ops})
    st = r.stock
    sim = simulate_toolpath(r.toolpath, TOOLS_MM, st, resolution=0.2, design=r.design)
    expected = r.design.volume_on_grid(sim.zmap.xs(), sim.zmap.ys(), sim.zmap.cell_area,
                                          sim.zmap.zmin)
    assert sim.removed_volume == pytest.approx(expected, rel=0.01)
    assert sim.max_gouge <= 1e-6 and sim.max_left <= 0.05


def test_flat_slot_ends_leave_exactly_the_square_corners(tmp_path):
    from millpath.part.step.build import Ap224Builder
    from millpath.simulate import simulate_toolpath
    b = Ap224Builder("FLAT-ENDS", units="mm", material="aluminium")
    b.block(60.0, 30.0, 20.0)
    b.slot((15.0, 15.0, 20.0), (1.0, 0.0), 30.0, 10.0, 6.0, ends=("flat", "flat"))
    (tmp_path / "s.stp").write_text(b.text())
    ctx = PlanContext(units="mm", stock=None, machine=Machine(), tools=TOOLS_MM,
                      base_dir=tmp_path)
    r = plan(ctx, validate({"step": "s.stp"}, PARAMS, "op", None, tmp_path))
    (rec,) = r.report["features"]["planned"]
    assert rec["tool"] == 2 and "square corners" in rec["note"]
    sim = simulate_toolpath(r.toolpath, TOOLS_MM, r.stock, resolution=0.1, design=r.design)
    expected = r.design.volume_on_grid(sim.zmap.xs(), sim.zmap.ys(), sim.zmap.cell_area,
                                       sim.zmap.zmin)
    corners = 4 * (1 - np.pi / 4) * 5.0 ** 2 * 6.0        # tool radius 5, depth 6
    assert expected - sim.removed_volume == pytest.approx(corners, rel=0.1)
    assert sim.max_gouge <= 1e-6


@pytest.mark.parametrize("width, centre_y", [
    (50.0, 25.0),           # the whole top: every side open
    (20.0, 10.0),           # a band along one edge: one side is a wall
])
def test_planar_faces_are_face_milled(tmp_path, width, centre_y, rs274):
    from millpath.part.step.build import Ap224Builder
    from millpath.post.writer import post
    from millpath.simulate import simulate_toolpath
    from support.rs274 import run_rs274
    b = Ap224Builder("FACE", units="mm", material="aluminium")
    b.block(100.0, 50.0, 20.0)
    b.planar_face((0.0, centre_y, 20.0), (1.0, 0.0), 100.0, width, 1.5)
    b.pocket((50.0, 35.0 if width < 50 else 25.0, 18.5 if width == 50 else 20.0), 4.0,
             "rectangular", length=30.0, width=10.0, corner_radius=5.0)
    (tmp_path / "f.stp").write_text(b.text())
    ctx = PlanContext(units="mm", stock=None, machine=Machine(), tools=TOOLS_MM,
                      base_dir=tmp_path)
    r = plan(ctx, validate({"step": "f.stp"}, PARAMS, "op", None, tmp_path))
    face = next(p for p in r.report["features"]["planned"] if p["type"] == "FACE")
    assert face["strategy"] == "face" and face["tool"] == 1        # largest end mill
    res = run_rs274(post(r.toolpath, TOOLS_MM), TOOLS_MM)
    assert res.ok, (res.error, res.error_line)
    st = r.stock
    sim = simulate_toolpath(r.toolpath, TOOLS_MM, st, resolution=0.25, design=r.design)
    expected = r.design.volume_on_grid(sim.zmap.xs(), sim.zmap.ys(), sim.zmap.cell_area,
                                       sim.zmap.zmin)
    assert sim.removed_volume == pytest.approx(expected, rel=0.01)
    assert sim.max_gouge <= 1e-6 and sim.rapids_through_material == 0
    assert sim.max_left <= 0.05


def test_fewer_tools_reuses_tools_already_in_use():
    base = run_plan("slots_pockets.stp")
    fewer = run_plan("slots_pockets.stp", fewer_tools=True)
    used = lambda r: {op.tool for op in r.toolpath.ops}      # noqa: E731
    assert len(used(fewer)) < len(used(base))
    assert "replaced by tools already in use" in " ".join(fewer.report["features"]["notes"])
    # same features, same strategies, no new compromise
    strat = lambda r: sorted((p["id"], p["strategy"]) for p in r.report["features"]["planned"])  # noqa: E731,E501
    assert strat(fewer) == strat(base)
    assert not any(p.get("note", "").startswith("corner radius")     # pocket compromise
                   for p in fewer.report["features"]["planned"])


@pytest.mark.parametrize("profile, dims", [
    ("rectangular", {"length": 40.0, "width": 26.0, "corner_radius": 6.0}),
    ("circular", {"diameter": 30.0}),
])
def test_pocket_floor_fillets_take_a_bull_nose_of_that_radius(tmp_path, profile, dims):
    from millpath.part.step.build import Ap224Builder
    from millpath.simulate import simulate_toolpath
    b = Ap224Builder("FILLET", units="mm", material="aluminium")
    b.block(60.0, 40.0, 20.0)
    b.pocket((30.0, 20.0, 20.0), 6.0, profile, floor_radius=1.0, **dims)
    (tmp_path / "p.stp").write_text(b.text())
    ctx = PlanContext(units="mm", stock=None, machine=Machine(), tools=TOOLS_MM,
                      base_dir=tmp_path)
    r = plan(ctx, validate({"step": "p.stp"}, PARAMS, "op", None, tmp_path))
    (rec,) = r.report["features"]["planned"]
    assert rec["tool"] == 7                              # bull nose D12 r1
    z = r.design.height(np.array([30.0, 30.0]), np.array([20.0, 20.0 + (13.0 if profile ==
                                                          "rectangular" else 15.0) - 0.5]))
    assert z[0] == pytest.approx(14.0) and z[1] == pytest.approx(14.0 + 1 - np.sqrt(0.75))
    sim = simulate_toolpath(r.toolpath, TOOLS_MM, r.stock, resolution=0.2, design=r.design)
    expected = r.design.volume_on_grid(sim.zmap.xs(), sim.zmap.ys(), sim.zmap.cell_area,
                                       sim.zmap.zmin)
    assert sim.removed_volume == pytest.approx(expected, rel=0.01)
    assert sim.max_gouge <= 1e-6 and sim.max_left <= 0.05


def test_pocket_floor_fillet_without_a_matching_bull_nose_is_reported(tmp_path):
    from millpath.part.step.build import Ap224Builder
    b = Ap224Builder("FILLET2", units="mm")
    b.block(60.0, 40.0, 20.0)
    b.pocket((30.0, 20.0, 20.0), 6.0, "circular", floor_radius=2.0, diameter=30.0)
    (tmp_path / "p.stp").write_text(b.text())
    ctx = PlanContext(units="mm", stock=None, machine=Machine(), tools=TOOLS_MM,
                      base_dir=tmp_path)
    # the only feature cannot be machined: the run is refused with the reason
    with pytest.raises(MillpathError, match="POCKET #.*bull nose end mill with corner "
                                            "radius 2"):
        plan(ctx, validate({"step": "p.stp"}, PARAMS, "op", None, tmp_path))
