"""DXF and polygon drawings: flattening within tolerance, units, joining, errors.

Truth: the analytic curves the test draws (circle radii, arc areas), not the reader."""

import math

import ezdxf
import numpy as np
import pytest

from millpath.errors import GeometryError
from millpath.part.drawing import read_dxf, region_from_polygon, regions_from_loops


def _save(doc, tmp_path, name="d.dxf"):
    p = tmp_path / name
    doc.saveas(p)
    return p


def _doc(insunits=4):
    doc = ezdxf.new()
    doc.header["$INSUNITS"] = insunits
    return doc, doc.modelspace()


def test_circle_chords_within_tolerance(tmp_path):
    doc, msp = _doc()
    msp.add_circle((10, 20), 15)
    tol = 0.01
    loops = read_dxf(_save(doc, tmp_path), "mm", tol)
    assert len(loops) == 1
    p = loops[0].points
    r = np.hypot(p[:, 0] - 10, p[:, 1] - 20)
    assert np.allclose(r, 15, atol=1e-9)          # vertices on the circle
    q = np.roll(p, -1, axis=0)
    chord = np.hypot(*(q - p).T)
    sag = 15 - np.sqrt(15 ** 2 - (chord / 2) ** 2)
    assert sag.max() <= tol + 1e-9


def test_lwpolyline_bulge_and_pieces_joined_any_order(tmp_path):
    doc, msp = _doc()
    # 40 x 20 rectangle whose right side is a half circle bulging out (bulge 1 = 180 deg)
    msp.add_lwpolyline([(0, 0, 0), (40, 0, 1), (40, 20, 0), (0, 20, 0)], format="xyb",
                       close=True, dxfattribs={"layer": "POCKET"})
    # the same shape as separate pieces, some reversed, shifted up by 100, on another layer
    a = {"layer": "OTHER"}
    msp.add_line((0, 120), (0, 100), dxfattribs=a)             # reversed
    msp.add_arc((40, 110), 10, -90, 90, dxfattribs=a)
    msp.add_line((40, 120), (0, 120), dxfattribs=a)
    msp.add_line((40, 100), (0, 100), dxfattribs=a)            # reversed
    tol = 0.005
    path = _save(doc, tmp_path)
    exact = 40 * 20 + math.pi * 10 ** 2 / 2
    for layer in ("POCKET", "other"):
        loops = read_dxf(path, "mm", tol, layer=layer)
        assert len(loops) == 1
        reg = regions_from_loops(loops)
        area = reg[0].polygon.area
        # chords cut inside the arc: the loss is at most arc length x tolerance
        assert exact - math.pi * 10 * tol - 1e-9 <= area <= exact + 1e-9
        pts = loops[0].points
        on_arc = pts[:, 0] > 40 + 1e-9
        d = np.hypot(pts[on_arc, 0] - 40, pts[on_arc, 1] - (20 if layer == "POCKET" else 120) + 10)
        assert np.allclose(d, 10, atol=1e-9)
    assert len(read_dxf(path, "mm", tol)) == 2


def test_insunits_inch_drawing_in_mm_job(tmp_path):
    doc, msp = _doc(insunits=1)
    msp.add_lwpolyline([(0, 0), (2, 0), (2, 1), (0, 1)], close=True)
    loops = read_dxf(_save(doc, tmp_path), "mm", 0.01)
    assert np.allclose(np.ptp(loops[0].points, axis=0), [50.8, 25.4])
    doc, msp = _doc(insunits=4)
    msp.add_lwpolyline([(0, 0), (25.4, 0), (25.4, 50.8), (0, 50.8)], close=True)
    loops = read_dxf(_save(doc, tmp_path, "mm.dxf"), "inch", 0.001)
    assert np.allclose(np.ptp(loops[0].points, axis=0), [1.0, 2.0])


def test_small_gap_joined_large_gap_reported(tmp_path):
    doc, msp = _doc()
    msp.add_line((0, 0), (10, 0))
    msp.add_line((10.004, 0), (10, 10))
    msp.add_line((10, 10), (0, 0))
    assert len(read_dxf(_save(doc, tmp_path), "mm", 0.001, join_tolerance=0.01)) == 1
    doc, msp = _doc()
    msp.add_line((0, 0), (10, 0))
    bad = msp.add_line((10, 0), (10, 10))
    msp.add_line((10, 10), (0, 0.5))
    with pytest.raises(GeometryError) as e:
        read_dxf(_save(doc, tmp_path, "open.dxf"), "mm", 0.001)
    msg = str(e.value)
    assert "open.dxf" in msg and "open contour" in msg
    assert "(0.0000, 0.5000)" in msg or "(0.0000, 0.0000)" in msg
    assert bad.dxf.handle in msg or "entity" in msg


def test_no_closed_contour_and_unknown_layer(tmp_path):
    doc, msp = _doc()
    msp.add_text("hello")
    with pytest.raises(GeometryError, match="no LINE"):
        read_dxf(_save(doc, tmp_path), "mm", 0.01)
    doc, msp = _doc()
    msp.add_circle((0, 0), 5, dxfattribs={"layer": "A"})
    with pytest.raises(GeometryError, match="layers in the file: A"):
        read_dxf(_save(doc, tmp_path, "l.dxf"), "mm", 0.01, layer="B")


def test_self_intersection_named_with_handle_and_place(tmp_path):
    doc, msp = _doc()
    e = msp.add_lwpolyline([(0, 0), (10, 10), (10, 0), (0, 10)], close=True)
    path = _save(doc, tmp_path)
    with pytest.raises(GeometryError) as ex:
        regions_from_loops(read_dxf(path, "mm", 0.01), path)
    msg = str(ex.value)
    assert f"entity {e.dxf.handle}" in msg and "(5.0000, 5.0000)" in msg


def test_nesting_islands_and_crossing_contours(tmp_path):
    doc, msp = _doc()
    msp.add_lwpolyline([(0, 0), (100, 0), (100, 60), (0, 60)], close=True)
    msp.add_circle((30, 30), 10)                  # island
    msp.add_circle((30, 30), 4)                   # pocket inside the island
    msp.add_lwpolyline([(200, 0), (220, 0), (220, 20)], close=True)   # second region
    regs = regions_from_loops(read_dxf(_save(doc, tmp_path), "mm", 0.001))
    assert len(regs) == 3
    assert len(regs[0].polygon.interiors) == 1
    assert regs[0].polygon.area == pytest.approx(6000 - math.pi * 100, abs=0.1)
    doc, msp = _doc()
    msp.add_lwpolyline([(0, 0), (100, 0), (100, 60), (0, 60)], close=True)
    msp.add_circle((100, 30), 10)
    with pytest.raises(GeometryError, match="cross or touch"):
        regions_from_loops(read_dxf(_save(doc, tmp_path, "x.dxf"), "mm", 0.001))


def test_polygon_keys_island_outside_and_crossing():
    sq = [[0, 0], [50, 0], [50, 50], [0, 50]]
    r = region_from_polygon(sq, [[[10, 10], [20, 10], [20, 20], [10, 20]]], "job.toml")
    assert r.polygon.area == pytest.approx(2500 - 100)
    with pytest.raises(GeometryError, match=r"islands\[1\].*not inside"):
        region_from_polygon(sq, [[[10, 10], [20, 10], [20, 20]],
                                 [[60, 10], [70, 10], [70, 20]]], "job.toml")
    with pytest.raises(GeometryError, match="polygon.*crosses itself"):
        region_from_polygon([[0, 0], [10, 10], [10, 0], [0, 10]], [], "job.toml")
