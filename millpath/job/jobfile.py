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
                   preamble, postamble (see millpath.post.writer.PostOptions)
    [limits]       max_extent (job units), max_layers, max_passes   (millpath.model.limits)
    [reference]    a document's published numbers the job reproduces (free-form
                   table, copied into report.json as "reference")
    [[tools]]      number, type, diameter, ...   (see millpath.io.toollib)
    [[operations]] type = "...", tool = N, ...   (keys per strategy)

Relative paths inside the file are resolved from the job file's folder.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from millpath.errors import JobError, Problems
from millpath.io.toollib import tools_from_tables
from millpath.io.schema import Param, parse_toml, validate
from millpath.io.tomllines import place
from millpath.model import Machine, Stock, Tool
from millpath.model.dialect import DIALECTS
from millpath.model.limits import (Limits, check_cells, check_tolerance, count_needed,
                                   MAX_TOLERANCE)
from millpath.plan.registry import strategy
from millpath.job.vocabulary import renamed
from millpath.io.text import read_text
from millpath.model.units import default

TOP = {
    "units": Param("str", choices=("mm", "inch"), doc="units of every length in the job"),
    "name": Param("str", "", doc="job name (default: the file's name)"),
    "description": Param("str", "", doc="free text"),
    "reference": Param("table", None, doc="a document's published numbers the job "
                       "reproduces (copied into report.json)"),
    "fit": Param("str", "none", choices=("none", "arcs", "arcs+cubics"),
                 doc="replace runs of lines by arcs (and XY G5 cubics) before posting"),
    "fit_tolerance": Param("float", None, positive=True, unit="length",
                           doc="largest distance of the fitted path from the planned one "
                               "(default 0.005 mm / 0.0002 in)"),
    "stock": Param("table", None),
    "machine": Param("table", None),
    "simulation": Param("table", None),
    "post": Param("table", None),
    "limits": Param("table", None),
    "tools": Param("list", []),
    "operations": Param("list"),
}

STOCK = {"box": Param("floats", None, length=6, unit="length",
                      doc="[xmin, ymin, zmin, xmax, ymax, zmax] of the raw block"),
         "cylinder": Param("floats", None, length=5, unit="length",
                           doc="[cx, cy, diameter, zmin, zmax]: a bar with a vertical axis "
                               "instead of a block (simulated as the bar)")}
MACHINE = {
    "rapid": Param("float", None, positive=True, unit="feed",
                   doc="rapid rate (default 5000 mm/min, 200 in/min)"),
    "max_feed": Param("float", None, positive=True, unit="feed",
                      doc="highest feed rate (default 3000 mm/min, 120 in/min)"),
    "acceleration": Param("float", None, positive=True,
                          doc="axis acceleration in units/s^2 (default 500 mm/s^2, 20 in/s^2)"),
    "units": Param("str", None, choices=("mm", "inch"),
                   doc="the machine's units: tools.tbl is written in them (default: the "
                       "job's)"),
}
POST = {
    "coolant": Param("str", None, choices=("flood", "mist", "off"),
                     doc="coolant of every operation (default: each operation's, flood)"),
    "work_offset": Param("str", "G54", choices=("G54", "G55", "G56", "G57", "G58", "G59",
                                                "G59.1", "G59.2", "G59.3"),
                         doc="work coordinate system written in the setup line"),
    "end": Param("str", "M2", choices=("M2", "M30"), doc="program end"),
    "line_numbers": Param("bool", False, doc="N words in steps of 10"),
    "tool_change": Param("str", "none", choices=("G30", "G53 G0 Z0", "none"),
                         doc="move written before each M6"),
    "program_number": Param("int", None, nonneg=True,
                            doc="written first as the comment (O<n>)"),
    "machine": Param("str", None, doc="a TOML file (relative to the job) describing one "
                     "machine: its [post] settings and [machine] rates and units; the "
                     "job's own keys win"),
    "dialect": Param("str", "linuxcnc", choices=tuple(DIALECTS),
                     doc="the control the program is written for and proven as: "
                         + "; ".join(f"{d.name} ({d.title})" for d in DIALECTS.values())),
    "preamble": Param("str", "", doc="G-code lines after the setup"),
    "postamble": Param("str", "", doc="G-code lines before the program end"),
}
#: the bounds of [limits], described by the Limits dataclass itself
LIMITS = {name: Param(kind, None, positive=True, unit=unit, doc=doc)
          for name, kind, unit, doc in Limits.described()}
