"""Operation ``profile``: cut along the contours of a drawing, each on its air side.

Keys (job units; feeds in units per minute; Z absolute, tool tip):

- geometry: ``dxf`` (+ ``layer``, ``join_tolerance``) or ``polygon`` (+ ``islands``);
  ``tolerance``: the operation's tolerance (default 0.01 mm / 0.0005 in): drawn curves
  are followed within a 20th of it, and the proof refuses a gouge deeper than it.
- ``side``: ``outside`` (default): the drawing's regions are the part: each outline is
  cut with the tool outside it, each hole, slot or bore inside it; ``inside``: the
  regions are openings: outlines from inside, islands from outside (see
  :mod:`millpath.plan.twod.contours`).
- which contours: ``contours`` (all, outer, inner), ``kinds`` (circle, slot, other),
  ``min_size``/``max_size`` (width), ``contour_layer`` (see :mod:`millpath.plan.twod.contours`).
- ``compensation``: ``cam`` (the tool-centre path: the contour offset by the tool
  radius, round joins within a 20th of the tolerance) or ``control`` (the contour
  itself between ``G41``/``G42 D<tool>`` and ``G40``; the control offsets it by the
  tool table's diameter). LinuxCNC refuses a concave corner or arc the tool cannot stay
  tangent to, so the contour programmed is the one the tool can follow: its concave
  corners, and notches narrower than the tool, rounded to the tool radius plus
  ``wear_margin`` (default 0.1 mm / 0.004 in: how much larger the control's radius, wear
  offset included, may be than the tool's); the material left there is what the tool
  cannot reach anyway, and the margin.
- ``direction``: ``climb`` (default: tool on the left, G41, with a clockwise spindle)
  or ``conventional`` (right, G42).
- ``lead_radius`` (default the tool diameter; must exceed the tool radius): tangent
  quarter-arc lead-in and lead-out on the tool side, each with a straight entry/exit of
  ``lead_radius`` (see :mod:`.leads`), entered by a helix beside the entry. A contour
  with no room for them at the middle of its longest straight stretch gets smaller
  leads (down to 1.5 times the tool radius, plus wear_margin under control
  compensation) or leads on the next longest
  stretches; one with room nowhere (a hole little wider than the tool) is entered by
  descending along its own path at ``ramp_angle`` (CAM compensation, no tabs; else an
  error naming the keys to change).
- ``top`` (default stock top), ``depth`` below it, ``stepdown``: levels; a bottom more
  than 0.5 mm / 0.02 in below the stock's is refused (:mod:`millpath.plan.sense`).
- ``tabs = N`` holding tabs on each outline (outer contour) ``tab_width`` long (default
  the tool diameter, measured along the contour) and ``tab_height`` above the bottom
  (default 0: no tabs), spread evenly; on levels below the tab top the tool climbs
  over them (straight up, then down along the path at no more than 45 degrees).
- ``rest``: levels whose path meets no material left by earlier operations are skipped.
- ``feed``, ``plunge_feed`` (default feed / 2), ``spindle``, ``safe_z``, ``ramp_angle``
  (helix and ramp descent, degrees, default 3).

Contours are cut holes first (nearest first), then outlines, each level by level. The
design (:mod:`.design`) is the part the drawing shows, extruded from the bottom to the
stock top.
"""

from __future__ import annotations

import math

import numpy as np
import shapely
from shapely.geometry import LineString, Point, Polygon
from shapely.geometry.polygon import orient

from millpath.errors import JobError, PlanningError
from millpath.io.schema import Param
from millpath.model import Operation, Toolpath
from millpath.model.control import CONCAVE_CORNER
from millpath.model.units import default
from millpath.plan.base import PlanContext, PlanResult
from millpath.plan.twod.contours import (SELECT_PARAMS, layer_polygons, material, order,
                                            profile_contours, select)
from millpath.plan.profile.design import ProfileDesign, slot_band
from millpath.plan.profile.leads import chords_by_length, leads, start_on_chord
from millpath.plan.twod.field import MaterialField, Raster, densify, stock_heights
from millpath.plan.twod.geometry import (CURVE_FRACTION, GEOMETRY_PARAMS, default_tolerance,
                                         load_regions)
