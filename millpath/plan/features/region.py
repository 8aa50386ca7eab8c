"""General pockets (floors recognised from a solid): tool choice, tool-centre regions
and clearing (job units).

A general :class:`~millpath.part.step.shapes.PocketShape` carries the floor's plan
region and ``keep``, the part's material above the floor. The tool centre may go where
a disc of the tool's radius stays out of ``keep`` (``keep`` eroded from the plane) and
near the floor (within a radius of the region), so it runs out past open sides and
stops at walls, islands and corners. Clearing: contour-parallel rings of that region
(all boundaries, islands included), innermost first, level by level; a link between
rings is a feed move only when it stays inside the cleared region, otherwise the tool
lifts above the stock, comes down at feed to the level already cleared and enters the
new level by a ramp along the ring (or a helix or zigzag ramp where the ring is too
short, :mod:`millpath.plan.entry`): an end mill never goes straight down into material. A finishing pass traces the region's boundary at every level, bottom up.
"""

from __future__ import annotations

import numpy as np
import shapely
from shapely.geometry import LineString, box
from shapely.geometry.polygon import orient

from millpath.model import Stock, Tool, Toolpath
from millpath.part.step.shapes import PocketShape
from millpath.plan.entry import helix_entry, ramp_entry
from millpath.plan.features.paths import RAMP_ANGLE, RAMP_LAPS, Heights, ramp_ring
from millpath.plan.levels import levels

#: distance a tool as wide as a passage is moved off its exact centre line (mm / inch
#: jobs scale it): the tool then cuts at most this much into the walls
SQUEEZE = {"mm": 1e-4, "inch": 4e-6}


def centre_region(p: PocketShape, r: float, stock: Stock, squeeze: float = 0.0):
    """Where the centre of a tool of radius ``r`` may go to cut the floor of ``p``."""
    x0, y0, x1, y1 = p.region.bounds
    m = 4 * r + 10.0 * max(1.0, r)
    big = box(min(x0, stock.xmin) - m, min(y0, stock.ymin) - m,
              max(x1, stock.xmax) + m, max(y1, stock.ymax) + m)
    free = big.difference(p.keep) if p.keep is not None and not p.keep.is_empty else big
    c = free.buffer(-(r - squeeze), join_style="mitre").intersection(
        p.region.buffer(r, quad_segs=16))
    polys = [g for g in getattr(c, "geoms", [c]) if g.geom_type == "Polygon" and g.area > 1e-12]
    return shapely.MultiPolygon(polys) if len(polys) != 1 else polys[0]


def _uncut(p: PocketShape, c, r: float, slack: float = 0.005) -> float:
    """Floor area the tool cannot reach (``slack``: the walls' chord margin, which the
    region of the floor overlaps)."""
    if c.is_empty:
        return p.region.area
    return p.region.difference(c.buffer(r + slack, quad_segs=16)).area


def region_tool(p: PocketShape, tools: list[Tool], tol: float, stock: Stock,
                units: str = "mm") -> tuple[str, Tool | None, str]:
    """(strategy 'region', tool, note): the largest end mill whose radius is within the
    corner radius and that reaches the whole floor; else the one leaving least floor."""
    if p.floor_radius > 0:
        cands = [t for t in tools if t.type == "bull"
                 and abs(t.corner_radius - p.floor_radius) <= tol]
        kind = f"bull nose end mill with corner radius {p.floor_radius:g}"
    else:
        cands = [t for t in tools if t.type == "flat"]
        kind = "flat end mill"
    if not cands:
        return "", None, f"no {kind} (floor fillet)" if p.floor_radius > 0 else f"no {kind}"
    sq = SQUEEZE.get(units, 1e-4)
    small = 1e-4 * p.region.area + 100 * tol * tol
    fits = []
    for t in sorted(cands, key=lambda t: (-t.diameter, t.number)):
        c = centre_region(p, t.radius, stock)
        if c.is_empty:
            c = centre_region(p, t.radius, stock, sq)
        if not c.is_empty:
            fits.append((t, _uncut(p, c, t.radius, 0.5 * tol)))
    if not fits:
        smallest = min(cands, key=lambda t: t.diameter)
        return "", None, (f"narrower than the smallest {kind} (T{smallest.number}, "
                          f"diameter {smallest.diameter:g})")
    depth_ok = [f for f in fits if f[0].flute_length >= p.depth - 1e-9] or fits
    good = [f for f in depth_ok if f[0].radius <= p.corner_radius + tol and f[1] <= small]
    if good:
        return "region", good[0][0], ""
    t, left = min(depth_ok, key=lambda f: (round(f[1], 6), f[0].diameter))
    if p.corner_radius < t.radius - tol:
        note = (f"corner radius {p.corner_radius:g} is below the tool radius {t.radius:g}: "
                "corners are left at the tool radius")
    else:
        note = ""
    if left > small and p.corner_radius >= t.radius - tol:
        note = f"{left:.3g} of the floor is narrower than T{t.number} and is left"
    return "region", t, note


def _parts(g) -> list:
    return [x for x in getattr(g, "geoms", [g]) if x.geom_type == "Polygon" and not x.is_empty]


def inner_points(region) -> np.ndarray:
    """Points (n, 2) just inside ``region``: its outlines pulled in by a thousandth of
    their size, and a point inside each part."""
    parts = _parts(region)
    inner = [q for p in parts for q in _parts(p.buffer(-1e-3 * max(1.0, p.length ** 0.5)))]
    pts = [np.asarray(q.exterior.coords)[:, :2] for q in (inner or parts)]
    pts += [np.asarray(p.representative_point().coords)[:, :2] for p in parts]
    return np.vstack(pts)


