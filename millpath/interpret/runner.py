"""The read-execute loop over a program's lines.

A program ends at M2/M30, or at a second ``%`` line when the first line is ``%``; a
file that just stops is an error on its last line, as in rs274 ("File ended with no
percent sign or program end"). On an error the motion list holds the motion before the
failing block. A program with o-words reads at most ``MAX_FLOW_CHARS`` characters
(:mod:`millpath.model.limits`). Long programs are split into lines a chunk (about 4 MB)
at a time.
"""

from __future__ import annotations

from typing import Iterator

from millpath.interpret.errors import GCodeError
from millpath.interpret.fastpath import FastPath
from millpath.gcode.lexer import MAX_LINE, read_block
from millpath.interpret.machine import Machine
from millpath.interpret.store import MotionList
from millpath.model.limits import FLOW_LINE_CHARS, MAX_FLOW_CHARS
from millpath.interpret.tools import load_tools

CHUNK = 1 << 22


def _chunks(text: str) -> Iterator[list[str]]:
    """The program's lines (as ``str.splitlines``), a few MB at a time."""
    pos = 0
    n = len(text)
    while pos < n:
        cut = text.find("\n", min(pos + CHUNK, n))
        end = n if cut < 0 else cut + 1
        yield text[pos:end].splitlines()
        pos = end


def _block(machine: Machine, raw: str, n: int) -> None:
    """Read and execute one line with the general reader."""
    if len(raw) > MAX_LINE:
        raise GCodeError("Command too long")
    mark = len(machine.store)
    params = machine.params
    params[5420], params[5421], params[5422] = machine.cur     # read-only: position
    params[5400] = float(machine.spindle_tool)                   # and tool in the spindle
    try:
        blk = read_block(raw, n, params, machine.named)
        if blk.empty:
            return
        machine.execute(blk)
    except GCodeError:
        machine.store.truncate(mark)
        raise
    for idx, val in blk.settings:
        if isinstance(idx, str):
            machine.named[idx] = val
        else:
            machine.params[idx] = val


def _run_flow(text: str, machine: Machine) -> tuple[str, MotionList, tuple[int, str] | None]:
    """Line by line with o-word control flow (subroutines, loops)."""
    from millpath.interpret.oword import Flow
    lines = text.splitlines()
    fast = FastPath(machine)
    percent = None
    k = 0
    n = 0
    executed = 0
    read = 0
    try:
        flow = Flow(lines, machine)
        while k < len(lines):
            raw = lines[k]
            n = k + 1
            if percent is None:
                s = raw.strip()
                if s:
                    percent = s.startswith("%")
                    if percent:
                        k += 1
                        continue
            elif percent and raw.strip().startswith("%"):
                machine.comp.flush(n)
                return machine.units, machine.store, None
            executed += 1
            read += len(raw)
            if not executed & 0xFFF:
                if not executed & 0xFFFF:
                    machine.store.flush()
                if read + FLOW_LINE_CHARS * executed > MAX_FLOW_CHARS:
                    raise GCodeError(f"the program read more than {MAX_FLOW_CHARS} characters "
                                     "through its loops and calls: endless loop?")
            if k in flow.ol:
                if len(raw) > MAX_LINE:
                    raise GCodeError("Command too long")
                k = flow.step(k)
                continue
            k += 1
            if percent is not None and len(raw) <= MAX_LINE and fast.try_line(raw, n):
                continue
            _block(machine, raw, n)
            if machine.ended:
                return machine.units, machine.store, None
    except GCodeError as e:
        return machine.units, machine.store, (getattr(e, "line", None) or n, e.message)
    msg = ("File ended with no percent sign" if percent
           else "File ended with no percent sign or program end")
    return machine.units, machine.store, (max(len(lines), 1), msg)


def run_program(text: str, tools, machine_units: str, sink=None, spindle_tool: int = 0,
                units: str | None = None, params: dict[int, float] | None = None
                ) -> tuple[str, MotionList, tuple[int, str] | None]:
    """Interpret ``text``; returns (units at the end, motions, (line, message) or None).
    With ``sink``, motion streams to it (see :class:`MotionList`); the records not yet
    handed over stay in the returned list. ``spindle_tool``: the tool already in the
    spindle when the program starts (as after ``T.. M6``; no length offset until G43).
    ``units``, ``params``: the machine's default units and stored parameters
    (:meth:`MachineState.set_up`); the list's ``reference`` is the part's frame."""
    machine = Machine(load_tools(tools), machine_units)
    machine.set_up(units, params)
    machine.store.reference = machine.reference()
    if spindle_tool:
        machine.load_spindle(spindle_tool)
    machine.store.sink = sink
    from millpath.interpret.oword import has_owords
    if has_owords(text):
        return _run_flow(text, machine)
    percent = None
    fast = FastPath(machine)
    n = 0
    base = 0                      # line number of the chunk's line 0, minus one
    try:
        for lines in _chunks(text):
            k = 0
            total = len(lines)
            # the fast path stops before the first line too long for rs274
            stop = total
            if total and max(map(len, lines)) > MAX_LINE:
                stop = next(i for i, s in enumerate(lines) if len(s) > MAX_LINE)
            while k < total:
                if percent is not None and k < stop:
                    k = fast.run(lines, k, base, stop)
                    if k >= total:
                        break
                raw = lines[k]
                k += 1
                n = base + k
                if percent is None:
                    s = raw.strip()
                    if s:
                        percent = s.startswith("%")
                        if percent:
                            continue
                elif percent and raw.strip().startswith("%"):
                    machine.comp.flush(n)
                    return machine.units, machine.store, None
                _block(machine, raw, n)
                if machine.ended:
                    return machine.units, machine.store, None
            base += total
            machine.store.flush()
    except GCodeError as e:
        return machine.units, machine.store, (getattr(e, "line", None) or n, e.message)
    last = max(base, 1)
    msg = ("File ended with no percent sign" if percent
           else "File ended with no percent sign or program end")
    return machine.units, machine.store, (last, msg)
