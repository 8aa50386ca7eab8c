"""``millpath warm``: compile millpath's numba kernels now, once per install.

millpath's hot loops are numba kernels, compiled on their first call and cached per
install (see :mod:`millpath`): the first job after an install or an upgrade spends
most of its time compiling. ``millpath warm`` does it ahead, visibly: it runs the
examples of ``millpath demo`` (one of each family, no pictures) into a temporary folder,
which calls every kernel a job calls, and leaves a mark in the cache folder so that a
second ``millpath warm`` returns at once.

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


@click.command()
def command() -> None:
    """Compile millpath's kernels now (once per install), so the first job starts
    quickly."""
    from millpath.cli.demo import chosen_jobs
    from millpath.errors import MillpathError
    from millpath.pipeline import run_job
    d = cache_dir()
    if d is None:
        raise MillpathError("no writable kernel cache folder (set MILLPATH_CACHE_DIR): "
                            "kernels are compiled in each run")
    if (d / DONE).exists():
        click.echo(f"kernels already compiled for this install ({d})")
        return
    from numba.core.event import Listener, register, unregister

    class _Count(Listener):
        def __init__(self):
            self.n = 0

        def on_start(self, event):
            pass

        def on_end(self, event):
            self.n += 1

    counter = _Count()
    t0 = time.perf_counter()
    with _locked(d / LOCK, True, "millpath: another `millpath warm` is compiling; "
                 "waiting for it"):
        if (d / DONE).exists():
            click.echo(f"kernels already compiled for this install ({d})")
            return
        register("numba:compile", counter)
        try:
            with tempfile.TemporaryDirectory(prefix="millpath-warm-") as tmp:
                for job in chosen_jobs(None, False):
                    click.echo(f"compiling with {job.parent.name} ...", err=True)
                    run_job(job, Path(tmp) / job.parent.name, progress=True,
                            pictures=False)
        finally:
            unregister("numba:compile", counter)
        seconds = time.perf_counter() - t0
        (d / DONE).write_text(f"{counter.n} compiles in {seconds:.0f} s\n")
    click.echo(f"compiled {counter.n} kernels in {seconds:.0f} s; cached in {d}")
