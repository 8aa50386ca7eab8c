"""AP224 in the RAMP conventions: a bore written from its
bottom with the axis +Z and a hole at its bottom written from the bore floor with the
axis -Z are read, planned and machined where the file puts them; with tools too short
the run is refused with the reach message and writes no program."""

import json
import math
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner

from millpath.cli.main import cli
from millpath.part.step.ap224 import read_part
from millpath.part.step.shapes import feature_shapes
from millpath.report.document import plan_sections

FIXTURE = Path(__file__).resolve().parent / "fixtures" / "ramp_bore.stp"

LONG_TOOLS = """
[[tools]]
number = 1
type = "flat"
diameter = 10.0
flutes = 3
flute_length = 90.0
stickout = 100.0
holder = [[40.0, 60.0]]
"""
SHORT_TOOLS = """
[[tools]]
number = 1
type = "flat"
diameter = 10.0
flutes = 3
flute_length = 30.0
stickout = 45.0
holder = [[32.0, 50.0]]
"""


def _job(tmp_path, tools):
    (tmp_path / "part.stp").write_bytes(FIXTURE.read_bytes())
    p = tmp_path / "job.toml"
    p.write_text('units = "mm"\n[simulation]\nresolution = 0.5\n' + tools
                 + '[[operations]]\ntype = "features"\nstep = "part.stp"\n')
    return p


def test_bore_from_its_bottom_and_hole_below_it_are_read_as_the_file_places_them():
    shapes = {s.id: s for s in feature_shapes(read_part(FIXTURE)).shapes}
    bore, hole = sorted(shapes.values(), key=lambda s: -s.diameter)
    # bore: origin z 7, axis +Z, 78 deep -> from its floor at 7 up to the bar top 85
    assert (bore.diameter, bore.z_top, bore.z_top - bore.depth) == (26.75, 85.0, 7.0)
    assert bore.bottom == "flat"
    # hole: origin z 7 on the bore floor, axis -Z, 7 long -> z 7 .. 0, out of the bar
    assert (hole.diameter, hole.z_top, hole.z_top - hole.depth) == (17.25, 7.0, 0.0)
    assert hole.bottom == "through"


def test_long_tools_machine_the_bore_then_the_hole_from_the_bore_floor(tmp_path):
    out = tmp_path / "out"
    r = CliRunner().invoke(cli, ["run", str(_job(tmp_path, LONG_TOOLS)), "-o", str(out),
                                 "--quiet"])
    assert r.exit_code == 0, r.stderr
    rep = json.loads((out / "report.json").read_text())
    (feats,) = plan_sections(rep, "features")
    planned = {p["id"]: p for p in feats["planned"]}
    hole = next(p for p in planned.values() if p["z"] < 0)
    assert hole["z_start"] == pytest.approx(7.0)        # never from the stock top at 85
    v = rep["verification"]
    assert v["holder_contacts"] == 0 and v["rapids_through_material"] == 0
    assert v["max_gouge"] <= v["resolution"] and rep["safety"]["status"] == "ok"
    assert (out / "program.ngc").exists()


def test_tools_too_short_refuse_with_the_reach_message(tmp_path):
    out = tmp_path / "out"
    job = _job(tmp_path, SHORT_TOOLS)
    r = CliRunner().invoke(cli, ["run", str(job), "-o", str(out), "--quiet"])
    assert r.exit_code == 1
    (line,) = r.stderr.strip().splitlines()
    assert line.startswith("millpath: error: ")
    assert "HOLE #34: needs 78 mm of reach, the longest tool reaches 45" in line
    assert not (out / "program.ngc").exists()


SLOT_FACE = FIXTURE.parent / "ramp_slot_face.stp"


