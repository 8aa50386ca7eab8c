"""Feature recognition on STEP solids: fixtures built with OpenCASCADE (AP214 and
AP242), the real AP203 solids of ../shared, planning, and verification of the machined
stock against the solid itself (rays cast on the B-rep, not the recognised features)."""

from __future__ import annotations

import json
import sys
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("OCP")
sys.path.insert(0, str(Path(__file__).parent))
import builder  # noqa: E402

from millpath.errors import MillpathError  # noqa: E402
from millpath.io.schema import validate  # noqa: E402
from millpath.model import Machine, Stock, Tool  # noqa: E402
from millpath.plan.base import PlanContext  # noqa: E402
from millpath.plan.features.operation import PARAMS, plan  # noqa: E402
from millpath.plan.features.solid import load_solid  # noqa: E402

TOL = 0.01
TOOLS = {
    1: Tool(1, "flat", 10.0, flutes=3, flute_length=35, stickout=50),
    2: Tool(2, "flat", 6.0, flutes=3, flute_length=35, stickout=50),
    3: Tool(3, "drill", 8.0, flute_length=45, stickout=60),
    4: Tool(4, "drill", 8.5, flute_length=45, stickout=60),
    5: Tool(5, "drill", 6.0, point_angle=118.0, flute_length=45, stickout=60),
    6: Tool(6, "drill", 12.0, point_angle=90.0, flute_length=20, stickout=40),  # countersink
    7: Tool(7, "ball", 10.0, flute_length=25, stickout=50),
    8: Tool(8, "drill", 10.0, flute_length=45, stickout=60),
    9: Tool(9, "bull", 10.0, corner_radius=1.5, flutes=3, flute_length=30, stickout=50),
}


@pytest.fixture(scope="module")
def parts(tmp_path_factory):
    d = tmp_path_factory.mktemp("afr")
    out = {}
    for name in ("holes_plate", "pockets_plate", "narrow_slot", "fillet_pocket"):
        shape = getattr(builder, name)()
        for schema in ("AP214", "AP242"):
            out[(name, schema)] = builder.write_step(shape, d / f"{name}_{schema}.step", schema)
        out[name] = shape
    return out


def kinds(sp):
    return sorted((f.type, f.name, f.description) for f in sp.part.features)


@pytest.mark.parametrize("schema", ["AP214", "AP242"])
def test_holes_of_every_kind_are_recognised(parts, schema):
    sp = load_solid(parts[("holes_plate", schema)])
    holes = {(round(f.placement.origin[0]), round(f.placement.origin[1]), f.name):
             (round(f.params["diameter"], 6), round(f.params["depth"], 3), f.texts["bottom"])
             for f in sp.part.features if f.type == "ROUND_HOLE"}
    tip = 3.0 / np.tan(np.radians(59.0))
    assert holes == {
        (15, 15, "hole"): (8.0, 30.0, "through"),
        (40, 15, "hole"): (10.0, 12.0, "flat"),
        (65, 15, "hole"): (6.0, round(15.0 + tip, 3), "conical"),
        (90, 15, "hole"): (10.0, 15.0, "spherical"),
        (20, 55, "counterbore"): (16.0, 6.0, "flat"),
        (20, 55, "hole"): (8.5, 24.0, "through"),
        (60, 55, "countersink"): (12.0, 6.0, "conical"),
        (60, 55, "hole"): (6.0, 27.0, "through"),
    }
    comp = sorted(f.name for f in sp.part.features if f.type == "COMPOSITE_HOLE")
    assert comp == ["counterbored hole", "countersunk hole"]
    assert all(f.faces for f in sp.part.features)
    assert sp.shapes.skipped == []


