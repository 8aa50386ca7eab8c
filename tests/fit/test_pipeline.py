"""`millpath run` with fit = "arcs+cubics": the fitted program passes the pipeline's
interpretation round trip and simulation without gouges."""

from __future__ import annotations

import re
import shutil
from pathlib import Path

import pytest

EXAMPLE = Path(__file__).resolve().parents[2] / "millpath" / "examples" / "features-pockets"


def test_run_with_fitting_writes_a_shorter_verified_program(tmp_path):
    if not (EXAMPLE / "job.toml").is_file():
        pytest.skip("the features-pockets example is not in this checkout")
    from millpath.pipeline import run_job
    for f in EXAMPLE.iterdir():
        shutil.copy(f, tmp_path / f.name)
    job = (tmp_path / "job.toml").read_text()
    from millpath.job.jobfile import load_job
    from millpath.pipeline import plan_job, post_job
    planned = load_job(tmp_path / "job.toml")
    tp, _, stock = plan_job(planned)
    as_planned = post_job(planned, tp, stock).text.count("\n")     # every planned point
    plain = run_job(tmp_path / "job.toml", tmp_path / "plain")     # collinear points merged
    (tmp_path / "job.toml").write_text(re.sub(r'(?m)^name = (.*)$',
                                              r'name = \1\nfit = "arcs+cubics"', job, count=1))
    fitted = run_job(tmp_path / "job.toml", tmp_path / "fitted")
    assert fitted.report["fit"]["mode"] == "arcs+cubics"
    # the fit's tolerance, read by the proof to its stated accuracy (its figure is a
    # bound: curves' chords carry their distance from the curve)
    ver = fitted.report["verification"]
    assert ver["max_gouge"] <= 0.005 + ver["accuracy"]
    assert fitted.report["lines"] < as_planned * 0.6
    assert fitted.report["lines"] < plain.report["lines"] < as_planned
    assert re.search(r"(?m)^(G1[789] )?G[235] ", fitted.program)