from millpath.plan.levels import levels
from millpath.plan.twod.heights import MOTION_PARAMS, end_mill, operation_heights, plunge_feed
from millpath.plan.twod.offsets import offset, polygons
from millpath.plan.twod.writer import PathWriter

PARAMS = {
    **GEOMETRY_PARAMS,
    "tool": Param("int", positive=True, doc="flat or bull end mill"),
    "side": Param("str", "outside", choices=("outside", "inside"),
          doc="'outside': the drawing's regions are the part (outlines cut from outside, "
              "holes and slots from inside); 'inside': they are openings (outlines from "
              "inside, islands from outside)"),
    **SELECT_PARAMS,
    "compensation": Param("str", "cam", choices=("cam", "control"),
          doc="'cam': the tool-centre path; 'control': the contour between G41/G42 and G40"),
    "wear_margin": Param("float", None, nonneg=True, unit="length",
          doc="control compensation: concave corners are programmed with a radius of at "
              "least the tool radius plus this (default 0.1 mm / 0.004 in)"),
    "direction": Param("str", "climb", choices=("climb", "conventional"),
          doc="climb (tool on the left, G41) or conventional (right, G42)"),
    "lead_radius": Param("float", None, positive=True, unit="length",
          doc="tangent lead-in/out arc radius (default: the tool diameter; more than the tool "
              "radius)"),
    "top": Param("float", None, unit="length", doc="Z of the contour's top (default: stock top)"),
    "depth": Param("float", positive=True, unit="length", doc="depth below top"),
    "stepdown": Param("float", positive=True, unit="length", doc="depth per level"),
    "tabs": Param("int", 0, nonneg=True, unit="count",
          doc="holding tabs spread evenly along each outline (outer contour)"),
    "tab_height": Param("float", 0.0, nonneg=True, unit="length",
          doc="tab height above the bottom (0: no tabs)"),
    "tab_width": Param("float", None, positive=True, unit="length",
          doc="tab length along the contour (default: the tool diameter)"),
    "rest": Param("bool", False,
          doc="skip levels whose path meets no material left by earlier operations"),
    **MOTION_PARAMS,
    "ramp_angle": Param("float", 3.0, positive=True, unit="deg",
          doc="descent angle of the helix (or the ramp along the path) at each entry"),
}


def _tab_intervals(L: float, n: int, width: float) -> list[tuple[float, float]]:
    """Arc-length intervals [a, b] of the tool-centre path lifted over ``n`` tabs."""
    if n <= 0:
        return []
    return [((k + 0.5) * L / n - width / 2, (k + 0.5) * L / n + width / 2) for k in range(n)]


def _with_tabs(pts: np.ndarray, z: float, z_tab: float, tabs, step: float):
    """(x, y, z) along the closed polyline ``pts`` (first point repeated at the end):
    at ``z`` except over the tab intervals, where it rises straight to ``z_tab`` and
    comes back down along the path at 45 degrees."""
    dense = densify(pts, step)
    s = np.concatenate([[0.0], np.cumsum(np.hypot(*np.diff(dense, axis=0).T))])
    zz = np.full(len(dense), z)
    drop = z_tab - z
    for a, b in tabs:
        over = (s >= a) & (s <= b)
        zz[over] = z_tab
        down = (s > b) & (s < b + drop)
        zz[down] = np.maximum(zz[down], z_tab - (s[down] - b))
    out = [np.array([dense[0][0], dense[0][1], zz[0]])]
    for k in range(1, len(dense)):
        if zz[k] > zz[k - 1] + 1e-12 and zz[k] == z_tab:      # climb straight up first
            out.append(np.array([dense[k - 1][0], dense[k - 1][1], z_tab]))
        out.append(np.array([dense[k][0], dense[k][1], zz[k]]))
    # keep only the points where something changes (straight runs at one Z collapse)
    keep = [out[0]]
    for k in range(1, len(out) - 1):
        a, b, c = keep[-1], out[k], out[k + 1]
        if abs(b[2] - a[2]) < 1e-12 and abs(c[2] - b[2]) < 1e-12 and k not in ():
            if _collinear(a, b, c):
                continue
        keep.append(b)
    keep.append(out[-1])
    return keep