@pytest.mark.parametrize("schema", ["AP214", "AP242"])
def test_pockets_slots_steps_islands_are_recognised(parts, schema):
    sp = load_solid(parts[("pockets_plate", schema)])
    f = {(round(x.placement.origin[0]), round(x.placement.origin[1])): x
         for x in sp.part.features if x.type in ("POCKET", "SLOT", "STEP")}
    a = f[(40, 30)]                                   # pocket with island + counterbore
    assert (a.type, a.name, a.texts["islands"]) == ("POCKET", "closed pocket", "1")
    assert (a.params["depth"], a.params["corner radius"]) == (10.0, 6.0)
    b, nested = f[(110, 25)], None
    nested = [x for x in sp.part.features if x.type == "POCKET" and x.params["depth"] == 5.0]
    assert b.name == "closed pocket" and b.params["depth"] == 8.0
    assert len(nested) == 1 and "level" in nested[0].texts         # in pocket B's floor
    slot = [x for x in sp.part.features if x.type == "SLOT"]
    assert len(slot) == 1 and slot[0].params["width"] == pytest.approx(10.0)
    assert slot[0].name == "open slot"                 # it breaks into pocket C
    assert sorted(slot[0].texts["ends"].split(", ")) == ["open", "radiused"]
    step = [x for x in sp.part.features if x.type == "STEP"]
    assert len(step) == 1 and step[0].params["depth"] == 5.0
    cb = [x for x in sp.part.features if x.type == "COMPOSITE_HOLE"]
    assert len(cb) == 1                                 # counterbore in pocket A's floor
    hole = [x for x in sp.part.features if x.id in cb[0].children and x.name == "counterbore"]
    assert hole[0].placement.origin[2] == pytest.approx(20.0)


def _ctx(units="mm", stock=None, base=Path(".")):
    return PlanContext(units=units, stock=stock, machine=Machine.default_for(units),
                       tools=TOOLS, base_dir=base)


def machined_vs_solid(path, shape, res, step=4, **over):
    """Plan, simulate, and compare the Z-map with rays cast on the solid at every
    ``step``-th cell: the solid's lowest and highest Z over the cell (centre and corners,
    as the simulator resolves walls to one cell) against the cell's simulated Z."""
    from millpath.simulate import simulate_toolpath
    ctx = _ctx(base=path.parent)
    r = plan(ctx, validate({"step": path.name, **over}, PARAMS, "op", None, path.parent))
    sim = simulate_toolpath(r.toolpath, TOOLS, r.stock, resolution=res, design=r.design)
    zm = sim.zmap
    X, Y = np.meshgrid(zm.xs()[::step], zm.ys()[::step])
    x, y = X.ravel(), Y.ravel()
    hx, hy = zm.dx / 2.0, zm.dy / 2.0
    rays = [builder.top_heights(shape, x + a, y + b, r.stock.zmax)
            for a, b in ((0, 0), (-hx, -hy), (hx, -hy), (-hx, hy), (hx, hy))]
    lo = np.maximum(np.min(rays, axis=0), zm.zmin)
    hi = np.maximum(np.max(rays, axis=0), zm.zmin)
    got = zm.heights[::step, ::step].ravel()
    return r, sim, got, (lo, hi)


@pytest.mark.slow
def test_holes_plate_is_machined_to_the_solid(parts):
    r, sim, got, truth = machined_vs_solid(parts[("holes_plate", "AP242")],
                                           parts["holes_plate"], 0.25)
    rep = r.report["features"]
    assert rep["unmachinable"] == []
    strat = {p["id"]: p["strategy"] for p in rep["planned"]}
    assert sorted(strat.values()).count("drill") >= 4
    assert sim.rapids_through_material == 0 and sim.holder_contacts == 0
    lo, hi = truth
    assert np.min(got - lo) >= -TOL - 1e-3             # nothing below the solid
    assert np.max(got - hi) <= TOL + 1e-3              # every feature cut to the solid
    assert sim.max_gouge <= TOL + 1e-3                 # and against the solid's own mesh


@pytest.mark.slow
def test_pockets_plate_is_machined_to_the_solid(parts):
    r, sim, got, truth = machined_vs_solid(parts[("pockets_plate", "AP214")],
                                           parts["pockets_plate"], 0.25)
    assert r.report["features"]["unmachinable"] == []
    lo, hi = truth
    assert np.min(got - lo) >= -TOL - 1e-3
    assert np.max(got - hi) <= TOL + 1e-3
    assert sim.rapids_through_material == 0


