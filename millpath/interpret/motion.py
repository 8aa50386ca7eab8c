"""The interpreter's result: the motion of a program (:class:`millpath.model.motion.Motion`),
or of the part before the failing block, with the error."""

from __future__ import annotations

from dataclasses import dataclass, field

from millpath.model.motion import Motion, Vec3

__all__ = ["InterpretResult", "InterpreterErrorInfo", "Motion", "Vec3"]


@dataclass
class InterpretResult:
    """Motion of a whole program, or of the part before the failing block."""

    units: str                      # "mm" | "inch": units in force at the end
    motions: list[Motion] = field(default_factory=list)
    error: "InterpreterErrorInfo | None" = None


@dataclass
class InterpreterErrorInfo:
    line: int
    message: str
