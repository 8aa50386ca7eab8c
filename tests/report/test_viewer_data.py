"""What view.html is made of, checked against analytic shapes and hand-written programs:
tool outlines, arc chords, the decimated stock, the operations list and ``millpath view``."""

from __future__ import annotations

import base64
import json
import math
import re

import numpy as np
import pytest
from click.testing import CliRunner

from millpath.cli.main import cli
from millpath.interpret.motion import Motion
from millpath.model.tool import Tool
from millpath.report.viewer import operations_from_program
from millpath.report.viewer.motionpack import ViewOperation, pack_motions
from millpath.report.viewer.stocksurface import display_surface
from millpath.report.viewer.toolshape import cutter_profile, tool_shape
from millpath.simulate import PlaneDesign, ZMap


# --- tool outlines ------------------------------------------------------------------------

def test_ball_profile_lies_on_the_sphere():
    t = Tool(1, "ball", 6.0, flute_length=12.0)
    prof = np.array(cutter_profile(t, steps=16))
    arc = prof[:-1]
    assert np.allclose(arc[:, 0] ** 2 + (arc[:, 1] - 3.0) ** 2, 9.0, atol=1e-12)
    assert tuple(prof[0]) == (0.0, 0.0) and tuple(arc[-1]) == pytest.approx((3.0, 3.0))
    assert tuple(prof[-1]) == (3.0, 12.0)


def test_bull_profile_flat_then_torus():
    t = Tool(2, "bull", 10.0, corner_radius=2.0, flute_length=20.0)
    prof = np.array(cutter_profile(t))
    assert tuple(prof[1]) == (3.0, 0.0)
    corner = prof[2:-1]
    assert np.allclose((corner[:, 0] - 3.0) ** 2 + (corner[:, 1] - 2.0) ** 2, 4.0, atol=1e-12)
    assert tuple(prof[-1]) == (5.0, 20.0)


def test_drill_and_flat_profiles():
    d = Tool(3, "drill", 10.0, point_angle=118.0, flute_length=40.0)
    p = cutter_profile(d)
    assert p[1] == pytest.approx((5.0, 5.0 / math.tan(math.radians(59.0))), abs=1e-12)
    f = Tool(4, "flat", 8.0, flute_length=15.0)
    assert cutter_profile(f) == [(0.0, 0.0), (4.0, 0.0), (4.0, 15.0)]


def test_tool_shape_cylinders_shank_then_holder():
    t = Tool(5, "flat", 6.0, flute_length=10.0, stickout=30.0, holder=[(20, 40), (40, 60)])
    s = tool_shape(t)
    assert s["cylinders"] == [[3.0, 10.0, 30.0, "shank"], [10.0, 30.0, 70.0, "holder"],
                              [20.0, 70.0, 130.0, "holder"]]


# --- motion polyline ------------------------------------------------------------------------