#: operation keys that set a depth per layer / a distance between side-by-side passes
LAYER_KEYS = ("stepdown", "stepdown_max")
PASS_KEYS = ("stepover",)
SIMULATION = {
    "resolution": Param("float", None, positive=True, unit="length",
                        doc="Z-map cell size (default: a tenth of the smallest tool "
                            "diameter)"),
    "enabled": Param("bool", True, doc="simulate and verify the program"),
    "design": Param("path", None, doc="the designed part (STL) the program is verified "
                                      "against (default: the operations' own designs)"),
    "exact": Param("bool", True, doc="measure gouge and material left grid-free, normal to "
                                     "the design, and prove the program with those figures "
                                     "(false: the Z-map's, bounded by its cell size)"),
    "pictures": Param("bool", True, doc="draw preview.png, stock.png and deviation.png "
                                        "(false: the program, report and view.html only, "
                                        "without matplotlib's start-up and drawing)"),
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
    limits: Limits = field(default_factory=Limits)
    reference: dict[str, Any] | None = None     # published numbers the job reproduces
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
    """Read a job file; raise JobError naming the file and key on any problem, or
    JobErrors naming every problem found, each at the line of its key."""
    p = Path(path)
    text = read_text(p, "job file", JobError)
    data = parse_toml(text, p)
    try:
        return job_from_dict(data, p)
    except JobError as e:
        raise place(e, text) from None


def job_from_dict(data: dict, path: Path | None = None) -> Job:
    """The job of a parsed job file; every unknown key, wrong type and out-of-range
    value is found and raised together (JobErrors)."""
    base = path.parent if path else Path.cwd()
    problems = Problems()
    top = validate(data, TOP, "", path, base, problems)
    units = top["units"] or "mm"
    limits = Limits.default_for(units)
    with problems.gather():
        if top["limits"] is not None:
            limits = _limits(validate(top["limits"], LIMITS, "limits", path), limits, path)
    stock = None
    with problems.gather():
        if top["stock"] is not None:
            stock = _stock(validate(top["stock"], STOCK, "stock", path), limits, units, path)
    machine = Machine.default_for(units)
    machine_units = ""
    post_table, machine_table = _machine_file(top["post"], top["machine"], path, base,
                                              problems)
    if machine_table is not None:
        m = validate(machine_table, MACHINE, "machine", path, problems=problems)
        machine = Machine(rapid=m["rapid"] or machine.rapid,
                          max_feed=m["max_feed"] or machine.max_feed,
                          acceleration=m["acceleration"] or machine.acceleration)
        machine_units = m["units"] or ""
    if top["fit_tolerance"] is not None:
        bad = check_tolerance(top["fit_tolerance"], units)
        if bad:
            problems.add(JobError(f"fit_tolerance: {bad}", path))
    sim = validate(top["simulation"] or {}, SIMULATION, "simulation", path, base, problems)
    if sim["resolution"] is not None and stock is not None:
        bad = check_cells(stock.size[0], stock.size[1], sim["resolution"], limits.max_cells)
        if bad:
            problems.add(JobError(f"simulation.resolution: {bad}", path))
    post = validate(post_table, POST, "post", path, base, problems)
    post.pop("machine", None)
    for key in ("preamble", "postamble"):
        with problems.gather():
            _check_gcode(post[key], f"post.{key}", path)
    tools: dict[int, Tool] = {}
    before = len(problems)
    if top["tools"] is not None:
        tools = tools_from_tables(top["tools"], path, units, limits, problems)
    tools_read = len(problems) == before      # every tool read: tool numbers are checkable
    ops = []
    if not top["operations"] and top["operations"] is not None:
        problems.add(JobError("operations: a job needs at least one [[operations]] entry",
                              path))
    for i, op in enumerate(top["operations"] or []):
        with problems.gather():
            params = _operation(op, i, path, base, problems)
            if params is None:
                continue
            where = f"operations[{i}]"
            if tools_read and isinstance(params.get("tool"), int) \
                    and params["tool"] not in tools:
                raise JobError(f"{where}.tool: tool {params['tool']} is not in the job's "
                               f"[[tools]]", path)
            _check_work(params, stock, limits, units, where, path)
            _check_scale(params, tools, sim["resolution"], units, where, path)
            ops.append((op["type"], params))
    problems.check()
    default_tol = default("path_tolerance", units)
    return Job(path=path, units=units, name=top["name"] or (path.stem if path else "job"),
               stock=stock, machine=machine, tools=tools, operations=ops, fit=top["fit"],
               fit_tolerance=top["fit_tolerance"] or default_tol, simulation=sim,
               limits=limits, reference=top["reference"], machine_units=machine_units,
               post=post)


def _operation(op: Any, i: int, path: Path | None, base: Path,
               problems: Problems) -> dict[str, Any] | None:
    """The validated keys of operation ``i``; None when it has problems (recorded)."""
    where = f"operations[{i}]"
    if not isinstance(op, dict):
        raise JobError(f"{where}: expected a table", path)
    if "type" not in op:
        raise JobError(f"{where}.type: missing required key", path)
    mod = strategy(op["type"], where, path)
    before = len(problems)
    body = renamed(op["type"], mod.PARAMS, {k: v for k, v in op.items() if k != "type"},
                   i, path, problems)
    params = validate(body, mod.PARAMS, where, path, base, problems)
    return params if len(problems) == before else None


def _limits(lim: dict[str, Any], limits: Limits, path: Path | None) -> Limits:
    """The job's [limits] over the units' defaults; none may be raised past its cap."""
    bad = Limits.raised(lim)
    if bad:
        raise JobError(f"limits.{bad[0]}: {bad[1]}", path)
    return Limits(**{k: lim[k] if lim[k] is not None else getattr(limits, k)
                     for k in Limits.keys()})


def _stock(st: dict[str, Any], limits: Limits, units: str, path: Path | None) -> Stock:
    """The [stock] block or bar, within the limits' extent."""
    if (st["box"] is None) == (st["cylinder"] is None):
        raise JobError("stock: give either box = [...] or cylinder = [...]", path)
    key = "box" if st["box"] is not None else "cylinder"
    try:
        if key == "box":
            stock = Stock.from_box(st["box"])
        else:
            cx, cy, d, z0, z1 = st["cylinder"]
            stock = Stock.from_cylinder(cx, cy, d / 2.0, z0, z1)
    except ValueError as e:
        raise JobError(f"stock.{key}: {e}", path) from None
    side = max(stock.size)
    if side > limits.max_extent:
        raise JobError(f"stock.{key}: a side of {side:g} {units} is larger than the "
                       f"{limits.max_extent:g} {units} limit (wrong units? raise "
                       f"[limits] max_extent if the machine is that big)", path)
    return stock


def _check_work(params: dict[str, Any], stock: Stock | None, limits: Limits, units: str,
                where: str, path: Path | None) -> None:
    """Refuse an operation whose steps would make more layers or passes than the limits
    allow, measured over the stock (or the operation's own depth), before planning."""
    if stock is not None:
        depth, across = stock.size[2], max(stock.size[0], stock.size[1])
    else:
        depth, across = params.get("depth") or 0.0, 0.0
    for keys, span, what, limit, name in (
            (LAYER_KEYS, depth, "layers", limits.max_layers, "max_layers"),
            (PASS_KEYS, across, "passes", limits.max_passes, "max_passes")):
        for key in keys:
            step = params.get(key)
            if not isinstance(step, float) or span <= 0:
                continue
            n = count_needed(span, step)
            if n > limit:
                raise JobError(f"{where}.{key}: {span:g} {units} at {step:g} {units} a step "
                               f"needs {n:g} {what}, more than the limit of {limit} "
                               f"(raise [limits] {name} if you mean it)", path)


def _check_scale(params: dict[str, Any], tools: dict[int, Tool], resolution: float | None,
                 units: str, where: str, path: Path | None) -> None:
    """Refuse a chordal tolerance coarser than machining allows, and a simulation cell
    wider than the operation's tool (the Z-map could not see what it cuts)."""
    tol = params.get("tolerance")
    if isinstance(tol, float) and tol > MAX_TOLERANCE(units):
        raise JobError(f"{where}.tolerance: {tol:g} {units} is coarser than the "
                       f"{MAX_TOLERANCE(units):g} {units} limit", path)
    tool = tools.get(params.get("tool")) if isinstance(params.get("tool"), int) else None
    if resolution is not None and tool is not None and resolution > tool.diameter:
        raise JobError(f"simulation.resolution: cells of {resolution:g} {units} are wider "
                       f"than the {tool.diameter:g} {units} tool {tool.number} of {where}: "
                       f"the simulation could not see what it cuts (use at most "
                       f"{tool.diameter / 4:g})", path)


def _machine_file(post: Any, machine: Any, path: Path | None, base: Path | None,
                  problems: Problems) -> tuple[Any, Any]:
    """The job's [post] and [machine] tables over those of the machine file its [post]
    names (``machine``: a TOML file, relative to the job, describing one machine: its
    [post] settings and its [machine] rates and units; the job's own keys win). Errors
    in the machine file name it."""
    if not isinstance(post, dict) or not isinstance(post.get("machine"), str):
        return post or {}, machine
    own_post = {k: v for k, v in post.items() if k != "machine"}
    mpath = Path(post["machine"])
    if not mpath.is_absolute() and base is not None:
        mpath = base / mpath
    with problems.gather():
        top = parse_toml(read_text(mpath, "machine file", JobError), mpath)
        extra = sorted(set(top) - {"post", "machine"})
        if extra:
            raise JobError(f"a machine file holds [post] and [machine] tables, not "
                           f"{extra[0]!r}", mpath)
        merged = []
        for name, schema, job_table in (("post", POST, own_post), ("machine", MACHINE, machine)):
            table = {k: v for k, v in (top.get(name) or {}).items() if k != "machine"}
            before = len(problems)
            validate(table, schema, name, mpath, base, problems)
            if len(problems) > before:  # named once, in the machine file
                table = {}
            merged.append({**table, **(job_table or {})} if table or job_table is not None
                          else None)
        return merged[0] or {}, merged[1]
    return own_post, machine


def _check_gcode(text: str, key: str, path: Path | None) -> None:
    """Read the G-code lines a job writes into its program (``[post]`` preamble and
    postamble) as the interpreter will, so that a bad word is named where the user wrote
    it, not at a line of the generated program. O-word lines are left to the run."""
    from millpath.gcode.errors import GCodeError
    from millpath.gcode.lexer import MAX_LINE, MAX_PARAM, read_block
    params = [0.0] * MAX_PARAM
    named: dict[str, float] = {}
    for k, raw in enumerate(text.splitlines(), 1):
        s = raw.strip()
        if not s or s.lstrip("/").lstrip().lower().startswith("o"):
            continue
        try:
            if len(s) > MAX_LINE:
                raise GCodeError("Command too long")
            blk = read_block(s, k, params, named)
        except GCodeError as e:
            raise JobError(f"{key}: line {k}: {e.message}", path) from None
        for idx, val in blk.settings:
            if isinstance(idx, str):
                named[idx] = val
            else:
                params[idx] = val
