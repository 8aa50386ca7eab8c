"""Azmi et al. (seeds/002) Example 2 as bundled in ``features-example-2``: the paper's
dimensions come back from ``millpath features --json``, and the machined volume is the
paper's slot and holes (an analytic volume, not the planner's own design)."""

from __future__ import annotations

import json
import math
from pathlib import Path

import pytest
from click.testing import CliRunner

from millpath.cli.main import cli
from millpath.report.document import plan_sections

EXAMPLE = Path(__file__).resolve().parents[2] / "millpath" / "examples" / "features-example-2"

# the paper's Example 2 (Figure 7, appendix "NC codes for Example2"); Y shifted by +150
STOCK = (300.0, 150.0, 25.0)
HOLES = [(18.7, 75.0), (281.2, 75.0)]
HOLE_D, HOLE_DEPTH = 16.6, 25.0
SLOT_W, SLOT_DEPTH, SLOT_LEN, SLOT_Y = 25.0, 12.5, 300.0, 150.0 - 27.5


def _features_json():
    r = CliRunner().invoke(cli, ["features", str(EXAMPLE / "part.stp"), "--json"])
    assert r.exit_code == 0, r.output
    return json.loads(r.output)


def test_features_json_gives_the_papers_dimensions():
    d = _features_json()
    s = d["stock"]
    assert (s["length"], s["width"], s["height"]) == STOCK
    holes = [f for f in d["features"] if f["type"] == "ROUND_HOLE"]
    slots = [f for f in d["features"] if f["type"] == "SLOT"]
    assert len(holes) == 2 and len(slots) == 1
    got = sorted((f["placement"]["origin"][0], f["placement"]["origin"][1]) for f in holes)
    assert [c for p in got for c in p] == pytest.approx([c for p in HOLES for c in p], abs=1e-9)
    for f in holes:
        comp = {c["type"]: c for c in f["components"]}
        assert comp["CIRCULAR_CLOSED_PROFILE"]["params"]["diameter"] == HOLE_D
        assert comp["PATH_FEATURE_COMPONENT"]["params"]["distance"] == HOLE_DEPTH
    comp = {c["type"]: c for c in slots[0]["components"]}
    prof = comp["SQUARE_U_PROFILE"]["params"]
    assert (prof["width"], prof["depth"]) == (SLOT_W, SLOT_DEPTH)
    assert comp["PATH_FEATURE_COMPONENT"]["params"]["distance"] == SLOT_LEN
    assert slots[0]["placement"]["origin"][1] == SLOT_Y


def test_make_part_writes_the_bundled_file():
    import importlib.util
    spec = importlib.util.spec_from_file_location("make_part", EXAMPLE / "make_part.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    assert mod.build() == (EXAMPLE / "part.stp").read_text()


def test_pipeline_machines_the_papers_volume(tmp_path, rs274):
    from millpath.pipeline import run_job
    from support.rs274 import run_rs274
    res = run_job(EXAMPLE / "job.toml", tmp_path)
    rep = res.report
    assert rep["reference"]["stock"] == list(STOCK)
    (feats,) = plan_sections(rep, "features")
    assert feats["unmachinable"] == []
    v = rep["verification"]
    volume = SLOT_W * SLOT_DEPTH * SLOT_LEN + 2 * math.pi * (HOLE_D / 2) ** 2 * HOLE_DEPTH
    assert v["removed_volume"] == pytest.approx(volume, rel=0.01)   # 0.5 mm Z-map cells
    assert v["max_gouge"] <= 1e-6 and v["rapids_through_material"] == 0
    r = run_rs274(res.program, res.job.tools, table_units="mm")
    assert r.ok, (r.error, r.error_line)
