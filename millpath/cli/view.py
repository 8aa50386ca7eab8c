"""``millpath view PROGRAM.ngc``: an interactive 3D view (view.html) of any program.

The program is interpreted and simulated as ``millpath simulate`` does (see
:mod:`millpath.cli.programs` for ``--tools``, ``--stock`` and ``--design``), then written
as one self-contained HTML page (:mod:`millpath.report.viewer`) that opens from disk in
a current browser with no network.
"""

from __future__ import annotations

import sys
from pathlib import Path

import click

from millpath.cli.programs import program_options, simulate_program
from millpath.errors import MillpathError


@click.command()
@program_options("Designed part (STL, or any surface millpath drop reads): the stock "
                 "is coloured by deviation from it.")
@click.option("--tolerance", type=float, default=None,
              help="Deviation drawn as neutral (default 0.01 mm / 0.0005 inch); the page "
                   "can change it.")
@click.option("-o", "--output", "output", type=click.Path(path_type=Path),
              default=Path("view.html"), show_default=True, help="HTML file to write.")
def command(program: Path, tools_path: Path | None, stock_text: str,
            design_path: Path | None, resolution: float | None, machine_units: str | None,
            spindle_tool: int,
            tolerance: float | None, output: Path) -> None:
    """Write an interactive 3D view of PROGRAM: tool path, stock, simulated stock
    coloured by deviation from the design, and a player that runs it move by move."""
    from millpath.report.viewer import write_view
    from millpath.simulate.approach import approach_from_above

    if tolerance is not None and not tolerance >= 0:
        raise MillpathError(f"--tolerance must be a length >= 0, not {tolerance}")
    sp = simulate_program(program, tools_path, stock_text, design_path, resolution,
                          progress=sys.stderr.isatty(), machine_units=machine_units,
                          spindle_tool=spindle_tool)
    motions = approach_from_above(sp.motions, sp.stock.zmax)
    if not motions:
        raise MillpathError("the program has no motion to show", program)
    write_view(output, program=program.read_text(errors="replace"), motions=motions,
               tools=sp.tools, stock=sp.stock, units=sp.units, sim=sp.result,
               design=sp.design, tolerance=tolerance, title=program.name,
               program_name=program.name)
    click.echo(f"wrote {output}")
