"""Operation type ``features``: machine the features of an AP224 file or a STEP solid.

Job keys (lengths in job units):

- ``step`` (path, required): the AP224 file; its stock is used when the job has none.
  A STEP file without AP224 features (AP203/AP214/AP242 solid) is recognised instead
  (:mod:`millpath.plan.features.solid`): ``body``, ``setup`` and ``stock_step`` apply,
  and the tessellated solid is the design the program is verified against.
- ``tool``: the only milling cutter to use (drills are still chosen from the library).
- ``tools``: tool numbers the planner may use (default: all the job's tools).
- ``allowance``: wall stock left by roughing, removed by the finishing pass
  (default 0.2 mm / 0.008 in).
- ``stepover``: radial distance between roughing rings (default 40 % of each tool's
  diameter; at most 90 % of it).
- ``stepdown``: largest depth per level (default half of each cutter's diameter).
- ``clearance``: rapid plane above the stock top (default 5 mm / 0.2 in); feeds start
  1 mm / 0.04 in above the top.
- ``max_rpm``: spindle limit (default 24000); ``speed_scale`` and ``feed_scale``:
  factors on the table's cutting speeds and chip loads (default 1);
  ``coolant``: flood, mist or off; ``fewer_tools``: drop a milling tool when tools
  already in use can do its features the same way (fewer tool changes, maybe slower);
  ``material``: a material class overriding the file's (see
  :data:`millpath.plan.features.cutting.MATERIALS`).

- ``exclude``: features left out, by id, or by face ('face 12') for a solid's
  recognised features (each feature made of that face); sub-features go with their
  feature. They are listed in the report's ``features.excluded``.
- ``rest``: keep only the moves whose tool meets more than ``allowance`` (default: the
  in-process stock's cell width) of the stock left by earlier operations, Z included
  (:mod:`millpath.plan.restcut`); the report's ``features.rest`` gives the figures.

Holes get canned cycles (G81; G73 chip breaking or G83 full retract pecks of one
diameter beyond three diameters deep), helical interpolation or a ball plunge; a
flat-bottom hole with a drill of its diameter is drilled and its point's cone milled
flat; a 'flat with taper' bottom is milled with a flat end mill in cone levels leaving
at most ``taper_cusp`` normal to the cone (:func:`paths.taper_bore`). Slots, pockets and planar faces are cleared by contour-parallel rings per level,
entered by ramps, plus a finishing wall pass (faces run out past the sides where they
leave the stock). Operations are grouped by tool (one tool change
per tool): region milling first, then drills, then other milling; within a tool,
higher feature tops first, then nearest neighbour. Each feature is milled from where
material still is (its own top when earlier features cleared it, else the stock top).
Coordinates are in the stock frame of the file (block corner at the origin).

The report section ``features`` lists every planned feature (strategy, tool, spindle,
feed, cycle, levels) and every feature left out with the reason.
"""

from __future__ import annotations

import dataclasses
from typing import Any

import numpy as np

from millpath.errors import JobError, PlanningError
from millpath.geometry.cutter import Cutter
from millpath.io.schema import Param
from millpath.model import Operation, Stock, Tool, Toolpath
from millpath.part.step.ap224 import read_part
from millpath.part.step.shapes import (FaceShape, HoleShape, PocketShape, SlotShape,
                                      feature_shapes)
from millpath.plan.base import PlanContext, PlanResult
from millpath.plan.features import paths
from millpath.plan.features.cutting import MATERIALS, material_class, speeds
from millpath.plan.features.design import FeatureDesign, slot_outline
from millpath.plan.features.region import (clear_general, general_regions, inner_points,
                                           region_tool)
from millpath.plan.features.select import (face_tool, hole_tool, matching_drill, pocket_tool,
                                           slot_tool)
from millpath.model.units import default, length_scale
from millpath.plan.restparams import REST_PARAMS


def _exclude_check(v: Any) -> str | None:
    for x in v:
        if isinstance(x, int) and not isinstance(x, bool) and x > 0:
            continue
        if isinstance(x, str) and _face_number(x) is not None:
            continue
        return "expected feature ids (numbers) or faces ('face 12')"
    return None


def _face_number(x: str) -> int | None:
    """12 for 'face 12' or 'FACE #12' (None when ``x`` is not that)."""
    w = x.replace("#", " ").split()
    if len(w) == 2 and w[0].lower() == "face" and w[1].isdigit():
        return int(w[1])
    return None


