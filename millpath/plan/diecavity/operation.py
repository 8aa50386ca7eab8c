"""Operation ``die-cavity``: a free-form cavity from scattered points.

Points -> four-point segments with C1 blends (closed) -> fewest chords within
``tolerance`` -> the programmed contour (chords the tool cannot follow removed, their
neighbours extended to meet; points on the post's number grid, 0.0001 mm / 0.00001 in)
-> per depth step: contour-parallel roughing from the inside out leaving ``allowance``
(each ring entered by a 3 degree ramp along it), then the wall finished on the offset
contour.

``compensation = "cam"`` writes the tool-centre path (arcs round convex corners,
concave corners trimmed, LinuxCNC's rules, see :mod:`millpath.part.curve.offset`);
``"control"`` writes the contour itself between ``G41 D<tool>`` and ``G40`` and lets
the control offset it; both interpret to the same motion. LinuxCNC joins corners that
turn 0.05 rad or less straight (no arc, no trim), so near such a corner turning ``a``
the tool can come up to about r (1 - cos a) closer to the wall than r; the largest
such approach to the true curve is measured and reported as ``finish_max_undercut``
(0.0009 mm for die-blanking at T = 0.001 mm, 0.0001 mm for die-published); a tolerance
the path cannot keep with chords at the number grid is refused, naming the least
tolerance it can keep. The contour is cut counter-clockwise with the tool on its
left (G41, climb milling with M3).

``entry`` (the EMC/LinuxCNC manual's entry moves, seeds/003 "Tool compensation":
the simple method, and the general one: an alignment move, then a straight and an arc
lead-in): ``"line"`` (default) turns on G41 on a straight move that ends on a short
line joining the contour at 0.06 rad; ``"arc"`` (with ``compensation = "control"``)
turns on G41 on a straight move perpendicular to the contour, 2 r long, followed by a
quarter arc of radius 2 r tangent to the first chord (counter-clockwise, the tool
inside it at radius r), and leaves with the mirrored quarter arc off the last chord
and G40 on a straight move 2 r further into the cavity. Lengths in job units; ``depth`` below the stock
top; a cavity at least as deep as the block is a through cavity cut ``breakthrough``
below the block bottom.
"""

from __future__ import annotations

import math

import numpy as np
import shapely
from shapely.geometry import LineString, Polygon
from shapely.geometry.polygon import orient
from shapely.validation import make_valid

from millpath.errors import GeometryError, JobError, PlanningError
from millpath.io.schema import Param
from millpath.model import Operation, Toolpath
from millpath.model.control import CONCAVE_CORNER
from millpath.part.curve.blend import build_curve
from millpath.part.curve.fourpoint import Curve
from millpath.part.curve.linearize import linearize_curve
from millpath.part.curve.offset import (CompensationError, boundary_distance,
                                        chords_on_offset, compensate, reachable_contour,
                                        sample_elements)
from millpath.part.curve.points import points_from_params
from millpath.plan.base import PlanContext, PlanResult
from millpath.plan.diecavity.design import CavityDesign
from millpath.plan.diecavity.roughing import rings, roughing_area
from millpath.plan.entry import ramp_laps, ring_segments
from millpath.model.units import default