def test_floor_fillet_and_free_form_face(parts):
    sp = load_solid(parts[("fillet_pocket", "AP242")])
    (p,) = [f for f in sp.part.features if f.type == "POCKET"]
    assert (p.params["depth"], p.params["corner radius"], p.params["floor radius"]) == \
        (8.0, 6.0, 1.5)
    (u,) = sp.shapes.skipped
    assert u.kind == "face" and u.reason.startswith("free-form face: use surface operations")


@pytest.mark.slow
def test_fillet_pocket_is_machined_with_a_bull_nose(parts):
    r, sim, got, (lo, hi) = machined_vs_solid(parts[("fillet_pocket", "AP242")],
                                              parts["fillet_pocket"], 0.2, step=3)
    (p,) = r.report["features"]["planned"]
    assert TOOLS[p["tool"]].type == "bull"
    assert np.min(got - lo) >= -TOL - 1e-3
    zm = sim.zmap
    X, Y = np.meshgrid(zm.xs()[::3], zm.ys()[::3])
    dimple = np.hypot(X.ravel() - 70.0, Y.ravel() - 52.0) < 4.0    # free-form: not cut
    assert np.max((got - hi)[~dimple]) <= TOL + 1e-3
    assert np.max((got - hi)[dimple]) > 1.0


def test_narrow_slot_is_listed_and_the_rest_is_machined(parts):
    path = parts[("narrow_slot", "AP214")]
    ctx = PlanContext(units="mm", stock=None, machine=Machine(), tools={1: TOOLS[1], 2: TOOLS[2]},
                      base_dir=path.parent)
    r = plan(ctx, validate({"step": path.name}, PARAMS, "op", None, path.parent))
    (u,) = r.report["features"]["unmachinable"]
    assert u["kind"] == "no tool" and "narrower than the smallest flat end mill" in u["reason"]
    (slot,) = [f for f in load_solid(path).part.features if f.type == "SLOT"]
    assert (slot.name, slot.texts["ends"], slot.params["width"]) == ("slot", "flat, flat",
                                                                      pytest.approx(3.0))
    assert [p["type"] for p in r.report["features"]["planned"]] == ["POCKET"]


def test_shared_hole_model_25_cylinder_faces(shared_dir):
    sp = load_solid(shared_dir / "step" / "hole_model.stp")
    from millpath.part.brep.faces import face_table
    cyl = {f.id for f in face_table(sp.solid) if f.kind == "cylinder"}
    assert len(cyl) == 25
    explained = {i for f in sp.part.features for i in f.faces} | \
        {u.id for u in sp.shapes.skipped if u.kind == "face"}
    assert cyl <= explained
    holes = [f for f in sp.part.features if f.type == "ROUND_HOLE"]
    # 24 concave cylinders (one per hole diameter; the 25th face is a boss's rounded
    # corner) plus the cones of 2 countersinks
    assert len(holes) == 26
    assert sum(1 for f in holes if f.name == "countersink") == 2
    assert sum(1 for f in sp.part.features if f.type == "COMPOSITE_HOLE") == 3


@pytest.mark.slow
def test_shared_simple_block_against_its_raw_piece(shared_dir):
    from millpath.simulate import simulate_toolpath
    d = shared_dir / "step"
    ctx = _ctx(base=d)
    r = plan(ctx, validate({"step": "simple_block_workpiece.stp",
                            "stock_step": "simple_block_rawpiece.stp"}, PARAMS, "op", None, d))
    assert r.stock.box == (0.0, 0.0, 0.0, 100.0, 100.0, 25.0)
    sim = simulate_toolpath(r.toolpath, TOOLS, r.stock, resolution=0.5, design=r.design)
    # SOURCES.md: the workpiece's volume is 231,000 mm3 of the 100 x 100 x 25 block
    assert sim.removed_volume == pytest.approx(250000.0 - 231000.0, abs=1.0)
    assert sim.max_gouge <= TOL and sim.max_left <= TOL


