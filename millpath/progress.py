"""Progress of long steps on stderr (rich), or nothing.

A :class:`Progress` is handed down to the steps that can take more than a second
(through :class:`millpath.plan.base.PlanContext` for planning). Each step opens a task::

    with progress.task("zigzag passes", total=estimate) as t:
        t.advance()                      # one unit done
        t.update(total=new_estimate, info="12,345 points")

Disabled (``Progress(False)``, or stderr not a terminal) every call does nothing, so
tests and pipes see no output.
"""

from __future__ import annotations

import sys
from contextlib import contextmanager
from typing import Iterator


class _Task:
    def __init__(self, bar, task_id, label: str):
        self._bar = bar
        self._id = task_id
        self._label = label

    def advance(self, n: float = 1.0) -> None:
        if self._bar is not None:
            self._bar.advance(self._id, n)

    def update(self, *, completed: float | None = None, total: float | None = None,
               info: str | None = None) -> None:
        if self._bar is None:
            return
        kw = {}
        if completed is not None:
            kw["completed"] = completed
        if total is not None:
            kw["total"] = total
        if info is not None:
            kw["description"] = f"{self._label} [dim]{info}[/]"
        self._bar.update(self._id, **kw)


class Progress:
    """Progress bars on stderr when ``enabled`` and stderr is a terminal."""

    def __init__(self, enabled: bool = True):
        self.enabled = bool(enabled) and sys.stderr.isatty()
        self._bar = None

    @contextmanager
    def task(self, label: str, total: float | None = None) -> Iterator[_Task]:
        """A bar for one step; ``total`` may be an estimate (updated later) or None."""
        if not self.enabled:
            yield _Task(None, None, label)
            return
        from rich.console import Console
        from rich.progress import (BarColumn, MofNCompleteColumn, Progress as Bar,
                                   TextColumn, TimeElapsedColumn, TimeRemainingColumn)
        bar = Bar(TextColumn("{task.description}"), BarColumn(), MofNCompleteColumn(),
                  TimeElapsedColumn(), TimeRemainingColumn(),
                  console=Console(stderr=True), transient=False)
        with bar:
            tid = bar.add_task(label, total=total)
            yield _Task(bar, tid, label)

    def note(self, text: str) -> None:
        """One line (an estimate, a stage done)."""
        if self.enabled:
            from rich.console import Console
            Console(stderr=True).print(text)


#: the silent instance (default of :class:`millpath.plan.base.PlanContext`)
QUIET = Progress(False)
