"""Operation ``pocket``: clear drawn regions (with islands) to a flat floor.

Keys (job units; feeds in units per minute; Z absolute, tool tip):

- geometry: ``dxf`` (+ ``layer``, ``join_tolerance``) or ``polygon`` + ``islands``;
  ``tolerance``: the operation's tolerance (default 0.01 mm / 0.0005 in): drawn curves
  are followed within a 20th of it, and the proof refuses a gouge deeper than it.
- which contours: every region of the drawing (an outline less its islands), or inside
  the contours ``contours`` (all, outer, inner), ``kinds`` (circle, slot, other),
  ``min_size``/``max_size`` (width) and ``contour_layer`` choose, each less the
  contours drawn inside it (see :mod:`millpath.plan.twod.contours`).
- ``tool``: flat or bull end mill; ``top`` (default: the stock top), ``depth`` below
  it, ``stepdown`` per level.
- ``strategy``: ``offset`` (rings from the inside out), ``zigzag`` (lines at
  ``angle`` degrees then a contour), ``adaptive`` (constant ``engagement``, a fraction
  of the diameter in (0, 1), default 0.15); ``stepover`` (default 0.4 D) for offset
  and zigzag and for the floor finish.
- ``allowance``: stock left on walls and floor by the clearing levels; when
  positive a second operation "pocket finish" cuts the walls at every level and the
  floor (rings ``stepover`` apart) to size.
- ``entry``: ``helix`` (radius ``helix_radius``, default 0.5 R, where it fits) or
  ``ramp`` (along the cut); both descend at ``ramp_angle`` degrees (default 3); a
  straight feed down only where the column is empty (in-process stock).
- ``direction``: ``climb`` (default; clockwise spindle) or ``conventional``.
- ``rest``: cut only where the in-process stock left by the earlier operations is more
  than ``allowance`` (at least ``tolerance``) above each level. Without it the
  operation still skips stretches where its tool meets no material.
- ``feed``, ``plunge_feed`` (default feed / 2), ``spindle``, ``safe_z`` (default: top
  + 5 mm / 0.2 in).
"""

from __future__ import annotations


import shapely
from shapely.geometry import Point

from millpath.errors import JobError, PlanningError
from millpath.io.schema import Param
from millpath.model import Operation, Toolpath
from millpath.plan.base import PlanContext, PlanResult
from millpath.plan.pocket.design import PocketDesign
from millpath.plan.pocket.emit import Emitter
from millpath.plan.pocket.passes import Cut, cusp, offset_cuts, order_nearest, zigzag_cuts
from millpath.plan.twod.contours import (SELECT_PARAMS, layer_polygons, pocket_regions,
                                         selecting)
from millpath.plan.twod.field import MaterialField, Raster, stock_heights
from millpath.plan.twod.geometry import GEOMETRY_PARAMS, default_tolerance, load_regions
from millpath.plan.levels import levels
from millpath.plan.twod.heights import MOTION_PARAMS, end_mill, operation_heights, plunge_feed
from millpath.plan.twod.offsets import offset, polygons, rings
from millpath.plan.twod.writer import PathWriter


def _fraction(v) -> str | None:
    return None if 0.0 < v < 1.0 else f"must be a fraction of the tool diameter in (0, 1), got {v!r}"


PARAMS = {
    **GEOMETRY_PARAMS,
    **SELECT_PARAMS,
    "tool": Param("int", positive=True, doc="flat or bull end mill"),
    "top": Param("float", None, doc="Z of the pocket top (default: stock top)", unit="length"),
    "depth": Param("float", positive=True, doc="below top", unit="length"),
    "stepdown": Param("float", positive=True, doc="depth per level", unit="length"),
    "strategy": Param("str", "offset", choices=("offset", "zigzag", "adaptive"),
          doc="clearing: offset rings, zigzag lines then a contour, or adaptive (constant "
              "engagement)"),
    "stepover": Param("float", None, positive=True, doc="default 0.4 D", unit="length"),
    "angle": Param("float", 0.0, doc="zigzag line angle from X, degrees", unit="deg"),
    "engagement": Param("float", 0.15, check=_fraction, doc="adaptive: width of cut / D", unit="ratio"),
    "allowance": Param("float", 0.0, nonneg=True, unit="length",
          doc="stock left on walls and floor by the clearing levels; when positive a 'pocket "
              "finish' pass cuts to size"),
    "entry": Param("str", "helix", choices=("helix", "ramp"),
          doc="entry into material: helix where it fits, or ramp along the cut"),
    "helix_radius": Param("float", None, positive=True, doc="default 0.5 x tool radius", unit="length"),
    "ramp_angle": Param("float", 3.0, positive=True, unit="deg",
          doc="descent angle of helix and ramp entries"),
    "direction": Param("str", "climb", choices=("climb", "conventional"),
          doc="climb (clockwise spindle) or conventional"),
    "rest": Param("bool", False,
          doc="cut only where earlier operations left more than the allowance"),
    **MOTION_PARAMS,
}