def test_arc_chords_within_display_tolerance_and_ends_exact():
    # a half circle of radius 10 about (0, 0) in XY, counter-clockwise, then a line
    arc = Motion("arc", 1, (10.0, 0.0, 0.0), (-10.0, 0.0, -2.0), feed=500, tool=1,
                 plane="XY", center=(0.0, 0.0, 0.0), rotation=1)
    line = Motion("feed", 2, (-10.0, 0.0, -2.0), (-10.0, 5.0, -2.0), feed=200, tool=1)
    dwell = Motion("dwell", 3, (-10.0, 5.0, -2.0), (-10.0, 5.0, -2.0), tool=1, dwell=1.0)
    tol = 0.01
    pk = pack_motions([arc, line, dwell], [ViewOperation("op", 1, 1)], chord_tol=tol)
    p = pk.points.astype(float)
    a = p[pk.first[0]:pk.last[0] + 1]
    assert np.allclose(a[0], arc.start, atol=1e-6) and np.allclose(a[-1], arc.end, atol=1e-6)
    assert np.allclose(np.hypot(a[:, 0], a[:, 1]), 10.0, atol=1e-5)
    assert np.all(np.diff(np.arctan2(a[:, 1], a[:, 0])) > 0)            # counter-clockwise
    # sagitta of each chord (distance of its middle from the circle) within tol
    mid = (a[1:, :2] + a[:-1, :2]) / 2
    assert (10.0 - np.hypot(mid[:, 0], mid[:, 1])).max() <= tol + 1e-6
    assert pk.first[1] == pk.last[0] and pk.last[1] == pk.first[1] + 1
    assert np.allclose(p[pk.last[1]], line.end)
    assert pk.first[2] == pk.last[2] == pk.last[1]                       # dwell: one point
    assert pk.kind.tolist() == [2, 1, 4] and pk.feed.tolist() == [500, 200, 0]
    # decimated for display: fewer points, every motion kept, ends still exact
    small = pack_motions([arc, line, dwell], [ViewOperation("op", 1, 1)], chord_tol=tol,
                         max_points=10)
    assert len(small.points) <= 10 and small.chord_tol > tol and len(small.first) == 3
    assert np.allclose(small.points[small.last[0]], arc.end, atol=1e-6)


def test_operations_from_program_comments_tool_changes_or_one():
    text = "G21\n(operation 1: rough)\nT1 M6\nG0 X0\n(operation 2: finish it)\nT2 M6\nG1 X1\n"
    mo = [Motion("traverse", 4, (0, 0, 0), (0, 0, 0), tool=1),
          Motion("feed", 7, (0, 0, 0), (1, 0, 0), tool=2, feed=100)]
    assert operations_from_program(text, mo) == [ViewOperation("rough", 1, 2),
                                                 ViewOperation("finish it", 2, 5)]
    text2 = "G21\nT3 M6 (first)\nG0 X0\nT 4 M06\nG1 X1\n"
    mo2 = [Motion("traverse", 3, (0, 0, 0), (0, 0, 0), tool=3),
           Motion("feed", 5, (0, 0, 0), (1, 0, 0), tool=4, feed=100)]
    assert operations_from_program(text2, mo2) == [ViewOperation("T3", 3, 2),
                                                   ViewOperation("T4", 4, 4)]
    assert operations_from_program("G0 X1\n", mo2[:1]) == [ViewOperation("program", 3, 1)]


# --- decimated stock ------------------------------------------------------------------------

def test_display_surface_keeps_every_blocks_extreme_deviation():
    rng = np.random.default_rng(7)
    ny, nx = 23, 37
    H = rng.uniform(-3.0, 0.0, (ny, nx))
    H[rng.random((ny, nx)) < 0.2] = 0.0                     # uncut cells at the stock top
    zm = ZMap(x0=0.0, y0=0.0, dx=0.5, dy=0.5, zmin=-5.0, ztop=0.0, heights=H.copy())
    zd = -1.5
    ds = display_surface(zm, PlaneDesign(zd), max_cells=104)      # 8 x 13 blocks of 3
    step = ds.step
    assert step == 3 and ds.heights.shape == (math.ceil(ny / 3), math.ceil(nx / 3))
    # the deviation by its definition: above the design = material left (> 0); below it
    # = gouge (< 0), counted only where the tool cut (below the stock top)
    dev = np.where(H > zd, H - zd, np.where(H < 0.0, H - zd, 0.0))
    for J in range(ds.heights.shape[0]):
        for I in range(ds.heights.shape[1]):
            blk = dev[J * step:(J + 1) * step, I * step:(I + 1) * step]
            want = blk.min() if -blk.min() > blk.max() else blk.max()
            assert ds.deviation[J, I] == pytest.approx(want, abs=1e-6)
            j, i = min(J * step + 1, ny - 1), min(I * step + 1, nx - 1)
            assert ds.heights[J, I] == pytest.approx(H[j, i], abs=1e-6)
            assert ds.xs[I] == pytest.approx((i + 0.5) * 0.5) and ds.ys[J] == pytest.approx((j + 0.5) * 0.5)
    assert ds.max_gouge == pytest.approx(-dev.min()) and ds.max_left == pytest.approx(dev.max())
    assert np.allclose(ds.design, zd)


