"""Load and validate a job file (TOML).

Layout::

    units = "mm"                      # or "inch"
    name = "..."                      # optional
    fit = "none"                      # "none" | "arcs" | "arcs+cubics"
    fit_tolerance = 0.005             # job units
    [stock]        box = [xmin, ymin, zmin, xmax, ymax, zmax]
    [machine]      rapid, max_feed (units/min), acceleration (units/s^2),
                   units ("mm" | "inch": the units of the machine's tool table;
                   default: the job's)
    [simulation]   resolution (job units), enabled (bool)
    [post]         coolant, work_offset, end, line_numbers, tool_change, program_number,
                   preamble, postamble (see millpath.post.linuxcnc.PostOptions)
    [[tools]]      number, type, diameter, ...   (see millpath.io.toollib)
    [[operations]] type = "...", tool = N, ...   (keys per strategy)

Relative paths inside the file are resolved from the job file's folder.
"""

from __future__ import annotations

import re
import tomllib
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from millpath.errors import JobError
from millpath.io.toollib import tools_from_tables
from millpath.job.schema import Param, validate
from millpath.model import Machine, Stock, Tool
from millpath.plan.registry import strategy
from millpath.io.text import read_text

TOP = {
    "units": Param("str", choices=("mm", "inch")),
    "name": Param("str", ""),
    "description": Param("str", ""),
    "fit": Param("str", "none", choices=("none", "arcs", "arcs+cubics")),
    "fit_tolerance": Param("float", None, positive=True),
    "stock": Param("table", None),
    "machine": Param("table", None),
    "simulation": Param("table", None),
    "post": Param("table", None),
    "tools": Param("list", []),
    "operations": Param("list"),
}

STOCK = {"box": Param("floats", length=6)}
MACHINE = {
    "rapid": Param("float", None, positive=True),
    "max_feed": Param("float", None, positive=True),
    "acceleration": Param("float", None, positive=True),
    "units": Param("str", None, choices=("mm", "inch")),
}
POST = {
    "coolant": Param("str", None, choices=("flood", "mist", "off")),
    "work_offset": Param("str", "G54", choices=("G54", "G55", "G56", "G57", "G58", "G59",
                                                "G59.1", "G59.2", "G59.3")),
    "end": Param("str", "M2", choices=("M2", "M30")),
    "line_numbers": Param("bool", False),
    "tool_change": Param("str", "none", choices=("G30", "G53 G0 Z0", "none")),
    "program_number": Param("int", None, nonneg=True),
    "preamble": Param("str", ""),
    "postamble": Param("str", ""),
}
SIMULATION = {
    "resolution": Param("float", None, positive=True),
    "enabled": Param("bool", True),
    "design": Param("path", None),
}


@dataclass
class Job:
    path: Path | None
    units: str
    name: str
    stock: Stock | None
    machine: Machine
    tools: dict[int, Tool]
    operations: list[tuple[str, dict[str, Any]]]      # (type, validated params)
    fit: str = "none"
    fit_tolerance: float = 0.005
    simulation: dict[str, Any] = field(default_factory=dict)
    machine_units: str = ""           # units of the machine (tool table); "" = the job's
    post: dict[str, Any] = field(default_factory=dict)   # [post]: PostOptions fields

    @property
    def table_units(self) -> str:
        """Units tools.tbl is written in: the machine's."""
        return self.machine_units or self.units

    @property
    def base_dir(self) -> Path:
        return self.path.parent if self.path else Path.cwd()


def load_job(path: str | Path) -> Job:
    """Read a job file; raise JobError naming the file and key on any problem."""
    p = Path(path)
    text = read_text(p, "job file", JobError)
    data = parse_toml(text, p)
    return job_from_dict(data, p)


def parse_toml(text: str, path: Path | None) -> dict:
    """tomllib.loads with errors as JobError naming the file and line."""
    try:
        return tomllib.loads(text)
    except tomllib.TOMLDecodeError as e:
        msg = str(e)
        line = None
        m = re.search(r"\s*\(at line (\d+), column \d+\)", msg)
        if m:
            line = int(m.group(1))
            msg = msg[:m.start()] + msg[m.end():]
        elif "(at end of document)" in msg:
            line = text.count("\n") + (0 if text.endswith("\n") else 1)
            msg = msg.replace(" (at end of document)", " at end of file")
        raise JobError(f"invalid TOML: {msg}", path, line) from None


def job_from_dict(data: dict, path: Path | None = None) -> Job:
    base = path.parent if path else Path.cwd()
    top = validate(data, TOP, "", path, base)
    units = top["units"]
    stock = None
    if top["stock"] is not None:
        st = validate(top["stock"], STOCK, "stock", path)
        try:
            stock = Stock.from_box(st["box"])
        except ValueError as e:
            raise JobError(f"stock.box: {e}", path) from None
    machine = Machine.default_for(units)
    machine_units = ""
    if top["machine"] is not None:
        m = validate(top["machine"], MACHINE, "machine", path)
        machine = Machine(rapid=m["rapid"] or machine.rapid,
                          max_feed=m["max_feed"] or machine.max_feed,
                          acceleration=m["acceleration"] or machine.acceleration)
        machine_units = m["units"] or ""
    sim = validate(top["simulation"] or {}, SIMULATION, "simulation", path, base)
    post = validate(top["post"] or {}, POST, "post", path, base)
    tools = tools_from_tables(top["tools"], path, units)
    ops = []
    if not top["operations"]:
        raise JobError("operations: a job needs at least one [[operations]] entry", path)
    for i, op in enumerate(top["operations"]):
        where = f"operations[{i}]"
        if not isinstance(op, dict):
            raise JobError(f"{where}: expected a table", path)
        if "type" not in op:
            raise JobError(f"{where}.type: missing required key", path)
        mod = strategy(op["type"], where, path)
        body = {k: v for k, v in op.items() if k != "type"}
        params = validate(body, mod.PARAMS, where, path, base)
        if "tool" in params and isinstance(params["tool"], int) and params["tool"] not in tools:
            raise JobError(f"{where}.tool: tool {params['tool']} is not in the job's [[tools]]",
                           path)
        ops.append((op["type"], params))
    default_tol = 0.0002 if units == "inch" else 0.005
    return Job(path=path, units=units, name=top["name"] or (path.stem if path else "job"),
               stock=stock, machine=machine, tools=tools, operations=ops, fit=top["fit"],
               fit_tolerance=top["fit_tolerance"] or default_tol, simulation=sim,
               machine_units=machine_units, post=post)