def _rings(comp, stepover: float) -> list[np.ndarray]:
    """Boundaries of the inward offsets of ``comp``, innermost first, each (n, 2)."""
    out = []
    k = 0
    while True:
        g = comp if k == 0 else comp.buffer(-k * stepover, join_style="mitre")
        parts = [q for q in _parts(g) if q.area > 1e-12]
        if not parts:
            break
        for q in parts:
            q = orient(q, 1.0)
            for ring in [q.exterior, *q.interiors]:
                out.append(np.asarray(ring.coords)[:-1])
        k += 1
    return out[::-1]


def _start_at(ring: np.ndarray, p) -> np.ndarray:
    i = int(np.argmin(((ring - np.asarray(p)) ** 2).sum(axis=1)))
    return np.roll(ring, -i, axis=0)


def _trace(tp: Toolpath, ring: np.ndarray, z: float, feed: float) -> None:
    for q in ring[1:]:
        tp.line(q[0], q[1], z, feed)
    tp.line(ring[0][0], ring[0][1], z, feed)


def enter(tp: Toolpath, ring: np.ndarray, z_from: float, z_to: float, inside,
          tool_radius: float, feed: float) -> None:
    """From straight above ``ring[0]`` at ``z_from`` (material-free) down to ``z_to``
    into material: a ramp along the closed ring when it is long enough (it returns to
    ``ring[0]``), else a helix, else a zigzag ramp, with the tool centre in ``inside``
    (prepared shapely area) and never below ``z_to``; a straight plunge only when none
    fits."""
    p = ring[0]
    closed = np.vstack([ring, ring[:1]])
    perim = float(np.hypot(*np.diff(closed, axis=0).T).sum())
    if perim * np.tan(np.radians(RAMP_ANGLE)) * RAMP_LAPS >= z_from - z_to:
        ramp_ring(tp, ring, z_from, z_to, feed)
        return

    def centre_ok(xs, ys):
        return bool(np.all(shapely.covers(inside, shapely.points(xs, ys))))

    def floor(xs, ys):
        return np.full(np.shape(xs), z_to)
    target = (float(p[0]), float(p[1]), z_to)
    hx = helix_entry(target, z_from, tool_radius, centre_ok=centre_ok, floor=floor)
    if hx is not None:
        tp.arc(target, (hx.center[0], hx.center[1], z_to), False, feed, turns=hx.turns)
        return
    rp = ramp_entry(target, z_from, tool_radius, centre_ok=centre_ok, floor=floor)
    if rp is not None:
        for q in rp.points(z_from):
            tp.line(*q, feed)
        return
    tp.line(p[0], p[1], z_to, feed)


def clear_general(tp: Toolpath, rough, finish, z_top: float, z_floor: float, h: Heights, *,
                  step_down: float, stepover: float, feed: float, plunge_feed: float,
                  tool_radius: float) -> None:
    """Clear the tool-centre region ``rough`` level by level from ``z_top`` to
    ``z_floor``, then trace ``finish``'s boundaries (see the module docstring)."""
    zs = levels(z_top, z_floor, step_down)
    comps = _parts(rough)
    if not comps:
        raise ValueError("the tool does not fit in the region")
    inside = rough.buffer(1e-6)
    shapely.prepare(inside)
    plans = [_rings(c, stepover) for c in comps]
    at_safe = True
    cur = None
    for z_prev, z in zip([z_top] + zs[:-1], zs):
        for rings in plans:
            for i, ring in enumerate(rings):
                ring = _start_at(ring, cur if cur is not None else ring[0])
                p = ring[0]
                link_ok = (not at_safe and cur is not None and inside.covers(
                    LineString([cur, p])))
                if link_ok:               # inside the cleared region (down a level: slower)
                    tp.line(p[0], p[1], z, feed if i else plunge_feed)
                else:
                    if not at_safe:
                        e = tp.moves[-1].end
                        tp.rapid(e[0], e[1], h.z_safe)
                    tp.rapid(p[0], p[1], h.z_safe)
                    tp.rapid(p[0], p[1], h.r_plane)
                    tp.line(p[0], p[1], z_prev, plunge_feed)
                    enter(tp, ring, z_prev, z, inside, tool_radius, plunge_feed)
                    at_safe = False
                _trace(tp, ring, z, feed)
                cur = ring[0]
    if finish is not None and not finish.equals(rough):
        for comp in _parts(finish):
            comp = orient(comp, 1.0)
            for ring in [comp.exterior, *comp.interiors]:
                r = _start_at(np.asarray(ring.coords)[:-1], cur)
                if not at_safe:
                    e = tp.moves[-1].end
                    tp.rapid(e[0], e[1], h.z_safe)
                tp.rapid(r[0][0], r[0][1], h.z_safe)
                tp.rapid(r[0][0], r[0][1], h.r_plane)
                tp.line(r[0][0], r[0][1], zs[-1], plunge_feed)
                at_safe = False
                for z in reversed(zs):
                    tp.line(r[0][0], r[0][1], z, feed)
                    _trace(tp, r, z, feed)
                cur = r[0]
    e = tp.moves[-1].end
    tp.rapid(e[0], e[1], h.z_safe)


def general_regions(p: PocketShape, tool: Tool, allowance: float, stock: Stock,
                    units: str = "mm"):
    """(roughing, finishing) tool-centre regions of ``tool`` in ``p``."""
    sq = SQUEEZE.get(units, 1e-4)
    fin = centre_region(p, tool.radius, stock)
    if fin.is_empty:
        fin = centre_region(p, tool.radius, stock, sq)
    rough = centre_region(p, tool.radius + allowance, stock)
    if rough.is_empty or _uncut(p, rough, tool.radius + allowance) > \
            _uncut(p, fin, tool.radius) + 1e-6:
        rough = fin
    return rough, fin