def check_fit(region, free, tool, file) -> None:
    """PlanningError if the tool does not fit in the region or through a neck of it."""
    comps = polygons(free)
    if not comps:
        mic = shapely.maximum_inscribed_circle(region.polygon, 1e-3)
        c = mic.coords[0]
        width = 2 * Point(c).distance(region.polygon.boundary)
        raise PlanningError(f"tool {tool.number} (diameter {tool.diameter:g}) does not fit in "
                            f"the pocket {region.name}: its widest place, round "
                            f"({c[0]:.3f}, {c[1]:.3f}), is {width:.4g} wide", file)
    if len(comps) > 1:
        comps.sort(key=lambda p: -p.area)
        a, b = shapely.ops.nearest_points(comps[0], comps[1])
        x, y = (a.x + b.x) / 2, (a.y + b.y) / 2
        raise PlanningError(f"tool {tool.number} (diameter {tool.diameter:g}) does not fit "
                            f"through the neck of the pocket {region.name} at "
                            f"({x:.3f}, {y:.3f})", file)


def plan(ctx: PlanContext, params: dict) -> PlanResult:
    file = ctx.job_file
    tool = end_mill(ctx, params, "a pocket")
    tol = params["tolerance"] or default_tolerance(ctx.units)
    regions = load_regions(params, ctx.units, file, ctx.parts)
    if selecting(params):       # inside the chosen contours (holes: their air inside)
        grown = load_regions({**params, "side": "outside"}, ctx.units, file, ctx.parts)
        regions = pocket_regions(regions, grown, {**params, "tolerance": tol},
                                 tol, layer_polygons(params, ctx.units, tol, file), file)
    R, D = tool.radius, tool.diameter
    allow = params["allowance"]
    heights = operation_heights(ctx, params)
    top, upper, safe, clearance = (heights.top, heights.upper, heights.safe_z,
                                   heights.clearance)
    stock_top = ctx.stock.zmax if ctx.stock is not None else None
    floor = top - params["depth"]
    stepover = params["stepover"] or 0.4 * D
    if stepover > D:
        raise JobError(f"stepover: {stepover:g} is more than the tool diameter", file)
    feed = params["feed"]
    plunge = plunge_feed(params)
    climb = params["direction"] == "climb"
    rest = params["rest"]
    threshold = max(allow, tol) if rest else tol
    hr = params["helix_radius"] or 0.5 * R

    tp = Toolpath(ctx.units)
    strategy = params["strategy"]
    label = f"pocket {strategy}" + (" rest" if rest else "")
    op = Operation("pocket", label, tool.number, spindle=params["spindle"], tolerance=tol,
                   info={"strategy": strategy, "rest": rest,
                         "bottom": {"key": "depth", "top": top, "depth": params["depth"]},
                         "engagement_target": params["engagement"] if strategy == "adaptive"
                         else None})
    tp.begin(op)
    w = PathWriter(tp, safe_z=safe, clear_z=upper + clearance, feed=feed, plunge_feed=plunge,
                   ramp_angle=params["ramp_angle"])
    em = Emitter(w, radius=R, helix_radius=hr, entry=params["entry"], clearance=clearance)
    rough_levels = levels(top, floor + allow, params["stepdown"])
    report = {"regions": [], "left_cells": 0}
    frees = []
    for reg in regions:
        free = offset(reg.polygon, -(R + allow))
        check_fit(reg, free, tool, params["dxf"] or file)
        frees.append(free)
    # offset and zigzag passes leave ridges between them, up to this high
    ridge = cusp(stepover, tool) if strategy != "adaptive" else 0.0
    for reg, free in zip(regions, frees):
        z_prev = None
        for z in rough_levels:
            z_from = upper + clearance if z_prev is None else min(upper + clearance,
                                                                  z_prev + ridge + clearance)
            if strategy == "adaptive":
                from millpath.plan.pocket.adaptive import adaptive_level
                left = adaptive_level(w, em, ctx, reg.polygon, free, tool, z, z_from,
                                      threshold, allow, params["engagement"], hr, climb,
                                      stock_top if stock_top is not None else top, rest)
                report["left_cells"] += left
            else:
                field = _field(ctx, free, R, z, threshold, stock_top, top)
                if strategy == "offset":
                    cuts = offset_cuts(free, stepover, climb, level_reach(tool, stepover))
                else:
                    cuts = zigzag_cuts(free, stepover, params["angle"], climb)
                cuts = order_nearest(cuts, w.pos[:2] if w.pos else None)
                em.level(cuts, z, z_from, field)
            z_prev = z
        report["regions"].append({"name": reg.name, "islands": len(reg.island_names),
                                  "area": round(reg.polygon.area, 4)})
    w.retract()
    op.info["entry_moves"] = list(em.entry_ranges)
    op.info["entries"] = dict(w.entries)
    if allow > 0:
        # offset and zigzag clear the whole free area to the floor's allowance; adaptive
        # clearing may leave cells (left_cells)
        _finish(tp, ctx, params, regions, tool, top, floor, safe, upper, clearance, stepover,
                feed, plunge, climb, rest, tol, hr, stock_top,
                cleared=strategy != "adaptive" or report["left_cells"] == 0)
    op.info["regions"] = report["regions"]
    op.info["left_cells"] = report["left_cells"]
    design = PocketDesign([r.polygon for r in regions], floor,
                          stock_top if stock_top is not None else top)
    return PlanResult(tp, design=design)


