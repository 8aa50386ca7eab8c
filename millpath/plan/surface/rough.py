"""Job operation ``type = "surface-rough"``: layered zigzag roughing above a surface.

The tool clears the stock down to the surface plus an ``allowance`` in Z layers
``stepdown`` apart, from the stock top down, so that finishing (``surface-finish``)
meets an even skin instead of the whole block. At every point of a pass the tip goes
to ``max(layer Z, drop-cutter Z + allowance)``: the drop-cutter Z (exact, holder and
shank clearance included, see :mod:`.sampler`) never lets the tool touch the surface,
the layer Z never lets it take more than ``stepdown`` at once. Passes run along
``angle`` (degrees from +X) ``stepover`` apart; each layer keeps only the stretches
that still have material above their target (the layer above did not reach them).
The rows stop up to a step-over short of a wall, so each layer ends with a contour
pass along the line where the floor rises through the layer (the boundary of what the
layer can reach, traced on a fine raster with ``contourpy``), leaving an even
allowance-plus-staircase on steep walls instead of step-over-wide slivers.

Keys (job units; feeds in units per minute): ``surface`` (as for surface-finish),
``divisions``, ``tool``, ``stepdown``, ``stepover`` (length; default 0.6 x the tool
diameter), ``allowance`` (default 0.3 mm / 0.012 in), ``angle``, ``feed``,
``plunge_feed``, ``spindle``, ``safe_z``, ``region`` (tool-tip box, default: the
surface grown by the tool radius), ``name``; ``rest``: keep only the stretches of the
passes where the tool meets the in-process stock left by earlier operations more than
the operation's tolerance above its surface, Z included
(:func:`millpath.plan.surface.rest.rest_passes`; report ``surface_rough.rest``).
"""

from __future__ import annotations

import math

import numpy as np

from millpath.errors import JobError, PlanningError
from millpath.io.schema import Param
from millpath.model.toolpath import Operation, Toolpath
from millpath.plan.base import PlanContext, PlanResult
from millpath.plan.surface.dropcutter import MeshHeight, surface_cutter
from millpath.plan.surface.estimate import (ROUGH_MAX_RASTER, CoarseRaster,
                                            RoughEstimate, estimate_rough)
from millpath.plan.material import MaterialBound
from millpath.plan.surface.linking import add_passes
from millpath.plan.surface.refine import refine_steps, refine_worst
from millpath.plan.surface.sampler import Sampler
from millpath.plan.surface.source import (PLUNGE_FEED, SURFACE_PARAMS, load_op_surface,
                                          op_surface_index, plunge_feed)
from millpath.plan.surface.waterline import index_runs
from millpath.plan.surface.zigzag import Pass, in_region
from millpath.model.units import default

PARAMS = {
    **SURFACE_PARAMS,
    "tool": Param("int", None, positive=True, doc="end mill (tool number)"),
    "stepdown": Param("float", None, positive=True,
          unit="length", doc="depth per layer (default 2 mm / 0.08 in)"),
    "stepover": Param("float", None, positive=True,
          unit="length", doc="distance between passes (default 0.6 x the tool diameter)"),
    "allowance": Param("float", None,
          unit="length", doc="stock left above the surface (default 0.3 mm / 0.012 in)"),
    "angle": Param("float", 0.0, unit="deg", doc="pass direction from +X"),
    "feed": Param("float", None, positive=True,
          unit="feed", doc="cutting feed (default 1500 mm/min / 60 in/min)"),
    "plunge_feed": PLUNGE_FEED,
    "spindle": Param("float", 8000.0, positive=True, unit="rpm", doc="spindle speed"),
    "safe_z": Param("float", None,
          unit="length", doc="retract height (default: above the stock top)"),
    "region": Param("floats", None, length=4,
          unit="length", doc="[xmin, ymin, xmax, ymax] of the tool tip (default: the surface "
                             "grown by the tool radius)"),
    "name": Param("str", "surface rough", doc="operation name in the program and report"),
    "rest": Param("bool", False, doc="cut only where earlier operations left material"),
}


