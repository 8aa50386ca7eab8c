"""The bundled ``features-*`` examples: valid jobs whose programs LinuxCNC accepts and
whose simulation removes exactly the features."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from millpath.job.jobfile import load_job
from millpath.plan.base import PlanContext
from millpath.plan.registry import strategy
from millpath.report.document import plan_sections

EXAMPLES = Path(__file__).resolve().parents[2] / "millpath" / "examples"
NAMES = sorted(p.name for p in EXAMPLES.glob("features-*") if (p / "job.toml").exists())


def plan_example(name: str):
    job = load_job(EXAMPLES / name / "job.toml")
    assert job.stock is None                      # the stock comes from the STEP file
    ctx = PlanContext(units=job.units, stock=None, machine=job.machine, tools=job.tools,
                      base_dir=job.base_dir, job_file=job.path)
    (op_type, params), = job.operations
    assert op_type == "features" and "tool" not in {k for k, v in params.items() if v}
    return job, strategy(op_type).plan(ctx, params)


def test_there_are_five_examples():
    assert NAMES == ["features-example-2", "features-holes-slot", "features-inch", "features-plate",
                     "features-pockets"]


@pytest.mark.parametrize("name", NAMES)
def test_example_is_accepted_by_rs274_and_cuts_the_features(name, rs274):
    from millpath.post.writer import post
    from millpath.simulate import simulate_toolpath
    from support.rs274 import run_rs274

    job, r = plan_example(name)
    rep = r.report["features"]
    assert rep["unmachinable"] == [] and rep["planned"]
    res = run_rs274(post(r.toolpath, job.tools, title=name), job.tools, table_units=job.units)
    assert res.ok, (res.error, res.error_line)
    stock = r.stock
    cell = job.simulation["resolution"]
    sim = simulate_toolpath(r.toolpath, job.tools, stock, resolution=cell, design=r.design)
    expected = r.design.volume_on_grid(sim.zmap.xs(), sim.zmap.ys(), sim.zmap.cell_area,
                                          sim.zmap.zmin)
    assert sim.removed_volume == pytest.approx(expected, rel=0.01)
    assert sim.max_gouge <= 1e-6
    assert sim.rapids_through_material == 0 and sim.holder_contacts == 0
    json.dumps(rep)                               # the report section is JSON


def test_pipeline_runs_an_example_and_merges_the_features_report(tmp_path, rs274):
    from millpath.pipeline import run_job
    run_job(EXAMPLES / "features-plate" / "job.toml", tmp_path)
    rep = json.loads((tmp_path / "report.json").read_text())
    assert rep["stock"] == [0.0, 0.0, 0.0, 225.0, 100.0, 12.5]     # from the STEP file
    (feats,) = plan_sections(rep, "features")           # namespaced per operation
    assert [p["strategy"] for p in feats["planned"]] == ["helical"] * 3
    v = rep["verification"]
    assert v["max_gouge"] <= 1e-6 and v["rapids_through_material"] == 0
    assert (tmp_path / "program.ngc").read_text().rstrip().endswith("M2")
