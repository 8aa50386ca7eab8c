"""The complete job example of the documentation (docs/concepts.md, "Job files") runs as
written: it is taken from the page itself, so the page cannot drift from what millpath
accepts."""

from __future__ import annotations

import json
import re
from pathlib import Path

from millpath.pipeline import run_job

PAGE = Path(__file__).resolve().parents[2] / "docs" / "concepts.md"


def test_documented_job_example_runs(tmp_path):
    text = PAGE.read_text()
    section = text[text.index("## Job files"):]
    job = re.search(r"```toml\n(.*?)```", section, re.S).group(1)
    (tmp_path / "job.toml").write_text(job)
    res = run_job(tmp_path / "job.toml", tmp_path / "out")
    report = json.loads((tmp_path / "out" / "report.json").read_text())
    assert (tmp_path / "out" / "program.ngc").is_file()
    v = report["verification"]
    assert v["rapids_through_material"] == 0 and v["holder_contacts"] == 0
    assert v["removed_volume"] > 0 and res.toolpath.moves
