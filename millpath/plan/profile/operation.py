"""Operation ``profile``: cut along drawn contours, outside or inside (issue 21).

Keys (job units; feeds in units per minute; Z absolute, tool tip):

- geometry: ``dxf`` (+ ``layer``, ``join_tolerance``) or ``polygon`` (+ ``islands``,
  ignored); the outer contour of each region is profiled. ``tolerance``: chordal
  tolerance (default 0.01 mm / 0.0005 in).
- ``side``: ``outside`` (the tool outside the contour) or ``inside``.
- ``compensation``: ``cam`` (the tool-centre path: the contour offset by the tool
  radius, round joins) or ``control`` (the contour itself between ``G41``/``G42
  D<tool>`` and ``G40``; the control offsets it by the tool table's diameter).
- ``direction``: ``climb`` (default: tool on the left, G41, with a clockwise spindle)
  or ``conventional`` (right, G42).
- ``lead_radius`` (default the tool diameter; must exceed the tool radius): tangent
  quarter-arc lead-in and lead-out on the tool side, each with a straight entry/exit of
  ``lead_radius`` (see :mod:`.leads`).
- ``top`` (default stock top), ``depth`` below it, ``stepdown``: levels.
- ``tabs = N`` holding tabs ``tab_width`` long (default the tool diameter, measured
  along the contour) and ``tab_height`` above the bottom (default 0: no tabs), spread
  evenly; on levels below the tab top the tool climbs over them (straight up, then down
  along the path at no more than 45 degrees).
- ``rest``: levels whose path meets no material left by earlier operations are skipped.
- ``feed``, ``plunge_feed`` (default feed / 2), ``spindle``, ``safe_z``, ``ramp_angle``
  (helix descent at the entry point, degrees, default 3).
"""

from __future__ import annotations

import math

import numpy as np
from shapely.geometry import LineString, Polygon
from shapely.geometry.polygon import orient

from millpath.errors import JobError, PlanningError
from millpath.io.schema import Param
from millpath.model import Operation, Toolpath
from millpath.plan.base import PlanContext, PlanResult
from millpath.plan.profile.leads import leads, start_on_longest
from millpath.plan.twod.field import MaterialField, Raster, densify, stock_heights
from millpath.plan.twod.geometry import GEOMETRY_PARAMS, default_tolerance, load_regions
from millpath.plan.levels import levels
from millpath.plan.twod.heights import MOTION_PARAMS, end_mill, operation_heights, plunge_feed
from millpath.plan.twod.offsets import offset, polygons
from millpath.plan.twod.writer import PathWriter

