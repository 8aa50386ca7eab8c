"""``millpath drop SURFACE --tool ball:6 --xy POINTS.csv``: drop-cutter at given points.

For each (x, y) of POINTS the tool comes down along -Z until it touches the surface;
the output row is ``x,y,z`` with ``z`` the tool tip Z (the cutter-location point),
in the surface's units. Optional columns: ``lifted`` (with ``--holder``) and the
contact point ``cx,cy,cz`` (with ``--contact``).
"""

from __future__ import annotations

import io
from pathlib import Path

import click
import numpy as np

from millpath.errors import MillpathError
from millpath.io.text import read_number_rows
from millpath.model.limits import (MAX_DIVISIONS, MAX_EXTENT, MAX_TOLERANCE,
                                   MIN_CHORD_TOLERANCE, TOOL_DIAMETER, check_coordinate)

_HELP_HOLDER = (
    "Holder cylinders DIAMETER:LENGTH[,DIAMETER:LENGTH...] stacked upward from the holder "
    "face, which sits --tool-length above the tip. Where the holder would touch the "
    "surface the tool is lifted until it clears it (column lifted = 1; the cutter no "
    "longer touches there).")


def read_points(path: Path) -> np.ndarray:
    """``(n, 2)`` x, y rows: comma, semicolon or whitespace separated; ``#`` comments,
    blank lines and one header line before the first row are allowed."""
    return read_number_rows(path, "x, y")


def parse_holder(spec: str, tool_length: float) -> tuple[tuple[float, float, float], ...]:
    """``D:L,D:L`` -> ``(radius, z_bottom, z_top)`` above the tip, from ``tool_length`` up."""
    out = []
    z = tool_length
    for part in spec.split(","):
        try:
            d, length = (float(v) for v in part.strip().split(":"))
        except ValueError:
            raise MillpathError(f"bad holder cylinder {part.strip()!r}: expected "
                                "DIAMETER:LENGTH", entity="--holder") from None
        if not (0 < d <= MAX_EXTENT.mm and 0 < length <= MAX_EXTENT.mm):
            raise MillpathError(f"bad holder cylinder {part.strip()!r}: diameter and length "
                                f"must be above 0 and at most {MAX_EXTENT.mm:g}",
                                entity="--holder")
        out.append((d / 2.0, z, z + length))
        z += length
    return tuple(out)


def _num(v: float) -> str:
    return f"{v:.12g}"


@click.command(name="drop")
@click.argument("surface", type=click.Path(dir_okay=False, path_type=Path))
@click.option("--tool", "tool_spec", required=True, metavar="SHAPE:D[:R]",
              help="ball:D, flat:D or bull:D:R (diameter D, corner radius R, surface units).")
@click.option("--xy", "points", required=True, type=click.Path(dir_okay=False, path_type=Path),
              help="x,y rows (comma, semicolon or whitespace separated; one header line "
                   "and # comments allowed).")
@click.option("--tool-length", type=float, default=None, metavar="L",
              help="Tip to holder face (stick-out); needed with --holder.")
@click.option("--holder", default=None, metavar="D:L[,D:L...]", help=_HELP_HOLDER)
@click.option("--holder-clearance", type=float, default=0.0, show_default=True,
              help="Gap kept between the holder and the surface.")
@click.option("--contact", is_flag=True,
              help="Add columns cx,cy,cz: where the cutter touches (empty where it touches "
                   "nothing, or where the holder lifted it).")
@click.option("--floor", "z_floor", type=float, default=None,
              help="Tip Z where the cutter touches nothing (default: the surface's lowest Z).")
@click.option("--divisions", type=int, default=160, show_default=True,
              help="Bezier surfaces: cells per direction; measured grids: least cells along "
                   "the longer side.")
@click.option("--chord-tolerance", type=float, default=0.01, show_default=True,
              help="STEP surfaces: largest distance between a face and its triangles.")
@click.option("-o", "--output", type=click.Path(dir_okay=False, path_type=Path), default=None,
              help="Write the rows to this CSV file (default: standard output).")
