"""An independent check of a written program against the geometry that generated it.

LinuxCNC's ``rs274`` interprets the program (not millpath's interpreter); its motion,
as tool tips (:func:`millpath.simulate.tip.tip_motions`), is sampled along lines and
arcs (helices included) and every sample below the stock top is checked with shapely
and numpy against the job's own numbers, not against millpath's proof:

- ``inside`` regions (pocket, inside profile, grid-pocket): the tool centre lies in the
  region at least ``R - tol`` from its boundary (outline and islands);
- ``outside`` regions (outside profile): the tool centre is at least ``R - tol`` from
  the part (outline less its holes);
- floors: no tip below ``floor - tol``; a grid-pocket's bottom surface (``surface(x, y)``,
  evaluated here from the job's Bezier net or measured points) stays under the tool's
  underside within ``tol`` at points spread over the tool's footprint;
- ``surface`` parts (surface-rough, surface-finish): OpenCAMLib drops the same cutter
  onto the job's mesh at every sample's XY; the tip stays at least ``allowance - tol``
  above the height it finds.

Millimetres or inches as the job; ``tol`` is the operation's promised tolerance.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable

import numpy as np
import shapely
from shapely.geometry import Polygon

_AXES = {"XY": (0, 1, 2), "XZ": (2, 0, 1), "YZ": (1, 2, 0)}


@dataclass
class Geometry:
    """What the job was generated from (job units)."""

    top: float
    radius: float
    tool_type: str
    corner_radius: float
    tol: float
    region: Polygon                      # the tool-centre side's region (see ``side``)
    side: str                            # "inside" | "outside" | "surface"
    floor: float = -math.inf
    surface: Callable[[np.ndarray, np.ndarray], np.ndarray] | None = None
    mesh: np.ndarray | None = None       # (n, 3, 3) triangles of a "surface" part
    allowance: float = 0.0               # material the tool leaves on ``mesh``
    #: an "air" part (2.5D features from the top): (floor Z, removed section) of each
    #: feature; at height z the tool centre must lie in the air of every feature whose
    #: floor is at or under z + tol, the block's outside included (``region``: the
    #: block's footprint)
    levels: list[tuple[float, Polygon]] = field(default_factory=list)


@dataclass
class CheckResult:
    ok: bool
    problems: list[str] = field(default_factory=list)
    samples: int = 0


def bezier_surface(net: list[list[float]], bounds) -> Callable:
    """z(x, y) of a Bezier net of heights over ``bounds`` (rows along Y from the lowest,
    entries along X), the control points evenly spaced over the box."""
    z = np.asarray(net, float)
    x0, y0, x1, y1 = bounds

    def bern(n: int, t: np.ndarray) -> np.ndarray:
        k = np.arange(n + 1)
        c = np.array([math.comb(n, i) for i in k], float)
        return c * t[:, None] ** k * (1 - t[:, None]) ** (n - k)

    def f(x, y):
        u = np.clip((np.asarray(x, float) - x0) / (x1 - x0), 0, 1)
        v = np.clip((np.asarray(y, float) - y0) / (y1 - y0), 0, 1)
        bu, bv = bern(z.shape[1] - 1, u), bern(z.shape[0] - 1, v)
        return np.einsum("ni,ij,nj->n", bv, z, bu)
    return f


def grid_surface(xs, ys, zs) -> Callable:
    """Bilinear z(x, y) through measured heights ``zs[j][i]`` at (xs[i], ys[j])."""
    from scipy.interpolate import RegularGridInterpolator
    f = RegularGridInterpolator((np.asarray(ys, float), np.asarray(xs, float)),
                                np.asarray(zs, float), method="linear")
    return lambda x, y: f(np.column_stack([y, x]))


def _arc_points(m, step: float) -> np.ndarray:
    i1, i2, i3 = _AXES[m.plane]
    s, e, c = np.asarray(m.start), np.asarray(m.end), np.asarray(m.center)
    a0 = math.atan2(s[i2] - c[i2], s[i1] - c[i1])
    a1 = math.atan2(e[i2] - c[i2], e[i1] - c[i1])
    r = math.hypot(s[i1] - c[i1], s[i2] - c[i2])
    turns = abs(m.rotation) - 1
    base = (a1 - a0) % (2 * math.pi) if m.rotation > 0 else (a0 - a1) % (2 * math.pi)
    if base < 1e-9:                      # end on the start: a full circle
        base = 2 * math.pi
    sweep = (base + 2 * math.pi * turns) * (1 if m.rotation > 0 else -1)
    n = max(2, int(math.ceil(abs(sweep) * max(r, 1e-9) / step)) + 1)
    t = np.linspace(0.0, 1.0, n)
    out = np.empty((n, 3))
    out[:, i1] = c[i1] + r * np.cos(a0 + sweep * t)
    out[:, i2] = c[i2] + r * np.sin(a0 + sweep * t)
    out[:, i3] = s[i3] + (e[i3] - s[i3]) * t
    return out


def sample(motions, step: float) -> np.ndarray:
    """Points (n, 3) along traverses, feeds and arcs at most ``step`` apart."""
    out = []
    prev = None
    for m in motions:
        start_known = prev is not None and np.allclose(m.start, prev, atol=1e-6)
        prev = m.end
        if not start_known and m.kind in ("traverse", "feed", "arc"):
            # the first move (or one after a tool-length change) comes from where the
            # machine stood: down from above to its end, as the proof takes it
            out.append(np.asarray([m.end], float))
            continue
        if m.kind in ("traverse", "feed"):
            s, e = np.asarray(m.start, float), np.asarray(m.end, float)
            n = max(2, int(math.ceil(np.linalg.norm(e - s) / step)) + 1)
            out.append(s + (e - s) * np.linspace(0, 1, n)[:, None])
        elif m.kind == "arc":
            out.append(_arc_points(m, step))
        elif m.kind in ("cubic", "nurbs"):
            raise ValueError(f"line {m.line}: {m.kind} motion is not sampled by this check")
    return np.concatenate(out) if out else np.zeros((0, 3))


def _profile(g: Geometry, r: np.ndarray) -> np.ndarray:
    r = np.clip(r, 0, g.radius)
    if g.tool_type == "flat":
        return np.zeros_like(r)
    rc = g.radius if g.tool_type == "ball" else g.corner_radius
    d = np.maximum(r - (g.radius - rc), 0.0)
    return rc - np.sqrt(np.maximum(rc * rc - d * d, 0.0))


def check_points(p: np.ndarray, g: Geometry) -> list[str]:
    """Problems of the tool-tip samples ``p`` (n, 3) against ``g``."""
    probs = []
    low = p[p[:, 2] < g.top - 1e-6]
    if not len(low):
        return probs
    if g.side == "surface":
        return _check_mesh(low, g)
    if g.side == "air":
        return _check_air(low, g)
    xy = low[:, :2]
    inside = shapely.contains_xy(g.region, xy[:, 0], xy[:, 1])
    d = shapely.distance(g.region.boundary, shapely.points(xy))
    if g.side == "inside":
        bad = ~inside | (d < g.radius - g.tol)
        depth = np.where(inside, g.radius - d, g.radius + d)
    else:
        bad = inside | (d < g.radius - g.tol)
        depth = np.where(inside, g.radius + d, g.radius - d)
    if bad.any():
        k = int(np.argmax(np.where(bad, depth, -np.inf)))
        probs.append(f"tool centre {depth[k]:.4f} into the wall at X{xy[k, 0]:.3f} "
                     f"Y{xy[k, 1]:.3f} Z{low[k, 2]:.3f} (allowed {g.tol:g})")
    under = low[:, 2] < g.floor - g.tol
    if under.any():
        k = int(np.argmin(low[:, 2]))
        probs.append(f"tip {g.floor - low[k, 2]:.4f} below the floor {g.floor:g} at "
                     f"X{low[k, 0]:.3f} Y{low[k, 1]:.3f}")
    if g.surface is not None:
        probs += _check_surface(low, g)
    return probs


def _air(g: Geometry, z: float) -> Polygon:
    """The air at height ``z`` under the top: outside the block, or in a feature whose
    floor is at or under ``z + tol``."""
    x0, y0, x1, y1 = g.region.bounds
    far = shapely.box(x0 - 1e3, y0 - 1e3, x1 + 1e3, y1 + 1e3)
    cut = [p for f, p in g.levels if f <= z + g.tol]
    solid = g.region.difference(shapely.union_all(cut)) if cut else g.region
    return far.difference(solid)


def _check_air(low: np.ndarray, g: Geometry) -> list[str]:
    floors = sorted({f for f, _ in g.levels if f > -math.inf})
    edges = [-math.inf] + [f - g.tol for f in floors] + [math.inf]
    worst, at = g.tol, None                      # how far into the part
    for lo, hi in zip(edges[:-1], edges[1:]):
        sel = (low[:, 2] >= lo) & (low[:, 2] < hi)
        if not sel.any():
            continue
        pts = low[sel]
        air = _air(g, float(pts[:, 2].min()))
        inside = shapely.contains_xy(air, pts[:, 0], pts[:, 1])
        d = np.where(inside, shapely.distance(air.boundary, shapely.points(pts[:, :2])),
                     -shapely.distance(air, shapely.points(pts[:, :2])))
        k = int(np.argmin(d))
        if g.radius - d[k] > worst:
            worst, at = g.radius - d[k], pts[k]
    if at is None:
        return []
    return [f"tool {worst:.4f} into the part at X{at[0]:.3f} Y{at[1]:.3f} Z{at[2]:.3f} "
            f"(allowed {g.tol:g})"]


def ocl_heights(tri: np.ndarray, g: Geometry, xy: np.ndarray, below: float,
                erode: float = 0.0) -> np.ndarray:
    """OpenCAMLib's drop-cutter: the tip height of ``g``'s cutter, eroded by ``erode``
    (every radius that much smaller), dropped onto the triangles at each point ``xy``
    (``below`` where it touches nothing)."""
    import opencamlib as ocl
    s = ocl.STLSurf()
    for t in tri:
        s.addTriangle(ocl.Triangle(*[ocl.Point(float(p[0]), float(p[1]), float(p[2]))
                                     for p in t]))
    d = 2 * (g.radius - erode)
    rc = g.corner_radius - erode
    kind = "flat" if g.tool_type == "bull" and rc <= 1e-6 else g.tool_type
    cutter = {"ball": lambda: ocl.BallCutter(d, 200.0),
              "flat": lambda: ocl.CylCutter(d, 200.0),
              "bull": lambda: ocl.BullCutter(d, rc, 200.0)}[kind]()
    b = ocl.BatchDropCutter()
    b.setSTL(s)
    b.setCutter(cutter)
    for x, y in xy:
        b.appendPoint(ocl.CLPoint(float(x), float(y), below))
    b.run()
    return np.array([p.z for p in b.getCLPoints()])


def _highest_within(tri: np.ndarray, xy: np.ndarray, radius: float) -> np.ndarray:
    """An upper bound of the height of the triangles ``tri`` within ``radius`` of each
    point ``xy``: the highest vertex of every grid cell, spread over the cells a
    triangle or the radius can reach."""
    from scipy.ndimage import maximum_filter
    v = tri.reshape(-1, 3)
    ext = float(np.max(tri[:, :, :2].max(axis=1) - tri[:, :, :2].min(axis=1)))
    cell = max(radius / 4.0, ext, 1e-3)
    lo = v[:, :2].min(axis=0)
    ij = np.floor((v[:, :2] - lo) / cell).astype(np.int64)
    shape = tuple(ij.max(axis=0) + 1)
    top = np.full(shape, -np.inf)
    np.maximum.at(top, (ij[:, 0], ij[:, 1]), v[:, 2])
    # a triangle reaches the cells next to its vertices' (it is at most a cell wide);
    # the radius reaches ceil(radius / cell) cells further
    k = 1 + int(math.ceil(radius / cell))
    top = maximum_filter(top, size=2 * k + 1, mode="constant", cval=-np.inf)
    q = np.floor((xy - lo) / cell).astype(np.int64)
    out = np.full(len(xy), -np.inf)
    ok = (q >= 0).all(axis=1) & (q[:, 0] < shape[0]) & (q[:, 1] < shape[1])
    out[ok] = top[q[ok, 0], q[ok, 1]]
    # a point off the grid but within reach of it: the highest point of all
    near = ~ok & (q >= -k).all(axis=1) & (q[:, 0] < shape[0] + k) & (q[:, 1] < shape[1] + k)
    out[near] = float(v[:, 2].max())
    return out


def _check_mesh(low: np.ndarray, g: Geometry) -> list[str]:
    """The tool eroded by ``tol`` (radius and corner; its tip ``tol`` higher, so the
    tip comparison below is within ``tol``) must clear the surface + allowance: the
    tool enters it by no more than ``tol`` in any direction, flank contacts included."""
    below = float(g.mesh[:, :, 2].min()) - 100.0
    # only samples the cutter could touch the part from go to OpenCAMLib: a tip at or
    # above the highest point of the mesh within its radius clears it
    near = low[:, 2] < _highest_within(g.mesh, low[:, :2], g.radius) + g.allowance + 1e-9
    low = low[near]
    if not len(low):
        return []
    z = ocl_heights(g.mesh, g, low[:, :2], below, erode=g.tol)
    short = z + g.allowance - low[:, 2]
    k = int(np.argmax(short))
    if short[k] > g.tol:
        return [f"tip {short[k]:.4f} under the surface + allowance {g.allowance:g} "
                f"(OpenCAMLib) at X{low[k, 0]:.3f} Y{low[k, 1]:.3f} Z{low[k, 2]:.3f} "
                f"(allowed {g.tol:g})"]
    return []


def _check_surface(low: np.ndarray, g: Geometry) -> list[str]:
    rings = np.linspace(0, 1, 6) * g.radius
    ang = np.linspace(0, 2 * math.pi, 25)[:-1]
    rr, aa = np.meshgrid(rings, ang)
    ox, oy = (rr * np.cos(aa)).ravel(), (rr * np.sin(aa)).ravel()
    lift = _profile(g, rr.ravel())
    worst, at = 0.0, None
    for a in range(0, len(low), 4000):
        c = low[a:a + 4000]
        qx, qy = c[:, :1] + ox, c[:, 1:2] + oy
        ins = shapely.contains_xy(g.region, qx, qy)
        z = np.full(qx.shape, -np.inf)
        if ins.any():
            z[ins] = g.surface(qx[ins], qy[ins])
        gouge = z - (c[:, 2:3] + lift)
        k = np.unravel_index(int(np.argmax(gouge)), gouge.shape)
        if gouge[k] > worst:
            worst, at = float(gouge[k]), (qx[k], qy[k])
    if worst > g.tol:
        return [f"bottom {worst:.4f} above the tool's underside at X{at[0]:.3f} "
                f"Y{at[1]:.3f} (allowed {g.tol:g})"]
    return []


def check_program(program: Path, tools_tbl: Path, units: str,
                  g: "Geometry | dict[int, Geometry]") -> CheckResult:
    """Interpret ``program`` with rs274 and check its tool tips against ``g`` (or, per
    tool number, against ``g[tool]``: each cutter against its own geometry)."""
    from millpath.simulate.tip import tip_motions
    from support.rs274 import run_rs274
    r = run_rs274(program, tools_tbl, table_units=units)
    if not r.ok:
        return CheckResult(False, [f"rs274: line {r.error_line}: {r.error}"])
    motions = tip_motions(r.motions, units)
    by_tool = g if isinstance(g, dict) else None
    groups: dict[int, list] = {}
    for m in motions:
        groups.setdefault(m.tool if by_tool else 0, []).append(m)
    probs, n = [], 0
    for tool, ms in groups.items():
        geo = by_tool.get(tool) if by_tool else g
        if geo is None:
            if any(m.kind != "traverse" for m in ms):
                probs.append(f"T{tool} moves but the job has no geometry for it")
            continue
        try:
            pts = sample(ms, max(geo.radius / 8.0, 0.02))
        except ValueError as e:
            return CheckResult(True, [f"not checked: {e}"])
        probs += [f"T{tool}: {p}" if by_tool else p for p in check_points(pts, geo)]
        n += len(pts)
    return CheckResult(not probs, probs, n)
