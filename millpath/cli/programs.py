"""Read, interpret and simulate a program given on the command line (``millpath
simulate`` and ``millpath view``).

``--tools`` is a LinuxCNC tool table (``T1 P1 D6 Z50``: flat end mills of diameter D)
or a TOML tool library (``[[tools]]`` with ``type``, ``diameter``, ``corner_radius``,
...), in the program's units. ``--stock`` is ``XMIN,YMIN,ZMIN,XMAX,YMAX,ZMAX`` in
program units. ``--design`` is the designed part in program units: an STL, or any
surface ``millpath drop`` reads (Bezier net ``.toml``, measured grid ``.csv``, STEP with
the ``step-brep`` extra). Errors are :class:`MillpathError` naming the file and line.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass
from pathlib import Path

import click

from millpath.errors import MillpathError
from millpath.model.dialect import DIALECTS
from millpath.model.units import default, length_scale


@dataclass
class ProgramArgs:
    """What ``millpath simulate`` and ``millpath view`` are given about a program: the
    PROGRAM argument, ``--tools``, ``--stock`` (text), ``--design``, ``--resolution``,
    ``--machine-units`` and ``--tool`` (see :func:`program_options`)."""

    program: Path
    tools: Path | None
    stock: str
    design: Path | None
    resolution: float | None
    machine_units: str | None
    spindle_tool: int
    setup: "MachineSetup | None" = None

    def simulate(self, *, progress: bool = False,
                 max_feed: float | None = None) -> "SimulatedProgram":
        """The program interpreted and simulated (:func:`simulate_program`)."""
        return simulate_program(self.program, self.tools, self.stock, self.design,
                                self.resolution, progress=progress,
                                machine_units=self.machine_units,
                                spindle_tool=self.spindle_tool, max_feed=max_feed,
                                setup=self.setup)


@dataclass
class MachineSetup:
    """The control as the program finds it: ``units`` it starts in (None: mm, as
    rs274), ``params`` its stored parameters (work offsets, G92) in ``params_units``,
    ``dialect`` the control family it reads the program as."""

    units: str | None = None
    params: dict[int, float] | None = None
    params_units: str | None = None
    dialect: str = "linuxcnc"

    def for_machine(self, machine_units: str) -> dict[int, float] | None:
        """The parameters in the interpreter's machine units."""
        if not self.params:
            return None
        from millpath.io.varfile import convert_params
        return convert_params(self.params,
                              length_scale(self.params_units or machine_units, machine_units))


def setup_options(func):
    """``--units``, ``--work-offset`` and ``--var``: the machine as the program finds it,
    handed to the command as ``setup`` (a :class:`MachineSetup`)."""
    options = [
        click.option("--units", "start_units", type=click.Choice(["inch", "mm"]), default=None,
                     help="Units the control starts in (a program without G20/G21 is read "
                          "in them; default mm, as rs274)."),
        click.option("--work-offset", "work_offset", default=None,
                     help="G54's offsets X,Y,Z in the machine units (where the part's zero "
                          "is in machine coordinates: G53 moves are placed from it)."),
        click.option("--var", "var_file", type=click.Path(path_type=Path), default=None,
                     help="LinuxCNC parameter file (.var): work offsets G54-G59.3, the work "
                          "system in force, G92, G28/G30, in the machine units."),
        click.option("--dialect", "dialect", type=click.Choice(sorted(DIALECTS)),
                     default="linuxcnc", help="The control the program is written for, read "
                     "as it reads it (default linuxcnc)."),
    ]

    @functools.wraps(func)
    def command(*args, start_units: str | None, work_offset: str | None,
                var_file: Path | None, dialect: str, **kw):
        from millpath.io.varfile import read_var, work_offset_params
        params: dict[int, float] = {}
        if var_file is not None:
            params.update(read_var(var_file))
        if work_offset is not None:
            params.update(work_offset_params(work_offset))
        return func(*args, setup=MachineSetup(start_units, params or None,
                                              kw.get("machine_units"), dialect), **kw)
    for option in reversed(options):
        command = option(command)
    return command