def _collinear(a, b, c) -> bool:
    u = b[:2] - a[:2]
    v = c[:2] - b[:2]
    return abs(u[0] * v[1] - u[1] * v[0]) <= 1e-12 * (np.hypot(*u) * np.hypot(*v) + 1e-30) \
        and float(u @ v) > 0


def plan(ctx: PlanContext, params: dict) -> PlanResult:
    file = ctx.job_file
    where = params["dxf"] or file
    tool = end_mill(ctx, params, "a profile")
    tol = params["tolerance"] or default_tolerance(ctx.units)
    regions = load_regions(params, ctx.units, file, ctx.parts)
    R = tool.radius
    rho = params["lead_radius"] or tool.diameter
    if rho <= R * 1.0001:
        raise JobError(f"lead_radius: {rho:g} must be larger than the tool radius {R:g}", file)
    heights = operation_heights(ctx, params)
    top, upper, safe, clearance = (heights.top, heights.upper, heights.safe_z,
                                   heights.clearance)
    stock_top = ctx.stock.zmax if ctx.stock is not None else top
    bottom = top - params["depth"]
    tab_h = params["tab_height"]
    if params["tabs"] and not 0 < tab_h < params["depth"]:
        raise JobError(f"tab_height: must be between 0 and the depth {params['depth']:g} "
                       f"when tabs are asked for, got {tab_h:g}", file)
    side_outside = params["side"] == "outside"
    every = profile_contours(regions, side_outside, tol)
    chosen = order(select(every, {**params, "tolerance": tol},
                          layer_polygons(params, ctx.units, tol, file), file))
    reach = 2 * (rho + tool.diameter) + tol
    lo = np.min([r.polygon.bounds[:2] for r in regions], axis=0) - reach
    hi = np.max([r.polygon.bounds[2:] for r in regions], axis=0) + reach
    if ctx.stock is not None:
        lo = np.minimum(lo, [ctx.stock.xmin - reach, ctx.stock.ymin - reach])
        hi = np.maximum(hi, [ctx.stock.xmax + reach, ctx.stock.ymax + reach])
    solid = material(regions, side_outside, (*lo, *hi))
    shapely.prepare(solid)

    tp = Toolpath(ctx.units)
    op = Operation("profile", f"profile {params['side']} ({params['compensation']})",
                   tool.number, spindle=params["spindle"], tolerance=tol,
                   info={"side": params["side"], "compensation": params["compensation"],
                         "bottom": {"key": "depth", "top": top, "depth": params["depth"]}})
    tp.begin(op)
    w = PathWriter(tp, safe_z=safe, clear_z=upper + clearance, feed=params["feed"],
                   plunge_feed=plunge_feed(params), ramp_angle=params["ramp_angle"])
    cut = _Cut(ctx, params, tool, tol, rho, w, tp, solid, top, bottom, upper, clearance,
               stock_top, where)
    report = []
    for c in chosen:
        entry = cut.contour(c)
        report.append({**c.to_json(tol), "entry": entry})
    w.retract()
    op.info["levels_skipped"] = cut.skipped
    op.info["contours"] = len(chosen)
    band = slot_band(chosen, max(2 * R - tool.corner_radius - tol, tol))
    walls = [np.asarray(orient(c.polygon, -1.0 if c.tool_outside else 1.0).exterior.coords)
             for c in chosen]
    zmin = ctx.stock.zmin if ctx.stock is not None else -math.inf
    through = bottom <= zmin + 1e-9
    design = ProfileDesign(solid, walls, band, bottom, stock_top, through,
                           with_floor=bottom >= zmin - 1e-9)
    return PlanResult(tp, design=design,
                      report={"profile": {"side": params["side"], "contours": report,
                                          "of": len(every), "through": through}})