def _tools_check(v: Any) -> str | None:
    if not all(isinstance(x, int) and not isinstance(x, bool) and x > 0 for x in v):
        return "expected a list of tool numbers"
    return None


PARAMS: dict[str, Param] = {
    "step": Param("path", doc="AP224 file or STEP solid"),
    "body": Param("any", None, check=lambda v: None if (isinstance(v, str) or (
        isinstance(v, int) and not isinstance(v, bool) and v > 0)) else
        "expected a solid's number (1, 2, ...) or name", doc="solid of a multi-body file"),
    "setup": Param("str", "+Z", choices=("+Z", "-Z", "+X", "-X", "+Y", "-Y"),
                   doc="the axis pointing up: the solid's, or the AP224 stock frame's"),
    "unmachinable": Param("str", "refuse", choices=("refuse", "list"),
                          doc="features this operation cannot machine (another setup, a "
                              "surface operation, no tool): 'refuse' the program (the proof "
                              "counts them) or 'list' them in the report, left on purpose"),
    "exclude": Param("list", None, check=_exclude_check,
                     doc="features left out: their ids (as `millpath features` lists "
                         "them) or, for a solid, 'face N' for the features made of face N; "
                         "listed in the report's features.excluded, not machined and not "
                         "counted as unmachinable"),
    "stock_step": Param("path", None, doc="STEP solid whose box is the stock"),
    "tool": Param("int", None, positive=True, doc="only milling cutter to use"),
    "tools": Param("list", None, check=_tools_check, doc="tool numbers allowed"),
    "allowance": Param("float", None, nonneg=True, unit="length",
                           doc="wall stock left by roughing, removed by the finishing pass "
                               "(default 0.2 mm / 0.008 in)"),
    **REST_PARAMS,
    "taper_cusp": Param("float", None, positive=True, unit="length",
                        doc="largest step left on a 'flat with taper' hole bottom's cone, "
                            "normal to it (default 0.02 mm / 0.0008 in)"),
    "stepover": Param("float", None, positive=True,
          unit="length", doc="radial distance between roughing rings (default 40 % of each tool's "
                             "diameter, at most 90 %)"),
    "stepdown": Param("float", None, positive=True, unit="length",
                          doc="largest depth per level (default half of each cutter's "
                              "diameter)"),
    "clearance": Param("float", None, positive=True,
          unit="length", doc="rapid plane above the stock top (default 5 mm / 0.2 in)"),
    "max_rpm": Param("float", 24000.0, positive=True, unit="rpm", doc="spindle speed limit"),
    "speed_scale": Param("float", 1.0, positive=True, doc="factor on table cutting speeds"),
    "feed_scale": Param("float", 1.0, positive=True, doc="factor on table chip loads"),
    "coolant": Param("str", "flood", choices=("flood", "mist", "off"), doc="coolant of every cut"),
    "fewer_tools": Param("bool", False, doc="replace milling tools by ones already in use"),
    "material": Param("str", "", check=lambda v: None if not v or v in MATERIALS else
                      f"unknown material class (known: {', '.join(MATERIALS)})",
          doc="material class overriding the file's (cutting data)"),
}


#: strategies that mill an area (planned before holes, see _group_key)
REGION = ("face", "slot", "pocket", "circular", "region")


@dataclasses.dataclass
class _Task:
    shape: Any
    strategy: str
    tool: Tool
    note: str = ""


def _scaled(shape, k: float):
    if k == 1.0:
        return shape
    f = {}
    for name in ("x", "y", "z_top", "diameter", "depth", "length", "width", "corner_radius",
                 "floor_radius"):
        if hasattr(shape, name):
            f[name] = getattr(shape, name) * k
    if isinstance(shape, HoleShape) and shape.bottom in ("spherical", "flat with radius"):
        f["bottom_radius"] = shape.bottom_radius * k
    if isinstance(shape, HoleShape) and shape.bottom == "flat with taper":
        f["final_diameter"] = shape.final_diameter * k
    if isinstance(shape, (SlotShape, FaceShape)):
        f["start"] = (shape.start[0] * k, shape.start[1] * k)
    if isinstance(shape, PocketShape):
        f["center"] = (shape.center[0] * k, shape.center[1] * k)
        if shape.profile == "general":
            from shapely import affinity
            f["region"] = affinity.scale(shape.region, k, k, origin=(0, 0))
            f["keep"] = affinity.scale(shape.keep, k, k, origin=(0, 0))
    return dataclasses.replace(shape, **f)


