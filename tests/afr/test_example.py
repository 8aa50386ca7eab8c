"""The bundled example ``solid-hole-model`` (a real AP203 solid from Siemens NX): LinuxCNC
accepts the program, the stock is cut to the solid within the tolerance where features
were recognised, and bad input stops ``millpath run`` with one line."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("OCP")

from millpath.job.jobfile import load_job  # noqa: E402
from millpath.plan.base import PlanContext  # noqa: E402
from millpath.plan.registry import strategy  # noqa: E402

EXAMPLE = Path(__file__).resolve().parents[2] / "millpath" / "examples" / "solid-hole-model"


@pytest.fixture(scope="module")
def planned():
    job = load_job(EXAMPLE / "job.toml")
    ctx = PlanContext(units=job.units, stock=None, machine=job.machine, tools=job.tools,
                      base_dir=job.base_dir, job_file=job.path)
    (op, params), = job.operations
    return job, strategy(op).plan(ctx, params)


def test_example_report_lists_what_is_not_machinable(planned):
    _, r = planned
    rep = r.report["features"]
    assert rep["solid"]["faces"] == 64 and rep["material_class"] == "aluminium"
    reasons = {u["id"]: u["reason"] for u in rep["unmachinable"]}
    assert "use surface operations" in reasons[57]                  # the inclined face
    assert "not reachable from +Z" in reasons[59]
    assert sum("drilled from below" in v for v in reasons.values()) == 1
    assert len(rep["unmachinable"]) == 3                 # every other feature is planned


@pytest.mark.slow
def test_example_is_accepted_by_rs274_and_cut_to_the_solid(planned, rs274):
    from millpath.post.writer import post
    from millpath.simulate import simulate_toolpath
    from support.rs274 import run_rs274
    job, r = planned
    res = run_rs274(post(r.toolpath, job.tools, title="solid-hole-model"), job.tools,
                    table_units="mm")
    assert res.ok, (res.error, res.error_line)
    sim = simulate_toolpath(r.toolpath, job.tools, r.stock, resolution=0.25, design=r.design)
    assert sim.max_gouge <= 0.01 + 1e-3
    assert sim.rapids_through_material == 0 and sim.holder_contacts == 0
    # material is left only under the inclined face (x -20..0, y 0..25) and in the two
    # sharp corners of pocket #35 (reported: left at the 3 mm tool's radius)
    zm = sim.zmap
    X, Y = np.meshgrid(zm.xs(), zm.ys())
    left = zm.heights - np.maximum(r.design.height(X, Y), zm.zmin)
    ramp = (X > -20.5) & (X < 0.5) & (Y > -0.5)
    corners = (np.hypot(X + 20.0, Y) < 1.5) | (np.hypot(X, Y) < 1.5)
    assert np.max(left[~ramp & ~corners]) <= 0.01 + 1e-3
    (p35,) = [p for p in r.report["features"]["planned"] if p["id"] == 35]
    assert "corners are left at the tool radius" in p35["note"]


def test_part_bigger_than_the_stock_stops_the_run(tmp_path):
    from click.testing import CliRunner
    from millpath.cli.main import cli
    text = (EXAMPLE / "job.toml").read_text().replace(
        'step = "part.stp"', f'step = "{EXAMPLE / "part.stp"}"')
    text = text.replace('[simulation]', '[stock]\nbox = [-50, -25, 0, 40, 25, 31]\n'
                        '[simulation]')
    job = tmp_path / "job.toml"
    job.write_text(text)
    res = CliRunner().invoke(cli, ["run", str(job), "-o", str(tmp_path / "out")])
    assert res.exit_code == 1
    line = res.output.strip()
    assert "\n" not in line and "part.stp: MANIFOLD_SOLID_BREP #93: the part" in line
    assert "bigger than the job's stock" in line
    assert not (tmp_path / "out").exists()


@pytest.mark.slow
def test_example_passes_the_exact_check_against_the_solid(tmp_path):
    """With ``[simulation] exact = true`` the program is measured against the STEP solid
    itself, meshed within a quarter of the accuracy (a height field of a 0.01 mm mesh puts a
    drilled cone's apex 0.45 mm too high and walls on grid lines where there are none:
    0.39 mm of false gouge)."""
    from millpath.pipeline import run_job
    text = (EXAMPLE / "job.toml").read_text().replace(
        'step = "part.stp"', f'step = "{EXAMPLE / "part.stp"}"').replace(
        "[simulation]\n", "[simulation]\nexact = true\n")
    job = tmp_path / "job.toml"
    job.write_text(text)
    res = run_job(job, tmp_path / "out")
    v = res.report["verification"]
    assert "STEP solid" in v["reference"] and v["accuracy"] == 0.001
    assert v["max_gouge"] <= 0.01 and v["holder_contacts"] == 0
    assert v["rapids_through_material"] == 0
    assert all(o["max_gouge"] <= 0.01 for o in v["by_operation"])
    assert res.report["safety"]["status"] == "ok"
