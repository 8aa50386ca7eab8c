"""RS274NGC interpreter: a program -> the motion a LinuxCNC 2.9 machine would make.

``interpret(program, tools=None, *, machine_units="inch") -> list[Motion]`` (a
:class:`MotionList`, a read-only sequence of :class:`Motion`) raises
:class:`InterpreterError` (``.line``, ``.message``, ``.motions``) on a G-code error;
``run(...) -> InterpretResult`` never raises for G-code errors.

``program`` is program text or a :class:`pathlib.Path`. ``tools`` is a LinuxCNC tool
table path, a list of ``ToolEntry`` or a dict of millpath ``Tool``; its values are in
``machine_units`` (rs274 reads tool tables as inches). Programs start in mm, G17, G90,
G94, G40, G49, G99 and G80 like rs274. Coordinates are program coordinates in program
units; see :mod:`millpath.interpret.motion`. O-word subroutines and loops within the
program are run (:mod:`millpath.interpret.oword`). A, B and C words are accepted as
rs274 does, but motion records only X, Y and Z. ``dialect`` (a
:class:`~millpath.model.dialect.Dialect` or its name; LinuxCNC by default) reads the
program as that control does (:mod:`millpath.interpret.dialect`).
"""

from __future__ import annotations

from pathlib import Path

from millpath.interpret.dialect import as_linuxcnc
from millpath.interpret.errors import InterpreterError
from millpath.interpret.motion import InterpretResult, InterpreterErrorInfo, Motion
from millpath.interpret.runner import run_program
from millpath.interpret.store import MotionList
from millpath.interpret.tools import load_tools
from millpath.model.dialect import LINUXCNC, Dialect, dialect as dialect_named

__all__ = ["interpret", "run", "InterpreterError", "Motion", "MotionList", "InterpretResult"]


def _text(program: str | Path) -> tuple[str, str | None]:
    if isinstance(program, Path):
        return program.read_text(encoding="utf-8", errors="replace"), str(program)
    return program, None


def _read(text: str, tools, d: Dialect | str | None) -> tuple[str, tuple[int, str] | None]:
    """The program as LinuxCNC blocks (see :mod:`millpath.interpret.dialect`)."""
    if d is None:
        return text, None
    d = dialect_named(d) if isinstance(d, str) else d
    return as_linuxcnc(text, d, () if d is LINUXCNC else set(load_tools(tools)))


def run(program: str | Path, tools=None, *, machine_units: str = "inch",
        sink=None, spindle_tool: int = 0, units: str | None = None,
        params: dict[int, float] | None = None,
        dialect: Dialect | str | None = None) -> InterpretResult:
    """Interpret a program; G-code errors are reported in ``result.error``. With
    ``sink(arrays, states, controls)``, motion streams to it in blocks and only the last
    block stays in ``result.motions`` (see :class:`MotionList`). ``spindle_tool``: the
    tool already in the spindle at the start (ValueError if not in ``tools``).
    ``units``: the units the control starts in (default mm, as rs274); ``params``: its
    stored parameters in machine units (work offsets, G92; a LinuxCNC ``.var`` file)."""
    text, _ = _text(program)
    text, refused = _read(text, tools, dialect)
    if refused:
        return InterpretResult(units=units or "mm", motions=MotionList(),
                               error=InterpreterErrorInfo(*refused))
    units, motions, err = run_program(text, tools, machine_units, sink, spindle_tool,
                                      units, params)
    info = InterpreterErrorInfo(err[0], err[1]) if err else None
    return InterpretResult(units=units, motions=motions, error=info)


def interpret(program: str | Path, tools=None, *, machine_units: str = "inch",
              spindle_tool: int = 0, units: str | None = None,
              params: dict[int, float] | None = None,
              dialect: Dialect | str | None = None) -> MotionList:
    """Interpret a program and return its motion; raise InterpreterError on an error.
    ``units``, ``params``, ``dialect``: as :func:`run`."""
    text, name = _text(program)
    text, refused = _read(text, tools, dialect)
    if refused:
        raise InterpreterError(refused[0], refused[1], MotionList(), name)
    units, motions, err = run_program(text, tools, machine_units, spindle_tool=spindle_tool,
                                      units=units, params=params)
    if err:
        raise InterpreterError(err[0], err[1], motions, name)
    return motions
