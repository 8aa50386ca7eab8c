"""``millpath simulate PROGRAM.ngc``: material removal, gouge check and cycle time.

The program is interpreted by millpath's RS274NGC interpreter and its motion swept
through a Z-map of the stock (see :mod:`millpath.simulate`). ``--tools`` is a LinuxCNC
tool table (``T1 P1 D6 Z50``: flat end mills of diameter D) or a TOML tool library
(``[[tools]]`` with ``type``, ``diameter``, ``corner_radius``, ...), in the program's
units. Everything printed is in program units.
"""

from __future__ import annotations

import json
import math
import sys
from pathlib import Path

import click

from millpath.errors import MillpathError


def _stock(text: str):
    from millpath.model.stock import Stock
    try:
        vals = [float(v) for v in text.replace(" ", "").split(",")]
        if len(vals) != 6 or not all(math.isfinite(v) for v in vals):
            raise ValueError
        return Stock.from_box(vals)
    except ValueError:
        raise MillpathError(f"--stock: expected XMIN,YMIN,ZMIN,XMAX,YMAX,ZMAX with each "
                            f"min below its max, got {text!r}") from None


def _read_tools(path: Path | None, units: str, table_k: float = 1.0):
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
    tools = {e.number: Tool(e.number, "flat", e.diameter * table_k, comment=e.comment)
             for e in entries if e.diameter > 0}
    return tools, path


def _interpret(program: Path, tool_arg, units: str):
    from millpath.interpret import InterpreterError, run
    res = run(program, tool_arg, machine_units=units)
    if res.error is not None:
        raise InterpreterError(res.error.line, res.error.message, res.motions, program)
    return res


@click.command()
@click.argument("program", type=click.Path(path_type=Path))
@click.option("--tools", "tools_path", type=click.Path(path_type=Path), default=None,
              help="LinuxCNC tool table (flat end mills) or TOML tool library.")
@click.option("--stock", "stock_text", required=True,
              help="Stock box XMIN,YMIN,ZMIN,XMAX,YMAX,ZMAX in program units.")
@click.option("--design", "design_path", type=click.Path(path_type=Path), default=None,
              help="Designed part (STL) for gouge and material-left checks.")
@click.option("--resolution", type=float, default=None,
              help="Z-map cell size (default: stock size / 1000, at most D/10 of the "
                   "smallest tool).")
@click.option("--machine-units", type=click.Choice(["inch", "mm"]), default=None,
              help="Units of a tool table whose header does not state them (default "
              "inch, as LinuxCNC's rs274).")
@click.option("--json", "as_json", is_flag=True, help="Print the results as JSON.")
@click.option("--png", "png", type=click.Path(path_type=Path), default=None,
              help="Write a shaded picture of the stock (and FILE_deviation.png with "
                   "--design).")
def command(program: Path, tools_path: Path | None, stock_text: str,
            design_path: Path | None, resolution: float | None, machine_units: str | None,
            as_json: bool, png: Path | None) -> None:
    """Simulate PROGRAM on a block of stock: removed volume, gouges, material left,
    rapids through material, holder contacts and cycle time."""
    from millpath.model.stock import Machine
    from millpath.simulate import MeshDesign, render_deviation, render_stock, simulate_motions

    if not program.is_file():
        raise MillpathError("program not found", program)
    stock = _stock(stock_text)
    design = MeshDesign.from_stl(design_path) if design_path is not None else None
    if tools_path is not None and tools_path.is_file() and tools_path.suffix.lower() != ".toml":
        # a LinuxCNC tool table is in the machine's units: its header, else the option
        from millpath.io.tooltable import file_table_units
        mu = file_table_units(tools_path) or machine_units or "inch"
        res = _interpret(program, tools_path, mu)
        units = res.units
        k = 1.0 if mu == units else (25.4 if mu == "inch" else 1.0 / 25.4)
        tools, tool_arg = _read_tools(tools_path, units, k)
    else:
        # TOML tool libraries are in the program's units: interpret in mm, again if inch
        tools, tool_arg = _read_tools(tools_path, "mm")
        res = _interpret(program, tool_arg, "mm")
        units = res.units
        if units == "inch":
            tools, tool_arg = _read_tools(tools_path, "inch")
            res = _interpret(program, tool_arg, "inch")
    motions = list(res.motions)
    used = sorted({m.tool for m in motions if m.kind != "dwell" and m.tool != 0})
    for t in used:
        if t not in tools:
            line = next(m.line for m in motions if m.tool == t)
            hint = (f" in {tools_path} (a tool table row needs a diameter D)"
                    if tools_path else "; give --tools")
            raise MillpathError(f"tool {t} is not defined{hint}", program, line)
    if not used and any(m.kind != "dwell" for m in motions):
        click.echo("millpath: warning: no tool is loaded (T.. M6): nothing is cut", err=True)
    if resolution is None:
        w, h, _ = stock.size
        resolution = max(w, h) / 1000.0
        if used:
            resolution = min(resolution, min(tools[t].diameter for t in used) / 10.0)
    if not (resolution > 0 and math.isfinite(resolution)):
        raise MillpathError(f"--resolution must be a positive length, not {resolution}")
    try:
        r = simulate_motions(motions, tools, stock, resolution=resolution, design=design,
                             machine=Machine.default_for(units),
                             progress=not as_json and sys.stderr.isatty())
    except ValueError as e:                    # --resolution too fine, a tool's shape
        raise MillpathError(str(e), program) from None
    if png is not None:
        render_stock(r.zmap, png, title=f"{program.name}: simulated stock", units=units)
        if design is not None:
            render_deviation(r.zmap, design, png.with_name(png.stem + "_deviation.png"),
                             units=units)
    j = r.to_json()
    if as_json:
        click.echo(json.dumps(j, indent=2))
        return
    u3 = f"{units}^3"
    click.echo(f"{program.name}: {len(motions)} motions, {units}, resolution {resolution:g}")
    click.echo(f"removed volume   {j['removed_volume']:.6g} {u3}")
    if design is not None:
        at = (lambda p: f" at X{p[0]:.4g} Y{p[1]:.4g}" if p else "")
        click.echo(f"max gouge        {j['max_gouge']:.4g} {units}{at(r.gouge_at)}")
        click.echo(f"max left         {j['max_left']:.4g} {units}{at(r.left_at)}")
        click.echo(f"left volume      {j['left_volume']:.6g} {u3}")
    click.echo(f"rapids through material  {j['rapids_through_material']}"
               + (f" (lines {', '.join(map(str, r.rapid_lines[:10]))})" if r.rapid_lines else ""))
    click.echo(f"holder contacts          {j['holder_contacts']}"
               + (f" (lines {', '.join(map(str, r.holder_lines[:10]))})" if r.holder_lines else ""))
    click.echo(f"cycle time       {j['cycle_time_s']:.1f} s")
