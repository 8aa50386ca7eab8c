"""docs/jobs.md and ``millpath keys`` come from the schemas the job loader validates with:
the checked-in file is what the generator writes, every section of the job
file and every operation type is in it, and every key the loader accepts is listed."""

from __future__ import annotations

from pathlib import Path

from click.testing import CliRunner

from millpath.cli.main import cli
from millpath.io.toollib import TOOL
from millpath.job import jobfile
from millpath.job.keys import markdown, sections
from millpath.plan.registry import STRATEGIES, strategy

DOC = Path(__file__).resolve().parents[2] / "docs" / "jobs.md"


def test_docs_jobs_md_is_current():
    assert DOC.read_text() == markdown(), \
        "docs/jobs.md is stale: run `millpath keys --markdown > docs/jobs.md`"


def test_every_accepted_key_is_documented():
    listed = {s.title: {k.name for k in s.keys} for s in sections()}
    for name in STRATEGIES:
        assert listed[f'[[operations]] type = "{name}"'] == set(strategy(name).PARAMS)
    assert listed["[[tools]]"] == set(TOOL)
    assert listed["[stock]"] == set(jobfile.STOCK)
    assert listed["[limits]"] == set(jobfile.LIMITS)
    assert listed["[post]"] == set(jobfile.POST)
    top = set(jobfile.TOP) - {"stock", "machine", "simulation", "limits", "post", "tools",
                              "operations"}
    assert listed["top level"] == top
    for s in sections():
        for k in s.keys:          # every section and every operation key has a meaning
            assert k.doc, f"{s.title} {k.name} has no description"


def test_keys_command_lists_one_type_and_refuses_an_unknown_one():
    r = CliRunner().invoke(cli, ["keys", "die-cavity"], terminal_width=200)
    assert r.exit_code == 0 and "stepdown" in r.output and "[stock]" not in r.output
    r = CliRunner().invoke(cli, ["keys", "no-such-op"])
    assert r.exit_code == 1 and r.output.startswith("millpath: error: unknown operation type")