PARAMS = {
    "tool": Param("int", positive=True, doc="flat end mill (tool number)"),
    "points": Param("points", None, doc="outline points [x, y], four per segment"),
    "points_file": Param("path", None, doc="CSV of outline points x, y"),
    "close": Param("bool", True, doc="blend the last segment back to the first"),
    "tolerance": Param("float", positive=True, doc="chordal tolerance (job units)", unit="length"),
    "depth": Param("float", positive=True, doc="cavity depth below the stock top", unit="length"),
    "stepdown": Param("float", positive=True, doc="depth per layer", unit="length"),
    "allowance": Param("float", 0.0, nonneg=True, doc="wall stock left by roughing", unit="length"),
    "stepover": Param("float", None, positive=True, doc="roughing stepover (default 0.5 D)",
          unit="length"),
    "compensation": Param("str", "cam", choices=("cam", "control"),
          doc="'cam': the tool-centre path; 'control': the contour between G41 and G40"),
    "entry": Param("str", "line", choices=("line", "arc"),
                   doc="lead-in/out under G41: line, or line + tangent arc (control only)"),
    "feed": Param("float", positive=True, unit="feed", doc="cutting feed"),
    "plunge_feed": Param("float", None, positive=True, doc="default: feed / 2", unit="feed"),
    "spindle": Param("float", 0.0,
          unit="rpm", doc="spindle speed, clockwise (M3); 0: spindle left off"),
    "safe_z": Param("float", None, doc="default: stock top + 5 mm (0.2 in)", unit="length"),
    "breakthrough": Param("float", 0.0, nonneg=True, doc="below the block bottom", unit="length"),
}

def _grid(units: str) -> float:
    """The post's number grid (0.0001 mm, 0.00001 in): the programmed contour is rounded
    to it first so that CAM and control offsets start from the same points."""
    return 10.0 ** -int(default("decimals", units))


#: how far, in grid steps, the post's rounding of the tool-centre path (half a step on
#: each axis) can bring it nearer the wall
ROUNDING = 0.5 * math.sqrt(2.0)


def _region(pts: np.ndarray, tol: float, r: float, file=None) -> tuple[Polygon, bool]:
    """The cavity as a valid polygon of the linearized curve; True if the curve
    crossed itself in negligible loops (dropped: the largest part is kept). A loop is
    negligible when none of it lies more than ``tol`` from the kept part's outline, or
    when it is small (a ten-thousandth of the area) and a tool of radius ``r`` cannot
    come within ``tol`` of it (in a corner too sharp for the tool, as where two
    segments meet at a point); GeometryError
    otherwise (a loop a blend makes between badly placed segments is a sliver of wall
    the tool would have to cut through or go round)."""
    poly = Polygon(pts)
    if poly.is_valid:
        return poly, False
    fixed = make_valid(poly)
    parts = [g for g in getattr(fixed, "geoms", [fixed]) if isinstance(g, Polygon)]
    if not parts:
        raise GeometryError("the outline does not enclose an area", file)
    main = max(parts, key=lambda g: g.area)
    # every face the outline encloses, split where it crosses itself: all but the
    # kept part are loops
    ring = shapely.linearrings(np.asarray(pts, float))
    faces = list(shapely.get_parts(shapely.polygonize([shapely.node(ring)])))
    big = max(faces, key=lambda g: g.intersection(main).area) if faces else main
    rim = main.exterior
    reach = None
    for other in faces:
        if other is big:
            continue
        far = shapely.distance(rim, shapely.points(np.asarray(other.exterior.coords)))
        if far.max() <= tol:
            continue
        if reach is None:
            reach = main.buffer(-r, quad_segs=16).buffer(r, quad_segs=16)
        if other.area > 1e-4 * main.area or shapely.distance(reach, other) <= tol:
            x, y = other.representative_point().coords[0]
            raise GeometryError(f"the outline crosses itself (a loop round ({x:.3f}, "
                                f"{y:.3f}) reaching {far.max():.3g} from the rest of "
                                "it); check the points and their order", file)
    return main, True


