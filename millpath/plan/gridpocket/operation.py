"""Job operation ``type = "grid-pocket"``: a free-form pocket by grid navigation.

Keys (job units: mm or inch; feeds in units per minute; Z absolute, tool tip):

- ``tool``: tool number (flat, ball or bull end mill).
- ``polygon``: the walls, ``[[x, y], ...]``, a simple polygon (convex or concave).
- ``bottom``: the pocket bottom, either
  ``{bezier = [[z, ...], ...]}``: a Bezier control net of Z values over ``box``
  (default: the polygon's bounding box), one inner list per row of constant Y from the
  lowest Y up, entries along X; or of full ``[x, y, z]`` control points; or
  ``{points = "file.csv"}``: measured ``x,y,z`` rows on a (near-)regular grid,
  interpolated ``linear`` (default) or ``cubic`` (key ``interpolation``).
- ``grid = [dx, dy]``: cell size (default D/2 both); larger than D/sqrt(2) is an error.
- ``grid_centre = [x, y]``: a cell centre the grid is anchored to (default: the cells
  tile the polygon's bounding box from its lower-left corner).
- ``navigation``: direction priority of the main path, ``wall-first`` (default, the
  thesis's Figs 9-12: the clockwise turn towards the wall first, then
  counter-clockwise) or ``straight-first`` (straight on first); see ``navigate``.
- ``depths`` (absolute floor Z per roughing layer) or ``stepdown`` (uniform depth of cut);
  neither: a single finish layer. A roughing layer cuts at ``max(bottom, floor)`` the
  cells whose bottom is below its floor; the last layer is always the finish: every
  cell, down to the bottom, at ``finish_feed``.
- ``motion``: ``line`` | ``arc`` | ``bezier``; ``tolerance``: fitting tolerance
  (default 0.0002 in / 0.005 mm); ``bezier_parameters``: ``chord`` (default) or
  ``uniform`` (the thesis's u1 = 1/(n-1)).
- ``zigzag``: X and Y clean-up runs (default true).
- ``feed``, ``finish_feed`` (default feed), ``plunge_feed`` (default feed / 2),
  ``spindle`` (rpm, required: a pocket is never cut with the spindle off), ``safe_z`` (default stock top + 0.2 in / 5 mm).
- ``rest``: keep only the moves whose tool meets more than ``allowance`` (default: the
  in-process stock's cell width) of the stock left by earlier operations, Z included
  (:mod:`millpath.plan.restcut`); the report's ``pocket.rest`` gives the figures.
- ``z_mode``: ``tool`` (drop the real tool onto the bottom: no gouge) or ``surface``
  (the tip on the surface under the tool centre, as in the thesis).
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import shapely

from millpath.errors import GeometryError, JobError
from millpath.io.schema import Param
from millpath.part.surface import BezierPatch, MeasuredGrid
from millpath.plan.base import PlanContext, PlanResult
from millpath.plan.gridpocket.cells import pocket_polygon, polygon_problem
from millpath.plan.gridpocket.planner import PocketSpec, plan_pocket
from millpath.model.units import default
from millpath.plan.restparams import REST_PARAMS

BOTTOM_KEYS = ("bezier", "box", "points", "interpolation")


def _num(v) -> bool:
    return isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v)


def _bottom_problem(t: dict) -> str | None:
    unknown = [k for k in t if k not in BOTTOM_KEYS]
    if unknown:
        return f"unknown key {unknown[0]!r} (allowed: {', '.join(BOTTOM_KEYS)})"
    if ("bezier" in t) == ("points" in t):
        return "give exactly one of bezier (control net) or points (CSV file)"
    if "bezier" in t:
        net = t["bezier"]
        if not isinstance(net, list) or len(net) < 2 or not all(isinstance(r, list) for r in net):
            return "bezier: expected a list of at least 2 rows"
        lens = {len(r) for r in net}
        if len(lens) != 1 or lens.pop() < 2:
            return "bezier: every row needs the same number (at least 2) of entries"
        flat = [v for r in net for v in r]
        if all(_num(v) for v in flat):
            pass
        elif all(isinstance(v, list) and len(v) == 3 and all(_num(c) for c in v) for v in flat):
            pass
        else:
            return "bezier: entries must be finite Z values or [x, y, z] points"
        if "box" in t:
            b = t["box"]
            if not (isinstance(b, list) and len(b) == 4 and all(_num(v) for v in b)
                    and b[0] < b[2] and b[1] < b[3]):
                return "box: expected [xmin, ymin, xmax, ymax] with min < max"
    else:
        if not isinstance(t["points"], str):
            return "points: expected a file name"
        if "box" in t:
            return "box: only with a bezier net"
        if t.get("interpolation", "linear") not in ("linear", "cubic"):
            return "interpolation: must be 'linear' or 'cubic'"
    return None


def _depths_problem(v: list[float]) -> str | None:
    if not v:
        return "expected at least one depth"
    if any(b >= a for a, b in zip(v, v[1:])):
        return "depths must be strictly descending (top layer first)"
    return None


def _grid_problem(v: list[float]) -> str | None:
    return None if all(x > 0 for x in v) else "cell sizes must be positive"


PARAMS: dict[str, Param] = {
    "tool": Param("int", positive=True, doc="tool number"),
    "polygon": Param("points", check=polygon_problem, doc="pocket walls [[x, y], ...]"),
    "bottom": Param("table", check=_bottom_problem, doc="{bezier = [[...]]} or {points = "
                                                        "'f.csv'}"),
    "grid": Param("floats", None, length=2, check=_grid_problem, doc="[dx, dy] cell size",
          unit="length"),
    "depths": Param("floats", None, check=_depths_problem, doc="floor Z of each layer",
          unit="length"),
    "stepdown": Param("float", None, positive=True, doc="uniform depth of cut", unit="length"),
    "grid_centre": Param("floats", None, length=2, unit="length",
                         doc="[x, y] of one cell centre the grid is anchored to "
                             "(default: cells tile the bounding box from its corner)"),
    "navigation": Param("str", "wall-first", choices=("wall-first", "straight-first"),
                        doc="direction priority of the main path: the thesis's "
                            "(turn towards the wall first) or straight on first"),
    "motion": Param("str", "line", choices=("line", "arc", "bezier"),
          doc="moves written: lines, arcs, or Bezier cubics (G5)"),
    "bezier_parameters": Param("str", "chord", choices=("chord", "uniform"),
                               doc="cubic fit parameters: chord length, or the thesis's "
                                   "uniform u1 = 1/(n-1)"),
    "tolerance": Param("float", None, positive=True, doc="fitting tolerance", unit="length"),
    "zigzag": Param("bool", True, doc="X and Y zigzag clean-up"),
    "feed": Param("float", positive=True, doc="roughing feed", unit="feed"),
    "finish_feed": Param("float", None, positive=True,
          unit="feed", doc="feed of the finish layer (default: feed)"),
    "plunge_feed": Param("float", None, positive=True,
          unit="feed", doc="feed down into material (default: feed / 2)"),
    "spindle": Param("float", positive=True, doc="rpm, clockwise (M3); required", unit="rpm"),
    "safe_z": Param("float", None, doc="retract height", unit="length"),
    "z_mode": Param("str", "tool", choices=("tool", "surface"),
          doc="'tool': the real tool dropped onto the bottom (no gouge); 'surface': the tip on "
              "the surface under the centre (the thesis)"),
    **REST_PARAMS,
    "force_grid": Param("bool", False, doc="accept cells larger than D/sqrt(2) "
                        "(leaves material uncut in plan view)"),
}


class PocketDesign:
    """The finished part seen from above: the stock top outside the walls, the bottom
    surface (never above the stock top) inside. Job units."""

    def __init__(self, polygon, surface, top: float):
        self.polygon = polygon
        self.surface = surface
        self.top = top
        shapely.prepare(polygon)

    def height(self, x, y) -> np.ndarray:
        x, y = np.broadcast_arrays(np.asarray(x, float), np.asarray(y, float))
        inside = shapely.contains_xy(self.polygon, x, y)
        z = np.full(x.shape, self.top)
        if inside.any():
            z[inside] = np.minimum(self.surface.height(x[inside], y[inside]), self.top)
        return z


def load_bottom(t: dict, polygon, base_dir: Path, file=None):
    """The bottom surface from a validated ``bottom`` table."""
    if "bezier" in t:
        net = np.array(t["bezier"], dtype=float)
        if net.ndim == 2:
            box = t.get("box") or list(polygon.bounds)
            return BezierPatch.from_heights(net.T, tuple(box))
        return BezierPatch(net.transpose(1, 0, 2))
    path = Path(t["points"])
    if not path.is_absolute():
        path = base_dir / path
    return MeasuredGrid.from_csv(path, method=t.get("interpolation", "linear"))


def check_coverage(surface, polygon, file=None) -> None:
    """GeometryError unless the bottom surface lies under the whole outline (a surface
    is never extrapolated silently into a pocket)."""
    ring = np.asarray(polygon.exterior.coords)
    t = np.linspace(0.0, 1.0, 33)[:-1, None]
    pts = np.concatenate([a + (b - a) * t for a, b in zip(ring[:-1], ring[1:])])
    if isinstance(surface, BezierPatch):
        ok = surface.uv_of(pts[:, 0], pts[:, 1])[2]
    else:
        xmin, ymin, xmax, ymax = surface.bounds
        slack = 1e-9 * max(1.0, xmax - xmin, ymax - ymin)
        ok = ((pts[:, 0] >= xmin - slack) & (pts[:, 0] <= xmax + slack)
              & (pts[:, 1] >= ymin - slack) & (pts[:, 1] <= ymax + slack))
    if not np.all(ok):
        x, y = pts[int(np.argmin(ok))]
        raise GeometryError(f"bottom: the surface does not reach the pocket outline at "
                            f"({x:g}, {y:g})", file)


def plan(ctx: PlanContext, params: dict) -> PlanResult:
    """Plan one grid-pocket operation (see the module docstring for the keys)."""
    f = ctx.job_file
    tool = ctx.tool(params["tool"])
    poly = pocket_polygon(params["polygon"], f)
    try:
        surface = ctx.parts.get(     # read once per job
            "grid-bottom", (params["bottom"], poly.bounds, ctx.base_dir),
            lambda: load_bottom(params["bottom"], poly, ctx.base_dir, f))
    except GeometryError as e:
        if e.file is None:
            e.file = str(f) if f else None
            e.message = f"bottom: {e.message}"
            e.args = (e.message,)
        raise
    check_coverage(surface, poly, f)
    top = ctx.stock.zmax if ctx.stock is not None else 0.0
    safe_z = params["safe_z"]
    if safe_z is None:
        safe_z = top + default("safe_clearance", ctx.units)
    if safe_z <= top:
        raise JobError(f"safe_z: {safe_z:g} must be above the stock top {top:g}", f)
    dx, dy = params["grid"] or (tool.diameter / 2.0, tool.diameter / 2.0)
    feed = params["feed"]
    spec = PocketSpec(
        polygon=poly, surface=surface, tool=tool, units=ctx.units, dx=dx, dy=dy, top=top,
        feed=feed, finish_feed=params["finish_feed"] or feed,
        plunge_feed=params["plunge_feed"] or feed / 2.0, safe_z=safe_z,
        tolerance=params["tolerance"] or default("path_tolerance", ctx.units),
        depths=params["depths"], step=params["stepdown"], motion=params["motion"],
        zigzag=params["zigzag"], spindle=params["spindle"], z_mode=params["z_mode"],
        force_grid=params["force_grid"], navigation=params["navigation"],
        grid_anchor=tuple(params["grid_centre"]) if params["grid_centre"] else None,
        bezier_parameters=params["bezier_parameters"], file=f)
    tp, report = plan_pocket(spec)
    if params["rest"] and ctx.remaining is not None:
        from millpath.plan.restcut import rest_filter
        allow = params["rest_allowance"]
        report["rest"] = rest_filter(
            tp, ctx.remaining, ctx.tools,
            allow if allow is not None else float(ctx.remaining.resolution), safe_z,
            default("feed_clearance", ctx.units))
    return PlanResult(toolpath=tp, design=PocketDesign(poly, surface, top),
                      report={"pocket": report})
