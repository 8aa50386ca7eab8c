"""The program layer: a posted program as a value (its text in a control's dialect, the
moves it carries out, line by line, and what the dialect made the post rewrite)."""

from millpath.program.linemap import LineMap
from millpath.program.program import Program, make_program

__all__ = ["LineMap", "Program", "make_program"]