def _position(s) -> tuple[float, float]:
    if isinstance(s, HoleShape):
        return (s.x, s.y)
    if isinstance(s, (SlotShape, FaceShape)):
        return s.start
    return s.center


def _order(tasks: list[_Task]) -> list[_Task]:
    """Region milling before holes; higher feature tops first (a pocket before the
    pocket or hole in its floor); nearest neighbour among equals."""
    out: list[_Task] = []
    cur = np.zeros(2)
    for group in ([t for t in tasks if t.strategy in REGION],
                  [t for t in tasks if t.strategy not in REGION]):
        left = list(group)
        while left:
            top = max(t.shape.z_top for t in left)
            d = [float(np.hypot(*(np.asarray(_position(t.shape)) - cur)))
                 if t.shape.z_top >= top - 1e-9 else np.inf for t in left]
            t = left.pop(int(np.argmin(d)))
            out.append(t)
            cur = np.asarray(_position(t.shape))
    return out


def plan(ctx: PlanContext, params: dict) -> PlanResult:
    """Plan all machinable features of the AP224 file ``params['step']``."""
    # the file, the solid and its mesh are read once per job (ctx.parts)
    part = ctx.parts.get("step", params["step"], lambda: read_part(params["step"]))
    solid = None
    solid_key = (params["step"], params["body"], params["setup"], params["stock_step"],
                 ctx.stock.box if ctx.stock is not None else None, ctx.units)
    if part.features and params["setup"] != "+Z":    # AP224: read from that side
        from millpath.part.step.setup import turned
        part = turned(part, params["setup"])
    if not part.features:            # a B-rep solid: recognise its features
        from millpath.plan.features.solid import load_solid
        solid = ctx.parts.get("step-solid", solid_key, lambda: load_solid(
            params["step"], body=params["body"], setup=params["setup"],
            stock_step=params["stock_step"], job_stock=ctx.stock, job_units=ctx.units))
        part = solid.part
    job_mm = length_scale(ctx.units, "mm")
    k = part.units.length_mm / job_mm
    shapes_set = solid.shapes if solid is not None else feature_shapes(part)
    out_ids = excluded_ids(part.features, params["exclude"] or [], params["step"])
    shapes = [_scaled(s, k) for s in shapes_set.shapes if s.id not in out_ids]
    excluded = [{"id": f.id, "type": f.type, "name": f.name} for f in part.features
                if f.id in out_ids]
    notes: list[str] = []

    file_stock = None
    if solid is not None:
        file_stock = Stock.from_box([v * k for v in solid.stock_box])
        if file_stock.zmax > solid.box[5] * k + 1e-3 / job_mm:
            top = [f.id for f in part.features if f.type == "PLANAR_FACE"]
            mid_y = (file_stock.ymin + file_stock.ymax) / 2.0
            shapes.append(FaceShape(top[0] if top else 0, (file_stock.xmin, mid_y),
                                    (1.0, 0.0), file_stock.size[0],
                                    file_stock.size[1], file_stock.zmax - solid.box[5] * k,
                                    file_stock.zmax))
    elif part.stock is not None:
        b = [v * k for v in part.stock.box()]
        if part.stock.shape == "cylinder":
            # the bar's axis is its placement's Z, the stock frame's: centre (0, 0)
            file_stock = Stock.from_cylinder(0.0, 0.0, b[3], b[2], b[5])
            notes.append("cylindrical stock: simulated as the bar (no material outside "
                         "its circle); planned within its bounding box")
        else:
            file_stock = Stock.from_box(b)
    stock = ctx.stock or file_stock
    if ctx.stock is not None and file_stock is not None and \
            max(abs(a - b) for a, b in zip(ctx.stock.box, file_stock.box)) > 1e-6:
        notes.append(f"the job's stock {list(ctx.stock.box)} differs from the file's "
                     f"{list(file_stock.box)}: features are placed in the file's frame")
    if stock is None:
        raise PlanningError("the STEP file has no stock and the job gives none",
                            params["step"])
    z_top = stock.zmax
    allowance = params["allowance"]
    if allowance is None:
        allowance = default("features_allowance", ctx.units)
    clearance = params["clearance"] or default("safe_clearance", ctx.units)
    h = paths.Heights(z_safe=z_top + clearance, r_plane=z_top + default("feed_clearance", ctx.units))
    breakthrough = default("breakthrough", ctx.units)
    tol = default("chord_tolerance", ctx.units)
    cusp = params["taper_cusp"] or default("taper_cusp", ctx.units)

    mat = params["material"] or material_class(part.material)
    if not params["material"] and not part.material:
        notes.append(f"the file names no material: cutting data for {mat} (set the "
                     "operation's material)")
    data = MATERIALS[mat]

    allowed = params["tools"]
    tools = [t for n, t in sorted(ctx.tools.items()) if allowed is None or n in allowed]
    if allowed is not None:
        for n in allowed:
            if n not in ctx.tools:
                raise JobError(f"tools: tool {n} is not in the job's [[tools]]", ctx.job_file)
    if params["tool"] is not None:
        only = ctx.tool(params["tool"], "tool")
        tools = [t for t in tools if t.type == "drill"] + [only]
    if not tools:
        raise PlanningError("the job has no tools to machine the features", ctx.job_file)

    tasks: list[_Task] = []
    unplanned: list = []            # recognised shapes without a tool: still in the design
    skipped = [dataclasses.asdict(u) for u in shapes_set.skipped if u.id not in out_ids]
    for s in shapes:
        def choose(candidates: list[Tool]):
            if isinstance(s, HoleShape):
                strat, tool, note = hole_tool(s, candidates, tol)
                if solid is not None and s.kind == "countersink" and tool is None:
                    # a countersink (or spot drill) of the cone's angle, at least as wide:
                    # its tip goes to the cone's apex, its wider part stays above the entry
                    cs = [t for t in candidates if t.type == "drill"
                          and t.diameter >= s.diameter - tol
                          and abs(t.point_angle - s.tip_angle) <= 1.0]
                    if cs:
                        strat, tool, note = "drill", min(cs, key=lambda t: t.diameter), ""
                if solid is not None and s.bottom == "flat" and strat == "drill":
                    strat, tool, note = "", None, ("flat bottom: no end mill smaller than the "
                                                   "hole (a pointed drill would leave its cone)")
                return strat, tool, note
            if isinstance(s, SlotShape):
                return slot_tool(s, candidates, tol)
            if isinstance(s, FaceShape):
                return face_tool(s, candidates, tol)
            if s.profile == "general":
                return region_tool(s, candidates, tol, stock, ctx.units)
            return pocket_tool(s, candidates, tol)

        reach, flutes = reach_needed(s, stock, breakthrough)
        strat, tool, note = choose([t for t in tools if reaches(t, reach, flutes)])
        if tool is None:
            _, tool_any, _ = choose(tools)
            if tool_any is not None:        # a tool would suit but none reaches the floor
                note = reach_reason(reach, flutes, tools, ctx.units)
                skipped.append({"id": s.id, "type": type(s).__name__.replace("Shape", "")
                                .upper(), "reason": note, "kind": "reach"})
                unplanned.append(s)
                continue
        if tool is None:
            skipped.append({"id": s.id, "type": type(s).__name__.replace("Shape", "").upper(),
                            "reason": note, "kind": "no tool"})
            unplanned.append(s)
            continue
        drill = (matching_drill(s, tools, tol)
                 if isinstance(s, HoleShape) and s.bottom == "flat" and strat == "helical"
                 else None)
        if drill is not None:       # drill first, then flatten the cone with the end mill
            tasks.append(_Task(s, "drill", drill, "flat bottom: the drill point's cone is "
                                                  f"milled flat with T{tool.number}"))
            tasks.append(_Task(s, "flatten", tool, note))
        else:
            tasks.append(_Task(s, strat, tool, note))

    if not tasks and (shapes or skipped):
        left_out = (f" ({len(excluded)} left out by exclude: "
                    + ", ".join(f"{x['type']} #{x['id']}" for x in excluded[:6])
                    + (", ..." if len(excluded) > 6 else "") + ")") if excluded else ""
        raise PlanningError("no feature can be machined: " + why_none(skipped) + left_out,
                            params["step"])
    merged = _consolidate(tasks, tol) if params["fewer_tools"] else []
    if merged:
        notes.append("tools used for few features were replaced by tools already in use: "
                     + ", ".join(f"T{a} -> T{b}" for a, b in merged))
    groups = _groups(tasks)
    order = sorted(groups, key=lambda n: _group_key(groups[n], n))
    # a flat-bottom hole whose end mill comes before its drill is milled in full
    rank = {n: i for i, n in enumerate(order)}
    drilled_at = {t.shape.id: rank[t.tool.number] for t in tasks if t.strategy == "drill"}
    late = {t.shape.id for t in tasks
            if t.strategy == "flatten" and rank[t.tool.number] < drilled_at[t.shape.id]}
    if late:
        tasks = [t for t in tasks if not (t.shape.id in late and t.strategy == "drill")]
        for t in tasks:
            if t.shape.id in late:
                t.strategy = "helical"
        groups = _groups(tasks)
        order = sorted(groups, key=lambda n: _group_key(groups[n], n))

    tp = Toolpath(units=ctx.units)
    planned = []
    done: list = []                 # shapes cut so far, in program order
    drilled: dict[int, Tool] = {}   # flat-bottom holes drilled so far -> their drill
    for n in order:
        group = _order(groups[n])
        tool = group[0].tool
        sp = speeds(tool, mat, ctx.units, max_rpm=params["max_rpm"],
                    max_feed=ctx.machine.max_feed, speed_scale=params["speed_scale"],
                    feed_scale=params["feed_scale"])
        stepover = params["stepover"] or 0.4 * tool.diameter
        if stepover > 0.9 * tool.diameter:
            notes.append(f"stepover {stepover:g} limited to 90 % of T{n}'s diameter")
            stepover = 0.9 * tool.diameter
        step_down = params["stepdown"] or 0.5 * tool.diameter
        kinds = sorted({t.strategy for t in group})
        tp.begin(Operation("features", f"T{n} {tool.type} D{tool.diameter:g}: "
                           f"{len(group)} feature(s) ({', '.join(kinds)})", n,
                           spindle=sp.rpm, coolant=params["coolant"],
                           info={"material": mat, "vc": round(sp.vc, 1), "chip": sp.chip},
                           tolerance=tol))
        for t in group:
            start = _material_top(t.shape, done, z_top)
            if t.strategy == "flatten":
                d = drilled[t.shape.id]
                start = min(start, t.shape.z_bottom + Cutter.of(d).tip_height)
            rec = _cut(tp, t, tool, sp, h, start, stock, data.chip_breaking, allowance,
                       stepover, step_down, breakthrough, cusp)
            if t.strategy == "drill" and isinstance(t.shape, HoleShape) \
                    and t.shape.bottom == "flat":
                drilled[t.shape.id] = tool
                done.append(dataclasses.replace(t.shape, bottom="conical",
                                                tip_angle=tool.point_angle))
            else:
                done.append(t.shape)
            rec = {k: round(v, 6) if isinstance(v, float) else v for k, v in rec.items()}
            rec.update(id=t.shape.id, type=type(t.shape).__name__.replace("Shape", "").upper(),
                       strategy=t.strategy, tool=n, rpm=sp.rpm, feed=sp.feed)
            if solid is not None:           # what was recognised: step, slot, counterbore ...
                rec["kind"] = t.shape.kind
            if t.note:
                rec["note"] = t.note
            planned.append(rec)

    if solid is not None:
        from millpath.plan.features.solid import SolidDesign
        design = ctx.parts.get("step-solid-design", (solid_key, tol),
                               lambda: SolidDesign(solid.solid, tol, ctx.units))
    else:
        design = FeatureDesign(z_top, [t.shape for t in tasks] + unplanned,
                               reach=max(stock.size) * 2 + 100.0)
    report = {"features": {
        "file": str(params["step"]),
        "product": part.product,
        "file_units": part.units.length,
        "material": part.material,
        "material_class": mat,
        "stock": part.stock.as_dict() if part.stock else None,
        **({"solid": solid.info, "recognised": [f.as_dict() for f in part.features]}
           if solid is not None else {}),
        "tool_changes": len(groups),
        "planned": planned,
        "unmachinable": skipped,
        "excluded": excluded,
        "unmachinable_policy": params["unmachinable"],
        "notes": notes,
    }}
    if params["rest"] and ctx.remaining is not None:
        from millpath.plan.restcut import rest_filter
        allow = params["rest_allowance"]
        report["features"]["rest"] = rest_filter(
            tp, ctx.remaining, ctx.tools,
            allow if allow is not None else float(ctx.remaining.resolution), h.z_safe,
            default("feed_clearance", ctx.units))
    return PlanResult(toolpath=tp, design=design, report=report,
                      stock=file_stock if ctx.stock is None else None)


