"""Errors that reach the user as one line: ``FILE[:LINE]: message``."""

from __future__ import annotations

from contextlib import contextmanager
from pathlib import Path
from typing import Iterator


class MillpathError(Exception):
    """A user-facing error about an input file.

    ``where`` names the file (and, when known, the line, entity or key) so the CLI can
    print ``millpath: error: FILE[:LINE]: message`` and exit with status 1.
    """

    def __init__(self, message: str, file: str | Path | None = None, line: int | None = None,
                 entity: str | None = None):
        super().__init__(message)
        self.message = message
        self.file = str(file) if file is not None else None
        self.line = line
        self.entity = entity

    def where(self) -> str:
        parts = []
        if self.file:
            parts.append(self.file)
        if self.line is not None:
            parts.append(str(self.line))
        w = ":".join(parts)
        if self.entity:
            w = f"{w}: {self.entity}" if w else self.entity
        return w

    def __str__(self) -> str:
        w = self.where()
        return f"{w}: {self.message}" if w else self.message


class MillpathWarning(UserWarning):
    """A warning about an input, shown by the command line as one line
    ``millpath: warning: FILE: message``. Issue it with :func:`warn`."""


def warn(message: str, file: str | Path | None = None, line: int | None = None) -> None:
    """Issue a :class:`MillpathWarning` naming ``file`` (and ``line``) like an error."""
    import warnings

    w = MillpathError(message, file, line).__str__()
    warnings.warn(MillpathWarning(w), stacklevel=2)


class JobError(MillpathError):
    """A job file is malformed: unknown key, wrong type, missing value."""


class PlanningError(MillpathError):
    """A strategy cannot plan the operation (tool too big for the pocket, ...)."""


class GeometryError(MillpathError):
    """Bad geometry: self-intersecting polygon, NaN coordinates, degenerate curve."""


#: the most job-file problems the command line prints before "... and N more"
MAX_SHOWN = 20


class JobErrors(JobError):
    """Every problem found in one reading of a job file, each a :class:`JobError`;
    ``str`` gives one line per problem."""

    def __init__(self, errors: list[JobError]):
        first = errors[0]
        super().__init__(first.message, first.file, first.line, first.entity)
        self.errors = list(errors)

    def lines(self, cap: int = MAX_SHOWN) -> list[str]:
        """One line per problem, at most ``cap`` of them, then "... and N more"."""
        out = [str(e) for e in self.errors[:cap]]
        if len(self.errors) > cap:
            out.append(f"... and {len(self.errors) - cap} more")
        return out

    def __str__(self) -> str:
        return "\n".join(str(e) for e in self.errors)


class Problems:
    """JobErrors gathered while reading one job, raised together by :meth:`check`."""

    def __init__(self) -> None:
        self.errors: list[JobError] = []

    def __len__(self) -> int:
        return len(self.errors)

    def add(self, e: JobError) -> None:
        self.errors += e.errors if isinstance(e, JobErrors) else [e]

    @contextmanager
    def gather(self) -> Iterator[None]:
        """Run a block; a JobError it raises is recorded and the reading goes on after
        the block."""
        try:
            yield
        except JobError as e:
            self.add(e)

    def check(self) -> None:
        """Raise :class:`JobErrors` when anything was recorded."""
        if self.errors:
            raise JobErrors(self.errors)