class _Cut:
    """Cuts one contour after another with the operation's settings (see :func:`plan`)."""

    def __init__(self, ctx, params, tool, tol, rho, w, tp, solid, top, bottom, upper,
                 clearance, stock_top, where):
        self.ctx, self.params, self.tool, self.tol, self.rho = ctx, params, tool, tol, rho
        self.w, self.tp, self.solid, self.where = w, tp, solid, where
        self.top, self.bottom, self.upper, self.clearance = top, bottom, upper, clearance
        self.stock_top = stock_top
        self.skipped = 0
        R = tool.radius
        # round joins of the tool-centre path within tolerance / 20 of the true offset
        step = 2 * math.acos(max(1.0 - CURVE_FRACTION * tol / R, -1.0))
        self.quad_segs = max(8, int(math.ceil(0.5 * math.pi / max(step, 1e-6))))

    def contour(self, c) -> str:
        """Plan every level of contour ``c``; the entry used: "lead" (helix beside the
        lead-in, tangent lead arcs) or "ramp" (down along the path, where no lead fits)."""
        p, tool, tp, w = self.params, self.tool, self.tp, self.w
        R, tol, rho = tool.radius, self.tol, self.rho
        outside = c.tool_outside
        contour = c.polygon
        side = 1 if p["direction"] == "climb" else -1
        control = p["compensation"] == "control"
        what = f"the contour {c.describe(tol)}"
        if control:
            margin = p["wear_margin"]
            if margin is None:
                margin = default("wear_margin", self.ctx.units)
            contour = followable(contour, R + margin, outside, tol / 100)
            if contour is None:
                raise PlanningError(f"tool {tool.number} (diameter {tool.diameter:g}) does "
                                    f"not fit inside {what} with control compensation "
                                    f"(wear_margin {margin:g}): use a smaller tool", self.where)
        # traversal with the tool on the left (climb): outside clockwise, inside ccw
        ring = np.asarray(orient(contour, -1.0 if outside else 1.0).exterior.coords)[:-1, :2]
        if side < 0:
            ring = ring[::-1]
        if control:
            # as the post writes it (the control's corners are those of the written
            # numbers), then only corners the control reaches
            grain = 10.0 ** -int(default("decimals", self.ctx.units))
            ring = reachable(on_grain(ring, grain), R + 0.5 * margin, side)
            # tab ramps split segments: into pieces the corners beside them leave room on
            reach = 2.0 * corner_reach(ring, R + 0.5 * margin, side) + 4.0 * grain
        ring0 = ring
        centre = offset(contour, R if outside else -R, self.quad_segs)
        cpolys = polygons(centre)
        if not cpolys:
            raise PlanningError(f"tool {tool.number} (diameter {tool.diameter:g}) does not "
                                f"fit inside {what}", self.where)
        if len(cpolys) > 1:
            raise PlanningError(f"tool {tool.number} (diameter {tool.diameter:g}) does not "
                                f"fit through a neck of {what}", self.where)
        cring = np.asarray(orient(cpolys[0], -1.0 if outside else 1.0).exterior.coords)[:-1, :2]
        if side < 0:
            cring = cring[::-1]
        hit = _meets(LineString(np.vstack([cring, cring[:1]])), R - 2 * CURVE_FRACTION * tol,
                     self.solid)
        if hit is not None:
            raise PlanningError(f"tool {tool.number} (diameter {tool.diameter:g}) cutting "
                                f"{what} would cut into the part at ({hit[0]:.3f}, "
                                f"{hit[1]:.3f}): another contour is nearer than the tool "
                                f"diameter", self.where)
        # the lead: at the middle of the longest straight stretch if it fits there, else
        # smaller, else on the next longest stretches
        base = [rho] if p["lead_radius"] else [rho * f for f in (1.0, 0.8, 0.65, 0.55)]
        floor = 1.5 * (R + (margin if control else 0.0))
        tries = [r for r in base if r > floor] + ([floor] if floor < base[-1] else [])
        if not tries:
            tries = [floor]
        Lc = Lp = None
        chords = chords_by_length(ring0)
        for k in chords:
            ring = start_on_chord(ring0, k)
            t = ring[1] - ring[0]
            P0c = ring[0] + R * side * np.array([-t[1], t[0]]) / np.hypot(*t)
            for rho_k in tries:
                Lc = leads(ring[0], t, side, rho_k, rho_k, offset=R)     # tool-centre leads
                Lp = leads(ring[0], t, side, rho_k, rho_k, offset=0.0)   # programmed leads
                if _leads_fit(Lc, P0c, R, self.solid, tol):
                    break
            else:
                Lc = Lp = None
            if Lc is not None:
                break
        else:
            ring = start_on_chord(ring0, chords[0])
            t = ring[1] - ring[0]
            P0c = ring[0] + R * side * np.array([-t[1], t[0]]) / np.hypot(*t)
        closed_c = np.vstack([cring, cring[:1]])
        at = LineString(closed_c).project(LineString([P0c, P0c]).centroid)
        cum = np.concatenate([[0.0], np.cumsum(np.hypot(*np.diff(closed_c, axis=0).T))])
        k = int(np.searchsorted(cum, at + 1e-9)) % len(cring)     # first vertex after P0c
        cring = np.vstack([P0c, np.roll(cring, -k, axis=0)])
        if np.hypot(*(cring[1] - cring[0])) < 1e-9:
            cring = cring[1:]
        tabs_here = p["tabs"] and c.outer
        if Lc is None and (control or tabs_here):
            why = "compensation = \"control\"" if control else "tabs"
            raise PlanningError(f"no room for the lead-in and lead-out of radius "
                                f"{tries[-1]:g} or more on any of the {len(chords)} longest "
                                f"straight stretches of {what} (first at ({ring[0][0]:.3f}, "
                                f"{ring[0][1]:.3f})): {why} needs them; use "
                                + ("compensation = \"cam\", " if control else "tabs = 0, ")
                                + "a smaller lead_radius or a smaller tool", self.where)
        path_c = np.vstack([cring, cring[:1]])
        L = float(np.hypot(*np.diff(path_c, axis=0).T).sum())
        width = p["tab_width"] or tool.diameter
        tabs = _tab_intervals(L, p["tabs"] if tabs_here else 0, width + tool.diameter)
        z_tab = self.bottom + p["tab_height"]
        feed = p["feed"]
        z_prev = None
        for z in levels(self.top, self.bottom, p["stepdown"]):
            if p["rest"] and self.ctx.remaining is not None and _nothing_left(
                    self.ctx, path_c, R, z, tol, self.stock_top):
                self.skipped += 1
                z_prev = z
                continue
            z_from = self.upper + self.clearance if z_prev is None else z_prev + self.clearance
            z_prev = z
            if Lc is None:
                # no room for leads (a small hole): down along the path, then a lap
                w.ramp_closed(cring, z_from, z)
                w.polyline(np.vstack([cring[1:], cring[:1]]), z)
                w.retract()
                continue
            # descend by a helix beside S (in the waste), then onto S
            w.helix(Lc.S[0] - 0.5 * R, Lc.S[1], 0.5 * R, z_from, z)
            if control:
                tp.compensation("left" if side > 0 else "right", d=tool.number)
                A, C, B, E, prog = Lp.A, Lp.C, Lp.B, Lp.E, ring
            else:
                A, C, B, E, prog = Lc.A, Lc.C, Lc.B, Lc.E, cring
            tp.line(A[0], A[1], z, feed)
            tp.arc((prog[0][0], prog[0][1], z), (C[0], C[1], z), not Lc.ccw, feed)
            loop = np.vstack([prog, prog[:1]])
            if tabs and z < z_tab - 1e-9:
                if control:
                    # tabs are measured on the tool-centre path; map by arc length
                    pts = _with_tabs(loop, z, z_tab, _scale(tabs, L, _length(loop)),
                                     max(tol * 10, reach))
                else:
                    pts = _with_tabs(loop, z, z_tab, tabs, tol * 10)
                for q in pts[1:]:
                    tp.line(q[0], q[1], q[2], feed)
            else:
                for q in loop[1:]:
                    tp.line(q[0], q[1], z, feed)
            tp.arc((B[0], B[1], z), (C[0], C[1], z), not Lc.ccw, feed)
            tp.line(E[0], E[1], z, feed)
            if control:
                # G40's first move goes from the compensated position to the programmed
                # point: make it the tool centre's own exit point (cleared by the lead-out),
                # not the contour-side point E, which may lie within a radius of a wall
                tp.compensation("off")
                tp.line(Lc.E[0], Lc.E[1], z, feed)
            w.pos = (float(Lc.E[0]), float(Lc.E[1]), z)
            w.retract()
        return "ramp" if Lc is None else "lead"


