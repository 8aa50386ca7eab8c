"""``millpath simulate`` and the PNG renderers."""

from __future__ import annotations

import json
import math

import pytest
from click.testing import CliRunner

from millpath.cli.main import cli
from millpath.model import Operation, Stock, Tool, Toolpath
from millpath.simulate import (BoxDesign, PlaneDesign, render_deviation, render_stock,
                               simulate_toolpath)

PROGRAM = """G21 G17 G90
T1 M6 G43 H1
S10000 M3
G0 X5.3 Y5.13 Z5
G1 Z-2 F200
G1 X35.7 F600
G0 Z5
G0 X20 Y20
G0 Z-1
G0 Z5
M2
"""


@pytest.fixture
def files(tmp_path):
    (tmp_path / "p.ngc").write_text(PROGRAM)
    (tmp_path / "tools.tbl").write_text("; values in mm\nT1 P1 D6 Z50 ;flat 6\n")
    (tmp_path / "tools.toml").write_text('[[tools]]\nnumber = 1\ntype = "ball"\n'
                                         'diameter = 6\n')
    return tmp_path


def _run(args):
    return CliRunner().invoke(cli, ["simulate", *map(str, args)])


def test_json_output_has_exactly_the_issue_keys_and_slot_volume(files):
    r = _run([files / "p.ngc", "--tools", files / "tools.tbl", "--stock",
              "0,0,-10,45,30,0", "--resolution", "0.12", "--json"])
    assert r.exit_code == 0, r.output
    j = json.loads(r.output)
    assert list(j) == ["removed_volume", "max_gouge", "max_left", "left_volume",
                       "rapids_through_material", "holder_contacts", "cycle_time_s",
                       "resolution", "by_operation"]
    slot = (35.7 - 5.3) * 6 * 2 + math.pi * 9 * 2
    hole = math.pi * 9 * 1          # the rapid down to Z-1 at X20 Y20
    assert j["removed_volume"] == pytest.approx(slot + hole, rel=0.005)
    assert j["rapids_through_material"] == 1
    assert j["max_gouge"] is None and j["resolution"] == 0.12
    assert j["cycle_time_s"] > 30.4 / 10       # at least the slot at 600 mm/min


def test_tool_library_gives_the_ball_shape(files):
    r = _run([files / "p.ngc", "--tools", files / "tools.toml", "--stock",
              "0,0,-10,45,30,0", "--resolution", "0.12", "--json"])
    assert r.exit_code == 0, r.output
    j = json.loads(r.output)
    L = 35.7 - 5.3
    # ball 6 at depth 2 < R: circular segment section, spherical cap ends
    R, d = 3.0, 2.0
    seg = R * R * math.acos((R - d) / R) - (R - d) * math.sqrt(2 * R * d - d * d)
    cap = math.pi * d * d * (3 * R - d) / 3
    cap1 = math.pi * 1.0 * (3 * R - 1.0) / 3                     # the rapid to Z-1
    assert j["removed_volume"] == pytest.approx(L * seg + cap + cap1, rel=0.005)


def test_design_png_and_human_output(files, tmp_path):
    stl = tmp_path / "floor.stl"
    v = [(0, 0, -1.5), (45, 0, -1.5), (45, 30, -1.5), (0, 30, -1.5)]
    tri = [(0, 1, 2), (0, 2, 3)]
    stl.write_text("solid f\n" + "".join(
        "facet normal 0 0 1\nouter loop\n" + "".join(f"vertex {v[i][0]} {v[i][1]} {v[i][2]}\n"
                                                    for i in t) + "endloop\nendfacet\n"
        for t in tri) + "endsolid f\n")
    png = tmp_path / "out.png"
    r = _run([files / "p.ngc", "--tools", files / "tools.tbl", "--stock", "0,0,-10,45,30,0",
              "--design", stl, "--resolution", "0.2", "--png", png])
    assert r.exit_code == 0, r.output
    assert "max gouge        0.5 mm" in r.output
    assert "rapids through material  1 (lines 9)" in r.output
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert (tmp_path / "out_deviation.png").stat().st_size > 1000


@pytest.mark.parametrize("args,msg", [
    (["--stock", "0,0,-10,45,30"], "--stock: expected"),
    (["--stock", "0,0,0,45,30,-10"], "--stock: expected"),
    (["--stock", "0,0,-10,45,30,0", "--design", "missing.stl"], "missing.stl: design file"),
    (["--stock", "0,0,-10,45,30,0", "--tools", "nope.tbl"], "nope.tbl: tool file not found"),
])
def test_user_errors_are_one_line(files, args, msg):
    r = _run([files / "p.ngc", *args])
    assert r.exit_code == 1
    assert msg in r.output
    assert r.output.count("\n") == 1


def test_gcode_error_names_file_and_line(files):
    bad = files / "bad.ngc"
    bad.write_text("G21\nG1 X1 Y1 Z1 F100\nG2 X5 Y5\nM2\n")
    r = _run([bad, "--tools", files / "tools.tbl", "--stock", "0,0,-10,45,30,0"])
    assert r.exit_code == 1
    assert f"{bad}:3:" in r.output


