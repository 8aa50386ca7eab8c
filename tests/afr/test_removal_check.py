"""Recognised features checked against the solid: a feature's removal volume must hold
none of the part's material. Truth: analytic volumes of the fixtures and OpenCASCADE
Booleans on the solid itself, never the recognised features."""

from __future__ import annotations

import math
import sys
from pathlib import Path

import pytest

from millpath.errors import PlanningError

pytest.importorskip("OCP")
sys.path.insert(0, str(Path(__file__).parent))
import builder  # noqa: E402

from shapely.geometry import box as sbox  # noqa: E402

from millpath.io.schema import validate  # noqa: E402
from millpath.model import Machine, Tool  # noqa: E402
from millpath.part.brep.removal import INSET, overlap, removal_solid, volume  # noqa: E402
from millpath.part.step.shapes import HoleShape, PocketShape  # noqa: E402
from millpath.plan.base import PlanContext  # noqa: E402
from millpath.plan.features.operation import PARAMS, plan  # noqa: E402
from millpath.plan.features.solid import load_solid  # noqa: E402


def _common(a, b) -> float:
    from OCP.BRepAlgoAPI import BRepAlgoAPI_Common
    return volume(BRepAlgoAPI_Common(a, b).Shape())


@pytest.fixture(scope="module")
def files(tmp_path_factory):
    d = tmp_path_factory.mktemp("removal")
    out = {}
    for name in ("window_over_bar", "raised_plate"):
        shape = getattr(builder, name)()
        out[name] = (shape, builder.write_step(shape, d / f"{name}.step"))
    return out


def test_the_removal_volume_of_a_through_opening_holds_the_bar_under_it(files):
    shape, _ = files["window_over_bar"]
    window = PocketShape(1, (40.0, 30.0), 0.0, "general", 38.0, 40.0, "through",
                         region=sbox(20, 15, 60, 45), keep=None)
    o = overlap(shape, removal_solid(window, 1.0, 40.0, 2.0))
    # the bar (r 8) along the window's length less the inset at both ends
    truth = math.pi * 8.0 ** 2 * (40.0 - 2 * INSET)
    assert o is not None
    assert o.volume == pytest.approx(truth, rel=1e-6)
    assert (o.box[2], o.box[5]) == pytest.approx((2.0, 18.0), abs=1e-6)


def test_a_hole_of_the_part_holds_no_material_and_a_shifted_one_does(files):
    shape, _ = files["raised_plate"]
    hole = HoleShape(1, 50.0, 30.0, 30.0, 10.0, 20.0, "through")
    assert overlap(shape, removal_solid(hole, 1.0, 30.0, 0.0)) is None
    off = HoleShape(1, 52.0, 30.0, 30.0, 10.0, 20.0, "through")
    o = overlap(shape, removal_solid(off, 1.0, 30.0, 0.0))
    from millpath.part.brep.removal import removal_solid as rs
    assert o.volume == pytest.approx(_common(shape, rs(off, 1.0, 30.0, 0.0)), rel=1e-9)
    # two discs of r 4.99 whose centres are 2 apart: the lune outside the hole, 20 deep
    r, R, d = 5.0 - INSET, 5.0, 2.0
    lens = (r * r * math.acos((d * d + r * r - R * R) / (2 * d * r))
            + R * R * math.acos((d * d + R * R - r * r) / (2 * d * R))
            - 0.5 * math.sqrt((-d + r + R) * (d + r - R) * (d - r + R) * (d + r + R)))
    assert o.volume == pytest.approx((math.pi * r * r - lens) * 20.0, rel=1e-6)


def test_recognised_features_of_the_bar_frame_cut_no_material(files):
    shape, path = files["window_over_bar"]
    sp = load_solid(path)
    through = [s for s in sp.shapes.shapes if getattr(s, "bottom", "") == "through"]
    assert len(through) == 2                      # the window either side of the bar
    for s in sp.shapes.shapes:
        r = removal_solid(s, 1.0, 40.0, 2.0)
        if r is not None:
            assert _common(shape, r) < 1e-4, s.id
    assert not any(f.type == "GENERAL_OUTSIDE_PROFILE" for f in sp.part.features)


def test_a_through_hole_over_air_is_a_through_hole_and_no_pocket(files):
    shape, path = files["raised_plate"]
    sp = load_solid(path)
    (h,) = [f for f in sp.part.features if f.type == "ROUND_HOLE"]
    assert h.texts["bottom"] == "through" and h.params["diameter"] == pytest.approx(10.0)
    assert [f.type for f in sp.part.features if f.type in ("POCKET",
                                                           "GENERAL_OUTSIDE_PROFILE")] == []
    assert not [u for u in sp.shapes.skipped if u.type == "ROUND_HOLE"]


def _ctx(path):
    tools = {1: Tool(1, "flat", 6.0, flutes=3, flute_length=45, stickout=60),
             2: Tool(2, "drill", 10.0, flute_length=45, stickout=60)}
    return PlanContext(units="mm", stock=None, machine=Machine(), tools=tools,
                       base_dir=path.parent)


def test_exclude_leaves_features_out_by_id_and_by_face(files):
    _, path = files["window_over_bar"]
    ctx = _ctx(path)
    full = plan(ctx, validate({"step": path.name}, PARAMS, "op", None, path.parent))
    ids = sorted(p["id"] for p in full.report["features"]["planned"])
    assert len(ids) == 2
    r = plan(_ctx(path), validate({"step": path.name, "exclude": [ids[0]]}, PARAMS, "op",
                                  None, path.parent))
    rep = r.report["features"]
    assert [p["id"] for p in rep["planned"]] == ids[1:]
    assert [x["id"] for x in rep["excluded"]] == [ids[0]]
    assert not rep["unmachinable"] or all(u["id"] != ids[0] for u in rep["unmachinable"])
    _, hpath = files["raised_plate"]
    sp = load_solid(hpath)
    (h,) = [f for f in sp.part.features if f.type == "ROUND_HOLE"]
    # the hole is the plate's only feature reachable from +Z: with it left out (by one of
    # its faces) nothing is left to machine, and the refusal says what was left out
    with pytest.raises(PlanningError, match=rf"left out by exclude: ROUND_HOLE #{h.id}\)"):
        plan(_ctx(hpath), validate({"step": hpath.name, "exclude": [f"face {h.faces[0]}"]},
                                   PARAMS, "op", None, hpath.parent))
