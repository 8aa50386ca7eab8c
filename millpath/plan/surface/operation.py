"""Job operation ``type = "surface-finish"``: zigzag finishing of a free-form surface.

Keys (lengths in the job's units, feeds in units per minute):

- ``surface``: an STL file (binary or ASCII), or a Bezier net as a table
  ``{ heights = [[z, ...], ...], box = [xmin, ymin, xmax, ymax] }`` (``heights[i][j]``:
  ``i`` along X, ``j`` along Y) or ``{ control = [[[x, y, z], ...], ...] }``, or a TOML file holding
  such a table; Bezier nets are tessellated into ``divisions`` x ``divisions`` cells
  (two triangles each). Also a measured grid (``.csv``/``.xyz``/``.txt`` of x, y, z, or
  ``{ grid = "points.csv", method = "cubic" }``) or a STEP file (optional extra
  ``millpath[step-brep]``, meshed within ``chord_tolerance``, default 0.01 mm /
  0.0004 in, in the job's units); see :mod:`millpath.part.surface.load`.
- ``tool`` or ``choose_tool = true`` (from the job's tools, see :mod:`.toolchoice`).
- ``tolerance``: chord tolerance along the passes; ``scallop``: scallop height.
- ``angle``: pass direction in degrees from +X; ``side_step``: ``"published"`` or
  ``"variable"``; ``strategy``: ``"zigzag"``, ``"waterline"`` (constant-Z contours,
  :mod:`.waterline`) or ``"steep-shallow"`` (waterline where the slope is at least
  ``steep_angle`` degrees, zigzag elsewhere, :mod:`.steep_shallow`); ``stepdown_max``:
  largest step between waterline levels (default the cutter's corner radius). Waterline
  scallops are measured along the surface normal (zigzag's vertically).
- ``feed``, ``plunge_feed``, ``spindle`` (rpm), ``safe_z`` (default: 5 mm / 0.2 in
  above the highest tool position), ``region`` ``[xmin, ymin, xmax, ymax]`` of the tool
  tip (default: the part's silhouette grown by the cutter radius, so the edges are
  finished too and the ball never runs down the outside of the part: passes and
  surface links are cut where the cutter would touch nothing), ``compare`` (default false): also plan the other side-step
  method and report both path counts.

The design handed to the simulator is the tessellated surface as a height field.
"""

from __future__ import annotations

import math

from contextlib import nullcontext

import numpy as np

from millpath.errors import JobError, PlanningError
from millpath.io.schema import Param
from millpath.model.toolpath import Operation, Toolpath
from millpath.plan.base import PlanContext, PlanResult
from millpath.geometry.cutter import BULL, Cutter
from millpath.plan.surface.dropcutter import MeshHeight, surface_cutter
from millpath.plan.surface.estimate import CoarseRaster, Estimate, estimate_finish
from millpath.plan.surface.linking import add_passes, stock_approach
from millpath.plan.surface.sampler import Sampler
from millpath.plan.surface.source import (PLUNGE_FEED, SURFACE_PARAMS, load_op_surface,
                                          op_surface_index, plunge_feed)
from millpath.plan.surface.steep_shallow import steep_shallow
from millpath.plan.surface.toolchoice import choose_tool
from millpath.plan.surface.waterline import WaterlineSettings, waterline
from millpath.plan.surface.zigzag import ZigzagSettings, zigzag
from millpath.model.units import default

