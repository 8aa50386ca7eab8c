"""The reader's error: a G-code error on one block, worded as LinuxCNC's rs274."""

from __future__ import annotations


class GCodeError(Exception):
    """Raised while reading or executing a block; the caller adds the line."""

    def __init__(self, message: str):
        super().__init__(message)
        self.message = message
