"""Progress on stderr for every stage of ``millpath run``: reading, indexing, planning
each operation, fitting, interpreting, simulating, the exact verification, rendering,
with counts, each bar ending at count/count (never "0/?" nor more done than its total);
``--quiet`` silences it. ``MILLPATH_PROGRESS=always`` makes the bars visible
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
          "verifying exactly: motions checked", "verifying exactly: material-left peaks",
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


def _counts_true(stderr: str) -> list[str]:
    """Bar lines whose count is unknown ("0/?") or over its total ("327/274")."""
    bad = []
    for line in stderr.splitlines():
        m = re.search(r"\b(\d[\d,]*)/(\d[\d,]*|\?)(?!\S)", line)
        if m and (m.group(2) == "?" or int(m.group(1).replace(",", ""))
                  > int(m.group(2).replace(",", ""))):
            bad.append(line)
    return bad


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
    assert not _counts_true(p.stderr), p.stderr
    assert "waterline levels" not in p.stderr        # a zigzag job has none
    q = _run(job, tmp_path / "quiet", "--quiet")
    assert q.returncode == 0 and q.stderr == "" and q.stdout == ""


@pytest.mark.slow
def test_surface_mould_run_shows_every_stage(tmp_path):
    p = _run(MOULD, tmp_path / "out")
    assert p.returncode == 0, p.stderr[-2000:]
    for label in STAGES:
        assert _done(p.stderr, label), f"{label!r}:\n{p.stderr[-3000:]}"
    assert not _counts_true(p.stderr), p.stderr[-3000:]
    for label in ("reading surface", "indexing", "zigzag pass lines"):
        assert label in p.stderr, f"{label!r}:\n{p.stderr[-3000:]}"
    assert _done(p.stderr, "planning operations")


def test_exact_check_reports_motions_checked_up_to_its_total():
    """verify_exact's progress: at least one update per block of motions, counts that
    never go back nor past their total, the last one total/total."""
    from contextlib import contextmanager

    import numpy as np

    from millpath.model import Stock, Tool
    from millpath.model.motion import Motion
    from millpath.simulate.exact import Reference, verify_exact
    prog = [Motion("feed", k + 1, (k * 0.5 - 10, 0.0, -1.0), (k * 0.5 - 10.5, 0.0, -1.0),
                   feed=500, tool=1) for k in range(40)]
    plate = np.array([[(-12, -5, -2), (12, -5, -2), (12, 5, -2)],
                      [(-12, -5, -2), (12, 5, -2), (-12, 5, -2)]], float)
    calls: list[tuple[int, int]] = []

    class Bar:
        def __init__(self, label, total):
            self.label, self.completed, self.total = label, 0.0, total

        def update(self, *, completed=None, total=None):
            self.completed = self.completed if completed is None else completed
            self.total = self.total if total is None else total
            if "motions" in self.label:
                calls.append((self.completed, self.total))

        def advance(self, n=1.0):
            self.update(completed=self.completed + n)

    class Bars:
        @contextmanager
        def task(self, label, total=None):
            yield Bar(label, total)

    verify_exact(prog, {1: Tool(1, "flat", 2.0)}, Stock(-12, -5, -3, 12, 5, 0),
                 [Reference(plate, "plate")], block=7, progress=Bars())
    assert len(calls) >= 40 // 7 + 1
    done = [d for d, _ in calls]
    assert done == sorted(done) and all(d <= t for d, t in calls)
    assert calls[-1][0] == calls[-1][1] >= len(prog)


def test_bars_end_at_their_count_and_never_past_their_total(monkeypatch, capsys):
    from millpath.progress import Progress
    monkeypatch.setenv("MILLPATH_PROGRESS", "always")
    monkeypatch.setenv("COLUMNS", "120")
    p = Progress(True)
    with p.session():
        with p.task("estimated low", total=274) as t:
            for _ in range(327):
                t.advance()
        with p.task("estimated high", total=10) as t:
            t.update(completed=4)
        with p.task("no estimate") as t:
            t.advance(3)
    err = capsys.readouterr().err
    assert "327/327" in err and "4/4" in err and "3/3" in err, err
    assert not _counts_true(err), err