PARAMS = {
    **SURFACE_PARAMS,
    "tool": Param("int", None, positive=True,
          doc="ball or bull-nose end mill (tool number); or choose_tool"),
    "choose_tool": Param("bool", False,
          doc="pick the largest ball under the smallest concave radius whose holder clears the "
              "part"),
    "tolerance": Param("float", None, positive=True,
          unit="length", doc="chordal tolerance along the passes (default 0.005 mm / 0.0002 in)"),
    "scallop": Param("float", None, positive=True,
          unit="length", doc="scallop (cusp) height left between passes (default 0.01 mm / 0.0004 "
                             "in)"),
    "angle": Param("float", 0.0, unit="deg", doc="pass direction from +X"),
    "strategy": Param("str", "zigzag", choices=("zigzag", "waterline", "steep-shallow"),
          doc="zigzag passes, waterline (constant-Z contours) or steep-shallow (both, split at "
              "steep_angle)"),
    "side_step": Param("str", "variable", choices=("published", "variable"),
          doc="side step between passes: variable (from the local slope) or the published "
              "formula"),
    "steep_angle": Param("float", 45.0, doc="degrees: waterline on slopes this steep and up",
          unit="deg"),
    "stepdown_max": Param("float", None, positive=True,
          unit="length", doc="largest step between waterline levels (default: the cutter's corner "
                             "radius)"),
    "feed": Param("float", None, positive=True,
          unit="feed", doc="cutting feed (default 1000 mm/min / 40 in/min)"),
    "plunge_feed": PLUNGE_FEED,
    "spindle": Param("float", 10000.0, positive=True, unit="rpm", doc="spindle speed"),
    "safe_z": Param("float", None,
          unit="length", doc="retract height (default: 5 mm / 0.2 in above the highest tool "
                             "position)"),
    "region": Param("floats", None, length=4, unit="length",
                    doc="[xmin, ymin, xmax, ymax] of the tool tip (default: the part's "
                    "silhouette grown by the cutter radius)"),
    "compare": Param("bool", False, doc="also plan the other side step (twice the work) "
                     "and report both pass counts"),
    "name": Param("str", "surface finish", doc="operation name in the program and report"),
    "rest": Param("bool", False, doc="cut only where earlier operations left material"),
    "rest_allowance": Param("float", None, nonneg=True, unit="length",
                            doc="rest: stock thinner than this is left (default: scallop)"),
}


