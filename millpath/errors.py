"""Errors that reach the user as one line: ``FILE[:LINE]: message``."""

from __future__ import annotations

from pathlib import Path


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