def why_none(skipped: list[dict], most: int = 6) -> str:
    """Each feature left out and why, reach problems first: '#12 ROUND_HOLE: ...; ...'
    (``most`` of them, then how many more)."""
    order = sorted(skipped, key=lambda u: u.get("kind") != "reach")
    parts = [f"{u['type']} #{u['id']}: {u['reason']}" for u in order[:most]]
    if len(order) > most:
        parts.append(f"and {len(order) - most} more")
    return "; ".join(parts) if parts else "no machinable feature"


def excluded_ids(features: list, exclude: list, file) -> set[int]:
    """Ids of the features ``exclude`` leaves out: each id given (and its sub-features),
    each feature made of a face 'face N'; JobError naming an id or face no feature has."""
    by_id = {f.id: f for f in features}
    out: set[int] = set()
    for x in exclude:
        n = _face_number(x) if isinstance(x, str) else None
        if n is not None:
            hit = [f.id for f in features if n in f.faces]
            if not hit:
                raise JobError(f"exclude: no recognised feature has face {n}", file)
            out.update(hit)
        elif x in by_id:
            out.add(x)
        else:
            raise JobError(f"exclude: the file has no feature #{x}", file)
    todo = list(out)
    while todo:
        f = by_id.get(todo.pop())
        for c in (f.children if f is not None else []):
            if c not in out:
                out.add(c)
                todo.append(c)
    return out


