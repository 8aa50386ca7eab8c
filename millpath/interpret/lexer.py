"""The interpreter's reader: :mod:`millpath.gcode.lexer` (one grammar for millpath's
interpreter and ``millpath fit``), under its old name."""

from __future__ import annotations

from millpath.gcode.lexer import (AXES, G_GROUP, INT_MIN, M_GROUP, MAX_LINE, MAX_NESTING,
                                  MAX_PARAM, TOLERANCE_EQUAL, Block, Reader, c_int, finite,
                                  normalize, read_block)

__all__ = ["AXES", "G_GROUP", "INT_MIN", "M_GROUP", "MAX_LINE", "MAX_NESTING", "MAX_PARAM",
           "TOLERANCE_EQUAL", "Block", "Reader", "c_int", "finite", "normalize", "read_block"]
