"""report.json: its sections as dataclasses, and the one writer.

A run's :class:`RunReport` holds the job's figures (program size, moves, stock, fit,
cycle time), one :class:`OperationSection` per operation of the tool path (a tool and
a phase of a strategy: moves, program lines, cycle time and where it goes, in-process
stock figures), one
:class:`PlanSection` per ``[[operations]]`` entry of the job (what its strategy
reported, under the strategy's own keys, e.g. ``features``, ``surface_finish``,
``pocket``, ``curve``), the verification section as the simulator wrote it (a plain
dict, passed through), and the safety verdict. Lengths in job units, times in seconds.
:func:`write_report` is the only writer of ``report.json``.
"""

from __future__ import annotations

import json
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

MOVE_KINDS = ("rapid", "line", "arc", "cubic", "drill")


@dataclass
class OperationSection:
    """One operation of the tool path."""

    type: str
    name: str
    tool: int
    spindle: float | None
    moves: dict[str, int]                 # counts by kind (MOVE_KINDS)
    cycle_time_s: float                   # of the interpreted program
    in_process: dict | None = None        # in-process stock figures, when carried
    lines: int | None = None              # program lines it carries out
    time: dict | None = None              # simulate.airtime.time_use's figures

    def to_json(self) -> dict:
        d = {"type": self.type, "name": self.name, "tool": self.tool,
             "spindle": self.spindle, "moves": self.moves,
             "cycle_time_s": round(self.cycle_time_s, 3)}
        if self.lines is not None:
            d["lines"] = self.lines
        if self.time is not None:
            d["time"] = self.time
        if self.in_process is not None:
            d["in_process"] = self.in_process
        return d


@dataclass
class PlanSection:
    """What the strategy of the job's operation ``index`` reported (its
    ``PlanResult.report``), kept apart from every other operation's."""

    index: int                            # position in the job's [[operations]]
    type: str                             # the operation's type
    sections: dict[str, Any] = field(default_factory=dict)

    def to_json(self) -> dict:
        return {"operation": self.index, "type": self.type, **self.sections}


@dataclass
class RunReport:
    """Everything report.json says about one run of a job."""

    job: str | None
    name: str
    units: str
    tool_table_units: str
    program: str | None                   # file written, None when refused
    lines: int
    bytes: int
    moves: dict[str, int]
    stock: list[float]
    fit: dict[str, Any]
    reference: dict | None = None         # the job's [reference], copied
    post: dict | None = None              # dialect, and what it made the post rewrite
    # simulate's (SimResult.to_json), passed through; with the exact check: max_gouge,
    # max_left (normal to the design), max_gouge_at / max_left_at {x, y, z, line,
    # operation}, gouging_moves, reference, accuracy, left_spacing, by_operation
    verification: dict = field(default_factory=dict)
    cycle_time_s: float = 0.0
    operations: list[OperationSection] = field(default_factory=list)
    plans: list[PlanSection] = field(default_factory=list)
    safety: dict | None = None
    seconds: float | None = None

    def to_json(self) -> dict:
        d: dict[str, Any] = {
            "job": self.job, "name": self.name, "units": self.units,
            "tool_table_units": self.tool_table_units, "program": self.program,
            "lines": self.lines, "bytes": self.bytes, "moves": self.moves,
            "stock": self.stock, "fit": self.fit}
        if self.reference:
            d["reference"] = self.reference
        if self.post:
            d["post"] = self.post
        d["verification"] = self.verification
        d["cycle_time_s"] = round(self.cycle_time_s, 3)
        d["operations"] = [o.to_json() for o in self.operations]
        d["plans"] = [p.to_json() for p in self.plans]
        if self.safety is not None:
            d["safety"] = self.safety
        if self.seconds is not None:
            d["seconds"] = round(self.seconds, 3)
        return d


def plan_sections(report: dict, key: str) -> list:
    """The ``key`` sections of every operation's plan in a report.json dict, in job
    order (e.g. ``plan_sections(rep, "features")``)."""
    return [p[key] for p in report.get("plans", []) if key in p]


def _json_default(o: Any) -> Any:
    if isinstance(o, (np.floating, np.integer)):
        return o.item()
    if isinstance(o, np.ndarray):
        return o.tolist()
    if isinstance(o, Path):
        return str(o)
    raise TypeError(f"cannot write {type(o).__name__} to JSON")


def report_text(report: dict) -> str:
    """The JSON text of a report dict (numpy numbers and paths converted)."""
    return json.dumps(report, indent=2, default=_json_default)


def write_report(path: Path, report: RunReport) -> dict:
    """Write ``report`` to ``path`` (report.json) and return the dict written."""
    d = report.to_json()
    Path(path).write_text(report_text(d))
    return d
