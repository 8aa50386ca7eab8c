"""``millpath simulate PROGRAM.ngc``: material removal, gouge check and cycle time.

The program is interpreted by millpath's RS274NGC interpreter and its motion swept
through a Z-map of the stock (see :mod:`millpath.simulate`). ``--tools`` is a LinuxCNC
tool table (``T1 P1 D6 Z50``: flat end mills of diameter D) or a TOML tool library
(``[[tools]]`` with ``type``, ``diameter``, ``corner_radius``, ...), in the program's
units. Everything printed is in program units.
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

import click

from millpath.cli.programs import ProgramArgs, program_options
from millpath.model.units import default


@click.command()
@program_options("exact gouge and material-left checks, measured normal to it.")
@click.option("--max-feed", type=float, default=None,
              help="Machine's feed limit for the cycle time, program units/min (default "
                   "3000 mm/min, 120 in/min); faster feeds are capped with a warning.")
@click.option("--json", "as_json", is_flag=True, help="Print the results as JSON.")
@click.option("--png", "png", type=click.Path(path_type=Path), default=None,
              help="Write a shaded picture of the stock (and FILE_deviation.png with "
                   "--design).")
def command(args: ProgramArgs, max_feed: float | None, as_json: bool,
            png: Path | None) -> None:
    """Simulate PROGRAM on a block of stock: removed volume, gouges, material left,
    rapids through material, holder contacts and cycle time."""
    from millpath.simulate import render_deviation, render_stock

    sp = args.simulate(progress=not as_json and sys.stderr.isatty(), max_feed=max_feed)
    program, tools_path = args.program, args.tools
    r, design, units, motions = sp.result, sp.design, sp.units, sp.motions
    resolution = sp.resolution
    if png is not None:
        render_stock(r.zmap, png, title=f"{program.name}: simulated stock", units=units)
        if design is not None:
            render_deviation(r.zmap, design, png.with_name(png.stem + "_deviation.png"),
                             units=units, gouge_at=r.gouge_at, left_at=r.left_at,
                             tolerance=default("verify_accuracy", units),
                             gouge=r.exact.max_gouge if r.exact else None,
                             left=r.exact.max_left if r.exact else None,
                             grid=r.design_grid)
    j = r.to_json()
    if as_json:
        click.echo(json.dumps(j, indent=2))
        return
    u3 = f"{units}^3"
    click.echo(f"{program.name}: {len(motions)} motions, {units}, resolution {resolution:g}")
    click.echo(f"removed volume   {j['removed_volume']:.6g} {u3}")
    if j["max_gouge"] is not None:
        def at(p):
            return (f" at X{p['x']:.4g} Y{p['y']:.4g} Z{p['z']:.4g}"
                    + (f" (line {p['line']})" if p.get("line") is not None else "")) if p else ""
        click.echo(f"max gouge        {j['max_gouge']:.4g} {units}{at(j.get('max_gouge_at'))}"
                   f", {j.get('gouging_moves', 0)} gouging motions")
        click.echo(f"max left         {j['max_left']:.4g} {units}{at(j.get('max_left_at'))}"
                   + (f" (sampled every {j['left_spacing']:.3g} {units}: material narrower "
                      "than that between samples can be missed)"
                      if j.get("left_spacing") else ""))
        click.echo(f"accuracy         {j.get('accuracy')} {units}")
        if j["left_volume"] is not None:
            click.echo(f"left volume      {j['left_volume']:.6g} {u3}")
    click.echo(f"rapids through material  {j['rapids_through_material']}"
               + (f" (lines {', '.join(map(str, r.rapid_lines[:10]))})" if r.rapid_lines else ""))
    click.echo(f"holder contacts          {j['holder_contacts']}"
               + (f" (lines {', '.join(map(str, r.holder_lines[:10]))})" if r.holder_lines else "")
               + ("" if tools_path is None or tools_path.suffix.lower() == ".toml" else
                  " (holders not checked: a tool table has no holder; use a .toml library)"))
    click.echo(f"cycle time       {j['cycle_time_s']:.1f} s")