def program_options(design_use: str):
    """The options ``millpath simulate`` and ``millpath view`` share: the PROGRAM
    argument, ``--tools``, ``--stock``, ``--design`` (``design_use``: what the command
    does with the design, for its help),
    ``--resolution``, ``--machine-units`` and ``--tool``, applied in that order and
    handed to the command as one :class:`ProgramArgs`, its argument ``program``."""
    options = [
        click.argument("program", type=click.Path(path_type=Path)),
        click.option("--tools", "tools_path", type=click.Path(path_type=Path), default=None,
                     help="LinuxCNC tool table (flat end mills) or TOML tool library."),
        click.option("--stock", "stock_text", required=True,
                     help="Stock box XMIN,YMIN,ZMIN,XMAX,YMAX,ZMAX in program units."),
        click.option("--design", "design_path", type=click.Path(path_type=Path),
                     default=None, help="Designed part (STL, or any surface millpath "
                                        f"drop reads): {design_use}"),
        click.option("--resolution", type=float, default=None,
                     help="Z-map cell size (default: stock size / 1000, at most D/10 of "
                          "the smallest tool the program cuts with)."),
        click.option("--machine-units", type=click.Choice(["inch", "mm"]), default=None,
                     help="Units of a tool table whose header does not state them "
                          "(default inch, as LinuxCNC's rs274)."),
        click.option("--tool", "spindle_tool", type=click.IntRange(min=0), default=0,
                     help="The tool already in the spindle when the program starts "
                          "(LinuxCNC's sample programs assume one; no length offset "
                          "until G43)."),
    ]

    def apply(func):
        @functools.wraps(func)
        def command(program: Path, tools_path: Path | None, stock_text: str,
                    design_path: Path | None, resolution: float | None,
                    machine_units: str | None, spindle_tool: int, setup: MachineSetup,
                    **others):
            return func(ProgramArgs(program, tools_path, stock_text, design_path, resolution,
                                    machine_units, spindle_tool, setup), **others)
        command = setup_options(command)
        for option in reversed(options):
            command = option(command)
        return command
    return apply


def parse_stock(text: str):
    """The stock box of ``--stock XMIN,YMIN,ZMIN,XMAX,YMAX,ZMAX``."""
    from millpath.model.stock import Stock
    try:
        vals = [float(v) for v in text.replace(" ", "").split(",")]
        if len(vals) != 6 or not all(math.isfinite(v) for v in vals):
            raise ValueError
        return Stock.from_box(vals)
    except ValueError:
        raise MillpathError(f"--stock: expected XMIN,YMIN,ZMIN,XMAX,YMAX,ZMAX with each "
                            f"min below its max, got {text!r}") from None


def read_tools(path: Path | None, units: str, table_k: float = 1.0):
    """Tool shapes by number, and what to hand the interpreter. A TOML library is read
    in ``units`` (the program's); a tool table's diameters are scaled by ``table_k``
    (machine units -> program units)."""
    from millpath.model.tool import Tool
    if path is None:
        return {}, None
    if not path.is_file():
        raise MillpathError("tool file not found", path)
    if path.suffix.lower() == ".toml":
        from millpath.io.toollib import read_tool_library
        tools = read_tool_library(path, units=units)
        return tools, tools
    from millpath.io.tooltable import read_tool_table
    entries = read_tool_table(path)
    # A table gives the diameter and the gauge length (Z), not the flutes, shank or holder:
    # the cutter is taken to run the whole gauge length (no shank, no holder), so no holder
    # contact is invented; a TOML library gives the real holder.
    tools = {}
    for e in entries:
        if e.diameter > 0:
            reach = e.offsets.get("Z", 0.0) * table_k
            reach = reach if reach > 0 else 1e6
            tools[e.number] = Tool(e.number, "flat", e.diameter * table_k, flute_length=reach,
                                   stickout=reach, comment=e.comment)
    return tools, path


