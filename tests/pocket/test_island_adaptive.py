"""An adaptive DXF pocket round a round island: written and proven at the operation's
tolerance (its default when the job gives none), with no fit to widen the allowance.

Truth: the 80 x 50 pocket and the 16 mm island the test draws with ezdxf
(tests/support/plates.py), measured analytically against the interpreted program."""

from __future__ import annotations

import math

import numpy as np

from millpath.interpret import interpret
from millpath.job.jobfile import load_job
from millpath.pipeline import run_job
from support import plates

JOB = """units = "mm"
name = "island"
fit = "none"
[stock]
box = [-5, -5, -10, 85, 55, 0]
[[tools]]
number = 1
type = "flat"
diameter = 8.0
flute_length = 20.0
stickout = 30.0
[[operations]]
type = "pocket"
tool = 1
dxf = "island.dxf"
depth = 3.0
stepdown = 3.0
strategy = "adaptive"
engagement = 0.3
feed = 1200.0
spindle = 10000
{extra}
"""
R = 4.0


def _centres(motions, step=0.25) -> np.ndarray:
    """Tool tip points (n, 3) along the feed lines and XY arcs."""
    out = []
    for m in motions:
        a, b = np.asarray(m.start), np.asarray(m.end)
        if m.kind == "feed":
            n = max(1, int(math.ceil(np.linalg.norm(b - a) / step)))
            out.append(a + np.linspace(0, 1, n + 1)[:, None] * (b - a))
        elif m.kind == "arc":
            c = np.asarray(m.center)
            r = math.hypot(*(a - c)[:2])
            t0, t1 = math.atan2(a[1] - c[1], a[0] - c[0]), math.atan2(b[1] - c[1], b[0] - c[0])
            turn = 1 if m.rotation > 0 else -1
            sw = (t1 - t0) % (2 * math.pi) if turn > 0 else -((t0 - t1) % (2 * math.pi))
            sw = sw or turn * 2 * math.pi
            sw += turn * 2 * math.pi * (abs(m.rotation) - 1)
            t = t0 + sw * np.linspace(0, 1, max(8, int(abs(sw) * r / step)) + 1)
            z = np.linspace(a[2], b[2], len(t))
            out.append(np.column_stack([c[0] + r * np.cos(t), c[1] + r * np.sin(t), z]))
    return np.vstack(out)


def test_adaptive_pocket_round_an_island_is_proven_at_its_tolerance(tmp_path):
    plates.write(plates.island_pocket(), tmp_path / "island.dxf")
    job = tmp_path / "job.toml"
    job.write_text(JOB.format(extra=""))
    res = run_job(job, tmp_path / "out", pictures=False)
    assert res.report["safety"]["status"] == "ok"
    assert (tmp_path / "out" / "program.ngc").is_file()
    # the operation carries its tolerance (the default, 0.01 mm): the proof's allowance
    assert [o.tolerance for o in res.toolpath.ops] == [0.01]
    ver = res.report["verification"]
    assert ver["reference"] == "operations[0] design"
    assert ver["max_gouge"] <= 0.01
    # the tool, below the top, keeps its radius from the drawn island and walls
    j = load_job(job)
    p = _centres(interpret(res.program, j.tools, machine_units="mm"))
    p = p[p[:, 2] < -1e-6]
    island, pocket = plates.island_pocket()[1], plates.island_pocket()[0]
    gap = plates.signed_distance(island, p[:, :2]) - R
    assert gap.min() >= -0.01, gap.min()
    assert gap.min() <= 0.05                       # and it goes round it
    wall = -plates.signed_distance(pocket, p[:, :2]) - R
    assert wall.min() >= -0.01, wall.min()


def test_the_operations_tolerance_key_is_the_proofs(tmp_path):
    plates.write(plates.island_pocket(), tmp_path / "island.dxf")
    job = tmp_path / "job.toml"
    job.write_text(JOB.format(extra="tolerance = 0.02"))
    from millpath.pipeline import plan_job
    tp, results, _ = plan_job(load_job(job))
    assert [o.tolerance for o in tp.ops] == [0.02]