def _reselect(t: _Task, tools: list[Tool], tol: float) -> tuple[Tool, str] | None:
    """Another tool from ``tools`` for task ``t`` with the same strategy and no new
    compromise (None if there is none)."""
    s = t.shape
    if t.strategy in ("helical", "flatten", "plunge"):
        strat, tool, note = hole_tool(s, tools, tol)
        ok = strat == ("helical" if t.strategy == "flatten" else t.strategy)
    elif t.strategy == "slot":
        strat, tool, note = slot_tool(s, tools, tol)
        ok = strat == "slot"
    elif t.strategy == "face":
        strat, tool, note = face_tool(s, tools, tol)
        ok = strat == "face"
    elif t.strategy in ("pocket", "circular"):
        strat, tool, note = pocket_tool(s, tools, tol)
        ok = strat == t.strategy and (not note or note.split(":")[0] == t.note.split(":")[0])
    else:
        return None
    if not ok or tool is None:
        return None
    if t.strategy in ("pocket", "circular") and note and not t.note:
        return None
    return tool, note


def _consolidate(tasks: list[_Task], tol: float) -> list[tuple[int, int]]:
    """Fewer tool changes: a milling tool whose every task another milling tool already
    in use can do the same way is dropped (least used first). Drills stay (a hole with
    a drill of its diameter is drilled). Returns the (dropped, replacement) pairs."""
    merged: list[tuple[int, int]] = []
    while True:
        use: dict[int, list[_Task]] = {}
        for t in tasks:
            use.setdefault(t.tool.number, []).append(t)
        mills = {n: ts[0].tool for n, ts in use.items() if ts[0].tool.type != "drill"}
        for n in sorted(mills, key=lambda m: (len(use[m]), mills[m].diameter)):
            others = [tool for m, tool in mills.items() if m != n]
            picks = [_reselect(t, others, tol) for t in use[n]]
            if others and all(p is not None for p in picks):
                for t, (tool, note) in zip(use[n], picks):
                    t.tool = tool
                    t.note = note
                merged.append((n, picks[0][0].number))
                break
        else:
            return merged


