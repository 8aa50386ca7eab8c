"""``millpath warm``: compile millpath's numba kernels now, once per install.

millpath's hot loops are numba kernels, compiled on their first call and cached per
install (see :mod:`millpath`): the first job after an install or an upgrade spends
most of its time compiling. ``millpath warm`` does it ahead, visibly, on two processes:
the examples of ``millpath demo`` planned and posted, and one of them run through the
proof, into a temporary folder, which calls every kernel a job calls; it leaves a mark
in the cache folder so that a second ``millpath warm`` returns at once. ``millpath
demo`` does the same before its first example.

Two compiles at once would do the same work twice: ``warm`` holds a lock in the cache
folder while it runs, and ``millpath run`` / ``millpath demo`` started meanwhile wait for
it (saying so) and then find the kernels compiled.
"""

from __future__ import annotations

import os
import tempfile
import time
from contextlib import contextmanager
from pathlib import Path
from typing import Iterator

import click

LOCK = "warm.lock"
DONE = "warm.done"


def cache_dir() -> Path | None:
    """The install's kernel cache folder (None: numba compiles in memory)."""
    d = os.environ.get("NUMBA_CACHE_DIR")
    return Path(d) if d else None


@contextmanager
def _locked(path: Path, exclusive: bool, waiting: str | None = None) -> Iterator[None]:
    import fcntl
    with open(path, "a+") as fh:
        try:
            fcntl.flock(fh, (fcntl.LOCK_EX if exclusive else fcntl.LOCK_SH) | fcntl.LOCK_NB)
        except BlockingIOError:
            if waiting:
                click.echo(waiting, err=True)
            fcntl.flock(fh, fcntl.LOCK_EX if exclusive else fcntl.LOCK_SH)
        try:
            yield
        finally:
            fcntl.flock(fh, fcntl.LOCK_UN)


def wait_for_warm() -> None:
    """Return once no ``millpath warm`` of this install is compiling."""
    d = cache_dir()
    if d is None or not (d / LOCK).exists() or (d / DONE).exists():
        return
    with _locked(d / LOCK, False, "millpath: waiting for `millpath warm` (compiling "
                 "kernels, once per install) to finish"):
        pass


def _counted(fn, *args) -> tuple[int, float]:
    """Call ``fn(*args)``; the number of numba compiles it made and its wall seconds."""
    from numba.core.event import Listener, register, unregister

    class Count(Listener):
        n = 0

        def on_start(self, event):
            pass

        def on_end(self, event):
            self.n += 1

    counter = Count()
    t0 = time.perf_counter()
    register("numba:compile", counter)
    try:
        fn(*args)
    finally:
        unregister("numba:compile", counter)
    return counter.n, time.perf_counter() - t0


def _plan(jobs: list[str]) -> None:
    """Plan, fit and post ``jobs``: the planners' kernels compiled."""
    from millpath.job.jobfile import load_job
    from millpath.pipeline import fit_job, plan_job, post_job
    for path in jobs:
        job = load_job(path)
        tp, _, stock = plan_job(job)
        post_job(job, fit_job(job, tp), stock)


def _prove(job: str, out: str) -> None:
    """``millpath run`` of ``job`` without pictures: the proof's kernels compiled."""
    from millpath.pipeline import run_job
    run_job(job, out, progress=False, pictures=False)


def compile_kernels(echo=click.echo) -> str:
    """Compile every kernel the examples of ``millpath demo`` call, unless this install
    has done it already; returns what was done. One compile per install: the exclusive
    lock makes a second caller wait and then find the kernels compiled.

    The work is split over two processes when the machine has two cores: one runs the
    proof (features-plate, no pictures), the other plans and posts the other examples
    (the planners' kernels); numba's cache is per function, so both fill it at once."""
    import multiprocessing as mp
    from concurrent.futures import ProcessPoolExecutor
    from millpath.cli.demo import chosen_jobs
    from millpath.errors import MillpathError
    d = cache_dir()
    if d is None:
        raise MillpathError("no writable kernel cache folder (set MILLPATH_CACHE_DIR): "
                            "kernels are compiled in each run")
    if (d / DONE).exists():
        return f"kernels already compiled for this install ({d})"
    t0 = time.perf_counter()
    with _locked(d / LOCK, True, "millpath: another `millpath warm` is compiling; "
                 "waiting for it"):
        if (d / DONE).exists():
            return f"kernels already compiled for this install ({d})"
        jobs = [str(j) for j in chosen_jobs(None, False)]
        proof = next((j for j in jobs if Path(j).parent.name == "features-plate"), jobs[0])
        plans = [j for j in jobs if j != proof]
        echo("compiling kernels, once per install (about two minutes on 2 cores) ...")
        with tempfile.TemporaryDirectory(prefix="millpath-warm-") as tmp:
            out = str(Path(tmp) / "proof")
            if (os.cpu_count() or 1) >= 2:
                with ProcessPoolExecutor(2, mp_context=mp.get_context("spawn")) as ex:
                    a = ex.submit(_counted, _prove, proof, out)
                    b = ex.submit(_counted, _plan, plans)
                    (na, ta), (nb, tb) = a.result(), b.result()
            else:
                (na, ta), (nb, tb) = _counted(_prove, proof, out), _counted(_plan, plans)
        n = na + nb
        seconds = time.perf_counter() - t0
        (d / DONE).write_text(f"{n} compiles in {seconds:.0f} s (the proof: {na} in "
                              f"{ta:.0f} s; the planners: {nb} in {tb:.0f} s)\n")
    return f"compiled {n} kernels in {seconds:.0f} s; cached in {d}"


@click.command()
def command() -> None:
    """Compile millpath's kernels now (once per install), so the first job starts
    quickly."""
    click.echo(compile_kernels(lambda m: click.echo(m, err=True)))