# --- millpath view ----------------------------------------------------------------------------

SLOT = """(a slot 1 mm deep across a 20 x 20 block)
G21 G90 G17
T1 M6
G43 H1
S1000 M3
G0 X-5 Y10 Z5
G1 Z-1 F100
G1 X25 F300
G0 Z5
M2
"""


def _data(html) -> dict:
    text = html.read_text()
    return json.loads(re.search(r'id="millpath-data">(.*?)</script>', text, re.S).group(1))


def _arr(s, dtype):
    return np.frombuffer(base64.b64decode(s), dtype=dtype)


@pytest.fixture
def slot_files(tmp_path):
    from millpath.part.surface.mesh import Mesh, write_stl
    (tmp_path / "slot.ngc").write_text(SLOT)
    (tmp_path / "tools.tbl").write_text("; tool table, values in mm\nT1 P1 D4 Z50 ;4 mm end mill\n")
    tri = np.array([[[-1, -1, -0.5], [21, -1, -0.5], [21, 21, -0.5]],
                    [[-1, -1, -0.5], [21, 21, -0.5], [-1, 21, -0.5]]], float)
    write_stl(Mesh(tri), tmp_path / "design.stl")
    return tmp_path


def test_view_command_marks_the_gouge_of_a_slot_cut_below_the_design(slot_files):
    d = slot_files
    out = d / "slot.html"
    r = CliRunner().invoke(cli, ["view", str(d / "slot.ngc"), "--tools", str(d / "tools.tbl"),
                                 "--stock", "0,0,-5,20,20,0", "--design", str(d / "design.stl"),
                                 "-o", str(out)])
    assert r.exit_code == 0, r.output
    data = _data(out)
    assert data["units"] == "mm" and data["stock"] == [0, 0, -5, 20, 20, 0]
    # the four motions of the program, with their lines, kinds and feeds
    p = data["path"]
    assert _arr(p["line"], "<i4").tolist() == [6, 7, 8, 9]
    assert _arr(p["kind"], "u1").tolist() == [0, 1, 1, 0]
    assert _arr(p["feed"], "<f4").tolist() == [0, 100, 300, 0]
    pts = _arr(p["points"], "<f4").reshape(-1, 3)
    ends = pts[_arr(p["last"], "<i4")]
    assert np.allclose(ends, [[-5, 10, 5], [-5, 10, -1], [25, 10, -1], [25, 10, 5]])
    assert data["operations"] == [{"name": "T1", "tool": 1, "first_line": 3}]
    assert data["tools"]["1"]["diameter"] == 4.0
    # the slot floor is 0.5 below the design plane, the uncut top 0.5 above it
    s = data["surface"]
    assert s["max_gouge"] == pytest.approx(0.5, abs=1e-9)
    assert s["max_left"] == pytest.approx(0.5, abs=1e-9)
    dev = _arr(s["deviation"], "<f4")
    assert dev.min() == pytest.approx(-0.5, abs=1e-6) and dev.max() == pytest.approx(0.5, abs=1e-6)
    gx, gy, gz = s["gouge_at"]
    assert abs(gy - 10) <= 2.0 and gz == pytest.approx(-1.0, abs=1e-9)
    assert s["left_at"][2] == pytest.approx(0.0, abs=1e-9) and abs(s["left_at"][1] - 10) > 2.0
    assert s["nx"] * s["ny"] <= 300_000 and s["step"] == 2       # 1000 x 1000 cells shown 1 in 2
    assert data["verification"]["max_gouge"] == pytest.approx(0.5, abs=1e-6)