def _groups(tasks: list[_Task]) -> dict[int, list[_Task]]:
    groups: dict[int, list[_Task]] = {}
    for t in tasks:
        groups.setdefault(t.tool.number, []).append(t)
    return groups


def _group_key(g: list[_Task], n: int):
    """Tool order: region milling first (largest tool first), then drills, then the
    other milling (helical holes, flattening of drilled holes)."""
    region = any(t.strategy in REGION for t in g)
    tool = g[0].tool
    return (0 if region else 1 if tool.type == "drill" else 2, -tool.diameter, n)


def reach_needed(shape, stock: Stock, breakthrough: float) -> tuple[float, float]:
    """(stick-out, flute length) a tool needs for ``shape`` (job units): its holder face
    must stay above the stock top with the tip at its lowest point (a through hole's
    tip goes ``breakthrough`` below the stock), and its flutes must cover the feature's
    own depth from its top to its floor (the stock bottom for a through hole)."""
    through = isinstance(shape, HoleShape) and shape.bottom == "through"
    floor = stock.zmin if through else shape.z_top - shape.depth
    return stock.zmax - floor + (breakthrough if through else 0.0), shape.z_top - floor


def reaches(tool: Tool, reach: float, flutes: float) -> bool:
    return tool.stickout >= reach - 1e-9 and tool.flute_length >= flutes - 1e-9