def plan(ctx: PlanContext, params: dict) -> PlanResult:
    inch = ctx.units == "inch"
    file = ctx.job_file
    mesh = load_op_surface(ctx, params)
    index = op_surface_index(ctx, params)
    design = MeshHeight(index)
    lo, hi = mesh.bounds
    extent = (float(lo[0]), float(lo[1]), float(hi[0]), float(hi[1]))
    region = tuple(params["region"]) if params["region"] else extent
    if not (region[0] < region[2] and region[1] < region[3]):
        raise JobError("region: xmin < xmax and ymin < ymax expected", file)
    report: dict = {}
    strategy = params["strategy"]
    if not 0.0 < params["steep_angle"] < 90.0:
        raise JobError("steep_angle: degrees between 0 and 90 expected", file)
    ext = np.maximum(np.ptp(mesh.triangles[:, :, 0], axis=1),
                     np.ptp(mesh.triangles[:, :, 1], axis=1))
    if params["choose_tool"]:
        tool, why = choose_tool(ctx.tools, index, design, region,
                                max(4.0 * float(np.mean(ext)), default("choose_tool_min_size", ctx.units)))
        report["tool_choice"] = why
        if tool is None:
            reasons = "; ".join(f"T{c['tool']}: {c['rejected']}" for c in why["candidates"]
                                if "rejected" in c) or "the job has no ball cutter"
            raise PlanningError("choose_tool: no ball cutter in the job's tools fits the "
                                f"surface's concave regions with its holder clear ({reasons})",
                                file)
    elif params["tool"] is not None:
        tool = ctx.tool(params["tool"], "tool")
    else:
        raise JobError("tool: give a tool number or choose_tool = true", file)
    try:
        cutter = surface_cutter(tool)
    except ValueError as e:
        raise PlanningError(str(e), file) from None
    _refuse_flat(cutter, tool, file)
    if not params["region"]:
        # the tip goes one cutter radius beyond the surface's edges so that the contact
        # point reaches the edge on any slope (the tool rolls over the edge there)
        region = (extent[0] - cutter.radius, extent[1] - cutter.radius,
                  extent[2] + cutter.radius, extent[3] + cutter.radius)
    tol = params["tolerance"] or default("path_tolerance", ctx.units)
    tol_p = path_tolerance(tol, ctx.units)        # the passes are planned to this
    scallop = params["scallop"] or default("scallop", ctx.units)
    feed = params["feed"] or default("finish_feed", ctx.units)
    plunge = plunge_feed(params, feed)
    sampler = Sampler(index, cutter, params["angle"], tuple(tool.holder_cylinders()),
                      z_floor=float(lo[2]),
                      holder_clearance=default("feed_clearance", ctx.units))

    tol_m = min(tol_p, 0.25 * scallop)
    est, coarse = estimate_finish(sampler, region, strategy=strategy, scallop=scallop,
                                  tolerance=tol_p, material_tolerance=tol_m,
                                  side_step=params["side_step"],
                                  steep_angle=params["steep_angle"],
                                  stepdown_max=params["stepdown_max"])
    refuse_impossible(est, sampler, region, strategy, scallop, tol_m, params, inch, file,
                      coarse)
    prog = ctx.progress
    prog.note(f"{params['name']}: about {est.pass_lines:,} pass lines, {est.levels:,} levels, "
              f"{est.points:,} points, {est.seconds:.0f} CPU-s (estimate)")

    def zz_settings(mode: str, bar=None) -> ZigzagSettings:
        return ZigzagSettings(tolerance=tol_p, scallop=scallop, region=region, side_step=mode,
                              material_tolerance=tol_m, trim_edges=not params["region"],
                              silhouette=not params["region"],
                              on_line=(lambda n: bar.update(completed=n)) if bar else None)

    def run(mode: str, bar=None):
        return zigzag(sampler, design, zz_settings(mode, bar))

    def wl_settings(bar=None) -> WaterlineSettings:
        return WaterlineSettings(
            tolerance=tol_p, scallop=scallop, region=region, material_tolerance=tol_m,
            stepdown_max=params["stepdown_max"], min_slope=params["steep_angle"],
            on_level=(lambda n, z: bar.update(completed=n, info=f"z {z:.4g}"))
            if bar else None)

    # a bar only for what the strategy runs (a zigzag has no waterline levels)
    zz_bar = (prog.task(f"{params['name']}: zigzag pass lines", total=est.pass_lines or None)
              if strategy != "waterline" else nullcontext())
    wl_bar = (prog.task(f"{params['name']}: waterline levels", total=est.levels or None)
              if strategy != "zigzag" else nullcontext())
    try:
        with zz_bar as zbar, wl_bar as wbar:
            if strategy == "zigzag":
                res = run(params["side_step"], zbar)
            elif strategy == "waterline":
                res = waterline(sampler, wl_settings(wbar))
            else:
                res = steep_shallow(sampler, design, zz_settings(params["side_step"], zbar),
                                    wl_settings(wbar), params["steep_angle"])
    except PlanningError as e:
        raise PlanningError(e.message, file) from None
    top = max(float(np.max(p.points[:, 2])) for p in res.passes) if res.passes else hi[2]
    safe_z = params["safe_z"]
    stock_top = ctx.stock.zmax if ctx.stock is not None else -np.inf
    if safe_z is None:
        safe_z = max(top, stock_top) + default("safe_clearance", ctx.units)
    elif safe_z < top:
        raise JobError(f"safe_z: {safe_z:g} is below the highest tool position {top:.4g}", file)
    elif safe_z <= stock_top:
        raise JobError(f"safe_z: {safe_z:g} is not above the stock top {stock_top:g}", file)
    tp = Toolpath(units=ctx.units)
    tp.begin(Operation("surface-finish", params["name"], tool.number, params["spindle"],
                       info={"side_step": params["side_step"], "scallop": scallop,
                             "tolerance": tol, "strategy": strategy}, tolerance=tol))
    passes, rest_info = res.passes, None
    if params["rest"] and ctx.remaining is not None:
        from millpath.plan.surface.rest import rest_passes
        thr = params["rest_allowance"] if params["rest_allowance"] is not None else scallop
        passes, rest_info = rest_passes(res.passes, ctx.remaining, tool, thr)
        rest_info.update(allowance=thr, cutting_length=round(
            float(sum(np.linalg.norm(np.diff(p.points, axis=0), axis=1).sum()
                      for p in passes)), 4))
    links = add_passes(tp, sampler, passes, feed=feed, plunge_feed=plunge, safe_z=safe_z,
                       clearance=default("feed_clearance", ctx.units), link_max=3.0 * cutter.radius,
                       tolerance=tol_p,
                       approach_z=(stock_approach(ctx.stock, cutter.radius)
                                   if ctx.stock is not None else np.inf),
                       silhouette=not params["region"])
    zres = res if strategy == "zigzag" else getattr(res, "zigzag", None)
    wres = res if strategy == "waterline" else getattr(res, "waterline", None)
    removed = wres.removed if wres is not None else {}
    n_lifted = (zres.n_lifted if zres is not None else 0) + removed.get("holder", 0)
    section = {
        "strategy": strategy,
        "tool": tool.number, "cutter": f"{cutter.name} D{2 * cutter.radius:g}"
        + (f" r{cutter.corner:g}" if cutter.kind == BULL else ""),
        "triangles": len(mesh), "region": list(map(float, region)),
        "tolerance": tol, "scallop": scallop, "angle": params["angle"],
        "side_step": params["side_step"],
        "pass_lines": zres.n_lines if zres is not None else 0,
        "pieces": len(res.passes), "cl_points": res.n_points,
        "estimate": est.to_json(),
        "cutting_length": round(res.length, 4), "links": links,
        "holder": {"cylinders": [list(c) for c in tool.holder_cylinders()],
                   "lifted_points": n_lifted,
                   "note": ("points lifted (zigzag) or not cut (waterline) so the shank or "
                            "holder clears the surface; material is left there")
                   if n_lifted else "no contact"},
    }
    if rest_info is not None:
        section["rest"] = rest_info
    if wres is not None:
        dz = -np.diff(wres.levels) if len(wres.levels) > 1 else np.zeros(1)
        section["waterline"] = {
            "levels": len(wres.levels), "contours": wres.n_contours,
            "cl_points": wres.n_points, "cutting_length": round(wres.length, 4),
            "z_top": round(float(wres.levels[0]), 6) if wres.levels else None,
            "z_bottom": round(float(wres.levels[-1]), 6) if wres.levels else None,
            "level_step_min": round(float(dz.min()), 6),
            "level_step_max": round(float(dz.max()), 6),
            "scallop_held_from_slope": params["steep_angle"],
            "max_chord_ratio": round(wres.max_chord_ratio, 4),
            "points_not_cut": removed,
            "raster_spacing": round(wres.raster.spacing, 6) if wres.raster else None,
        }
    if strategy == "steep-shallow":
        section["steep_shallow"] = {
            "steep_angle": params["steep_angle"], "overlap": round(res.overlap, 6),
            "steep_fraction": round(res.steep_fraction, 4),
            "zigzag_pieces": res.zigzag_pieces,
            "zigzag_cutting_length": round(res.length - wres.length, 4)}
    if params["compare"] and strategy == "zigzag":
        other = "published" if params["side_step"] == "variable" else "variable"
        o = run(other)
        section["compare"] = {
            params["side_step"]: {"pass_lines": res.n_lines, "cutting_length": round(res.length, 3)},
            other: {"pass_lines": o.n_lines, "cutting_length": round(o.length, 3)},
        }
    if "tool_choice" in report:
        section["tool_choice"] = report.pop("tool_choice")
    section = {"operation": params["name"], **section}
    report["surface_finish"] = [section]          # a list: one entry per operation
    return PlanResult(tp, design, report)


