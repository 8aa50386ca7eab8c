"""Drawing keys of pocket and profile operations and the regions they name.

``dxf = "part.dxf"`` (with ``layer``, ``join_tolerance``) or ``polygon = [[x, y], ...]``
with ``islands = [[[x, y], ...], ...]``; ``tolerance`` (job units) is the operation's
chordal tolerance.

A drawing's curves (arcs, circles, bulges, splines, ellipses) become contours that
follow them within ``CURVE_FRACTION x tolerance`` and lie on their air side (where the
tool may go): flattened with chords within half of that (vertices on the curve) and
then moved by as much toward the air (:func:`millpath.part.drawing.shift_region`). The
air is inside the contour for a pocket and an inside profile, outside it for an
outside profile (``side = "outside"``). Tool paths offset from such a contour keep the
tool out of the drawn material by construction, and a design made from it (the pocket's
floor and walls) holds all the drawn material and at most a sliver of the drawn air
along its walls: a gouge measured against it is the true one or more (by at most the
bound), the material left the true one or less.
A circle of radius ``r`` takes about ``pi sqrt(r / (CURVE_FRACTION x tolerance))``
chords (r = 12 mm at 0.01 mm: about 490). Polygon keys are taken as exact.
"""

from __future__ import annotations

from millpath.errors import JobError
from millpath.io.schema import Param
from millpath.part.cache import PartCache
from millpath.part.drawing import (Region, read_dxf, region_from_polygon, regions_from_loops,
                                   shift_region)
from millpath.model.units import default

GEOMETRY_PARAMS = {
    "dxf": Param("path", None, doc="DXF drawing of the contours"),
    "layer": Param("str", None, doc="DXF layer (default: all layers)"),
    "join_tolerance": Param("float", None, positive=True,
                            doc="largest gap closed between entity ends (default 10 x tolerance)", unit="length"),
    "polygon": Param("points", None, doc="outer contour [[x, y], ...]"),
    "islands": Param("list", None, doc="islands [[[x, y], ...], ...] inside the polygon"),
    "tolerance": Param("float", None, positive=True, unit="length",
                       doc="the operation's tolerance: drawn curves followed within a 20th "
                           "of it; the deepest gouge its proof allows (default 0.01 mm / "
                           "0.0005 in)"),
}


#: drawn curves are followed within this fraction of the operation's tolerance
CURVE_FRACTION = 1.0 / 20.0


def default_tolerance(units: str) -> float:
    return default("drawing_tolerance", units)


def load_regions(params: dict, units: str, file=None,
                 parts: PartCache | None = None) -> list[Region]:
    """The regions (outer contour with islands) the operation's keys describe; a
    drawing is read once per ``parts`` cache (the job's) and air side. A drawing's
    contours are within ``CURVE_FRACTION x tolerance`` of its curves, on their air side
    (see the module docstring)."""
    tol = params["tolerance"] or default_tolerance(units)
    if (params["dxf"] is None) == (params["polygon"] is None):
        raise JobError("give exactly one of dxf (a drawing) or polygon (points)", file)
    if params["dxf"] is not None:
        if params["islands"] is not None:
            raise JobError("islands: not used with dxf (islands are the drawing's inner "
                           "contours)", file)
        half = 0.5 * CURVE_FRACTION * tol        # chords within it, then moved by it
        grow = params.get("side") == "outside"   # the air outside the contour

        def load() -> list[Region]:
            loops = read_dxf(params["dxf"], units, half, layer=params["layer"],
                             join_tolerance=params["join_tolerance"] or 10.0 * tol)
            return [shift_region(r, half if grow else -half)
                    for r in regions_from_loops(loops, params["dxf"])]
        if parts is None:
            return load()
        key = (params["dxf"], units, tol, params["layer"], params["join_tolerance"], grow)
        return list(parts.get("drawing", key, load))
    islands = params["islands"] or []
    for k, q in enumerate(islands):
        if (not isinstance(q, list) or len(q) < 3
                or not all(isinstance(p, list) and len(p) in (2, 3) and all(
                    isinstance(v, (int, float)) and not isinstance(v, bool) for v in p)
                    for p in q)):
            raise JobError(f"islands[{k}]: expected a list of at least 3 points [x, y]", file)
    return [region_from_polygon(params["polygon"], islands, file)]
