"""Offset clearing leaves no core: the passes of a level, each cutting the level to
within the ridge height up to ``level_reach`` around it (the flat bottom's radius, or
half the stepover), cover the whole free area, for stepovers up to the diameter
(shapely's buffer is the truth). Before, a stepover wider than the flat radius left
the inside of the innermost ring, and lunes at the corners, standing."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest
import shapely
from shapely.geometry import LineString, Polygon

from millpath.model import Tool
from millpath.plan.pocket.operation import level_reach
from millpath.plan.pocket.passes import cusp, offset_cuts
from millpath.plan.twod.offsets import offset

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "bench"))
import generated_shapes as gs  # noqa: E402


def _uncovered(free, cuts, reach: float) -> float:
    swept = shapely.union_all([LineString(np.vstack([c.pts, c.pts[:1]]) if c.closed
                                          else c.pts).buffer(reach) for c in cuts])
    return free.difference(swept.buffer(1e-6)).area


@pytest.mark.parametrize("seed", range(12))
def test_rings_cover_the_free_area(seed):
    rng = np.random.default_rng([seed, 303])
    d = float(rng.uniform(3, 12))
    tool = (Tool(1, "flat", d) if rng.random() < 0.5 else
            Tool(1, "bull", d, corner_radius=round(float(rng.uniform(0.1, 0.4)) * d, 2)))
    kind = str(rng.choice(gs.KINDS))
    poly = Polygon(gs.polygon(rng, kind, (0, 0), float(rng.uniform(40, 80)),
                              float(rng.uniform(40, 60)), tool.diameter))
    free = offset(poly, -tool.radius)
    stepover = float(rng.uniform(0.5, 1.0)) * tool.diameter
    reach = level_reach(tool, stepover)
    cuts = offset_cuts(free, stepover, True, reach)
    assert _uncovered(free, cuts, reach) < 1e-4 * free.area


def test_a_stepover_wider_than_the_flat_radius_left_a_core():
    """A 10 x 6.6 free area, R = 2.5, stepover 3.4: one ring, whose inside is a 5 x 1.6
    core the tool does not reach; with the inner rings, none."""
    free = Polygon([(0, 0), (10, 0), (10, 6.6), (0, 6.6)])
    tool = Tool(1, "flat", 5.0)
    old = offset_cuts(free, 3.4, True)
    assert len(old) == 1
    assert _uncovered(free, old, 2.5) == pytest.approx(5 * 1.6, rel=1e-3)
    new = offset_cuts(free, 3.4, True, level_reach(tool, 3.4))
    assert _uncovered(free, new, 2.5) < 1e-9
    assert sorted(c.inset for c in new if c.closed) == pytest.approx([0.0, 0.95 * 2.5])


@pytest.mark.parametrize("stepover, want", [(2.0, 0.0), (4.0, 1 - (1 - 0.5 ** 2) ** 0.5),
                                             (4.9, 1 - (1 - 0.95 ** 2) ** 0.5)])
def test_ridge_between_passes_of_a_bull_nose(stepover, want):
    """A 5 mm bull nose with 1 mm corners: the flat bottoms (radius 1.5) overlap up to a
    stepover of 3; beyond, the corners leave a ridge 1 - sqrt(1 - (gap / 2)^2) high."""
    assert cusp(stepover, Tool(1, "bull", 5.0, corner_radius=1.0)) == pytest.approx(want)