def reach_reason(reach: float, flutes: float, tools: list[Tool], units: str) -> str:
    """Why no tool reaches: 'needs 85 mm of reach, the longest tool reaches 45'."""
    longest = max(t.stickout for t in tools)
    if longest < reach - 1e-9:
        return (f"needs {reach:.4g} {units} of reach, the longest tool reaches "
                f"{longest:.4g}")
    fl = max(t.flute_length for t in tools if t.stickout >= reach - 1e-9)
    return (f"needs {flutes:.4g} {units} of flute length with {reach:.4g} of reach, the "
            f"longest flutes of a tool that reaches are {fl:.4g}")


def _material_top(shape, done: list, z_stock: float) -> float:
    """Z where milling of ``shape`` starts: its own top when the features cut before it
    have cleared down to that top over its whole area (e.g. a hole in a pocket floor),
    else the stock top (material above it is still there and is cut on the way)."""
    if shape.z_top >= z_stock - 1e-9:
        return z_stock
    if done:
        if isinstance(shape, HoleShape):
            a = np.linspace(0.0, 2 * np.pi, 16, endpoint=False)
            r = 0.95 * shape.diameter / 2.0
            x = np.append(shape.x + r * np.cos(a), shape.x)
            y = np.append(shape.y + r * np.sin(a), shape.y)
        elif getattr(shape, "profile", "") == "general":
            xy = inner_points(shape.region)
            x, y = xy[:, 0], xy[:, 1]
        else:
            poly = (slot_outline(shape, 0.0) if isinstance(shape, SlotShape)
                    else shape.outline(4))
            inner = poly.buffer(-0.05 * min(getattr(shape, "width", 0.0) or poly.length,
                                            poly.length) / 2.0)
            pts = np.asarray((inner if not inner.is_empty else poly).exterior.coords)
            c = poly.centroid
            x, y = np.append(pts[:, 0], c.x), np.append(pts[:, 1], c.y)
        cleared = FeatureDesign(z_stock, list(done)).height(x, y)
        if float(np.max(cleared)) <= shape.z_top + 1e-9:
            return shape.z_top
    return z_stock


def _cut(tp: Toolpath, t: _Task, tool: Tool, sp, h: paths.Heights, z_start: float,
         stock: Stock, chip_breaking: bool, allowance: float, stepover: float,
         step_down: float, breakthrough: float, cusp: float) -> dict:
    s = t.shape
    if isinstance(s, HoleShape):
        floor = stock.zmin - breakthrough if s.bottom == "through" else s.z_bottom
        if t.strategy == "drill":
            tip = floor - (Cutter.of(tool).tip_height if s.bottom == "through" else 0.0)
            depth = z_start - tip          # drilled length in material
            if depth > 3 * tool.diameter:
                cycle = "G73" if chip_breaking and depth <= 6 * tool.diameter else "G83"
                peck = tool.diameter
            else:
                cycle, peck = "G81", 0.0
            paths.drill(tp, s.x, s.y, tip, h, sp.feed, cycle, peck)
            return {"cycle": cycle, "peck": peck, "z": tip}
        if t.strategy == "plunge":
            paths.plunge(tp, s.x, s.y, floor, h, sp.plunge)
            return {"z": floor}
        if t.strategy == "taper":
            n = paths.taper_bore(tp, s.x, s.y, s.diameter / 2.0, s.final_diameter / 2.0,
                                 s.tip_angle / 2.0, tool.radius, z_start, floor, h,
                                 step_down=step_down, stepover=stepover,
                                 allowance=allowance, cusp=cusp, feed=sp.feed,
                                 plunge_feed=sp.plunge)
            return {"z": floor, "levels": n, "z_start": z_start, "cusp": cusp}
        paths.bore(tp, s.x, s.y, s.diameter / 2.0, tool.radius, z_start, floor, h,
                   step_down=step_down, stepover=stepover, allowance=allowance,
                   feed=sp.feed, plunge_feed=sp.plunge)
        return {"z": floor, "levels": len(paths.levels(z_start, floor, step_down)),
                "z_start": z_start}
    floor = stock.zmin - breakthrough if getattr(s, "bottom", "") == "through" else \
        s.z_top - s.depth
    if t.strategy == "region":
        rough, finish = general_regions(s, tool, allowance, stock)
        clear_general(tp, rough, finish, z_start, floor, h, step_down=step_down,
                      stepover=stepover, feed=sp.feed, plunge_feed=sp.plunge,
                      tool_radius=tool.radius)
        return {"z": floor, "levels": len(paths.levels(z_start, floor, step_down)),
                "z_start": z_start}
    if t.strategy == "circular":
        paths.bore(tp, s.center[0], s.center[1], s.diameter / 2.0, tool.radius, z_start,
                   floor, h, step_down=step_down, stepover=stepover, allowance=allowance,
                   feed=sp.feed, plunge_feed=sp.plunge)
        return {"z": floor, "levels": len(paths.levels(z_start, floor, step_down)),
                "z_start": z_start}
    if isinstance(s, SlotShape):
        rough, finish = _slot_regions(s, tool.radius, allowance, stock)
    elif isinstance(s, FaceShape):
        rough, finish = _face_regions(s, tool.radius, allowance, stock)
    else:
        outline = s.outline(16)
        rough = outline.buffer(-(tool.radius + allowance), join_style="mitre")
        finish = outline.buffer(-tool.radius, join_style="mitre")
        if rough.is_empty:
            rough = finish
        if finish.is_empty:
            raise PlanningError(f"#{s.id}: tool T{tool.number} does not fit the pocket")
    paths.clear_region(tp, rough, finish, z_start, floor, h, step_down=step_down,
                       stepover=stepover, feed=sp.feed, plunge_feed=sp.plunge)
    return {"z": floor, "levels": len(paths.levels(z_start, floor, step_down)),
            "z_start": z_start}


