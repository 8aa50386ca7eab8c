"""Progress of long steps on stderr (rich), or nothing.

A :class:`Progress` is handed down to the steps that can take more than a second
(through :class:`millpath.plan.base.PlanContext` for planning, to the simulator for the
sweep). Each step opens a task::

    with progress.task("zigzag passes", total=estimate) as t:
        t.advance()                      # one unit done
        t.update(total=new_estimate, info="12,345 points")

All tasks open at the same time share one display (one line each, with counts, elapsed
time and a time estimate); :meth:`Progress.session` keeps the display open across
several steps (``millpath run`` holds one for the whole run).

While a display is open, numba compiling a kernel (the first run after an install or an
upgrade: the compiled kernels are cached, see :mod:`millpath`) shows as a task of its
own, "compiling kernels (once per install)", with the count and the kernel's name.

Disabled (``Progress(False)``, or stderr not a terminal) every call does nothing, so
tests and pipes see no output; ``MILLPATH_PROGRESS=always`` in the environment shows
the bars on a non-terminal stderr too (their final state, printed when the display
closes).
"""

from __future__ import annotations

import os
import sys
import threading
from contextlib import contextmanager
from typing import Iterator


class _Task:
    """One bar. Its count never shows more done than the total: an estimate found low
    is raised to the count; a task that ends normally ends at count/count (the work it
    did is all there was)."""

    def __init__(self, bar, task_id, label: str, total: float | None):
        self._bar = bar
        self._id = task_id
        self._label = label
        self.completed = 0.0
        self.total = total

    def advance(self, n: float = 1.0) -> None:
        self.update(completed=self.completed + n)

    def update(self, *, completed: float | None = None, total: float | None = None,
               info: str | None = None) -> None:
        if self._bar is None:
            return
        if completed is not None:
            self.completed = completed
        if total is not None:
            self.total = total
        if self.total is not None and self.completed > self.total:
            self.total = self.completed
        kw = {"completed": self.completed, "total": self.total}
        if info is not None:
            kw["description"] = f"{self._label} [dim]{info}[/]"
        self._bar.update(self._id, **kw)

    def finish(self) -> None:
        """The true final state: everything counted was the whole task."""
        if self._bar is not None:
            self._bar.update(self._id, completed=self.completed, total=self.completed)


class _Compiles:
    """A numba event listener counting kernel compiles into a task of ``bar``."""

    LABEL = "compiling kernels (once per install)"

    def __init__(self, bar):
        from numba.core.event import Listener

        outer = self

        class _L(Listener):
            def on_start(self, event):
                outer.start(event)

            def on_end(self, event):
                outer.end(event)

        self.listener = _L()
        self.bar = bar
        self.task = None
        self.count = 0
        self.lock = threading.Lock()

    def start(self, event) -> None:
        d = event.data.get("dispatcher") if isinstance(event.data, dict) else None
        name = getattr(getattr(d, "py_func", None), "__qualname__", "")
        with self.lock:
            if self.task is None:
                self.task = self.bar.add_task(self.LABEL, total=None)
            self.bar.update(self.task, description=f"{self.LABEL} [dim]{name}[/]")

    def end(self, event) -> None:
        with self.lock:
            self.count += 1
            self.bar.update(self.task, completed=self.count)

    def close(self) -> None:
        with self.lock:
            if self.task is not None:
                self.bar.update(self.task, description=self.LABEL, completed=self.count,
                                total=self.count)


class Progress:
    """Progress bars on stderr when ``enabled`` and stderr is a terminal (or
    ``MILLPATH_PROGRESS=always``)."""

    def __init__(self, enabled: bool = True):
        forced = os.environ.get("MILLPATH_PROGRESS", "") == "always"
        self.enabled = bool(enabled) and (forced or sys.stderr.isatty())
        self._bar = None
        self._depth = 0
        self._compiles: _Compiles | None = None

    @contextmanager
    def session(self) -> Iterator["Progress"]:
        """Keep one display open for every task started inside."""
        if not self.enabled:
            yield self
            return
        self._open()
        try:
            yield self
        finally:
            self._close()

    @contextmanager
    def task(self, label: str, total: float | None = None) -> Iterator[_Task]:
        """A bar for one step; ``total`` may be an estimate (updated later) or None.
        When the step ends normally the bar shows count/count."""
        if not self.enabled:
            yield _Task(None, None, label, total)
            return
        bar = self._open()
        tid = bar.add_task(label, total=total)
        try:
            task = _Task(bar, tid, label, total)
            yield task
            task.finish()
        finally:
            self._close()

    def note(self, text: str) -> None:
        """One line (an estimate, a stage done), above the bars when they are shown."""
        if not self.enabled:
            return
        if self._bar is not None:
            self._bar.console.print(text)
        else:
            from rich.console import Console
            Console(stderr=True).print(text)

    def _open(self):
        if self._bar is None:
            from rich.console import Console
            from rich.progress import (BarColumn, MofNCompleteColumn, Progress as Bar,
                                       TextColumn, TimeElapsedColumn, TimeRemainingColumn)
            self._bar = Bar(TextColumn("{task.description}"), BarColumn(),
                            MofNCompleteColumn(), TimeElapsedColumn(), TimeRemainingColumn(),
                            console=Console(stderr=True), transient=False)
            self._bar.start()
            self._compiles = _listen(self._bar)
        self._depth += 1
        return self._bar

    def _close(self) -> None:
        self._depth -= 1
        if self._depth == 0 and self._bar is not None:
            bar, self._bar = self._bar, None
            if self._compiles is not None:
                from numba.core.event import unregister
                unregister("numba:compile", self._compiles.listener)
                self._compiles.close()
                self._compiles = None
            bar.stop()


def _listen(bar) -> _Compiles | None:
    """A compile counter registered with numba (None if numba is not importable)."""
    try:
        from numba.core.event import register
    except ImportError:                 # pragma: no cover - numba is a dependency
        return None
    c = _Compiles(bar)
    register("numba:compile", c.listener)
    return c


#: the silent instance (default of :class:`millpath.plan.base.PlanContext`)
QUIET = Progress(False)