def _curvature_report(curve: Curve, radius: float, samples: int = 400) -> list[dict]:
    """Stretches of the curve bending round the tool (toward the cavity) tighter than
    the tool radius: the tool cannot reach into them."""
    out = []
    for i, seg in enumerate(curve.segments):
        u = np.linspace(0.0, 1.0, samples + 1)
        k = seg.curvature(u)
        tight = k > 1.0 / radius
        if not tight.any():
            continue
        idx = np.flatnonzero(tight)
        splits = np.flatnonzero(np.diff(idx) > 1)
        for run in np.split(idx, splits + 1):
            j = run[np.argmax(k[run])]
            p = seg.at(u[j])
            out.append({"segment": i, "u": [float(u[run[0]]), float(u[run[-1]])],
                        "min_radius": float(1.0 / k[j]), "at": [float(p[0]), float(p[1])]})
    # corners where two segments meet without C1 and turn toward the cavity
    for j in curve.junctions():
        if j["derivative_gap"] > 1e-6 and (j["tangent_turn_deg"] > 0
                                           or abs(j["tangent_turn_deg"]) > 170):
            out.append({"segment": j["after"], "u": [1.0, 1.0], "min_radius": 0.0,
                        "at": j["point"], "corner_deg": j["tangent_turn_deg"]})
    return out


def _start_order(q: np.ndarray, r: float) -> np.ndarray:
    """Contour vertices in the order to try them as the start: the straightest
    stretches (least turning within 3 r behind the vertex) first."""
    t = np.roll(q, -1, axis=0) - q
    L = np.hypot(t[:, 0], t[:, 1])
    return np.argsort(_turn_behind(t, L, r), kind="stable")


def _turn_behind(t: np.ndarray, L: np.ndarray, r: float) -> np.ndarray:
    """At each vertex k of a closed contour (edge directions ``t`` from vertex k, edge
    lengths ``L``), the signed turning within 3 r of contour behind it (radians)."""
    m = len(t)
    ang = np.arctan2(t[:, 1], t[:, 0])
    turn = np.angle(np.exp(1j * (ang - np.roll(ang, 1))))        # at vertex k
    score = np.empty(m)
    cs = np.concatenate([[0.0], np.cumsum(np.concatenate([turn, turn, turn]))])
    pos = np.concatenate([[0.0], np.cumsum(np.concatenate([L, L, L]))])
    for k in range(m):
        kk = k + m
        lo = np.searchsorted(pos, pos[kk] - 3 * r)
        score[k] = cs[kk + 1] - cs[lo]
    return score