def command(surface: Path, tool_spec: str, points: Path, tool_length: float | None,
            holder: str | None, holder_clearance: float, contact: bool,
            z_floor: float | None, divisions: int, chord_tolerance: float,
            output: Path | None) -> None:
    """Drop a cutter onto SURFACE at each point of --xy and print x,y,z rows: z is
    the tool tip Z (cutter-location point) where the cutter first touches the surface
    coming down along -Z.

    SURFACE: STL (binary or ASCII), TOML Bezier net, measured grid (.csv, .xyz, .txt
    of x,y,z) or STEP (needs millpath[step-brep]). All lengths are in the surface's
    units. The first output line is a header naming the columns.

    \b
    Example:
      millpath drop part.stl --tool bull:10:2 --xy points.csv --contact -o cl.csv
    """
    from millpath.io.atomic import write_text
    from millpath.part.surface.load import load_surface
    from millpath.geometry.cutter import Cutter
    from millpath.plan.surface.dropcutter import build_index, drop
    from millpath.plan.surface.sampler import Sampler

    try:
        cutter = Cutter.parse(tool_spec)
    except ValueError as e:
        raise MillpathError(str(e), entity="--tool") from None
    # the surface's units are known once it is read: bounds loose enough for either
    lo, hi = TOOL_DIAMETER[0].inch, TOOL_DIAMETER[1].mm
    if not (lo <= 2.0 * cutter.radius <= hi):
        raise MillpathError(f"a diameter of {2.0 * cutter.radius:g} is outside {lo:g} .. "
                            f"{hi:g} (surface units)", entity="--tool")
    if not (1 <= divisions <= MAX_DIVISIONS):
        raise MillpathError(f"must be 1 .. {MAX_DIVISIONS}, got {divisions}",
                            entity="--divisions")
    if not (MIN_CHORD_TOLERANCE <= chord_tolerance <= MAX_TOLERANCE.mm):
        raise MillpathError(f"must be {MIN_CHORD_TOLERANCE:g} .. {MAX_TOLERANCE.mm:g} "
                            f"(surface units), got {chord_tolerance:g}",
                            entity="--chord-tolerance")
    cylinders: tuple[tuple[float, float, float], ...] = ()
    if holder is not None:
        if tool_length is None:
            raise MillpathError("give --tool-length (tip to holder face) with --holder",
                                entity="--holder")
        if not (0 < tool_length <= MAX_EXTENT.mm):
            raise MillpathError(f"must be above 0 and at most {MAX_EXTENT.mm:g} (surface "
                                f"units), got {tool_length:g}", entity="--tool-length")
        cylinders = parse_holder(holder, tool_length)
    elif tool_length is not None:
        raise MillpathError("places the holder face; give --holder too",
                            entity="--tool-length")
    if not (0 <= holder_clearance <= MAX_EXTENT.mm):
        raise MillpathError(f"must be 0 .. {MAX_EXTENT.mm:g} (surface units), got "
                            f"{holder_clearance:g}", entity="--holder-clearance")
    if z_floor is not None and check_coordinate(z_floor):
        raise MillpathError(check_coordinate(z_floor), entity="--floor")
    xy = read_points(points)
    mesh = load_surface(str(surface), divisions, Path("."), chord_tolerance=chord_tolerance)
    floor = float(mesh.bounds[0][2]) if z_floor is None else z_floor
    index = build_index(mesh)
    hit = drop(index, cutter, xy)                  # -inf where the cutter touches nothing
    zc = np.maximum(hit.z, floor)
    zh = Sampler(index, cutter, 0.0, cylinders,
                 holder_clearance=holder_clearance).holder_lift(xy[:, 0], xy[:, 1])
    lifted = zh > zc + 1e-9
    z = np.maximum(zc, zh)
    touching = np.isfinite(hit.z) & (hit.z >= z - 1e-9)   # not floored, not lifted
    cols = (["x", "y", "z"] + (["lifted"] if holder is not None else [])
            + (["cx", "cy", "cz"] if contact else []))
    buf = io.StringIO()
    buf.write(",".join(cols) + "\n")
    for k in range(len(xy)):
        row = [_num(xy[k, 0]), _num(xy[k, 1]), _num(z[k])]
        if holder is not None:
            row.append("1" if lifted[k] else "0")
        if contact:
            row += [_num(v) for v in hit.cc[k]] if touching[k] else ["", "", ""]
        buf.write(",".join(row) + "\n")
    if output is None:
        click.echo(buf.getvalue(), nl=False)
    else:
        write_text(output, buf.getvalue())