def test_undefined_tool_in_table_is_reported_with_its_line(files):
    (files / "t2.tbl").write_text("T1 P1 D6 Z50\nT2 P2 D0 Z40\n")
    prog = files / "t2.ngc"
    prog.write_text("G21\nT2 M6\nG0 X1 Y1 Z1\nG1 Z-1 F100\nM2\n")
    r = _run([prog, "--tools", files / "t2.tbl", "--stock", "0,0,-10,45,30,0"])
    assert r.exit_code == 1
    assert "tool 2 is not defined" in r.output


def test_renderers_write_readable_pngs(tmp_path):
    tp = Toolpath()
    tp.begin(Operation("t", "t", 1))
    tp.rapid(10.3, 10.2, 5)
    tp.line(10.3, 10.2, -2.2, 100)
    tp.line(30.1, 20.4, -2.2, 300)
    tp.line(30.1, 10.2, -1.0, 300)
    design = BoxDesign(-2.0, [(25, 0, 40, 40, -0.5)])
    r = simulate_toolpath(tp, {1: Tool(1, "ball", 6.0)}, Stock(0, 0, -5, 40, 30, 0),
                          resolution=0.1, design=design)
    a = render_stock(r.zmap, tmp_path / "stock.png", units="mm")
    b = render_deviation(r.zmap, design, tmp_path / "dev.png", units="mm")
    import matplotlib.image as mpimg
    for p in (a, b):
        img = mpimg.imread(p)
        assert img.shape[0] > 300 and img.shape[1] > 600
    img = mpimg.imread(b)[..., :3]
    redish = (img[..., 0] > 0.6) & (img[..., 1] < 0.45) & (img[..., 2] < 0.45)
    blueish = (img[..., 2] > 0.35) & (img[..., 0] < 0.3)
    assert redish.sum() > 100 and blueish.sum() > 100       # gouge and material left
    # flat design: only material left, no red at all
    c = render_deviation(r.zmap, PlaneDesign(-5.0), tmp_path / "left.png")
    img = mpimg.imread(c)[..., :3]
    assert ((img[..., 0] > 0.6) & (img[..., 1] < 0.45) & (img[..., 2] < 0.45)).sum() == 0


def test_inch_program_with_inch_tool_library(tmp_path):
    (tmp_path / "p.ngc").write_text("G20 G17 G90\nT2 M6 G43 H2\nG0 X0.53 Y0.41 Z0.2\nG1 Z-0.1 F10\n"
                                    "G1 X2.37 F20\nG0 Z0.2\nM2\n")
    (tmp_path / "t.toml").write_text('[[tools]]\nnumber = 2\ntype = "flat"\n'
                                     'diameter = 0.25\n')
    r = _run([tmp_path / "p.ngc", "--tools", tmp_path / "t.toml", "--stock",
              "0,0,-1,3,1,0", "--resolution", "0.005", "--json"])
    assert r.exit_code == 0, r.output
    j = json.loads(r.output)
    expected = ((2.37 - 0.53) * 0.25 + math.pi * 0.125 ** 2) * 0.1
    assert j["removed_volume"] == pytest.approx(expected, rel=0.005)
    # 1.84 in at 20 in/min plus the plunge at 10 in/min, inch machine defaults
    assert j["cycle_time_s"] > 1.84 / 20 * 60 + 0.3 / 10 * 60 * 0.5


def test_program_without_a_tool_change_warns_that_nothing_is_cut(tmp_path):
    (tmp_path / "p.ngc").write_text("G21\nG0 X1 Y1 Z1\nG1 Z-1 F100\nM2\n")
    r = CliRunner().invoke(
        cli, ["simulate", str(tmp_path / "p.ngc"), "--stock", "0,0,-5,10,10,0", "--json"])
    assert r.exit_code == 0, r.output
    assert json.loads(r.stdout)["removed_volume"] == 0
    assert "no tool is loaded" in r.stderr


def test_a_tool_table_invents_no_holder(tmp_path):
    """A tool table gives a diameter and a gauge length, no flutes, shank or holder: a
    25 mm deep slot with a 50 mm long tool is no holder contact (it was counted as one
    from a made-up 20 mm flute and a shank above it), and the summary says holders
    were not checked."""
    (tmp_path / "p.ngc").write_text("G21 G17 G90\nT1 M6 G43\nS10000 M3\nG0 X-5 Y10 Z5\n"
                                    "G1 Z-25 F200\nG1 X40 F600\nG0 Z5\nM2\n")
    (tmp_path / "tools.tbl").write_text("; values in mm\nT1 P1 D6 Z50 ;flat 6\n")
    args = [tmp_path / "p.ngc", "--tools", tmp_path / "tools.tbl", "--stock",
            "0,0,-30,35,20,0", "--resolution", "0.5"]
    r = _run([*args, "--json"])
    assert r.exit_code == 0, r.output
    assert json.loads(r.output)["holder_contacts"] == 0
    r = _run(args)
    assert "holders not checked" in r.output