def test_part_bigger_than_the_stock(parts):
    path = parts[("narrow_slot", "AP214")]
    ctx = _ctx(stock=Stock.from_box([0, 0, 0, 50, 40, 20]), base=path.parent)
    with pytest.raises(MillpathError, match=r"MANIFOLD_SOLID_BREP #\d+: the part .* is bigger "
                                            r"than the job's stock"):
        plan(ctx, validate({"step": path.name}, PARAMS, "op", None, path.parent))


def test_no_solid_and_open_shell_are_one_line_errors(tmp_path):
    from OCP.BRepBuilderAPI import BRepBuilderAPI_MakeFace
    from OCP.gp import gp_Dir, gp_Pln, gp_Pnt
    from millpath.part.brep.reader import read_solids
    face = BRepBuilderAPI_MakeFace(gp_Pln(gp_Pnt(0, 0, 0), gp_Dir(0, 0, 1)), 0, 10, 0, 10).Face()
    p = builder.write_step(face, tmp_path / "face.step")
    with pytest.raises(MillpathError, match="open shell|no solid") as e:
        read_solids(p)
    assert str(p) in str(e.value) and "\n" not in str(e.value)
    from click.testing import CliRunner
    from millpath.cli.main import cli
    res = CliRunner().invoke(cli, ["features", str(p)])
    assert res.exit_code == 1
    assert res.output.startswith(f"millpath: error: {p}: ") and res.output.count("\n") == 1
    empty = tmp_path / "empty.step"
    empty.write_text("ISO-10303-21;\nHEADER;\nFILE_DESCRIPTION((''),'2;1');\n"
                     "FILE_NAME('','',(''),(''),'','','');\nFILE_SCHEMA(('AP214'));\nENDSEC;\n"
                     "DATA;\nENDSEC;\nEND-ISO-10303-21;\n")
    with pytest.raises(MillpathError, match="no solid|cannot read"):
        read_solids(empty)


def test_cli_lists_recognised_features_with_faces(parts):
    from click.testing import CliRunner
    from millpath.cli.main import cli
    res = CliRunner().invoke(cli, ["features", str(parts[("holes_plate", "AP214")]), "--json"])
    assert res.exit_code == 0, res.output
    doc = json.loads(res.output)
    assert doc["solid"]["faces"] == 18
    assert {f["type"] for f in doc["features"]} == {"ROUND_HOLE", "COMPOSITE_HOLE",
                                                     "PLANAR_FACE"}
    assert all(f["faces"] for f in doc["features"])
    res = CliRunner().invoke(cli, ["features", str(parts[("holes_plate", "AP214")])])
    assert res.exit_code == 0 and "countersunk hole" in res.output


def test_setup_axis_turns_the_part(parts, tmp_path):
    from OCP.BRepBuilderAPI import BRepBuilderAPI_Transform
    from OCP.gp import gp_Ax1, gp_Dir, gp_Pnt, gp_Trsf
    t = gp_Trsf()
    t.SetRotation(gp_Ax1(gp_Pnt(0, 0, 0), gp_Dir(1, 0, 0)), -np.pi / 2)   # +Z -> +Y
    turned = BRepBuilderAPI_Transform(parts["holes_plate"], t, True).Shape()
    p = builder.write_step(turned, tmp_path / "turned.step")
    assert not any(f.type == "ROUND_HOLE" for f in load_solid(p).part.features)
    sp = load_solid(p, setup="+Y")
    assert sum(1 for f in sp.part.features if f.type == "ROUND_HOLE") == 8


def test_missing_opencascade_names_the_extra(parts, monkeypatch):
    from millpath.part.brep.reader import read_solids
    monkeypatch.setitem(sys.modules, "OCP", None)          # import OCP -> ImportError
    with pytest.raises(MillpathError, match=r"millpath\[step-brep\]") as e:
        read_solids(parts[("holes_plate", "AP214")])
    assert "holes_plate_AP214.step" in str(e.value)