def _chords(q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Unit directions ``(m, 2)`` and lengths ``(m,)`` of the chords q[k] -> q[k+1] of
    the closed contour ``q``."""
    t = np.roll(q, -1, axis=0) - q
    L = np.hypot(t[:, 0], t[:, 1])
    return t / L[:, None], L


def _overlap(q: np.ndarray, L: np.ndarray, k: int, length: float) -> tuple[list, int]:
    """The contour vertices after q[k] up to the first at least ``length`` of contour
    past it, and the (unwrapped) index j of that last one."""
    m = len(q)
    acc, j = 0.0, k
    while acc < length:
        acc += L[j % m]
        j += 1
    return [q[i % m] for i in range(k + 1, j + 1)], j


def _quarter(centre, start, end, rad: float, n: int = 24) -> np.ndarray:
    """Points of the counter-clockwise arc about ``centre`` from ``start`` to ``end``
    at radius ``rad`` (the tool centre inside a programmed arc)."""
    a0 = math.atan2(start[1] - centre[1], start[0] - centre[0])
    a1 = math.atan2(end[1] - centre[1], end[0] - centre[0])
    if a1 <= a0:
        a1 += 2 * math.pi
    th = np.linspace(a0, a1, n)
    return np.column_stack([centre[0] + rad * np.cos(th), centre[1] + rad * np.sin(th)])


def arc_entry(q: np.ndarray, region_in: Polygon, r: float, grid: float):
    """The arc lead-in and lead-out under G41 (contour counter-clockwise, tool left).

    For a start vertex q[k] with first chord direction t and inward normal n: the arc
    of radius 2 r about C = q[k] + 2 r n from P = C - 2 r t to q[k] (counter-clockwise,
    tangent to the chord at q[k]) is entered by a straight move from S = P + 2 r n
    (the G41 move, longer than r as LinuxCNC requires). After the contour and an
    overlap of at least 2 r past q[k] ending at q[j] (last chord direction te, normal
    ne), the mirrored arc about Ce = q[j] + 2 r ne runs to Pe = Ce + 2 r te, and G40 is
    turned on by a straight move to X = Pe + 2 r ne. The tool centre (the straight
    moves, and the arcs at radius r about C and Ce) must stay inside ``region_in``.

    Returns ``(k, S, P, C, overlap, Ce, Pe, X)`` with the points on the program's
    ``grid``; PlanningError when no vertex leaves room."""
    m = len(q)
    t, L = _chords(q)
    n = np.stack([-t[:, 1], t[:, 0]], axis=1)
    rho = 2.0 * r

    def g(p):
        return np.round(np.asarray(p, float) / grid) * grid

    def inside(pts) -> bool:
        return bool(region_in.contains(LineString(pts)))

    for k in _start_order(q, r):
        C = q[k] + rho * n[k]
        P = g(C - rho * t[k])
        S = g(P + rho * n[k])
        tool_in = [S, P + r * t[k]] + list(_quarter(C, P, q[k], rho - r)[1:])
        if not inside(tool_in):
            continue
        ov, j = _overlap(q, L, k, 2 * r)
        jm = (j - 1) % m
        qe = q[j % m]
        Ce = qe + rho * n[jm]
        Pe = g(Ce + rho * t[jm])
        X = g(Pe + rho * n[jm])
        tool_out = list(_quarter(Ce, qe, Pe, rho - r)) + [X]
        if not inside(tool_out):
            continue
        return int(k), S, P, C, ov, Ce, Pe, X
    raise PlanningError("no place on the contour leaves room for an arc lead-in of the "
                        f"tool (radius {2 * r:g} arcs); use entry = \"line\"")


def _entry(q: np.ndarray, region_in: Polygon, r: float, grid: float):
    """Pick the contour start and the lead-in: returns (k, S, A, exit_point, overlap).

    The lead-in ends with a line A -> q[k] turning 0.06 rad onto the first chord (a
    concave corner for LinuxCNC, trimmed exactly; 0.05 rad or less would be joined
    straight and nick the wall), entered from S perpendicular to it, 2 r away
    (LinuxCNC needs the first compensated move to be longer than r). Candidates are
    tried from the straightest stretches; the tool centre on the lead-in and lead-out
    must stay inside ``region_in`` (the cavity eroded by r)."""
    m = len(q)
    t, L = _chords(q)
    # turning within 3 r behind each vertex: prefer stretches bending away
    score = _turn_behind(t, L, r)
    phi = 0.06
    c, sn = math.cos(-phi), math.sin(-phi)
    d_in = np.stack([c * t[:, 0] - sn * t[:, 1], sn * t[:, 0] + c * t[:, 1]], axis=1)
    n_in = np.stack([-d_in[:, 1], d_in[:, 0]], axis=1)
    # on the program's number grid, so LinuxCNC starts from the very same points
    a_pts = np.round((q - 2.0 * r * d_in) / grid) * grid
    s_pts = np.round((a_pts + 2.0 * r * n_in) / grid) * grid
    inside = shapely.contains_xy(region_in, s_pts[:, 0], s_pts[:, 1])
    for k in np.argsort(score, kind="stable"):
        if not inside[k]:
            continue
        A, S = a_pts[k], s_pts[k]
        lead = compensate(S, [A, q[k], q[(k + 1) % m]], r, "left")
        path = sample_elements(S, lead[:-1], r / 4)
        if not region_in.contains(LineString(path)):
            continue
        # lead-out: after overlapping at least 2 r past q[k], straight in by r
        ov, j = _overlap(q, L, k, 2 * r)
        jm = (j - 1) % m
        nj = np.array([-t[jm, 1], t[jm, 0]])
        exit_point = np.round((q[j % m] + 2.0 * r * nj) / grid) * grid
        if not region_in.contains(LineString([q[j % m] + 1.01 * r * nj, exit_point])):
            continue
        return int(k), S, A, exit_point, ov
    raise PlanningError("no place on the contour leaves room for a lead-in of the tool "
                        f"(a {2 * r:g} line in, clear of the walls): use "
                        "compensation = \"cam\" or a smaller tool")


def _hop(tp: Toolpath, cur, to, safe: float, z_down: float) -> None:
    """Rapid up from ``cur`` (None: already at ``safe``) to ``safe``, across to ``to``
    and down to ``z_down``."""
    if cur is not None:
        tp.rapid(cur[0], cur[1], safe)
    tp.rapid(to[0], to[1], safe)
    tp.rapid(to[0], to[1], z_down)


#: at most this many chord tolerances are tried to bring the finishing path within
#: the tolerance of the wall (see ``plan``)
CHORD_ATTEMPTS = 6

#: ramp angle of roughing entries (degrees): the tool descends along the ring
RAMP_DEG = 3.0


def _ramp(tp: Toolpath, ring: np.ndarray, z_from: float, z_to: float, feed: float) -> None:
    """Descend from ``z_from`` to ``z_to`` at RAMP_DEG while following the closed
    ``ring`` from its first point (as many laps as needed), ending back at its first
    point; a ring too short to ramp on gets a straight plunge."""
    closed, seg, lap = ring_segments(ring)
    need = (z_from - z_to) / math.tan(math.radians(RAMP_DEG))
    if lap < 1e-3 or need <= 0:
        tp.line(ring[0][0], ring[0][1], z_to, feed)
        return
    laps = max(1, int(math.ceil(need / lap - 1e-9)))
    ramp_laps(tp, closed, seg, laps, z_from, z_to, feed)


def _grid_round(pts: np.ndarray, grid: float) -> np.ndarray:
    q = np.round(pts / grid) * grid
    keep = np.ones(len(q), bool)
    keep[1:] = np.any(q[1:] != q[:-1], axis=1)
    q = q[keep]
    if np.all(q[-1] == q[0]):
        q = q[:-1]
    return q


def plan(ctx: PlanContext, params: dict) -> PlanResult:
    """Plan the cavity; see the module docstring for the keys."""
    where = "die-cavity"
    tool = ctx.tool(params["tool"], f"{where}.tool")
    if tool.type != "flat":
        raise JobError(f"{where}.tool: tool {tool.number} is a {tool.type} cutter; the "
                       "die cavity needs a flat end mill", ctx.job_file)
    if ctx.stock is None:
        raise JobError(f"{where}: the job needs a [stock] box", ctx.job_file)
    pts = ctx.parts.get("curve-points", (params["points"], params["points_file"]),
                        lambda: points_from_params(params["points"], params["points_file"],
                                                   ctx.job_file, where)).copy()
    src = params["points_file"] or ctx.job_file
    curve = build_curve(pts, close=params["close"], file=src)
    if not curve.closed:
        raise GeometryError("the outline is not closed (set close = true)", src)
    if curve.signed_area() < 0:
        curve = curve.reversed()
    tol = params["tolerance"]
    r = tool.radius
    # The finishing path comes nearer the wall than r by the chords' sagitta plus,
    # where LinuxCNC joins a corner turning 0.05 rad or less straight, r (1 - cos a):
    # both shrink with the chord tolerance, so the chords are made finer until the
    # measured approach is within the tolerance (the published chords when it already is),
    # or the chords reach the program's number grid, below which finer chords cannot help.
    chord_tol = tol
    for attempt in range(CHORD_ATTEMPTS):
        lin = linearize_curve(curve, chord_tol)
        region, crossed = _region(lin.polyline(), tol, r, src)
        grid = _grid(ctx.units)
        # the contour of the valid cavity (small self-crossing loops cut off), CCW
        ring = np.asarray(orient(region, 1.0).exterior.coords)[:-1]
        verts = _grid_round(ring, grid)

        # the programmed contour: what the tool can follow
        region_in = region.buffer(-r + 10 * grid, quad_segs=32)
        if region_in.is_empty:
            raise PlanningError(f"the cavity is too small for tool {tool.number} "
                                f"(diameter {tool.diameter})", ctx.job_file)
        eroded = region.buffer(-r, quad_segs=64)
        lobes = [g for g in getattr(eroded, "geoms", [eroded]) if g.area > 1e-9]
        if len(lobes) > 1:
            where_ = ", ".join(f"({g.representative_point().x:.3f}, "
                               f"{g.representative_point().y:.3f})" for g in lobes)
            raise PlanningError(f"the cavity narrows below the diameter of tool {tool.number}, "
                                f"which would have to cut {len(lobes)} separate parts (around "
                                f"{where_}); use a smaller tool", ctx.job_file)
        t = np.roll(verts, -1, axis=0) - verts
        t /= np.hypot(t[:, 0], t[:, 1])[:, None]
        mids = 0.5 * (verts + np.roll(verts, -1, axis=0)) + r * np.stack([-t[:, 1], t[:, 0]], 1)
        dist = boundary_distance(region_in, mids)
        keep = chords_on_offset(verts, r, "left", eroded, 20 * grid)
        try:
            reach = reachable_contour(verts, r, "left", start=int(np.argmin(dist)), keep=keep)
        except CompensationError as e:
            p = verts[e.index % len(verts)]
            raise PlanningError(f"{e} near ({p[0]:.3f}, {p[1]:.3f})", ctx.job_file) from None
        # corners where removed chords were bridged are new points: put them on the grid
        q = np.round(reach.points / grid) * grid
        # long chords get a middle point, a place to enter the contour (a lead-in ends 2 r
        # along the chord it joins)
        nxt = np.roll(q, -1, axis=0)
        long = np.hypot(*(nxt - q).T) > 5 * r
        if long.any():
            mid = np.round(0.5 * (q + nxt) / grid) * grid
            q = np.insert(q, np.flatnonzero(long) + 1, mid[long], axis=0)
        if params["entry"] == "arc" and params["compensation"] != "control":
            raise JobError(f"{where}.entry: \"arc\" is the lead-in under G41 "
                           "(compensation = \"control\"); the CAM path enters on a line",
                           ctx.job_file)
        arc_in = arc_entry(q, region_in, r, grid) if params["entry"] == "arc" else None
        k, S, A, exit_point, overlap = _entry(q, region_in, r, grid)
        if arc_in is not None:
            # the line entry's own start k serves the undercut measure; the program
            # starts at the arc entry's vertex
            ka, S_arc, P_arc, C_arc, ov_arc, Ce_arc, Pe_arc, X_arc = arc_in
        q = np.roll(q, -k, axis=0)
        prog = [A] + list(q) + [q[0]] + [np.asarray(p) for p in overlap]
        try:
            elements = compensate(S, prog, r, "left")
        except CompensationError as e:
            raise PlanningError(f"cutter compensation fails at contour point {e.index}: {e}",
                                ctx.job_file) from None
        # how far the finishing path comes to the true wall (negative: inside it)
        path = sample_elements(S, elements, max(tol, r / 50))
        # ... measured against the true curve, sampled 4 times finer than the chords
        per = 4 * max(sl.chords for sl in lin.segments)
        true, _ = _region(curve.sample(per), tol, r, src)
        shapely.prepare(true)
        gap = boundary_distance(true, path)
        inside = shapely.contains_xy(true, path[:, 0], path[:, 1])
        clearance = np.where(inside, gap, -gap) - r
        if inside.all():
            # nearest approach between the samples too (lines exactly; an arc's chords
            # lie nearer the wall than the arc)
            clearance = np.append(clearance, shapely.distance(
                true.exterior, shapely.linestrings(path)) - r)
        undercut = float(max(0.0, -clearance.min()))
        # the post moves every point of the path by up to half a grid step on each axis
        if undercut + ROUNDING * grid <= tol or chord_tol <= grid \
                or attempt == CHORD_ATTEMPTS - 1:
            break                # within the tolerance, or chords at the number grid
        room = max(tol - ROUNDING * grid, 0.25 * tol)
        chord_tol = max(grid, chord_tol * max(0.25, 0.9 * room / undercut))
    if undercut > tol + ROUNDING * grid:
        # chords at the number grid and the path still comes nearer the wall than the
        # tolerance, by more than the post's rounding: the proof would refuse the
        # program, so refuse the job instead, naming the least tolerance it keeps
        least = math.ceil(undercut / grid - 1e-9) * grid
        raise JobError(f"{where}.tolerance: {tol:g} is tighter than tool {tool.number} "
                       f"can follow this cavity: with chords at the program's number grid "
                       f"({grid:g}) it still comes {undercut:.4g} into the wall where the "
                       f"offset chords are joined straight (turns of 0.05 rad or less); "
                       f"give tolerance = {least:.6g} or more", ctx.job_file)

    # layers
    st = ctx.stock
    top = st.zmax
    thick = st.zmax - st.zmin
    depth = params["depth"]
    through = depth >= thick - 1e-9
    bottom = (st.zmin - params["breakthrough"]) if through else top - depth
    total = top - bottom
    n_layers = max(1, int(math.ceil(total / params["stepdown"] - 1e-9)))
    zs = [top - min(total, (i + 1) * params["stepdown"]) for i in range(n_layers)]
    safe = params["safe_z"] if params["safe_z"] is not None else top + default("safe_clearance", ctx.units)
    clear = default("feed_clearance", ctx.units)
    feed = params["feed"]
    plunge = params["plunge_feed"] or feed / 2.0
    stepover = params["stepover"] or 0.5 * tool.diameter
    if stepover > tool.diameter:
        raise JobError(f"{where}.stepover: larger than the tool diameter", ctx.job_file)

    simp = max(params["allowance"], tol) / 10
    area = roughing_area(region, r, params["allowance"] + simp,
                         simplify=max(params["allowance"] / 4, tol))
    rough = [np.asarray(LineString(np.vstack([g, g[:1]])).simplify(simp).coords)[:-1]
             for g in rings(area, stepover)]
    area_ok = [a.buffer(1e-6) for a in area]

    tp = Toolpath(units=ctx.units)
    tp.begin(Operation("die-cavity", f"die cavity ({params['compensation']})", tool.number,
                       spindle=params["spindle"],
                       info={"layers": n_layers, "compensation": params["compensation"]},
                       tolerance=tol))
    if arc_in is not None:
        qa = np.roll(q, k - ka, axis=0)          # the contour from the arc entry's vertex
        S, exit_point = S_arc, X_arc
    tp.rapid(S[0], S[1], safe)
    z_prev = top
    for z in zs:
        # roughing, inside out
        cur = None
        for ring in rough:
            if cur is not None:
                ring = np.roll(ring, -int(np.argmin(np.hypot(*(ring - cur).T))), axis=0)
            start = ring[0]
            if cur is not None and any(a.contains(LineString([cur, start])) for a in area_ok):
                tp.line(start[0], start[1], z, feed)
            else:
                _hop(tp, cur, start, safe, z_prev + clear)
                tp.line(start[0], start[1], z_prev, plunge)
                _ramp(tp, ring, z_prev, z, plunge)
            for p in ring[1:]:
                tp.line(p[0], p[1], z, feed)
            tp.line(start[0], start[1], z, feed)
            cur = start
        # finishing the wall
        if cur is not None and region_in.contains(LineString([cur, S])):
            tp.line(S[0], S[1], z, feed)
        else:
            _hop(tp, cur, S, safe, z_prev + clear)
            tp.line(S[0], S[1], z, plunge)
        if arc_in is not None:
            tp.compensation("left", d=tool.number)
            tp.line(P_arc[0], P_arc[1], z, feed)
            tp.arc((qa[0][0], qa[0][1], z), (C_arc[0], C_arc[1], z), False, feed)
            for p in list(qa[1:]) + [qa[0]] + [np.asarray(p) for p in ov_arc]:
                tp.line(p[0], p[1], z, feed)
            tp.arc((Pe_arc[0], Pe_arc[1], z), (Ce_arc[0], Ce_arc[1], z), False, feed)
            tp.compensation("off")
        elif params["compensation"] == "control":
            tp.compensation("left", d=tool.number)
            for p in prog:
                tp.line(p[0], p[1], z, feed)
            tp.compensation("off")
        else:
            for e in elements:
                if e.kind == "line":
                    tp.line(e.end[0], e.end[1], z, feed)
                else:
                    tp.arc((e.end[0], e.end[1], z), (e.center[0], e.center[1], z),
                           e.clockwise, feed)
        tp.line(exit_point[0], exit_point[1], z, feed)
        tp.rapid(exit_point[0], exit_point[1], safe)
        z_prev = z

    unreachable = []
    swept = LineString(path).buffer(r, quad_segs=16)
    shapely.prepare(swept)
    for run in reach.removed:
        idx = np.array(run)
        pv = verts[idx]
        uncut = shapely.distance(swept, shapely.points(pv))
        unreachable.append({"chords": len(run), "from": [float(v) for v in pv[0]],
                            "to": [float(v) for v in verts[(idx[-1] + 1) % len(verts)]],
                            "at": [float(v) for v in pv[np.argmax(uncut)]],
                            "max_uncut": float(uncut.max())})
    # sharp corners the programmed contour keeps (trimmed by the offset) leave material
    # in the corner too: report those leaving more than the tolerance
    t_q = np.roll(q, -1, axis=0) - q
    ang = np.arctan2(t_q[:, 1], t_q[:, 0])
    turn = np.angle(np.exp(1j * (ang - np.roll(ang, 1))))         # at vertex k, left > 0
    on_curve = {tuple(v) for v in np.round(verts / grid).astype(np.int64).tolist()}
    sharp = [k_ for k_ in np.flatnonzero(turn > CONCAVE_CORNER)  # bridged: reported above
             if tuple(np.round(q[k_] / grid).astype(np.int64).tolist()) in on_curve]
    if len(sharp):
        uncut = shapely.distance(swept, shapely.points(q[sharp]))
        for k_, u_ in zip(sharp, uncut):
            if u_ > tol:
                unreachable.append({"chords": 0, "from": q[k_].tolist(), "to": q[k_].tolist(),
                                    "at": q[k_].tolist(), "max_uncut": float(u_),
                                    "corner_deg": float(np.degrees(turn[k_]))})
    report = lin.report()
    report.update({
        "closed": curve.closed, "segments_count": len(curve.segments),
        "junctions": curve.junctions(),
        "self_intersecting": crossed,
        "area": float(region.area),
        "tool_radius": r,
        "programmed_points": int(len(q)),
        "removed_chords": int(sum(len(x) for x in reach.removed)),
        "unreachable_corners": unreachable,
        "tight_curvature": _curvature_report(curve, r),
        "finish_max_undercut": undercut,
        "finish_chord_tolerance": chord_tol,
        "program_grid": grid,
        "compensation": params["compensation"],
        "layers": [float(z) for z in zs],
        "through": through,
        "roughing_rings": len(rough),
        "entry": {"method": params["entry"], "start": [float(S[0]), float(S[1])],
                  "contour_point": ([float(v) for v in qa[0]] if arc_in is not None
                                    else [float(q[0][0]), float(q[0][1])])},
    })
    floor = -math.inf if through else bottom
    design = CavityDesign(true, top, floor, deepest=bottom)
    return PlanResult(tp, design=design, report={"curve": report})
