"""The first run after an install: kernels run on threads (the same results as one
thread), compiling shows in the progress display, ``millpath warm`` compiles once and
makes a concurrent run wait, and the demo runs one example of each family."""

from __future__ import annotations

import subprocess
import sys
import threading
import time

import numba
import numpy as np
import pytest
from click.testing import CliRunner
from numba import njit

from millpath.cli.demo import SHORT, chosen_jobs, example_jobs
from millpath.cli.main import cli
from millpath.threads import over_range, per_thread


@njit(nogil=True)
def _squares(lo, hi, x, out):
    for i in range(lo, hi):
        out[i] = x[i] * x[i]


@njit(nogil=True)
def _fail_at(lo, hi, bad, out):
    for i in range(lo, hi):
        if i == bad:
            raise ValueError("bad item")
        out[i] = 1.0


@pytest.mark.parametrize("n", [0, 1, 7, 1000, 100_003])
def test_chunks_cover_the_range_once(n):
    x = np.arange(n, dtype=float)
    out = np.full(n, -1.0)
    over_range(_squares, n, x, out)
    assert np.array_equal(out, x * x)


def test_one_thread_runs_in_the_caller():
    threads = numba.get_num_threads()
    numba.set_num_threads(1)
    seen = []
    try:
        over_range(lambda lo, hi: seen.append((lo, hi, threading.current_thread())), 50)
    finally:
        numba.set_num_threads(threads)
    assert seen == [(0, 50, threading.current_thread())]


def test_an_error_in_a_chunk_is_raised_in_the_caller():
    out = np.zeros(10_000)
    with pytest.raises(ValueError, match="bad item"):
        over_range(_fail_at, len(out), 7_777, out)


def test_per_thread_calls_each_thread_once():
    seen = []
    per_thread(lambda t, n: seen.append((t, n)))
    n = numba.get_num_threads()
    assert sorted(seen) == [(t, n) for t in range(n)]


def test_compiling_shows_in_the_progress_display(monkeypatch, capsys):
    from millpath.progress import Progress
    monkeypatch.setenv("MILLPATH_PROGRESS", "always")

    @njit
    def fresh(a):                       # not cached: compiled on its first call
        return a + 1

    p = Progress(True)
    with p.session():
        with p.task("a step", total=1) as t:
            assert fresh(1) == 2
            t.advance()
    err = capsys.readouterr().err
    assert "compiling kernels (once per install)" in err and "a step" in err


def test_demo_runs_one_example_per_family_by_default():
    names = {j.parent.name for j in example_jobs()}
    assert set(SHORT) <= names
    assert [j.parent.name for j in chosen_jobs(None, False)] == sorted(SHORT)
    assert len(chosen_jobs(None, True)) == len(names)
    assert [j.parent.name for j in chosen_jobs("surface-cav", False)] == ["surface-cavity"]


def test_warm_compiles_once_and_marks_the_cache(monkeypatch, tmp_path):
    """The proof's and the planners' tasks each run once, their compiles are counted and
    the cache marked; a second warm does nothing. (The tasks are stand-ins compiling one
    small kernel each, run in this process: the real split over two processes runs in
    the README's demo command, which CI runs first.)"""
    import millpath.cli.demo as demo
    import millpath.cli.warm as warm
    monkeypatch.setenv("NUMBA_CACHE_DIR", str(tmp_path))
    one = [j for j in example_jobs() if j.parent.name == "pocket-casestudy-line"]
    monkeypatch.setattr(demo, "chosen_jobs", lambda only, every: one)
    monkeypatch.setattr(warm.os, "cpu_count", lambda: 1)
    calls = []

    def task(name):
        def run(*args):
            calls.append((name, args))
            njit(lambda x: x + 1)(1)
        return run
    monkeypatch.setattr(warm, "_prove", task("prove"))
    monkeypatch.setattr(warm, "_plan", task("plan"))
    r = CliRunner().invoke(cli, ["warm"])
    assert r.exit_code == 0, r.output
    assert "compiled 2 kernels" in r.output and (tmp_path / "warm.done").exists()
    assert [c[0] for c in calls] == ["prove", "plan"]
    assert calls[0][1][0] == str(one[0]) and calls[1][1] == ([],)
    r = CliRunner().invoke(cli, ["warm"])
    assert r.exit_code == 0 and "already compiled" in r.output and len(calls) == 2


def test_a_run_waits_for_a_warm_in_progress(monkeypatch, tmp_path, capsys):
    from millpath.cli.warm import LOCK, wait_for_warm
    monkeypatch.setenv("NUMBA_CACHE_DIR", str(tmp_path))
    holder = subprocess.Popen(
        [sys.executable, "-c", "import fcntl, sys, time\n"
         f"f = open({str(tmp_path / LOCK)!r}, 'a+'); fcntl.flock(f, fcntl.LOCK_EX)\n"
         "print('locked', flush=True); time.sleep(1.5)"], stdout=subprocess.PIPE, text=True)
    assert holder.stdout.readline().strip() == "locked"
    t0 = time.perf_counter()
    wait_for_warm()
    waited = time.perf_counter() - t0
    holder.wait()
    assert waited > 0.5
    assert "waiting for `millpath warm`" in capsys.readouterr().err
