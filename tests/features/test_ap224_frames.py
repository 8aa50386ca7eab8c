"""AP224 placements as ISO 10303-224 defines them (ISO/TS 10303-1814, Machining
features): a slot's origin at one end of its course of travel on its floor, placement Z
along the course, Y away from the part (the U profile opens towards +Y). Files are
written by the builder from those rules; the removed volume is checked against an
OpenCASCADE solid built from the same rules (stock minus the slot's box)."""

from __future__ import annotations

import math

import pytest

from millpath.part.step.ap224 import read_part
from millpath.part.step.build import Ap224Builder
from millpath.part.step.shapes import SlotShape, feature_shapes

pytest.importorskip("OCP")


def _box_solid(corner, d, length, width, height):
    """An OpenCASCADE box: ``corner`` and edges along d (XY unit), +Z x d and +Z."""
    from OCP.BRepPrimAPI import BRepPrimAPI_MakeBox
    from OCP.gp import gp_Ax2, gp_Dir, gp_Pnt
    ax = gp_Ax2(gp_Pnt(*corner), gp_Dir(0, 0, 1), gp_Dir(d[0], d[1], 0.0))
    return BRepPrimAPI_MakeBox(ax, length, width, height).Shape()


def _volume(shape) -> float:
    from millpath.part.brep.removal import volume
    return volume(shape)


def _slot_solid(s: SlotShape):
    """The planner's slot (flat ends) as a solid: its outline from floor to top."""
    from millpath.part.brep.removal import _prism
    from millpath.plan.features.design import slot_outline
    return _prism(slot_outline(s, 0.0), s.z_top - s.depth, s.z_top)


@pytest.mark.parametrize("direction", [(1.0, 0.0), (0.6, 0.8)])
def test_a_slot_placed_as_the_standard_defines_it_removes_its_volume(tmp_path, direction):
    from OCP.BRepAlgoAPI import BRepAlgoAPI_Common, BRepAlgoAPI_Cut
    b = Ap224Builder("SLOTTED", material="aluminium 6061-T6")
    b.block(100.0, 80.0, 20.0)
    start = (20.0, 20.0, 14.0)                       # on the floor, 6 below the top
    b.slot_iso(start, direction, 40.0, 12.0, 6.0, ends=("flat", "flat"))
    f = tmp_path / "slot.stp"
    f.write_text(b.text())
    shapes = feature_shapes(read_part(f))
    assert not shapes.skipped
    (s,) = shapes.shapes
    assert s.z_top == pytest.approx(20.0) and s.depth == pytest.approx(6.0)
    # the standard's slot: from the origin along Z (the course) for its length, the
    # width centred across X, rising along Y (+Z here) from the floor by its depth
    d = direction
    across = (-d[1], d[0])
    corner = (start[0] - across[0] * 6.0, start[1] - across[1] * 6.0, start[2])
    truth = _box_solid(corner, d, 40.0, 12.0, 6.0)
    stock = _box_solid((0.0, 0.0, 0.0), (1.0, 0.0), 100.0, 80.0, 20.0)
    part_truth = BRepAlgoAPI_Cut(stock, truth).Shape()
    part_got = BRepAlgoAPI_Cut(stock, _slot_solid(s)).Shape()
    both = _volume(BRepAlgoAPI_Common(part_truth, part_got).Shape())
    assert _volume(part_truth) == pytest.approx(100 * 80 * 20 - 40 * 12 * 6, abs=1e-6)
    # symmetric difference of the two parts: nothing
    assert _volume(part_truth) + _volume(part_got) - 2 * both == pytest.approx(0.0, abs=1e-6)


def test_a_slot_whose_profile_opens_downward_is_for_the_other_side(tmp_path):
    b = Ap224Builder("UNDER")
    b.block(100.0, 80.0, 20.0)
    f = b.slot_iso((20.0, 40.0, 6.0), (1.0, 0.0), 40.0, 12.0, 6.0)
    # turn the placement about its Z (the course) by 180 degrees: Y points down
    sf_text = b.text()
    path = tmp_path / "under.stp"
    path.write_text(sf_text)
    part = read_part(path)
    (feat,) = part.features
    feat.placement.ref = tuple(-v for v in feat.placement.ref)
    shapes = feature_shapes(part)
    assert not shapes.shapes
    assert "other side" in shapes.skipped[0].reason
    assert math.isclose(abs(feat.placement.axis[0]), 1.0)


def test_setup_turns_an_ap224_part_to_the_side_it_is_machined_from(tmp_path):
    b = Ap224Builder("UNDERSIDE")
    b.block(100.0, 60.0, 20.0)
    # a 10 mm hole 8 deep into the bottom face at (30, 15): entry on z 0, depth along +Z
    b.hole((30.0, 15.0, 0.0), 10.0, 8.0, bottom="flat", axis=(0.0, 0.0, 1.0))
    f = tmp_path / "under.stp"
    f.write_text(b.text())
    from millpath.part.step.setup import turned
    top = feature_shapes(read_part(f))
    assert not top.shapes and "other side" in top.skipped[0].reason
    part = turned(read_part(f), "-Z")
    assert part.stock.box() == pytest.approx((0, 0, 0, 100.0, 60.0, 20.0))
    (h,) = feature_shapes(part).shapes
    # turned about X: y -> 60 - y, the bottom face becomes the top
    assert (h.x, h.y, h.z_top, h.depth) == pytest.approx((30.0, 45.0, 20.0, 8.0))
    side = turned(read_part(f), "+X")
    assert side.stock.box() == pytest.approx((0, 0, 0, 20.0, 60.0, 100.0))