def test_several_bodies_need_body_and_inch_files_keep_their_units(parts, tmp_path):
    from OCP.BRep import BRep_Builder
    from OCP.Interface import Interface_Static
    from OCP.TopoDS import TopoDS_Compound
    from millpath.part.brep.reader import read_solids
    comp = TopoDS_Compound()
    bb = BRep_Builder()
    bb.MakeCompound(comp)
    bb.Add(comp, parts["narrow_slot"])
    bb.Add(comp, builder.cut(builder.box(100, 0, 0, 140, 40, 10),
                             builder.cylinder(120, 20, -1, 5.0, 12)))
    Interface_Static.SetCVal_s("write.step.unit", "INCH")
    try:
        p = builder.write_step(comp, tmp_path / "two.step")
    finally:
        Interface_Static.SetCVal_s("write.step.unit", "MM")
    assert len(read_solids(p).bodies) == 2
    with pytest.raises(MillpathError, match=r"2 solids .* body = N"):
        load_solid(p)
    sp = load_solid(p, body=2)
    assert sp.part.units.length == "inch"
    (h,) = [f for f in sp.part.features if f.type == "ROUND_HOLE"]
    assert h.params["diameter"] == pytest.approx(10.0 / 25.4)
    assert h.placement.origin[0] == pytest.approx(120.0 / 25.4)
    ctx = _ctx(base=tmp_path)
    r = plan(ctx, validate({"step": p.name, "body": 2}, PARAMS, "op", None, tmp_path))
    assert r.stock.box == pytest.approx((100.0, 0.0, 0.0, 140.0, 40.0, 10.0), abs=1e-6)
    (d,) = [m for m in r.toolpath.moves if m.kind == "drill"]
    assert (d.end[0], d.end[1]) == pytest.approx((120.0, 20.0))
    with pytest.raises(MillpathError, match="body 3"):
        load_solid(p, body=3)


@pytest.mark.slow
def test_larger_stock_is_faced_and_the_outer_profile_cut(parts):
    from millpath.simulate import simulate_toolpath
    path = parts[("narrow_slot", "AP214")]
    tools = {1: TOOLS[1], 2: TOOLS[2]}
    stock = Stock.from_box([-6, -6, 0, 66, 46, 22])
    ctx = PlanContext(units="mm", stock=stock, machine=Machine(), tools=tools,
                      base_dir=path.parent)
    r = plan(ctx, validate({"step": path.name}, PARAMS, "op", None, path.parent))
    rep = r.report["features"]
    kinds = sorted(p["type"] for p in rep["planned"])
    assert kinds == ["FACE", "POCKET", "POCKET"]                   # face, profile, pocket
    assert [u["kind"] for u in rep["unmachinable"]] == ["no tool"]  # the 3 mm slot
    sim = simulate_toolpath(r.toolpath, tools, stock, resolution=0.25, design=r.design)
    zm = sim.zmap
    X, Y = np.meshgrid(zm.xs()[::3], zm.ys()[::3])
    x, y = X.ravel(), Y.ravel()
    truth = np.maximum(builder.top_heights(parts["narrow_slot"], x, y, 22.0), zm.zmin)
    got = zm.heights[::3, ::3].ravel()
    wall = np.zeros_like(got, dtype=bool)     # cells within a cell of a vertical wall
    for xw in (0.0, 60.0, 10.0, 50.0, 20.0, 40.0):
        wall |= np.abs(x - xw) < 0.25
    for yw in (0.0, 40.0, 5.0, 8.0, 15.0, 35.0):
        wall |= np.abs(y - yw) < 0.25
    slot = (x > 9.5) & (x < 50.5) & (y > 4.5) & (y < 8.5)
    ok = ~wall & ~slot
    assert np.max(np.abs(got - truth)[ok]) <= TOL + 1e-3
    assert np.all(got[slot & ~wall] >= truth[slot & ~wall] - TOL)
    assert sim.max_gouge <= TOL + 1e-3


