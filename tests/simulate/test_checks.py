"""Gouge, material left, rapids through material, holder contact, designs."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from millpath.errors import MillpathError
from millpath.model import Operation, Stock, Tool, Toolpath
from millpath.simulate import (BoxDesign, HeightFieldDesign, MeshDesign, PlaneDesign,
                               simulate_toolpath)


def _tp(tool: int = 1) -> Toolpath:
    tp = Toolpath()
    tp.begin(Operation("test", "test", tool))
    return tp


def _raster(tp, x0, y0, x1, y1, z, step, feed=500):
    """Zig-zag the tool centre over [x0, x1] x [y0, y1] at depth z."""
    tp.rapid(x0, y0, 5)
    tp.line(x0, y0, z, 100)
    y, k = y0, 0
    while True:
        tp.line(x1 if k % 2 == 0 else x0, y, z, feed)
        if y >= y1 - 1e-9:
            break
        y = min(y + step, y1)
        tp.line(x1 if k % 2 == 0 else x0, y, z, feed)
        k += 1
    tp.rapid(tp.moves[-1].end[0], tp.moves[-1].end[1], 5)


TOOL = Tool(1, "flat", 6.0, flute_length=15, stickout=25)
STOCK = Stock(0, 0, -10, 40, 40, 0)


def test_cut_0_2_below_a_planar_design_reports_a_gouge_of_0_2():
    tp = _tp()
    _raster(tp, 8, 8, 32, 32, -2.2, 4)
    res = 6.0 / 50
    r = simulate_toolpath(tp, {1: TOOL}, STOCK, resolution=res, design=PlaneDesign(-2.0))
    assert r.max_gouge == pytest.approx(0.2, abs=res)
    assert r.max_gouge == pytest.approx(0.2, abs=1e-9)       # flat floor: exact
    assert r.max_left == pytest.approx(2.0, abs=1e-9)        # uncut border
    j = r.to_json()
    assert set(j) == {"removed_volume", "max_gouge", "max_left", "left_volume",
                      "rapids_through_material", "holder_contacts", "cycle_time_s",
                      "resolution", "max_gouge_at", "max_left_at", "gouging_moves",
                      "reference", "accuracy", "left_spacing", "left_measured_to",
                      "max_left_uncut", "by_operation"}
    # the border is 2 mm of stock, measured (the cap is twice the diameter, 12 mm)
    assert j["left_measured_to"] == pytest.approx(12.0) and j["max_left_uncut"] is False
    assert j["accuracy"] == 0.001 and j["reference"] == "design"
    assert j["gouging_moves"] > 0 and j["max_gouge_at"]["z"] == pytest.approx(-2.0)
    assert j["max_gouge"] == pytest.approx(0.2, abs=j["accuracy"])     # exact check


def test_pocket_cut_exactly_to_its_walls_reports_no_gouge():
    # design: 3 deep pocket 20 x 20; the tool centre stays R inside the walls.
    # (o: generic offset so no row of cell centres lies exactly on a wall)
    o = 0.031
    design = BoxDesign(0.0, [(10 + o, 10 + o, 30 + o, 30 + o, -3.0)])
    tp = _tp()
    _raster(tp, 13 + o, 13 + o, 27 + o, 27 + o, -3.0, 3.5)
    for x, y in ((13, 13), (27, 13), (27, 27), (13, 27), (13, 13)):   # wall pass
        tp.line(x + o, y + o, -3.0, 500)
    r = simulate_toolpath(tp, {1: TOOL}, STOCK, resolution=0.12, design=design)
    assert r.max_gouge == pytest.approx(0.0, abs=1e-9)
    # square corners a round tool cannot reach: material left up to the wall height
    assert r.max_left == pytest.approx(3.0, abs=1e-9)
    corner = (3 * 3 - math.pi * 9 / 4) * 4 * 3            # 4 corners, 3 deep
    assert r.left_volume == pytest.approx(corner, rel=0.03)


def test_tool_half_a_millimetre_into_a_wall_gouges_by_the_wall_height():
    design = BoxDesign(0.0, [(10, 10, 30, 30, -3.0)])
    tp = _tp()
    _raster(tp, 13, 13, 27.5, 27, -3.0, 3.5)                 # 0.5 past the X wall
    r = simulate_toolpath(tp, {1: TOOL}, STOCK, resolution=0.12, design=design)
    assert r.max_gouge == pytest.approx(3.0, abs=1e-9)
    x, y = r.gouge_at
    assert 30 < x < 30.5 and 10 < y < 30          # in the wall the tool entered


def test_without_design_gouge_and_left_are_null():
    tp = _tp()
    _raster(tp, 8, 8, 12, 12, -1, 3)
    j = simulate_toolpath(tp, {1: TOOL}, STOCK, resolution=0.2).to_json()
    assert j["max_gouge"] is None and j["max_left"] is None and j["left_volume"] is None


def test_rapid_into_material_is_counted_once_per_move():
    tp = _tp()
    tp.rapid(10, 10, 5)
    tp.rapid(10, 10, -2)            # rapid plunge into the stock
    tp.rapid(30, 10, -2)            # and through it
    tp.rapid(30, 10, 5)             # leaving along its own hole: no material
    tp.rapid(10, 30, 5)
    r = simulate_toolpath(tp, {1: TOOL}, STOCK, resolution=0.2)
    assert r.rapids_through_material == 2
    assert r.rapid_lines == [1, 2]


def test_rapid_skimming_the_surface_it_cut_is_not_counted():
    tp = _tp()
    tp.rapid(10, 10, 5)
    tp.line(10, 10, -2, 100)
    tp.line(30, 10, -2, 100)
    tp.rapid(10, 10, -2)            # back along the slot floor: nothing left to hit
    r = simulate_toolpath(tp, {1: TOOL}, STOCK, resolution=0.2)
    assert r.rapids_through_material == 0


def test_shank_above_the_flutes_touching_stock_is_a_holder_contact():
    tool = Tool(1, "flat", 6.0, flute_length=5, stickout=20, holder=[(30.0, 40.0)])
    deep = _tp()
    deep.rapid(10, 10, 5)
    deep.line(10, 10, -8, 100)      # 8 deep with 5 mm of flute: the shank rubs
    deep.line(30, 10, -8, 100)
    r = simulate_toolpath(deep, {1: tool}, STOCK, resolution=0.2)
    assert r.holder_contacts >= 1
    shallow = _tp()
    shallow.rapid(10, 10, 5)
    shallow.line(10, 10, -4, 100)
    shallow.line(30, 10, -4, 100)
    assert simulate_toolpath(shallow, {1: tool}, STOCK, resolution=0.2).holder_contacts == 0


def test_holder_cylinder_meeting_the_stock_beside_the_cut_is_a_contact():
    tool = Tool(1, "flat", 6.0, flute_length=20, stickout=22, holder=[(30.0, 40.0)])
    tp = _tp()
    tp.rapid(10, 10, 5)
    tp.line(10, 10, -4, 100)        # holder face at z = 18: clear
    tp.line(10, 10, -25 + 4.0, 100)  # below z = -21 + 22 = 1? no: face at 1 > 0, clear
    tp.line(10, 10, -24, 100)        # face at -2: the 30 mm holder hits the stock top
    r = simulate_toolpath(tp, {1: tool}, Stock(0, 0, -30, 40, 40, 0), resolution=0.25)
    assert r.holder_lines == [3]


def test_unknown_tool_is_an_error_naming_the_tool():
    tp = _tp(7)
    tp.rapid(1, 1, 1)
    tp.line(2, 2, -1, 100)
    with pytest.raises(ValueError, match="tool 7"):
        simulate_toolpath(tp, {1: TOOL}, STOCK, resolution=0.5)


def test_compensation_moves_cannot_be_simulated_from_a_toolpath():
    tp = _tp()
    tp.rapid(1, 1, 1)
    tp.compensation("left", 1)
    tp.line(2, 2, -1, 100)
    with pytest.raises(ValueError, match="interpreted motion"):
        simulate_toolpath(tp, {1: TOOL}, STOCK, resolution=0.5)


def _box_stl(path: Path, x0, y0, z0, x1, y1, z1) -> None:
    v = [(x0, y0, z0), (x1, y0, z0), (x1, y1, z0), (x0, y1, z0),
         (x0, y0, z1), (x1, y0, z1), (x1, y1, z1), (x0, y1, z1)]
    faces = [(0, 2, 1), (0, 3, 2), (4, 5, 6), (4, 6, 7), (0, 1, 5), (0, 5, 4),
             (1, 2, 6), (1, 6, 5), (2, 3, 7), (2, 7, 6), (3, 0, 4), (3, 4, 7)]
    lines = ["solid box"]
    for f in faces:
        lines.append("  facet normal 0 0 0\n    outer loop")
        lines += [f"      vertex {v[i][0]} {v[i][1]} {v[i][2]}" for i in f]
        lines.append("    endloop\n  endfacet")
    lines.append("endsolid box")
    path.write_text("\n".join(lines) + "\n")


def test_mesh_design_from_stl_is_the_top_of_the_mesh(tmp_path):
    p = tmp_path / "box.stl"
    _box_stl(p, 5, 5, -10, 35, 35, -2)
    d = MeshDesign.from_stl(p)
    h = d.height(np.array([20.0, 5.0, 35.0, 4.9, 50.0]), np.array([20.0, 20.0, 35.0, 20, 0]))
    assert h[:3] == pytest.approx([-2, -2, -2])
    assert np.isneginf(h[3]) and np.isneginf(h[4])
    tp = _tp()
    _raster(tp, 8, 8, 32, 32, -2.2, 4)
    r = simulate_toolpath(tp, {1: TOOL}, STOCK, resolution=0.12, design=d)
    assert r.max_gouge == pytest.approx(0.2, abs=1e-9)


def test_missing_or_broken_stl_is_a_user_error(tmp_path):
    with pytest.raises(MillpathError, match="not found"):
        MeshDesign.from_stl(tmp_path / "none.stl")
    bad = tmp_path / "bad.stl"
    bad.write_bytes(b"\x00" * 10)
    with pytest.raises(MillpathError):
        MeshDesign.from_stl(bad)


def test_height_field_design_interpolates_and_is_empty_outside():
    x = np.array([0.0, 10.0])
    y = np.array([0.0, 10.0])
    d = HeightFieldDesign(x, y, np.array([[0.0, 10.0], [0.0, 10.0]]))
    assert d.height(np.array([2.5, 7.5]), np.array([5.0, 5.0])) == pytest.approx([2.5, 7.5])
    assert np.isneginf(d.height(np.array([11.0]), np.array([5.0]))[0])


def test_progress_bar_run_gives_the_same_result(monkeypatch):
    import millpath.simulate.simulator as sim
    monkeypatch.setattr(sim, "CHUNK", 7)          # several kernel calls, bar shown
    tp = _tp()
    _raster(tp, 8, 8, 32, 32, -1.0, 2.5)
    a = simulate_toolpath(tp, {1: TOOL}, STOCK, resolution=0.2, progress=True)
    monkeypatch.setattr(sim, "CHUNK", 20_000)
    b = simulate_toolpath(tp, {1: TOOL}, STOCK, resolution=0.2)
    assert np.array_equal(a.zmap.heights, b.zmap.heights)
    assert a.to_json() == b.to_json()


def test_motion_without_geometry_is_swept_as_a_straight_chord():
    from millpath.model.motion import Motion
    from millpath.simulate import simulate_motions
    ms = [Motion("traverse", 1, (5.0, 5.0, 5.0), (5.0, 5.0, 1.0), tool=1),
          Motion("feed", 2, (5.0, 5.0, 1.0), (5.0, 5.0, -1.0), feed=100, tool=1),
          Motion("nurbs", 3, (5.0, 5.0, -1.0), (25.0, 5.0, -1.0), feed=100, tool=1),
          Motion("dwell", 4, (25.0, 5.0, -1.0), (25.0, 5.0, -1.0), dwell=2.0, tool=1)]
    r = simulate_motions(ms, {1: TOOL}, STOCK, resolution=0.1)
    assert r.removed_volume == pytest.approx((20 * 6 + math.pi * 9) * 1, rel=0.01)
    assert r.cycle_time_s > 2.0 + 20 / (100 / 60)


def test_moves_with_an_empty_spindle_cut_nothing():
    from millpath.model.motion import Motion
    from millpath.simulate import simulate_motions
    ms = [Motion("traverse", 1, (5.0, 5.0, 5.0), (5.0, 5.0, -1.0), tool=0),
          Motion("traverse", 2, (5.0, 5.0, -1.0), (5.0, 5.0, 5.0), tool=0),
          Motion("feed", 3, (5.0, 5.0, 5.0), (5.0, 5.0, -1.0), feed=100, tool=1)]
    r = simulate_motions(ms, {1: TOOL}, STOCK, resolution=0.1)
    assert r.removed_volume == pytest.approx(math.pi * 9, rel=0.01)
    assert r.rapids_through_material == 0


def test_through_opening_cut_below_the_stock_is_neither_gouge_nor_left():
    # a 10 x 10 through opening; the tool goes 1 mm below the stock bottom inside it
    o = 0.017
    design = BoxDesign(0.0, [(15 + o, 15 + o, 25 + o, 25 + o, -np.inf)])
    tp = _tp()
    _raster(tp, 18 + o, 18 + o, 22 + o, 22 + o, -11.0, 2.0)
    for x, y in ((18, 18), (22, 18), (22, 22), (18, 22), (18, 18)):
        tp.line(x + o, y + o, -11.0, 500)
    r = simulate_toolpath(tp, {1: TOOL}, STOCK, resolution=0.1, design=design)
    assert r.max_gouge == pytest.approx(0.0, abs=1e-9)
    assert r.max_left == pytest.approx(10.0, abs=1e-9)       # the opening's corners
    assert r.zmap.heights.min() == STOCK.zmin


def test_height_field_design_uses_nearest_sample_next_to_a_hole():
    x = np.array([0.0, 1.0, 2.0])
    y = np.array([0.0, 1.0])
    z = np.array([[1.0, 2.0, -np.inf], [1.0, 2.0, -np.inf]])
    d = HeightFieldDesign(x, y, z)
    h = d.height(np.array([0.5, 1.2, 1.8]), np.array([0.5, 0.5, 0.5]))
    assert h[0] == pytest.approx(1.5)
    assert h[1] == 2.0 and np.isneginf(h[2])


def test_motions_swept_in_blocks_cut_exactly_as_in_one_go():
    """``sweep_motions`` makes chords a block of motions at a time (memory bounded by the
    block, not the program): the stock, the flags and the chord count are those of one
    block holding the whole program (a program with arcs, helices, plunges and a rapid
    through material, random but seeded)."""
    from millpath.interpret import interpret
    from millpath.io.tooltable import parse_tool_table
    from millpath.simulate.simulator import sweep_motions
    from millpath.simulate.zmap import ZMap
    rng = np.random.default_rng(12)
    lines = ["G21 G17 G90", "T1 M6", "G0 X5 Y5 Z5", "G1 Z-2 F200"]
    for _ in range(60):
        x, y = rng.uniform(5, 35, 2)
        if rng.random() < 0.3:
            lines.append(f"G2 X{x:.3f} Y{y:.3f} R{rng.uniform(16, 30):.3f} Z{-rng.uniform(0, 4):.3f}")
        else:
            lines.append(f"G1 X{x:.3f} Y{y:.3f} Z{-rng.uniform(0, 4):.3f}")
    lines += ["G0 Z-1", "G0 X38 Y38", "G0 Z5", "M2"]
    motions = interpret("\n".join(lines) + "\n", parse_tool_table("T1 P1 D6 Z50\n"),
                        machine_units="mm")
    assert len(motions) >= 64 and motions[-1].end[2] == 5.0     # interpreted to the end
    tools = {1: TOOL}
    whole, blocks = ZMap.from_stock(STOCK, 0.25), ZMap.from_stock(STOCK, 0.25)
    f1, n1 = sweep_motions(whole, motions, tools, 0.01, block=10**9)
    f2, n2 = sweep_motions(blocks, motions, tools, 0.01, block=7)
    assert n1 == n2 and n1 > len(motions)
    assert np.array_equal(whole.heights, blocks.heights)
    assert np.array_equal(f1[0], f2[0]) and np.array_equal(f1[1], f2[1])
    assert f1[0].sum() >= 1                      # the rapid at Z-1 is seen in both