#: chords of the corners rounded for the control: 8 to 11 a quarter circle, so each
#: turns by at least about 0.1 rad (GEOS splits a corner in equal parts of at least three
#: quarters of a quarter circle over this): on finer chords the control's offset leaves
#: each (radius - tool radius) x turn of room, less than the post's rounding takes
FILLET_SEGS = (8, 11)


def followable(contour, r: float, outside: bool, eps: float):
    """The contour a tool of radius ``r`` can stay tangent to all along: ``contour``
    (a polygon) opened on its air side (outside if ``outside``, else inside) by a disc
    of radius ``r``: concave corners rounded to radius ``r`` by chords of
    :data:`FILLET_SEGS` a quarter circle (on the air side of the arc: material left),
    notches narrower than ``2 r`` closed over, convex corners kept (outside: exactly;
    inside: within ``eps``, on the air side), points within ``eps`` of a line merged.
    Never on the material's side of ``contour``. None if no tool of radius ``r`` fits
    (inside), or the polygon it fits in splits in several (a neck)."""
    fine = max(8, int(math.ceil(0.5 * math.pi / (2 * math.acos(max(1.0 - eps / r, -1.0))))))
    coarse = min(max(fine, FILLET_SEGS[0]), FILLET_SEGS[1])
    if outside:
        grown = polygons(offset(contour, r, fine))
        if not grown:
            return None
        grown = Polygon(max(grown, key=lambda g: g.area).exterior)
        back = polygons(offset(grown, -r, coarse).union(contour))
    else:
        shrunk = polygons(offset(contour, -r, fine))
        if len(shrunk) != 1:
            return None
        back = polygons(offset(shrunk[0], r, coarse))
    if not back:
        return None
    return Polygon(max(back, key=lambda g: g.area).exterior).simplify(eps)


