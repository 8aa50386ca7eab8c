"""``millpath fit PROGRAM.ngc --tolerance T``: arcs and cubics for an existing program,
read back by the interpreter before it is written (:mod:`millpath.fit.readback`)."""

from __future__ import annotations

import time
from pathlib import Path

import click

from millpath.errors import MillpathError
from millpath.io.atomic import write_text


@click.command(name="fit")
@click.argument("program", type=click.Path(dir_okay=False, path_type=Path))
@click.option("--tolerance", "-t", type=float, required=True,
              help="Largest distance between the original and the fitted path "
                   "(program units).")
@click.option("--mode", type=click.Choice(["arcs", "arcs+cubics"]), default="arcs",
              show_default=True, help="Fit arcs only, or arcs and G5 cubics (XY).")
@click.option("--min-radius", type=float, default=0.0, show_default=True,
              help="Arcs get a larger radius than this (program units), e.g. the tool "
                   "radius, so that concave arcs stay larger than the tool.")
@click.option("-o", "--output", type=click.Path(dir_okay=False, path_type=Path),
              default=None, help="Output program (default: PROGRAM-fit.ngc beside it).")
def command(program: Path, tolerance: float, mode: str, min_radius: float,
            output: Path | None) -> None:
    """Rewrite runs of G1 moves in PROGRAM as G2/G3 arcs (and G5 cubics) within
    --tolerance; every other line stays as written. The output is read back by the
    interpreter and compared with PROGRAM's motion before it is written."""
    from millpath.fit import MAX_RADIUS_MM, fit_program
    from millpath.fit.program import FitStats
    from millpath.model.limits import MAX_TOLERANCE
    # the program's units are known once it is read: bounds loose enough for either
    if not (0 < tolerance <= MAX_TOLERANCE.mm):
        raise MillpathError(f"--tolerance {tolerance:g}: the fit tolerance must be above 0 "
                            f"and at most {MAX_TOLERANCE.mm:g} (program units)", program)
    if not (0 <= min_radius <= MAX_RADIUS_MM):
        raise MillpathError(f"--min-radius {min_radius:g}: the min radius must be 0 .. "
                            f"{MAX_RADIUS_MM:g} (program units; larger arcs are written as "
                            f"lines)", program)
    stats = FitStats()
    try:
        text = program.read_text()
    except UnicodeDecodeError:
        raise MillpathError("not a text file", program) from None
    t0 = time.perf_counter()
    try:
        out = fit_program(text, tolerance, mode, min_radius=min_radius, file=str(program),
                          stats=stats)
    except ValueError as e:                    # --tolerance / --min-radius out of range
        raise MillpathError(str(e), program) from None
    dt = time.perf_counter() - t0
    target = output if output is not None else program.with_name(program.stem + "-fit.ngc")
    if target.resolve() == program.resolve():
        raise MillpathError("the output would overwrite the input program; give -o", program)
    from millpath.verify.readback import read_back
    back = read_back(text, out, tolerance, file=program)   # nothing unproven is written
    write_text(target, out)
    before = sum(1 for l in text.splitlines() if l.strip())
    after = sum(1 for l in out.splitlines() if l.strip())
    click.echo(f"{target}: {before} -> {after} blocks, {len(text.encode())} -> "
               f"{len(out.encode())} bytes ({dt:.2f} s); read back: {back.motions} "
               f"motions, {back.compared} fitted, within {back.deviation:.4g} of the "
               f"program")
    if stats.rewritten == 0:
        click.echo(why_unchanged(stats, tolerance))


def why_unchanged(s, tolerance: float) -> str:
    """Why ``millpath fit`` rewrote nothing, from its :class:`FitStats`."""
    if s.moves == 0:
        return "nothing to fit: the program has no G1 moves with coordinates"
    parts = [f"nothing fitted: of {s.moves} G1 moves"]
    if s.kept:
        parts.append(f"{s.kept} could not be fitted within --tolerance {tolerance:g} "
                     f"(merging two neighbouring moves into one line needs a deviation "
                     f"of {s.merge_min:.4g}; {s.merge_max:.4g} to change every run)")
    for why, n in sorted(s.skipped.items(), key=lambda kv: -kv[1]):
        parts.append(f"{n} {why}")
    return parts[0] + ", " + "; ".join(parts[1:])