@pytest.mark.parametrize("args, message", [
    (["--stock", "0,0,-5,20,20"], "--stock: expected XMIN,YMIN,ZMIN,XMAX,YMAX,ZMAX"),
    (["--stock", "0,0,-5,20,20,0", "--tolerance", "-1"], "--tolerance must be a length"),
])
def test_view_bad_options_are_one_line_errors_and_write_nothing(slot_files, args, message):
    d = slot_files
    out = d / "x.html"
    r = CliRunner().invoke(cli, ["view", str(d / "slot.ngc"), "--tools", str(d / "tools.tbl"),
                                 *args, "-o", str(out)])
    assert r.exit_code == 1
    assert r.output.startswith("millpath: error: ") and r.output.count("\n") == 1
    assert message in r.output and "Traceback" not in r.output
    assert not out.exists() and not list(d.glob(".x.html*"))


def test_view_program_error_names_file_and_line(slot_files):
    d = slot_files
    (d / "bad.ngc").write_text("G21 G90\nG1 X1 Y1 Z1\nG2 X5 Q\n")
    out = d / "bad.html"
    r = CliRunner().invoke(cli, ["view", str(d / "bad.ngc"), "--stock", "0,0,-5,20,20,0",
                                 "-o", str(out)])
    assert r.exit_code == 1 and r.output.count("\n") == 1
    assert r.output.startswith(f"millpath: error: {d / 'bad.ngc'}:")
    assert not out.exists()


def test_program_text_cannot_break_out_of_the_page(tmp_path):
    from millpath.model.stock import Stock
    from millpath.report.viewer import write_view
    program = "(</script><!--<script>alert(1)</script> see http://example.com)\nG0 X1 Y2 Z3\n"
    mo = [Motion("traverse", 2, (0.0, 0.0, 3.0), (1.0, 2.0, 3.0), tool=0)]
    out = write_view(tmp_path / "v.html", program=program, motions=mo, tools={},
                     stock=Stock(0, 0, -1, 10, 10, 0), units="mm", title="<b>t</b>")
    text = out.read_text()
    block = re.search(r'id="millpath-data">(.*?)</script>', text, re.S).group(1)
    assert "<" not in block and "/" not in block.replace("\\/", "")
    assert json.loads(block)["program"] == program
    assert "<title>&lt;b&gt;t&lt;/b&gt;</title>" in text
    assert text.count("</script>") == 3            # import map, data, viewer script


def test_a_bar_stock_is_shown_as_a_cylinder():
    """Cylindrical stock: the page carries the bar's circle, and the simulated
    surface has material only over it (the analytic circle at every display vertex)."""
    from millpath.interpret import interpret
    from millpath.model import Stock
    from millpath.report.viewer.scene import scene_data
    from millpath.simulate import simulate_motions
    tools = {1: Tool(1, "flat", 4.0, flute_length=20, stickout=30)}
    stock = Stock.from_cylinder(10.0, 10.0, 8.0, -5.0, 0.0)
    motions = interpret(SLOT, tools, machine_units="mm")
    sim = simulate_motions(motions, tools, stock, resolution=0.1)
    data = scene_data(program=SLOT, motions=motions, tools=tools, stock=stock, units="mm",
                      sim=sim)
    assert data["stock_cylinder"] == [10.0, 10.0, 8.0]
    assert data["stock"] == [2.0, 2.0, -5.0, 18.0, 18.0, 0.0]
    s = data["surface"]
    xs, ys = _arr(s["xs"], "<f4"), _arr(s["ys"], "<f4")
    h = _arr(s["heights"], "<f4").reshape(len(ys), len(xs))
    X, Y = np.meshgrid(xs.astype(float), ys.astype(float))
    rho = np.hypot(X - 10.0, Y - 10.0)
    slot = np.abs(Y - 10.0) <= 2.0 + 1e-6
    assert np.all(h[rho > 8.0 + 1e-4] == -5.0)                 # air around the bar
    assert np.all(h[(rho < 8.0 - 1e-4) & ~slot] == 0.0)        # the uncut top
    assert np.all(h[(rho < 8.0 - 1e-4) & (np.abs(Y - 10.0) < 2.0 - 1e-4)] == -1.0)