def _corners(P: np.ndarray, r: float, side: int):
    """Of the closed ring ``P`` (see :func:`reachable`): each segment's length (segment
    k: P[k] -> P[k+1]), whether each vertex is concave, and how much of the segment
    ending at it (``back``) and of the one starting at it (``ahead``) the control's
    offset takes there."""
    d = np.roll(P, -1, axis=0) - P
    L = np.hypot(d[:, 0], d[:, 1])
    t = d / np.maximum(L, 1e-300)[:, None]
    tin = np.roll(t, 1, axis=0)                          # segment ending at vertex k
    cross = tin[:, 0] * t[:, 1] - tin[:, 1] * t[:, 0]
    dot = np.einsum("ij,ij->i", tin, t)
    concave = side * cross > 1e-12
    turn = np.arctan2(np.abs(cross), dot)
    corner = concave & (turn >= CONCAVE_CORNER * (1.0 - 1e-3))   # may be a corner
    join = concave & (turn <= CONCAVE_CORNER * (1.0 + 1e-3))     # may be a join
    # at a corner the offsets meet r * tan(turn / 2) back along each segment
    back = np.where(corner, r * np.abs(cross) / np.maximum(1.0 + dot, 1e-12), 0.0)
    ahead = np.maximum(back, np.where(join, r * np.abs(cross), 0.0))
    return L, concave, back, ahead


def corner_reach(ring: np.ndarray, r: float, side: int) -> float:
    """The most any corner of ``ring`` takes of a segment next to it under the control's
    offset (see :func:`reachable`): pieces of a segment at least this long plus the
    post's rounding are reachable."""
    if len(ring) < 3:
        return 0.0
    _, _, back, ahead = _corners(np.asarray(ring, float)[:, :2], r, side)
    return float(max(back.max(), ahead.max()))


def on_grain(ring: np.ndarray, grain: float) -> np.ndarray:
    """``ring`` (n, 2, not closed) rounded to multiples of ``grain`` (the post's last
    decimal), points that round onto the one before dropped."""
    P = np.round(np.asarray(ring, float) / grain) * grain
    keep = np.any(np.abs(P - np.roll(P, 1, axis=0)) > 0.5 * grain, axis=1)
    return P[keep] if keep.any() else P[:1]