PARAMS = {
    **GEOMETRY_PARAMS,
    "tool": Param("int", positive=True, doc="flat or bull end mill"),
    "side": Param("str", choices=("outside", "inside"), doc="tool outside or inside the contour"),
    "compensation": Param("str", "cam", choices=("cam", "control"),
          doc="'cam': the tool-centre path; 'control': the contour between G41/G42 and G40"),
    "direction": Param("str", "climb", choices=("climb", "conventional"),
          doc="climb (tool on the left, G41) or conventional (right, G42)"),
    "lead_radius": Param("float", None, positive=True, unit="length",
          doc="tangent lead-in/out arc radius (default: the tool diameter; more than the tool "
              "radius)"),
    "top": Param("float", None, unit="length", doc="Z of the contour's top (default: stock top)"),
    "depth": Param("float", positive=True, unit="length", doc="depth below top"),
    "stepdown": Param("float", positive=True, unit="length", doc="depth per level"),
    "tabs": Param("int", 0, nonneg=True, unit="count",
          doc="holding tabs spread evenly along each contour"),
    "tab_height": Param("float", 0.0, nonneg=True, unit="length",
          doc="tab height above the bottom (0: no tabs)"),
    "tab_width": Param("float", None, positive=True, unit="length",
          doc="tab length along the contour (default: the tool diameter)"),
    "rest": Param("bool", False,
          doc="skip levels whose path meets no material left by earlier operations"),
    **MOTION_PARAMS,
    "ramp_angle": Param("float", 3.0, positive=True, unit="deg",
          doc="helix descent angle at the entry point"),
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
    tool = end_mill(ctx, params, "a profile")
    regions = load_regions(params, ctx.units, file, ctx.parts)
    R = tool.radius
    rho = params["lead_radius"] or tool.diameter
    if rho <= R * 1.0001:
        raise JobError(f"lead_radius: {rho:g} must be larger than the tool radius {R:g}", file)
    heights = operation_heights(ctx, params)
    top, upper, safe, clearance = (heights.top, heights.upper, heights.safe_z,
                                   heights.clearance)
    stock_top = ctx.stock.zmax if ctx.stock is not None else None
    bottom = top - params["depth"]
    tab_h = params["tab_height"]
    if params["tabs"] and not 0 < tab_h < params["depth"]:
        raise JobError(f"tab_height: must be between 0 and the depth {params['depth']:g} "
                       f"when tabs are asked for, got {tab_h:g}", file)
    feed = params["feed"]
    plunge = plunge_feed(params)
    side = 1 if params["direction"] == "climb" else -1
    outside = params["side"] == "outside"
    control = params["compensation"] == "control"
    tol = params["tolerance"] or default_tolerance(ctx.units)

    tp = Toolpath(ctx.units)
    op = Operation("profile", f"profile {params['side']} ({params['compensation']})",
                   tool.number, spindle=params["spindle"],
                   info={"side": params["side"], "compensation": params["compensation"]})
    tp.begin(op)
    w = PathWriter(tp, safe_z=safe, clear_z=upper + clearance, feed=feed, plunge_feed=plunge,
                   ramp_angle=params["ramp_angle"])
    skipped = 0
    for reg in regions:
        contour = Polygon(reg.polygon.exterior)
        # traversal with the tool on the left (climb): outside clockwise, inside ccw
        ring = np.asarray(orient(contour, -1.0 if outside else 1.0).exterior.coords)[:-1, :2]
        if side < 0:
            ring = ring[::-1]
        ring = start_on_longest(ring)
        t = ring[1] - ring[0]
        centre = offset(contour, R if outside else -R)
        cpolys = polygons(centre)
        if not cpolys:
            raise PlanningError(f"tool {tool.number} (diameter {tool.diameter:g}) does not fit "
                                f"inside the contour {reg.name}", params["dxf"] or file)
        if len(cpolys) > 1:
            raise PlanningError(f"tool {tool.number} (diameter {tool.diameter:g}) does not fit "
                                f"through a neck of the contour {reg.name}",
                                params["dxf"] or file)
        cring = np.asarray(orient(cpolys[0], -1.0 if outside else 1.0).exterior.coords)[:-1, :2]
        if side < 0:
            cring = cring[::-1]
        P0c = ring[0] + R * side * np.array([-t[1], t[0]]) / np.hypot(*t)
        closed_c = np.vstack([cring, cring[:1]])
        at = LineString(closed_c).project(LineString([P0c, P0c]).centroid)
        cum = np.concatenate([[0.0], np.cumsum(np.hypot(*np.diff(closed_c, axis=0).T))])
        k = int(np.searchsorted(cum, at + 1e-9)) % len(cring)     # first vertex after P0c
        cring = np.vstack([P0c, np.roll(cring, -k, axis=0)])
        if np.hypot(*(cring[1] - cring[0])) < 1e-9:
            cring = cring[1:]
        tries = [rho] if params["lead_radius"] else [rho * f for f in (1.0, 0.8, 0.65, 0.55)]
        for rho_k in tries:
            Lc = leads(ring[0], t, side, rho_k, rho_k, offset=R)     # tool-centre leads
            Lp = leads(ring[0], t, side, rho_k, rho_k, offset=0.0)   # programmed leads
            if _leads_fit(Lc, cring[0], R, contour, outside):
                break
        else:
            raise PlanningError(f"no room for the lead-in and lead-out of radius "
                                f"{tries[-1]:g} or more at ({ring[0][0]:.3f}, "
                                f"{ring[0][1]:.3f}) of the contour {reg.name}",
                                params["dxf"] or file)
        path_c = np.vstack([cring, cring[:1]])
        L = float(np.hypot(*np.diff(path_c, axis=0).T).sum())
        width = params["tab_width"] or tool.diameter
        tabs = _tab_intervals(L, params["tabs"], width + tool.diameter)
        z_tab = bottom + tab_h
        z_prev = None
        for z in levels(top, bottom, params["stepdown"]):
            if params["rest"] and ctx.remaining is not None and _nothing_left(
                    ctx, path_c, R, z, tol, stock_top if stock_top is not None else top):
                skipped += 1
                z_prev = z
                continue
            z_from = upper + clearance if z_prev is None else z_prev + clearance
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
                    pts = _with_tabs(loop, z, z_tab, _scale(tabs, L, _length(loop)), tol * 10)
                else:
                    pts = _with_tabs(loop, z, z_tab, tabs, tol * 10)
                for p in pts[1:]:
                    tp.line(p[0], p[1], p[2], feed)
            else:
                for p in loop[1:]:
                    tp.line(p[0], p[1], z, feed)
            tp.arc((B[0], B[1], z), (C[0], C[1], z), not Lc.ccw, feed)
            tp.line(E[0], E[1], z, feed)
            if control:
                tp.compensation("off")
            w.pos = (float(E[0]), float(E[1]), z)
            w.retract()
            z_prev = z
    w.retract()
    op.info["levels_skipped"] = skipped
    return PlanResult(tp)


def _leads_fit(Lc, start, R: float, contour: Polygon, outside: bool) -> bool:
    """True if the leads' tool-centre path, and the helix beside S, keep the tool in the
    waste (outside the contour for an outside profile, inside it for an inside one)."""
    hr = 0.5 * R
    lead = LineString(np.vstack([[Lc.S - [2 * hr, 0]], [Lc.S], _arc(Lc.A, start, Lc.C, Lc.ccw),
                                 _arc(start, Lc.B, Lc.C, Lc.ccw), [Lc.E]]))
    swept = lead.buffer(R - 1e-4)
    if outside:
        return not swept.intersects(contour.buffer(-1e-4))
    return contour.buffer(1e-4).contains(swept)


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
