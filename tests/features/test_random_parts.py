"""Random prismatic AP224 parts: every plan cuts exactly its features (simulated)."""

from __future__ import annotations

import numpy as np
import pytest

from millpath.io.schema import validate
from millpath.model import Machine, Tool
from millpath.part.step.build import Ap224Builder
from millpath.plan.base import PlanContext
from millpath.plan.features.operation import PARAMS, plan

TOOLS = {
    1: Tool(1, "flat", 16.0, flutes=3, flute_length=35, stickout=55),
    2: Tool(2, "flat", 8.0, flutes=3, flute_length=25, stickout=40),
    3: Tool(3, "flat", 4.0, flutes=2, flute_length=15, stickout=30),
    4: Tool(4, "drill", 6.0, flute_length=40, stickout=60),
    5: Tool(5, "drill", 10.0, flute_length=50, stickout=70),
    6: Tool(6, "ball", 8.0, flute_length=20, stickout=40),
}


def random_part(seed: int) -> str:
    rng = np.random.default_rng(seed)
    b = Ap224Builder(f"RANDOM-{seed}", units="mm", material="aluminium")
    nx, ny, cell, top = 3, 2, 40.0, 20.0
    b.block(nx * cell, ny * cell, top)
    for i in range(nx):
        for j in range(ny):
            cx, cy = (i + 0.5) * cell, (j + 0.5) * cell
            kind = rng.integers(0, 6)
            depth = float(rng.uniform(2.0, 12.0))
            if kind == 0:
                d = float(rng.choice([6.0, 10.0, rng.uniform(9.0, 30.0)]))
                b.hole((cx, cy, top), d, top, bottom="through")
            elif kind == 1:
                b.hole((cx, cy, top), float(rng.uniform(9.0, 30.0)), depth, bottom="flat")
            elif kind == 2:
                b.hole((cx, cy, top), 8.0, depth + 4.0, bottom="spherical", radius=4.0)
            elif kind == 3:
                L, W = float(rng.uniform(15, 34)), float(rng.uniform(12, 30))
                b.pocket((cx, cy, top), depth, "rectangular", length=L, width=W,
                         corner_radius=float(rng.choice([2.0, 4.0, 8.0])),
                         angle_ref=(1.0, 0.0, 0.0))
            elif kind == 4:
                b.pocket((cx, cy, top), depth, "circular", diameter=float(rng.uniform(12, 34)))
            else:
                w = float(rng.choice([4.0, 8.0, rng.uniform(9, 16)]))
                # flat ends leave square corners by nature: see test_plan
                b.slot((cx - 10.0, cy, top), (1.0, 0.0), 20.0, w, depth,
                       ends=("radiused", "radiused"))
    return b.text()


@pytest.mark.parametrize("seed", range(6))
def test_random_part_is_cut_exactly(tmp_path, seed):
    from millpath.simulate import simulate_toolpath
    (tmp_path / "part.stp").write_text(random_part(seed))
    ctx = PlanContext(units="mm", stock=None, machine=Machine(), tools=TOOLS,
                      base_dir=tmp_path)
    r = plan(ctx, validate({"step": "part.stp"}, PARAMS, "op", None, tmp_path))
    rep = r.report["features"]
    assert rep["unmachinable"] == [] and len({p["id"] for p in rep["planned"]}) == 6
    st = r.stock
    sim = simulate_toolpath(r.toolpath, TOOLS, st, resolution=0.4, design=r.design)
    expected = r.design.volume_on_grid(sim.zmap.xs(), sim.zmap.ys(), sim.zmap.cell_area,
                                          sim.zmap.zmin)
    assert sim.removed_volume == pytest.approx(expected, rel=0.01)
    assert sim.max_gouge <= 1e-6
    assert sim.rapids_through_material == 0 and sim.holder_contacts == 0