def _slot_regions(s: SlotShape, r: float, allowance: float, stock: Stock):
    """Roughing and finishing regions of the tool centre in a slot (LineString when the
    tool is as wide as the slot)."""
    from shapely.geometry import LineString

    d = np.asarray(s.direction)
    a = np.asarray(s.start, float)
    b = a + d * s.length
    # open ends: run out past the stock edge by the tool radius
    out = max(stock.size) + r + 1.0
    if s.ends[0] == "open":
        a = _exit(a, -d, stock) - d * (r + 1.0)
    if s.ends[1] == "open":
        b = _exit(b, d, stock) + d * (r + 1.0)

    def region(off: float):
        half = s.width / 2.0 - off
        aa = a + d * off if s.ends[0] == "flat" else a
        bb = b - d * off if s.ends[1] == "flat" else b
        if half <= 1e-6:
            return LineString([aa, bb])
        outline = slot_outline(dataclasses.replace(
            s, start=(float(aa[0]), float(aa[1])),
            length=float(np.linalg.norm(bb - aa)), width=2 * half,
            ends=tuple("radiused" if e == "radiused" else "flat" for e in s.ends)), out)
        return outline

    finish = region(r)
    rough = region(r + allowance) if s.width / 2.0 - r - allowance > 1e-6 else finish
    return rough, finish


def _face_regions(f: FaceShape, r: float, allowance: float, stock: Stock):
    """Roughing and finishing regions of the tool centre on a face: the tool may leave
    the face only where it leaves the stock (open sides), and runs out past those by its
    radius so the whole face is cut."""
    from shapely.geometry import box
    face = f.outline()
    s = box(stock.xmin, stock.ymin, stock.xmax, stock.ymax)
    big = s.buffer(max(stock.size) + 4 * r + 10.0, join_style="mitre")
    allowed = face.union(big.difference(s))
    near = face.buffer(r, join_style="mitre")
    finish = _one_area(allowed.buffer(-r, join_style="mitre").intersection(near), f.id, r)
    rough = _one_area(allowed.buffer(-(r + allowance), join_style="mitre").intersection(near),
                      f.id, r)
    return (rough if not rough.is_empty else finish), finish


def _one_area(g, fid: int, r: float):
    """The polygon of ``g`` once slivers and touching lines are dropped."""
    if g.geom_type == "Polygon" or g.is_empty:
        return g
    parts = sorted((p for p in getattr(g, "geoms", []) if p.geom_type == "Polygon"),
                   key=lambda p: -p.area)
    if not parts or any(p.area > 1e-6 * r * r for p in parts[1:]):
        raise PlanningError(f"#{fid}: the face's tool region is not one area")
    return parts[0]


def _exit(p: np.ndarray, d: np.ndarray, stock: Stock) -> np.ndarray:
    """Where the ray from ``p`` along ``d`` leaves the stock's XY box (p if outside)."""
    ts = []
    for i, (lo, hi) in enumerate(((stock.xmin, stock.xmax), (stock.ymin, stock.ymax))):
        if abs(d[i]) > 1e-12:
            ts.append(((hi if d[i] > 0 else lo) - p[i]) / d[i])
    t = max(0.0, min(ts)) if ts else 0.0
    return p + d * t