def _slot_face_fixtures():
    import importlib.util
    spec = importlib.util.spec_from_file_location("make_fixtures",
                                                  FIXTURE.parent / "make_fixtures.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def test_fixtures_match_their_generator():
    mod = _slot_face_fixtures()
    assert SLOT_FACE.read_text() == mod.ramp_slot_face().text()
    assert FIXTURE.read_text() == mod.ramp_bore().text()


def test_slot_and_face_placed_on_their_floors_with_the_axis_up_are_read_as_written():
    from millpath.part.step.p21 import parse
    from millpath.part.step.shapes import FaceShape, SlotShape
    up = feature_shapes(read_part(SLOT_FACE))
    down = feature_shapes(read_part(parse(_slot_face_fixtures().ramp_slot_face(False).text())))
    assert up.skipped == [] and down.skipped == []
    for shapes in (up.shapes, down.shapes):
        face = next(s for s in shapes if isinstance(s, FaceShape))
        slot = next(s for s in shapes if isinstance(s, SlotShape))
        # the face lowers the top 20 -> 18.5; the slot runs from the faced top to 12.5
        assert (face.z_top, face.z_top - face.depth) == (20.0, 18.5)
        assert (slot.z_top, slot.z_top - slot.depth) == (18.5, 12.5)
        assert (slot.start, slot.end, slot.width) == ((0.0, 15.0), (60.0, 15.0), 10.0)


def test_a_slot_whose_span_leaves_the_stock_is_listed_with_the_reason():
    from millpath.part.step.build import Ap224Builder
    from millpath.part.step.p21 import parse
    b = Ap224Builder("SLOT-ABOVE", units="mm")
    b.block(60.0, 30.0, 20.0)
    # origin on the top face but the axis +Z: the slot would run 6 mm above the block
    f = b.slot((0.0, 15.0, 20.0), (1.0, 0.0), 60.0, 10.0, 6.0, axis=(0.0, 0.0, 1.0))
    shapes = feature_shapes(read_part(parse(b.text())))
    (u,) = shapes.skipped
    assert u.id == f and u.type == "SLOT" and "outside the stock" in u.reason


def test_slot_and_face_are_machined_where_the_file_puts_them(tmp_path):
    from millpath.io.schema import validate
    from millpath.model import Machine, Tool
    from millpath.plan.base import PlanContext
    from millpath.plan.features.operation import PARAMS, plan
    from millpath.simulate import simulate_toolpath
    tools = {1: Tool(1, "flat", 20.0, flutes=3, flute_length=40, stickout=60),
             2: Tool(2, "flat", 8.0, flutes=3, flute_length=30, stickout=45)}
    (tmp_path / "p.stp").write_bytes(SLOT_FACE.read_bytes())
    ctx = PlanContext(units="mm", stock=None, machine=Machine(), tools=tools,
                      base_dir=tmp_path)
    r = plan(ctx, validate({"step": "p.stp"}, PARAMS, "op", None, tmp_path))
    assert r.report["features"]["unmachinable"] == []
    sim = simulate_toolpath(r.toolpath, tools, r.stock, resolution=0.25)
    z = sim.zmap.heights
    X, Y = np.meshgrid(sim.zmap.xs(), sim.zmap.ys())
    # the analytic part: top 18.5 after facing, 12.5 in the slot |y - 15| <= 5
    dist = np.abs(Y - 15.0)
    truth = np.where(dist <= 5.0 + 1e-9, 12.5, 18.5)
    assert z.min() >= 12.5 - 1e-6 and np.all(z >= truth - 1e-6)        # no gouge
    clear = np.abs(dist - 5.0) > 1e-6                                   # off the walls
    assert np.all(z[clear] <= np.where(dist <= 5.0, 12.5, 18.5)[clear] + 0.01)
    assert sim.removed_volume == pytest.approx(60 * 30 * 1.5 + 60 * 10 * 6.0, rel=0.01)


def _annulus(r: float, cell: float) -> float:
    """Area of the ring r +- half a cell diagonal: the most a Z-map of cells ``cell``
    wide, filled where the cell centre is inside the circle, can differ from pi r^2."""
    h = cell * math.sqrt(2.0) / 2.0
    return math.pi * ((r + h) ** 2 - (r - h) ** 2)


def test_cylindrical_stock_is_a_cylinder_in_the_zmap():
    from millpath.model import Stock
    from millpath.simulate.zmap import ZMap
    st = Stock.from_cylinder(0.0, 0.0, 46.125, 0.0, 85.0)         # the RAMP bar
    assert st.box == (-46.125, -46.125, 0.0, 46.125, 46.125, 85.0)
    z = ZMap.from_stock(st, 0.25)
    exact = math.pi * 46.125 ** 2 * 85.0
    assert abs(z.material_volume() - exact) <= _annulus(46.125, 0.25) * 85.0
    assert z.removed_volume() == 0.0
    # the corners of the box hold no material
    assert z.height_at(-46.0, -46.0) == 0.0 and z.height_at(0.0, 0.0) == 85.0


def test_the_ramp_bar_is_simulated_as_a_cylinder(tmp_path):
    from millpath.io.schema import validate
    from millpath.model import Machine, Tool
    from millpath.plan.base import PlanContext
    from millpath.plan.features.operation import PARAMS, plan
    from millpath.simulate import simulate_toolpath
    tools = {1: Tool(1, "flat", 10.0, flutes=3, flute_length=90, stickout=100,
                     holder=((40.0, 60.0),))}
    (tmp_path / "p.stp").write_bytes(FIXTURE.read_bytes())
    ctx = PlanContext(units="mm", stock=None, machine=Machine(), tools=tools,
                      base_dir=tmp_path)
    r = plan(ctx, validate({"step": "p.stp"}, PARAMS, "op", None, tmp_path))
    assert r.stock.cylinder == (0.0, 0.0, 46.125)
    sim = simulate_toolpath(r.toolpath, tools, r.stock, resolution=0.25, design=r.design)
    assert sim.rapids_through_material == 0 and sim.holder_contacts == 0
    assert sim.max_gouge <= 1e-6             # the air around the bar is not a gouge
    bar = math.pi * 46.125 ** 2 * 85.0
    bore = math.pi * 13.375 ** 2 * 78.0
    hole = math.pi * 8.625 ** 2 * 7.0
    z = sim.zmap
    slack = (_annulus(46.125, z.dx) * 85.0 + _annulus(13.375, z.dx) * 78.0
             + _annulus(8.625, z.dx) * 7.0)
    assert abs(z.material_volume() - (bar - bore - hole)) <= slack
    assert abs(sim.removed_volume - (bore + hole)) <= slack - _annulus(46.125, z.dx) * 85.0


@pytest.mark.parametrize("stock, message", [
    ("cylinder = [0, 0, 92.25, 0, 85]", None),
    ("box = [0, 0, 0, 1, 1, 1]\ncylinder = [0, 0, 92.25, 0, 85]", "stock: give either"),
    ("cylinder = [0, 0, -3, 0, 85]", "stock.cylinder: a cylinder needs a positive radius"),
    ("cylinder = [0, 0, 92.25]", "stock.cylinder: expected 5 numbers"),
])
def test_a_job_stock_may_be_a_bar(tmp_path, stock, message):
    from millpath.errors import JobError
    from millpath.job.jobfile import load_job
    p = tmp_path / "job.toml"
    p.write_text(f'units = "mm"\n[stock]\n{stock}\n[[operations]]\ntype = "features"\n'
                 'step = "part.stp"\n')
    if message is None:
        job = load_job(p)
        assert job.stock.cylinder == (0.0, 0.0, 46.125)
        assert job.stock.box == (-46.125, -46.125, 0.0, 46.125, 46.125, 85.0)
        return
    with pytest.raises(JobError) as e:
        load_job(p)
    assert str(e.value).startswith(str(p)) and message in str(e.value)