def interpret_program(program: Path, tool_arg, units: str, spindle_tool: int = 0,
                      setup: MachineSetup | None = None):
    """Interpret ``program`` with machine units ``units`` (``spindle_tool`` already in the
    spindle; ``setup``: the control's starting units and stored parameters); an error
    raises :class:`millpath.interpret.InterpreterError` naming the line."""
    from millpath.interpret import InterpreterError, run
    setup = setup or MachineSetup()
    try:
        res = run(program, tool_arg, machine_units=units, spindle_tool=spindle_tool,
                  units=setup.units, params=setup.for_machine(units), dialect=setup.dialect)
    except ValueError:
        raise MillpathError(f"--tool {spindle_tool}: no such tool in the tool table "
                            "(give --tools with it)", program) from None
    if res.error is not None:
        raise InterpreterError(res.error.line, res.error.message, res.motions, program)
    return res


def read_design(path: Path, units: str, stock=None):
    """The designed part of ``--design`` (program units) as (a height function for the
    Z-map, or None when it has no top surface; the exact check's references). Errors
    name the file: unreadable, non-finite vertices, no triangles, or a design wholly
    outside the stock (mixed units)."""
    from millpath.part.surface.load import load_surface
    from millpath.simulate import MeshDesign
    from millpath.simulate.exact import Reference, orient_outward
    if not path.is_file():
        raise MillpathError("design file not found", path)
    try:
        # a STEP design meshed within a quarter of the check's accuracy
        mesh = load_surface(str(path.resolve()), 200, path.parent, path, units=units,
                            chord_tolerance=default("verify_accuracy", units) / 4)
    except MillpathError as e:
        if e.file is None:
            e.file = str(path)
        raise
    tri = mesh.triangles
    if stock is not None:
        lo, hi = tri.reshape(-1, 3).min(axis=0), tri.reshape(-1, 3).max(axis=0)
        b = stock.box
        if (hi[0] < b[0] or lo[0] > b[3] or hi[1] < b[1] or lo[1] > b[4] or hi[2] < b[2]
                or lo[2] > b[5]):
            raise MillpathError(f"the design lies wholly outside the stock {list(b)} "
                                f"(design box {lo.round(4).tolist()} to "
                                f"{hi.round(4).tolist()}; different units?)", path)
    try:
        design = MeshDesign(tri)          # its top surface, for the Z-map's figures
    except ValueError:
        design = None                     # walls only: the exact check alone
    return design, [Reference(orient_outward(tri), path.name, None)]


CUTTING = ("feed", "arc", "cubic", "nurbs")


def feed_warning(program: Path, line: int, feed: float, count: int, max_feed: float,
                 units: str) -> str:
    """One line: the first feed above the machine's limit, by its program line."""
    more = (f" ({count - 1} more move{'s' if count > 2 else ''} above it)" if count > 1
            else "")
    return (f"millpath: warning: {program}:{line}: feed F{feed:.10g} {units}/min exceeds the "
            f"machine's max_feed {max_feed:g} {units}/min; the cycle time assumes "
            f"{max_feed:g}{more}")


def check_feeds(motions, max_feed: float) -> tuple[int, float, int] | None:
    """(line, feed, count) of the cutting moves faster than ``max_feed`` (units per
    minute; inverse-time moves are not compared), or None."""
    over = [m for m in motions if m.kind in CUTTING and m.feed_mode != "inverse_time"
            and m.feed > max_feed]
    if not over:
        return None
    return over[0].line, over[0].feed, len(over)


def default_resolution(stock, motions, tools: dict) -> float:
    """The stock's longer side / 1000, at most a tenth of the smallest tool that cuts
    (feeds, arcs, splines; else that moves) in the program: tools of the table the
    program never uses do not count."""
    w, h, _ = stock.size
    resolution = max(w, h) / 1000.0
    cutting = {m.tool for m in motions if m.kind in CUTTING and m.tool != 0}
    moving = {m.tool for m in motions if m.kind != "dwell" and m.tool != 0}
    used = [t for t in (cutting or moving) if t in tools]
    if used:
        resolution = min(resolution, min(tools[t].diameter for t in used) / 10.0)
    return resolution