def refuse_impossible(est: Estimate, sampler: Sampler, region, strategy: str,
                      scallop: float, tol_m: float, params: dict, inch: bool, file,
                      raster: CoarseRaster | None = None) -> None:
    """Raise at once, with the numbers and a way out, when the estimate exceeds what the
    planners plan (5000 zigzag pass lines, 3000 waterline levels); ``raster``: the
    estimate's coarse raster, reused for the suggestions."""
    max_lines, max_levels = ZigzagSettings.max_passes, WaterlineSettings.max_levels
    if est.pass_lines <= max_lines and est.levels <= max_levels:
        return
    unit = "in" if inch else "mm"
    d = 2.0 * sampler.cutter.radius
    what, n, limit = (("passes", est.pass_lines, max_lines) if est.pass_lines > max_lines
                      else ("levels", est.levels, max_levels))
    h2 = scallop
    n2 = n
    for _ in range(16):                      # the scallop that needs under 80 % of it
        h2 *= 2.0
        e2, r2 = estimate_finish(sampler, region, strategy=strategy, scallop=h2,
                                tolerance=params["tolerance"] or tol_m,
                                material_tolerance=min(tol_m, 0.25 * h2),
                                side_step=params["side_step"],
                                steep_angle=params["steep_angle"],
                                stepdown_max=params["stepdown_max"], raster=raster)
        raster = raster or r2
        n2 = e2.pass_lines if what == "passes" else e2.levels
        if n2 <= 0.8 * limit:
            break
    raise PlanningError(
        f"scallop {scallop:g} {unit} needs about {n:,} {what} with a {d:g} {unit} "
        f"{sampler.cutter.name} (at most {limit:,} are planned); "
        + (f"scallop {h2:g} {unit} needs about {n2:,}; or use a larger ball"
           if n2 <= limit else f"even scallop {h2:g} {unit} needs about {n2:,} (the "
           "slopes set the step)")
        + ("" if strategy == "steep-shallow" else ', or strategy = "steep-shallow"'), file)