def reachable(ring: np.ndarray, r: float, side: int) -> np.ndarray:
    """``ring`` (n, 2, not closed, followed with the tool on side ``side``: +1 left)
    with the concave vertices dropped that a tool of radius ``r`` offset by the control
    cannot reach. LinuxCNC offsets each segment by ``r``; at a corner turning towards
    the tool by more than :data:`CONCAVE_CORNER` it ends the segment before where the
    two offsets meet, ``r tan(turn / 2)`` back along each; at a smaller turn towards
    the tool (a tangent join) the next segment starts where the last offset ended,
    ``r sin(turn)`` along it. A segment whose offset would run backwards is refused.
    Turns within a thousandth of the threshold are taken both ways. Dropping a concave
    vertex replaces two segments by their chord, on the tool's side: material left,
    never cut."""
    pts = [np.asarray(q, float) for q in ring]
    for _ in range(4 * len(pts) + 4):
        n = len(pts)
        if n < 3:
            break
        P = np.asarray(pts)
        L, concave, back, ahead = _corners(P, r, side)
        bad = (L - ahead - np.roll(back, -1)) <= 0.0          # segment k too short
        drop = set()
        for k in np.flatnonzero(bad):
            j = (k + 1) % n if concave[(k + 1) % n] else k
            if concave[j] and j not in drop and (j - 1) % n not in drop \
                    and (j + 1) % n not in drop:
                drop.add(j)
        if not drop:
            break
        pts = [q for k, q in enumerate(pts) if k not in drop]
    return np.asarray(pts)


def _meets(path: LineString, r: float, solid) -> tuple[float, float] | None:
    """A point where the tool of radius ``r`` along ``path`` meets ``solid``, or None."""
    swept = path.buffer(r)
    if not swept.intersects(solid):
        return None
    p = swept.intersection(solid).representative_point()
    return p.x, p.y


def _leads_fit(Lc, start, R: float, solid, tol: float) -> bool:
    """True if the leads' tool-centre path, and the helix beside S, keep the tool out of
    the part's material ``solid``."""
    hr = 0.5 * R
    lead = LineString(np.vstack([[Lc.S], _arc(Lc.A, start, Lc.C, Lc.ccw),
                                 _arc(start, Lc.B, Lc.C, Lc.ccw), [Lc.E]]))
    helix = Point(Lc.S[0] - hr, Lc.S[1]).buffer(hr + R - 2 * CURVE_FRACTION * tol)
    return _meets(lead, R - 2 * CURVE_FRACTION * tol, solid) is None and \
        not helix.intersects(solid)


def _arc(a, b, c, ccw: bool, n: int = 16) -> np.ndarray:
    """Points on the arc about ``c`` from ``a`` to ``b`` (counter-clockwise if ``ccw``)."""
    t0 = math.atan2(a[1] - c[1], a[0] - c[0])
    t1 = math.atan2(b[1] - c[1], b[0] - c[0])
    sw = (t1 - t0) % (2 * math.pi) if ccw else -((t0 - t1) % (2 * math.pi))
    r = math.hypot(a[0] - c[0], a[1] - c[1])
    t = t0 + sw * np.linspace(0, 1, n + 1)
    return np.column_stack([c[0] + r * np.cos(t), c[1] + r * np.sin(t)])


def _length(pts: np.ndarray) -> float:
    return float(np.hypot(*np.diff(pts, axis=0).T).sum())


def _scale(tabs, L_from: float, L_to: float):
    f = L_to / L_from if L_from > 0 else 1.0
    return [(a * f, b * f) for a, b in tabs]


def _nothing_left(ctx, path_c: np.ndarray, R: float, z: float, tol: float, top: float) -> bool:
    """True if the tool along ``path_c`` at ``z`` meets no material of the in-process stock."""
    poly = LineString(path_c).buffer(R * 2)
    h = R / 8.0
    raster = Raster.around(poly.bounds, h, 0.0)
    field = MaterialField(stock_heights(ctx.remaining, raster, top), raster, z, tol, R)
    return not field.touches(densify(path_c, h)).any()