@dataclass
class SimulatedProgram:
    """A program interpreted and simulated on its stock (program units)."""

    units: str
    motions: list            # tool tips in the program's frame, as LinuxCNC moves them
    tools: dict              # tool shapes by number
    stock: object            # millpath.model.stock.Stock
    design: object | None
    resolution: float
    result: object           # millpath.simulate.SimResult


def simulate_program(program: Path, tools_path: Path | None, stock_text: str,
                     design_path: Path | None, resolution: float | None, *,
                     progress: bool = False,
                     machine_units: str | None = None, spindle_tool: int = 0,
                     max_feed: float | None = None,
                     setup: MachineSetup | None = None) -> SimulatedProgram:
    """Interpret ``program`` and simulate it on the stock. A LinuxCNC tool table is in
    the machine's units: those its header states, else ``machine_units``, else inch
    (as LinuxCNC's rs274); a TOML tool library is in the program's units (read in mm
    first, again in inch if the program says G20).

    ``spindle_tool``: the tool in the spindle when the program starts (LinuxCNC's
    sample programs assume one). ``max_feed`` (units/min, program units; default the
    machine's, 3000 mm/min or 120 in/min) caps the feeds of the cycle time; a one-line
    warning names the first line whose feed is above it.

    Default ``resolution``: see :func:`default_resolution`."""
    from millpath.model.stock import Machine
    from millpath.simulate import simulate_motions

    if not program.is_file():
        raise MillpathError("program not found", program)
    stock = parse_stock(stock_text)
    if design_path is not None and not design_path.is_file():
        raise MillpathError("design file not found", design_path)
    if tools_path is not None and tools_path.is_file() and \
            tools_path.suffix.lower() != ".toml":
        from millpath.io.tooltable import file_table_units
        mu = file_table_units(tools_path) or machine_units or "inch"
        res = interpret_program(program, tools_path, mu, spindle_tool, setup)
        units = res.units
        tools, tool_arg = read_tools(tools_path, units, length_scale(mu, units))
    else:
        tools, tool_arg = read_tools(tools_path, "mm")
        res = interpret_program(program, tool_arg, "mm", spindle_tool, setup)
        units = res.units
        if units == "inch":
            tools, tool_arg = read_tools(tools_path, "inch")
            res = interpret_program(program, tool_arg, "inch", spindle_tool, setup)
    design, refs = (read_design(design_path, units, stock) if design_path is not None
                    else (None, None))
    from millpath.simulate.tip import tip_motions
    motions = tip_motions(res.motions, units)     # tool tips, as the machine moves them
    used = sorted({m.tool for m in motions if m.kind != "dwell" and m.tool != 0})
    for t in used:
        if t not in tools:
            line = next(m.line for m in motions if m.tool == t)
            hint = (f" in {tools_path} (a tool table row needs a diameter D)"
                    if tools_path else "; give --tools")
            raise MillpathError(f"tool {t} is not defined{hint}", program, line)
    if not used and any(m.kind != "dwell" for m in motions):
        click.echo("millpath: warning: no tool is loaded (T.. M6, or --tool N for the tool "
                   "already in the spindle): nothing is cut", err=True)
    if resolution is None:
        resolution = default_resolution(stock, motions, tools)
    if not (resolution > 0 and math.isfinite(resolution)):
        raise MillpathError(f"--resolution must be a positive length, not {resolution}")
    machine = Machine.default_for(units)
    if max_feed is not None:
        if not (max_feed > 0 and math.isfinite(max_feed)):
            raise MillpathError(f"--max-feed must be a positive feed, not {max_feed}")
        machine = Machine(machine.rapid, max_feed, machine.acceleration)
    fast = check_feeds(motions, machine.max_feed)
    if fast is not None:
        click.echo(feed_warning(program, fast[0], fast[1], fast[2], machine.max_feed, units),
                   err=True)
    try:
        r = simulate_motions(motions, tools, stock, resolution=resolution, design=design,
                             machine=machine, progress=progress,
                             references=refs, accuracy=default("verify_accuracy", units))
    except ValueError as e:                    # --resolution too fine, a tool's shape
        raise MillpathError(str(e), program) from None
    return SimulatedProgram(units, motions, tools, stock, design, resolution, r)
