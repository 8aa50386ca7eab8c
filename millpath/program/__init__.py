"""The program layer: what a posted program is beside its text (which planned move and
operation each of its lines carries out)."""

from millpath.program.linemap import LineMap

__all__ = ["LineMap"]