def path_tolerance(tol: float, units: str) -> float:
    """The chord tolerance the passes are planned to, inside the operation's ``tol``:
    room for the post's rounding of each point (half a step of its last decimal on each
    axis) and 5 % for the chords' deviation between the points where it is checked."""
    grid = 10.0 ** -int(default("decimals", units))
    return max(0.95 * tol - 0.5 * math.sqrt(3.0) * grid, 0.5 * tol)


def _refuse_flat(cutter: Cutter, tool, file) -> None:
    """Finishing passes are spaced by the scallop a ball or a bull's corner leaves."""
    if cutter.corner <= 0.0:
        raise JobError(f"tool: T{tool.number} is a flat end mill; surface-finish spaces its "
                       "passes by the scallop of a ball or bull-nose corner: give a ball "
                       "or bull cutter, or choose_tool = true", file)


def preflight(ctx: PlanContext, params: dict) -> None:
    """Refuse an impossible request before any operation of the job is planned (the
    pipeline calls this for every operation first): the estimate of :func:`plan` with the
    given tool (skipped with ``choose_tool``, where :func:`plan` does it)."""
    if params["choose_tool"] or params["tool"] is None:
        return
    mesh = load_op_surface(ctx, params)
    tool = ctx.tool(params["tool"], "tool")
    try:
        cutter = surface_cutter(tool)
    except ValueError:
        return
    _refuse_flat(cutter, tool, ctx.job_file)
    lo, hi = mesh.bounds
    region = tuple(params["region"]) if params["region"] else (
        lo[0] - cutter.radius, lo[1] - cutter.radius, hi[0] + cutter.radius,
        hi[1] + cutter.radius)
    inch = ctx.units == "inch"
    tol = path_tolerance(params["tolerance"] or default("path_tolerance", ctx.units),
                         ctx.units)
    scallop = params["scallop"] or default("scallop", ctx.units)
    tol_m = min(tol, 0.25 * scallop)
    sampler = Sampler(op_surface_index(ctx, params), cutter, params["angle"], (),
                      z_floor=float(lo[2]))
    est, coarse = estimate_finish(sampler, region, strategy=params["strategy"],
                                  scallop=scallop, tolerance=tol, material_tolerance=tol_m,
                                  side_step=params["side_step"],
                                  steep_angle=params["steep_angle"],
                                  stepdown_max=params["stepdown_max"])
    refuse_impossible(est, sampler, region, params["strategy"], scallop, tol_m, params, inch,
                      ctx.job_file, coarse)