def level_reach(tool, stepover: float) -> float:
    """How far from a pass ``tool`` cuts the level to within the ridge that passes
    ``stepover`` apart leave (:func:`millpath.plan.pocket.passes.cusp`): its flat
    bottom's radius, or half the stepover where that is more."""
    return max(tool.radius - tool.corner_radius, 0.5 * stepover)


def _field(ctx, free, R, z, threshold, stock_top, top) -> MaterialField | None:
    """The material field at ``z`` from the in-process stock; None for a full block."""
    if ctx.remaining is None:
        return None
    h = R / 8.0
    raster = Raster.around(free.bounds, h, R + 2 * h)
    heights = stock_heights(ctx.remaining, raster, stock_top if stock_top is not None else top)
    reach = raster.inside(offset(free, R), margin=h)
    return MaterialField(heights, raster, z, threshold, R, reach)


def _finish(tp, ctx, params, regions, tool, top, floor, safe, upper, clearance, stepover,
            feed, plunge, climb, rest, tol, hr, stock_top, cleared: bool) -> None:
    """Walls at every level and the floor, to size (the allowance left by clearing);
    ``cleared``: the clearing took the whole free area down to the floor's allowance
    (rings well inside it are entered from just above that; otherwise every entry
    starts above the stock)."""
    R = tool.radius
    op = Operation("pocket", "pocket finish" + (" rest" if rest else ""), tool.number,
                   spindle=params["spindle"], tolerance=tol, info={"strategy": "finish", "rest": rest})
    tp.begin(op)
    w = PathWriter(tp, safe_z=safe, clear_z=upper + clearance, feed=feed, plunge_feed=plunge,
                   ramp_angle=params["ramp_angle"])
    em = Emitter(w, radius=R, helix_radius=hr, entry="ramp", clearance=clearance)
    allow = params["allowance"]
    thr = max(allow, tol) if rest else tol
    ridge = cusp(stepover, tool)
    for reg in regions:
        free0 = offset(reg.polygon, -R)
        wall_levels = levels(top, floor, params["stepdown"])
        z_prev = None
        for z in wall_levels:
            # (where clearing left cells, every entry starts above the stock)
            z_from = (upper + clearance if z_prev is None or not cleared
                      else z_prev + clearance)
            field = _field(ctx, free0, R, z, thr, stock_top, top) if rest else None
            if z > floor + 1e-9:
                cuts = [Cut(r if climb else r[::-1], True, p)
                        for p in polygons(free0) for r in rings(p)]
            else:
                cuts = offset_cuts(free0, stepover, climb, level_reach(tool, stepover))
            cuts = order_nearest(cuts, w.pos[:2] if w.pos else None)
            if z > floor + 1e-9:
                em.level(cuts, z, z_from, field)
            else:
                # the floor: clearing left the allowance and ridges between its passes;
                # the walls' allowance stands to the last wall level, so a ring whose
                # entry may reach it starts from there
                deep = min(z_from, z + allow + ridge + clearance)
                for c in cuts:
                    em.level([c], z, deep if cleared and c.inset >= R + allow + 2 * hr
                             else z_from, field)
            z_prev = z
    w.retract()
    op.info["entry_moves"] = list(em.entry_ranges)
    op.info["entries"] = dict(w.entries)
