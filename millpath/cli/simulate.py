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


def _read_tools(path: Path | None, units: str):
    """Tool shapes by number, and what to hand the interpreter."""
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
    tools = {e.number: Tool(e.number, "flat", e.diameter, comment=e.comment)
             for e in entries if e.diameter > 0}
    return tools, path


def _design(path: Path, stock):
    """The design file as (height-field design for the Z-map, exact-check references).
    Errors name the file: unreadable, non-finite vertices, no triangles, or a design
    wholly outside the stock (mixed units)."""
    from millpath.part.surface.load import load_surface
    from millpath.simulate import MeshDesign
    from millpath.simulate.exact import Reference, orient_outward
    if not path.is_file():
        raise MillpathError("design file not found", path)
    try:
        mesh = load_surface(str(path.resolve()), 64, path.parent, path)
    except MillpathError as e:
        if e.file is None:
            e.file = str(path)
        raise
    tri = mesh.triangles
    lo, hi = tri.reshape(-1, 3).min(axis=0), tri.reshape(-1, 3).max(axis=0)
    b = stock.box
    if (hi[0] < b[0] or lo[0] > b[3] or hi[1] < b[1] or lo[1] > b[4] or hi[2] < b[2]
            or lo[2] > b[5]):
        raise MillpathError(f"the design lies wholly outside the stock {list(b)} "
                            f"(design box {lo.round(4).tolist()} to {hi.round(4).tolist()}; "
                            "different units?)", path)
    try:
        design = MeshDesign(tri)          # its top surface, for the Z-map's figures
    except ValueError:
        design = None                     # walls only: the exact check alone
    return design, [Reference(orient_outward(tri), path.name, None)]


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
              help="Designed part (STL, STEP with millpath[step-brep], Bezier net .toml) "
                   "for the exact gouge and material-left checks.")
@click.option("--resolution", type=float, default=None,
              help="Z-map cell size (default: stock size / 1000, at most D/10 of the "
                   "smallest tool).")
@click.option("--json", "as_json", is_flag=True, help="Print the results as JSON.")
@click.option("--png", "png", type=click.Path(path_type=Path), default=None,
              help="Write a shaded picture of the stock (and FILE_deviation.png with "
                   "--design).")
def command(program: Path, tools_path: Path | None, stock_text: str,
            design_path: Path | None, resolution: float | None, as_json: bool,
            png: Path | None) -> None:
    """Simulate PROGRAM on a block of stock: removed volume, gouges, material left,
    rapids through material, holder contacts and cycle time."""
    from millpath.model.stock import Machine
    from millpath.simulate import MeshDesign, render_deviation, render_stock, simulate_motions

    if not program.is_file():
        raise MillpathError("program not found", program)
    stock = _stock(stock_text)
    design, refs = None, None
    if design_path is not None:
        design, refs = _design(design_path, stock)
    # tool files are in the program's units: interpret once in mm, again if it is inch
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
    r = simulate_motions(motions, tools, stock, resolution=resolution, design=design,
                         machine=Machine.default_for(units),
                         progress=not as_json and sys.stderr.isatty(), references=refs,
                         accuracy=0.001 if units == "mm" else 0.00004)
    if png is not None:
        render_stock(r.zmap, png, title=f"{program.name}: simulated stock", units=units)
        if design is not None:
            render_deviation(r.zmap, design, png.with_name(png.stem + "_deviation.png"),
                             units=units, gouge_at=r.gouge_at, left_at=r.left_at,
                             gouge=r.exact.max_gouge if r.exact else None,
                             left=r.exact.max_left if r.exact else None)
    j = r.to_json()
    if as_json:
        click.echo(json.dumps(j, indent=2))
        return
    u3 = f"{units}^3"
    click.echo(f"{program.name}: {len(motions)} motions, {units}, resolution {resolution:g}")
    click.echo(f"removed volume   {j['removed_volume']:.6g} {u3}")
    if refs is not None:
        def at(p):
            return (f" at X{p['x']:.4g} Y{p['y']:.4g} Z{p['z']:.4g}"
                    + (f" (line {p['line']})" if p.get("line") is not None else "")) if p else ""
        click.echo(f"max gouge        {j['max_gouge']:.4g} {units}{at(j.get('max_gouge_at'))}"
                   f", {j.get('gouging_moves', 0)} gouging motions")
        click.echo(f"max left         {j['max_left']:.4g} {units}{at(j.get('max_left_at'))}")
        click.echo(f"accuracy         {j.get('accuracy')} {units} (normal to the design)")
        if j["left_volume"] is not None:
            click.echo(f"left volume      {j['left_volume']:.6g} {u3}")
    click.echo(f"rapids through material  {j['rapids_through_material']}"
               + (f" (lines {', '.join(map(str, r.rapid_lines[:10]))})" if r.rapid_lines else ""))
    click.echo(f"holder contacts          {j['holder_contacts']}"
               + (f" (lines {', '.join(map(str, r.holder_lines[:10]))})" if r.holder_lines else ""))
    click.echo(f"cycle time       {j['cycle_time_s']:.1f} s")
