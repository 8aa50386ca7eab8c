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

from millpath.cli.programs import ProgramArgs, program_options
from millpath.errors import MillpathError
from millpath.model.limits import MAX_TOLERANCE


@click.command()
@program_options("the stock is coloured by deviation from it.")
@click.option("--tolerance", type=float, default=None,
              help="Deviation drawn as neutral (default 0.01 mm / 0.0005 inch); the page "
                   "can change it.")
@click.option("-o", "--output", "output", type=click.Path(path_type=Path),
              default=Path("view.html"), show_default=True, help="HTML file to write.")
def command(args: ProgramArgs, tolerance: float | None, output: Path) -> None:
    """Write an interactive 3D view of PROGRAM: tool path, stock, simulated stock
    coloured by deviation from the design, and a player that runs it move by move."""
    from millpath.report.viewer import write_view
    from millpath.simulate.approach import approach_from_above

    if tolerance is not None and not 0 <= tolerance <= MAX_TOLERANCE.mm:
        raise MillpathError(f"--tolerance must be a length of 0 .. {MAX_TOLERANCE.mm:g} "
                            f"(program units), not {tolerance:g}")
    program = args.program
    sp = args.simulate(progress=sys.stderr.isatty())
    motions = approach_from_above(sp.motions, sp.stock.zmax)
    if not motions:
        raise MillpathError("the program has no motion to show", program)
    write_view(output, program=program.read_text(errors="replace"), motions=motions,
               tools=sp.tools, stock=sp.stock, units=sp.units, sim=sp.result,
               design=sp.design, tolerance=tolerance, title=program.name,
               program_name=program.name)
    click.echo(f"wrote {output}")