def rough_passes(sampler: Sampler, region, top: float, stepdown: float, step_over: float,
                 allowance: float, tolerance: float) -> tuple[list[Pass], list[float]]:
    """Layer by layer, the zigzag stretches that still cut (tip points in XY frame)."""
    x0, y0, x1, y1 = region
    corners = sampler.uw(np.array([x0, x1, x1, x0]), np.array([y0, y0, y1, y1]))
    umin, umax = corners[:, 0].min(), corners[:, 0].max()
    wmin, wmax = corners[:, 1].min(), corners[:, 1].max()
    du = min(0.5, sampler.cutter.radius / 4.0)
    u = np.linspace(umin, umax, max(2, int(math.ceil((umax - umin) / du)) + 1))
    nw = max(1, int(math.ceil((wmax - wmin) / step_over)))
    ws = np.linspace(wmin, wmax, nw + 1)
    inside, floor, touch = _raster(sampler, region, u, ws)
    if not touch.any():
        return [], []
    # a fine raster of the same floor for the contour pass of each layer
    wf = np.linspace(wmin, wmax, max(2, int(math.ceil((wmax - wmin) / du)) + 1))
    inside_f, floor_f, touch_f = _raster(sampler, region, u, wf)
    floor_f = floor_f + allowance
    floor = floor + allowance
    # the lowest layer reaches the lowest floor of the fine raster too (the rows are
    # a step-over apart and may all miss a narrow cavity's bottom)
    lowest = float(min(floor[touch].min(), floor_f[touch_f].min() if touch_f.any()
                       else np.inf))
    # off the surface (no contact) the layers alone limit the depth
    floor = np.where(touch, floor, lowest)
    floor_f = np.where(touch_f, floor_f, lowest)
    levels = []
    z = top - stepdown
    while z > lowest - stepdown:
        levels.append(max(z, lowest))
        if z <= lowest:
            break
        z -= stepdown
    passes: list[Pass] = []
    above = top
    for k, level in enumerate(levels):
        target = np.maximum(floor, level)
        cuts = inside & (target < above - 1e-9)       # material left by the layer above
        for row in range(len(ws)):
            pieces = []
            for run in index_runs(cuts[row]):
                # one station of margin so the stretch starts and ends clear of the wall
                a, b = max(run[0] - 1, 0), min(run[-1] + 1, len(u) - 1)
                a = a if inside[row, a] else run[0]
                b = b if inside[row, b] else run[-1]
                if b <= a:
                    continue
                P = np.column_stack([u[a:b + 1], np.full(b - a + 1, ws[row]),
                                     target[row, a:b + 1]])
                P = _refine_floor(sampler, P, level, allowance, tolerance)
                pieces.append(P)
            if row % 2 == 1:
                pieces = [P[::-1] for P in pieces[::-1]]
            for P in pieces:
                xyp = sampler.xy(P[:, 0], P[:, 1])
                passes.append(Pass(np.column_stack([xyp, P[:, 2]]),
                                   np.zeros(len(P), bool)))
        for P in _layer_contours(sampler, u, wf, floor_f, inside_f, level, above,
                                 allowance, tolerance, du):
            xyp = sampler.xy(P[:, 0], P[:, 1])
            passes.append(Pass(np.column_stack([xyp, P[:, 2]]), np.zeros(len(P), bool)))
        above = level
    return passes, levels


