"""Progress on stderr for every stage of ``millpath run`` (issue 23.4): reading,
indexing, planning each operation, fitting, interpreting, simulating, rendering, with
counts; ``--quiet`` silences it. ``MILLPATH_PROGRESS=always`` makes the bars visible
on the captured (non-terminal) stderr."""

from __future__ import annotations

import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
MOULD = ROOT / "millpath" / "examples" / "surface-mould" / "job.toml"

#: stage label -> how many times it must show a completed count "n/n"
STAGES = ("reading the job", "planning operations", "fitting and posting",
          "interpreting the program", "simulating: motions swept",
          "rendering pictures and viewer")


def _run(job: Path, out: Path, *extra: str) -> subprocess.CompletedProcess:
    env = dict(os.environ, MILLPATH_PROGRESS="always", COLUMNS="160")
    return subprocess.run([sys.executable, "-m", "millpath.cli.main", "run", str(job),
                           "-o", str(out), *extra], capture_output=True, text=True,
                          env=env, timeout=1800)


def _done(stderr: str, label: str) -> bool:
    """A bar line for ``label`` that shows a finished count (n/n with n > 0)."""
    for line in stderr.splitlines():
        if label in line:
            m = re.search(r"\b(\d[\d,]*)/(\d[\d,]*)\b", line)
            if m and m.group(1) == m.group(2) and m.group(1) != "0":
                return True
    return False


def _small_job(tmp_path: Path) -> Path:
    job = tmp_path / "job.toml"
    job.write_text('units = "mm"\n[stock]\nbox = [0, 0, 0, 60, 40, 11]\n[[tools]]\n'
                   'number = 1\ntype = "ball"\ndiameter = 6\n[[operations]]\n'
                   'type = "surface-finish"\ntool = 1\n'
                   'surface = { box = [0, 0, 60, 40], heights = [[10, 11, 10], '
                   '[11, 8, 11], [10, 11, 10]] }\ntolerance = 0.01\nscallop = 0.2\n'
                   'feed = 1500\nspindle = 12000\n')
    return job


def test_every_stage_of_a_small_run_shows_progress_and_quiet_silences_it(tmp_path):
    job = _small_job(tmp_path)
    p = _run(job, tmp_path / "out")
    assert p.returncode == 0, p.stderr
    for label in STAGES + ("reading surface", "indexing", "zigzag pass lines"):
        assert label in p.stderr, f"no progress for {label!r}:\n{p.stderr}"
    for label in STAGES:
        assert _done(p.stderr, label), f"{label!r} never finished:\n{p.stderr}"
    q = _run(job, tmp_path / "quiet", "--quiet")
    assert q.returncode == 0 and q.stderr == "" and q.stdout == ""


@pytest.mark.slow
def test_surface_mould_run_shows_every_stage(tmp_path):
    p = _run(MOULD, tmp_path / "out")
    assert p.returncode == 0, p.stderr[-2000:]
    for label in STAGES:
        assert _done(p.stderr, label), f"{label!r}:\n{p.stderr[-3000:]}"
    for label in ("reading surface", "indexing", "zigzag pass lines"):
        assert label in p.stderr, f"{label!r}:\n{p.stderr[-3000:]}"
    assert _done(p.stderr, "planning operations")