def test_solid_with_an_open_shell_is_refused(parts, tmp_path):
    import re
    from millpath.part.brep.reader import read_solids
    text = parts[("narrow_slot", "AP214")].read_text()
    m = re.search(r"CLOSED_SHELL\('[^']*',\(#\d+,", text)
    assert m is not None
    broken = text[:m.start()] + re.sub(r"\(#\d+,", "(", text[m.start():m.end()]) + \
        text[m.end():]
    p = tmp_path / "open.step"
    p.write_text(broken)
    # OpenCASCADE makes a shell of it (or a solid with free edges): either way one line
    with pytest.raises(MillpathError, match=r"MANIFOLD_SOLID_BREP #\d+: the (part is an open "
                                            r"shell|solid's shell is open)"):
        read_solids(p)


def test_flat_bottomed_hole_is_never_just_drilled(parts):
    path = parts[("holes_plate", "AP214")]
    tools = {8: TOOLS[8], 3: TOOLS[3]}                  # 10 and 8 mm drills, no end mill
    ctx = PlanContext(units="mm", stock=None, machine=Machine(), tools=tools,
                      base_dir=path.parent)
    r = plan(ctx, validate({"step": path.name}, PARAMS, "op", None, path.parent))
    rep = r.report["features"]
    flat = [f.id for f in load_solid(path).part.features
            if f.type == "ROUND_HOLE" and f.texts["bottom"] == "flat"
            and f.params["diameter"] == 10.0]
    assert flat and all(p["id"] not in flat for p in rep["planned"])
    (u,) = [u for u in rep["unmachinable"] if u["id"] == flat[0]]
    assert "pointed drill" in u["reason"]
    assert any(p["strategy"] == "drill" and p["tool"] == 3 for p in rep["planned"])


def test_undercut_is_listed_as_unreachable(tmp_path):
    """A side window under the top (z 5..10, open at y = 0): its floor is under material
    and its ceiling faces down; the open pocket from the top is still planned."""
    shape = builder.unify(builder.cut(builder.box(0, 0, 0, 60, 40, 20),
                                      builder.box(20, -1, 5, 40, 20, 10),
                                      builder.rounded_rect(43, 10, 57, 30, 15, 6, 3.0)))
    p = builder.write_step(shape, tmp_path / "undercut.step", "AP242")
    sp = load_solid(p)
    reasons = [u.reason for u in sp.shapes.skipped]
    assert any("under material" in r for r in reasons)
    assert any("faces down above the part's bottom" in r for r in reasons)
    assert [s.kind for s in sp.shapes.shapes] == ["pocket"]


@pytest.mark.slow
def test_countersink_with_a_wider_countersink_tool(parts):
    from millpath.simulate import simulate_toolpath
    path = parts[("holes_plate", "AP214")]
    tools = {k: t for k, t in TOOLS.items() if k != 6}
    tools[10] = Tool(10, "drill", 16.0, point_angle=90.0, flute_length=10, stickout=40)
    ctx = PlanContext(units="mm", stock=None, machine=Machine(), tools=tools,
                      base_dir=path.parent)
    r = plan(ctx, validate({"step": path.name}, PARAMS, "op", None, path.parent))
    (cs,) = [p for p in r.report["features"]["planned"] if p["kind"] == "countersink"]
    assert (cs["tool"], cs["strategy"]) == (10, "drill")
    ms = [m for m in r.toolpath.moves if m.kind == "drill" and r.toolpath.tool_of(m) == 10]
    (m,) = [m for m in ms if (m.end[0], m.end[1]) == (60.0, 55.0)]
    assert m.end[2] == pytest.approx(30.0 - 6.0)                  # the cone's apex
    # the 12 mm countersink is cut to the solid: rays on the cone at radius 4.5
    a = np.linspace(0, 2 * np.pi, 12, endpoint=False)
    x, y = 60 + 4.5 * np.cos(a), 55 + 4.5 * np.sin(a)
    stock = r.stock
    sim = simulate_toolpath(r.toolpath, tools, stock, resolution=0.25, design=r.design)
    truth = builder.top_heights(parts["holes_plate"], x, y, 30.0)
    got = np.array([sim.zmap.height_at(px, py) for px, py in zip(x, y)])
    assert np.max(np.abs(got - truth)) <= 0.25 + TOL      # one cell on a 45 degree cone