def _raster(sampler: Sampler, region, u: np.ndarray, w: np.ndarray
            ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """On the (w, u) grid: inside the region, the tip Z clear of the surface (cutter and
    holder), and where the cutter touches the surface at all."""
    U, W = np.meshgrid(u, w)
    inside = in_region(sampler, region, U, W)
    zc, cu, _ = sampler.cut(U.ravel(), W.ravel())            # one drop for Z and contact
    floor = np.maximum(zc, sampler.holder_lift(U.ravel(), W.ravel(), below=zc))
    touch = np.isfinite(cu).reshape(U.shape) & inside
    return inside, floor.reshape(U.shape), touch


def _layer_contours(sampler: Sampler, u: np.ndarray, w: np.ndarray, floor: np.ndarray,
                    inside: np.ndarray, level: float, above: float, allowance: float,
                    tolerance: float, spacing: float) -> list[np.ndarray]:
    """The contour pass of one layer (rows u, w, z): the line where the floor (drop Z
    plus allowance) rises through the layer's Z, i.e. the boundary of what the layer
    can reach. The zigzag rows stop up to a step-over short of a wall; this pass takes
    the wall of every layer down to the allowance. Stretches that would cut nothing
    (the layer above already reached them) and stretches outside the region are
    left out. Points are lifted to ``max(level, floor)`` exactly and chords refined."""
    import contourpy
    eps = max(0.25 * tolerance, 1e-6)
    z = np.ma.masked_array(floor, mask=~inside)
    gen = contourpy.contour_generator(u, w, z, line_type=contourpy.LineType.Separate)
    out: list[np.ndarray] = []
    for line in gen.lines(level + eps):
        if len(line) < 3 or np.hypot(*np.ptp(line, axis=0)) < spacing:
            continue
        zs, _ = sampler.z_safe(line[:, 0], line[:, 1])
        zt = np.maximum(zs + allowance, level)
        cuts = zt < above - 1e-9
        for run in index_runs(cuts):
            if len(run) < 2:
                continue
            P = np.column_stack([line[run], zt[run]])
            P = _refine_floor(sampler, P, level, allowance, tolerance)
            out.append(P)
    return out


def _refine_floor(sampler: Sampler, P: np.ndarray, level: float, allowance: float,
                  tolerance: float, checks: int = 7) -> np.ndarray:
    """Split chords that come closer to the surface than the allowance less
    ``tolerance`` at any of ``checks`` evenly spaced interior points (the points
    themselves are exact; beside a vertical wall the floor jumps, and a midpoint alone
    misses a jump in the first quarter of a chord); the worst point is inserted."""
    def judge(Q, zt):
        want = np.maximum(zt + allowance, level)
        return want - Q[..., 2], want

    P = refine_worst(sampler, P, judge, tolerance, 1e-3, checks)
    return refine_steps(sampler, P, judge, tolerance, 1e-3)


def _settings(ctx: PlanContext, params: dict):
    """(mesh, tool, cutter, region, stepdown, step_over, allowance), checked."""
    file = ctx.job_file
    if ctx.stock is None:
        raise JobError("surface-rough needs the job's [stock] box (the layers start at its "
                       "top)", file)
    mesh = load_op_surface(ctx, params)
    if params["tool"] is None:
        raise JobError("tool: give the roughing tool's number", file)
    tool = ctx.tool(params["tool"], "tool")
    try:
        cutter = surface_cutter(tool)
    except ValueError as e:
        raise PlanningError(str(e), file) from None
    lo, hi = mesh.bounds
    if params["region"]:
        region = tuple(params["region"])
        if not (region[0] < region[2] and region[1] < region[3]):
            raise JobError("region: xmin < xmax and ymin < ymax expected", file)
    else:
        region = (lo[0] - cutter.radius, lo[1] - cutter.radius,
                  hi[0] + cutter.radius, hi[1] + cutter.radius)
    stepdown = params["stepdown"] or default("rough_stepdown", ctx.units)
    step_over = params["stepover"] or 0.6 * 2.0 * cutter.radius
    if step_over > 2.0 * cutter.radius:
        raise JobError(f"stepover: {step_over:g} is more than the tool diameter", file)
    allowance = params["allowance"] if params["allowance"] is not None else \
        default("rough_allowance", ctx.units)
    if allowance < 0:
        raise JobError("allowance: must not be negative", file)
    return mesh, tool, cutter, region, stepdown, step_over, allowance


def estimate(ctx: PlanContext, params: dict, sampler: Sampler | None = None
             ) -> RoughEstimate:
    """The operation's estimate (:func:`.estimate.estimate_rough`); raises at once, with
    the numbers and a way out, when it needs more raster nodes than are planned (the
    job loader already refuses too many layers or rows, see ``[limits]``)."""
    mesh, tool, cutter, region, stepdown, step_over, allowance = _settings(ctx, params)
    inch = ctx.units == "inch"
    unit = "in" if inch else "mm"
    lo, _ = mesh.bounds
    d = 2 * cutter.radius
    station = min(0.5, cutter.radius / 4.0)          # as rough_passes
    if sampler is None:
        sampler = Sampler(op_surface_index(ctx, params), cutter, params["angle"])
    us = CoarseRaster.build(sampler, region, n=40).us_per_drop
    bottom = float(lo[2]) + allowance
    e = estimate_rough(region, ctx.stock.zmax, bottom, stepdown, step_over, station,
                       params["angle"], us)
    if e.raster > ROUGH_MAX_RASTER:
        raise PlanningError(
            f"region {region[2] - region[0]:.4g} x {region[3] - region[1]:.4g} {unit} "
            f"needs about {e.raster:,} drop-cutter points for a {d:g} {unit} tool (at "
            f"most {ROUGH_MAX_RASTER:,}, about 1 GB); a {2 * d:g} {unit} tool needs about "
            f"{e.raster // 4:,}; or use a smaller region", ctx.job_file)
    return e


def preflight(ctx: PlanContext, params: dict) -> None:
    """Refuse an impossible request before any operation of the job is planned."""
    estimate(ctx, params)


def plan(ctx: PlanContext, params: dict) -> PlanResult:
    inch = ctx.units == "inch"
    file = ctx.job_file
    mesh, tool, cutter, region, stepdown, step_over, allowance = _settings(ctx, params)
    lo, hi = mesh.bounds
    feed = params["feed"] or (60.0 if inch else 1500.0)
    plunge = plunge_feed(params, feed)
    index = op_surface_index(ctx, params)
    sampler = Sampler(index, cutter, params["angle"], tuple(tool.holder_cylinders()),
                      z_floor=min(float(lo[2]), ctx.stock.zmin),
                      holder_clearance=0.04 if inch else 1.0)
    tol = 0.25 * allowance if allowance > 0 else (0.0004 if inch else 0.01)
    est = estimate(ctx, params, sampler)
    ctx.progress.note(f"{params['name']}: about {est.levels:,} layers of {est.pass_lines:,} "
                      f"rows, {est.points:,} points at most, {est.seconds:.0f} CPU-s "
                      "(estimate)")
    passes, levels = rough_passes(sampler, region, ctx.stock.zmax, stepdown, step_over,
                                  allowance, tol)
    rest_info = None
    # what the passes meet, holder included: the stock (beside it nothing), or the
    # in-process stock for rest; each pass is cut into it as it is added
    material = MaterialBound(region, tool, ctx.stock.zmax, min(0.5, cutter.radius / 4.0),
                             tol + (0.0001 if inch else 0.001), holder=True)
    material.clip(stock=ctx.stock)
    if params["rest"] and ctx.remaining is not None and passes:
        from millpath.plan.surface.rest import rest_passes
        passes, rest_info = rest_passes(passes, ctx.remaining, tool, tol)
        rest_info["threshold"] = tol
        material.clip(heights=ctx.remaining.height,
                      step=float(getattr(ctx.remaining, "resolution", cutter.radius / 8)))
    if not passes and rest_info is None:
        raise PlanningError("surface-rough: the stock top is already below the surface "
                            "plus allowance; nothing to rough", file)
    clear = default("safe_clearance", ctx.units)
    safe_z = params["safe_z"] if params["safe_z"] is not None else ctx.stock.zmax + clear
    if safe_z <= ctx.stock.zmax:
        raise JobError(f"safe_z: {safe_z:g} is not above the stock top {ctx.stock.zmax:g}",
                       file)
    tp = Toolpath(units=ctx.units)
    tp.begin(Operation("surface-rough", params["name"], tool.number, params["spindle"],
                       info={"stepdown": stepdown, "allowance": allowance}, tolerance=tol))
    links = {"retract": 0}
    if passes:
        links = add_passes(tp, sampler, passes, feed=feed, plunge_feed=plunge, safe_z=safe_z,
                           clearance=0.04 if inch else 1.0, link_max=0.0, tolerance=tol,
                           allowance=allowance, stock=ctx.stock, material=material)
    design = MeshHeight(index)
    section = {
        "operation": params["name"], "tool": tool.number,
        "cutter": f"{cutter.name} D{2 * cutter.radius:g}", "layers": len(levels),
        "levels": [round(z, 4) for z in levels], "stepdown": stepdown,
        "stepover": step_over, "allowance": allowance, "pieces": len(passes),
        "retracts": links["retract"], "low_links": links.get("low", 0),
        "estimate": est.to_json(),
        "cl_points": int(sum(len(p.points) for p in passes)),
    }
    if rest_info is not None:
        section["rest"] = rest_info
    return PlanResult(tp, design, {"surface_rough": [section]})
