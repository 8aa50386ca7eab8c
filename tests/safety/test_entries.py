"""No straight plunge into material beyond the bundled examples: a
grid-pocket with roughing layers and a concave outline (wall laps at every floor), and a
general pocket region whose innermost ring is too short for a ramp along it. Checked
with the Z-map scan of tests/safety/scan.py (millpath.simulate, not the planners)."""

from __future__ import annotations

import math
import sys
from pathlib import Path

import pytest
import shapely

from millpath.interpret import interpret
from millpath.io.tooltable import parse_tool_table, tool_table_text
from millpath.job.jobfile import load_job
from millpath.model import Operation, Stock, Tool, Toolpath
from millpath.pipeline import fit_job, plan_job, post_job

sys.path.insert(0, str(Path(__file__).parent))
from scan import plunge_violations  # noqa: E402

JOB = """units = "inch"
[stock]
box = [-0.2, -0.2, -1.0, 3.2, 2.2, 0.0]
[simulation]
resolution = 0.01
[[tools]]
number = 1
type = "{tool}"
diameter = 0.25
flute_length = 1.0
stickout = 1.5
[[operations]]
type = "grid-pocket"
tool = 1
polygon = [[0, 0], [3, 0], [3, 1], [1.2, 1], [1.2, 2], [0, 2]]
bottom = {{ bezier = [[-0.2, -0.5, -0.2], [-0.3, -0.6, -0.3], [-0.2, -0.5, -0.2]] }}
depths = [-0.15, -0.3, -0.45]
feed = 10
spindle = 5000
"""


@pytest.mark.parametrize("tool", ["flat", "ball"])
def test_grid_pocket_layers_and_wall_laps_never_plunge_into_material(tmp_path, tool):
    p = tmp_path / "job.toml"
    p.write_text(JOB.format(tool=tool))
    job = load_job(p)
    tp, _, stock = plan_job(job)
    phases = [tp.ops[m.op].info["phase"] for m in tp.moves]
    assert phases.count("wall") and phases.count("rough")
    program = post_job(job, fit_job(job, tp), stock).text
    text = tool_table_text(job.tools, job.units, job.table_units)
    motions = interpret(program, parse_tool_table(text), machine_units=job.table_units)
    assert plunge_violations(motions, job.tools, stock, 0.01) == []


def test_a_short_innermost_ring_is_entered_by_a_ramp_not_a_plunge():
    from millpath.plan.features.paths import Heights
    from millpath.plan.features.region import clear_general
    from millpath.simulate.path import toolpath_motions
    # a 14 x 12 mm region for a 10 mm tool: the tool-centre region is a 4 x 2 mm box,
    # whose ring (12 mm) at 5 degrees descends 1 mm a lap: 12 mm deep needs a helix
    # or zigzag ramp
    tool = Tool(1, "flat", 10.0, flute_length=30.0, stickout=45.0)
    region = shapely.box(-2.0, -1.0, 2.0, 1.0)
    tp = Toolpath("mm")
    tp.begin(Operation("features", "pocket", 1, spindle=8000))
    h = Heights(z_safe=25.0, r_plane=22.0)
    clear_general(tp, region, region, 20.0, 8.0, h, step_down=12.0, stepover=4.0,
                  feed=600.0, plunge_feed=200.0, tool_radius=5.0)
    stock = Stock(-7.0, -6.0, 0.0, 7.0, 6.0, 20.0)
    motions, _ = toolpath_motions(tp)
    assert plunge_violations(motions, {1: tool}, stock, 0.1) == []
    # below the top (z 20) every descending feed move is a ramp no steeper than 5
    # degrees (a zigzag from the ring's corner, where no helix circle fits)
    pos, descents = None, 0
    for m in tp.moves:
        if pos is not None and m.kind == "line" and m.end[2] < pos[2] and pos[2] <= 20.0:
            run = math.hypot(m.end[0] - pos[0], m.end[1] - pos[1])
            assert pos[2] - m.end[2] <= run * math.tan(math.radians(5.0)) + 1e-9
            descents += 1
        pos = m.end
    assert descents >= 2 and min(m.end[2] for m in tp.moves) == 8.0
