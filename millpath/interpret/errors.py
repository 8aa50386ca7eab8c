"""The interpreter's error: a G-code error on one block, as LinuxCNC reports it."""

from __future__ import annotations

from millpath.errors import MillpathError
from millpath.gcode.errors import GCodeError

__all__ = ["InterpreterError", "GCodeError"]


class InterpreterError(MillpathError):
    """A program error on source line ``line`` (1-based).

    ``message`` follows the wording of LinuxCNC's rs274 where practical; ``motions``
    holds the motion interpreted before the failing block.
    """

    def __init__(self, line: int, message: str, motions=None, file=None):
        super().__init__(message, file, line)
        self.motions = motions if motions is not None else []

