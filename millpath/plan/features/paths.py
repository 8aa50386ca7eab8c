"""Toolpath generators for features: drilling cycles, helical boring and clearing of
convex regions by contour-parallel rings.

All functions append moves to a :class:`~millpath.model.Toolpath` whose operation is
already begun, in job units, tool tip coordinates. They start and end at ``z_safe``.
Circular moves are counter-clockwise seen from +Z: climb milling inside a hole or pocket
with a clockwise (M3) spindle. End mills are assumed centre-cutting (plunges at the
plunge feed).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from millpath.model import Toolpath
from millpath.plan.entry import ramp_laps, ring_segments
from millpath.plan.levels import levels


@dataclass(frozen=True)
class Heights:
    """``z_safe``: rapid plane between features; ``r_plane``: feed starts here (above the
    stock top); both in job units."""

    z_safe: float
    r_plane: float


def drill(tp: Toolpath, x: float, y: float, z_tip: float, h: Heights, feed: float,
          cycle: str, peck: float = 0.0) -> None:
    """One canned cycle at (x, y) to the tip depth ``z_tip``, returning to ``z_safe``."""
    tp.rapid(x, y, h.z_safe)
    tp.drill(x, y, z_tip, h.r_plane, feed, cycle=cycle, peck=peck if cycle != "G81" else 0.0,
             retract_initial=True)


def plunge(tp: Toolpath, x: float, y: float, z_floor: float, h: Heights, plunge_feed: float) -> None:
    """Straight plunge (a ball end mill into a spherical bottom) and retract."""
    tp.rapid(x, y, h.z_safe)
    tp.rapid(x, y, h.r_plane)
    tp.line(x, y, z_floor, plunge_feed)
    tp.rapid(x, y, h.z_safe)


def ring_radii(inner: float, outer: float, stepover: float) -> list[float]:
    """Radii of the tool centre from ``inner`` to ``outer`` at most ``stepover`` apart."""
    if outer <= inner + 1e-12:
        return [outer]
    n = int(math.ceil((outer - inner) / stepover - 1e-9))
    return [inner + (outer - inner) * k / n for k in range(n + 1)]


def bore(tp: Toolpath, cx: float, cy: float, radius: float, tool_radius: float,
         z_top: float, z_floor: float, h: Heights, *, step_down: float, stepover: float,
         allowance: float, feed: float, plunge_feed: float) -> None:
    """Helical interpolation of a round hole or circular pocket of ``radius``.

    Per level: one helix turn at the innermost ring (radius <= tool radius / 2, so no
    core is left) down to the level and a flat circle there, then full circles outward
    to ``radius - tool_radius - allowance``. With an allowance, a finishing wall pass
    follows: a helix at ``radius - tool_radius``, one turn per level from the top, and a
    flat circle at the floor.
    """
    final = radius - tool_radius
    if final <= 0:
        raise ValueError("the tool is not smaller than the hole")
    rough = max(final - allowance, 0.0)
    inner = min(0.5 * tool_radius, rough)
    radii = ring_radii(inner, rough, stepover)
    zs = levels(z_top, z_floor, step_down)
    r0 = radii[0]
    tp.rapid(cx + r0, cy, h.z_safe)
    tp.rapid(cx + r0, cy, h.r_plane)
    tp.line(cx + r0, cy, z_top, plunge_feed)
    for z in zs:
        if r0 > 1e-6:
            tp.arc((cx + r0, cy, z), (cx, cy, z), False, plunge_feed)   # helix, one turn
            tp.arc((cx + r0, cy, z), (cx, cy, z), False, feed)          # flat circle
        else:
            tp.line(cx, cy, z, plunge_feed)
        for r in radii[1:]:
            tp.line(cx + r, cy, z, feed)
            tp.arc((cx + r, cy, z), (cx, cy, z), False, feed)
        if len(radii) > 1:
            tp.line(cx + r0, cy, z, feed)
    if rough < final - 1e-9:
        tp.line(cx, cy, zs[-1], feed)
        tp.rapid(cx, cy, h.r_plane)
        tp.line(cx, cy, z_top, plunge_feed)
        tp.line(cx + final, cy, z_top, feed)
        for z in zs:
            tp.arc((cx + final, cy, z), (cx, cy, z), False, feed)
        tp.arc((cx + final, cy, zs[-1]), (cx, cy, zs[-1]), False, feed)
    end = tp.moves[-1].end
    tp.line(cx, cy, end[2], feed)
    tp.rapid(cx, cy, h.z_safe)


def taper_bore(tp: Toolpath, cx: float, cy: float, radius: float, final_radius: float,
               half_angle_deg: float, tool_radius: float, z_top: float, z_floor: float,
               h: Heights, *, step_down: float, stepover: float, allowance: float,
               cusp: float, feed: float, plunge_feed: float) -> int:
    """A round hole with a 'flat with taper' bottom: a flat of ``final_radius`` at
    ``z_floor`` and a cone (half angle ``half_angle_deg`` from the axis) up to the
    wall of ``radius``; returns the number of cone levels.

    The cylinder above the cone is bored as :func:`bore`; the cone is milled in levels
    ``dz = cusp / sin(half angle)`` apart (at most ``step_down``), each level bored out
    to the cone's radius at that level, so the stairs leave at most ``cusp`` normal to
    the cone and never cut into it (the cone widens upward)."""
    half = math.radians(half_angle_deg)
    z_cone = z_floor + (radius - final_radius) / math.tan(half)    # where the cone meets the wall
    if z_cone < z_top - 1e-9:
        bore(tp, cx, cy, radius, tool_radius, z_top, z_cone, h, step_down=step_down,
             stepover=stepover, allowance=allowance, feed=feed, plunge_feed=plunge_feed)
    z_prev = min(z_top, z_cone)
    zs = levels(z_prev, z_floor, min(step_down, cusp / math.sin(half)))
    for z in zs:
        rc = final_radius + (z - z_floor) * math.tan(half)
        bore(tp, cx, cy, rc, tool_radius, z_prev, z, h, step_down=z_prev - z + 1.0,
             stepover=stepover, allowance=0.0, feed=feed, plunge_feed=plunge_feed)
        z_prev = z
    return len(zs)


def _rings(region, stepover: float) -> list[np.ndarray]:
    """Contour-parallel rings of a convex region, innermost first, each (n, 2) CCW."""
    from shapely.geometry.polygon import orient

    rings = []
    k = 0
    while True:
        g = region if k == 0 else region.buffer(-k * stepover, join_style="mitre")
        if g.is_empty or g.area <= 1e-12:
            break
        if g.geom_type != "Polygon":
            g = max(g.geoms, key=lambda p: p.area)
        rings.append(np.asarray(orient(g, 1.0).exterior.coords)[:-1])
        k += 1
    return rings[::-1]


#: steepest ramp into material along a ring or a slot centreline (degrees)
RAMP_ANGLE = 5.0
#: most laps of a ring a ramp may take before a straight plunge is used instead
RAMP_LAPS = 10


def ramp_ring(tp: Toolpath, ring: np.ndarray, z0: float, z1: float, feed: float) -> bool:
    """Descend from ``z0`` to ``z1`` following the closed ``ring`` (starting and ending at
    its first point), no steeper than :data:`RAMP_ANGLE`; a straight plunge when that
    would take more than :data:`RAMP_LAPS` laps. True when it ramped (or had nothing to
    descend), False after a straight plunge."""
    closed, seg, perim = ring_segments(ring)
    dz = z0 - z1
    if dz <= 1e-12:
        return True
    per_lap = perim * math.tan(math.radians(RAMP_ANGLE))
    if per_lap <= 0 or dz / per_lap > RAMP_LAPS:
        tp.line(ring[0][0], ring[0][1], z1, feed)
        return False
    laps = max(1, int(math.ceil(dz / per_lap - 1e-9)))
    ramp_laps(tp, closed, seg, laps, z0, z1, feed)
    return True


def _start_at(ring: np.ndarray, p: np.ndarray) -> np.ndarray:
    i = int(np.argmin(((ring - p) ** 2).sum(axis=1)))
    return np.roll(ring, -i, axis=0)


def clear_region(tp: Toolpath, centre_region, finish_region, z_top: float, z_floor: float,
                 h: Heights, *, step_down: float, stepover: float, feed: float,
                 plunge_feed: float) -> None:
    """Clear a convex region level by level.

    ``centre_region``: where the tool centre may go while roughing (the outline offset
    inward by tool radius + allowance), a shapely Polygon or, for a tool as wide as a
    slot, a LineString (the centreline). ``finish_region``: the outline offset by the
    tool radius (Polygon or LineString), traced once per level after roughing when it
    differs from the roughing boundary. Entries ramp along the innermost ring (or the
    centreline) no steeper than :data:`RAMP_ANGLE`.
    """
    zs = levels(z_top, z_floor, step_down)
    if centre_region.geom_type == "LineString":
        pts = np.asarray(centre_region.coords)[:, :2]
        tp.rapid(pts[0][0], pts[0][1], h.z_safe)
        tp.rapid(pts[0][0], pts[0][1], h.r_plane)
        length = float(np.hypot(*np.diff(pts, axis=0).T).sum())
        tan = math.tan(math.radians(RAMP_ANGLE))
        tp.line(pts[0][0], pts[0][1], z_top, plunge_feed)
        z_prev, seq = z_top, pts            # the tool is at seq[0]
        for z in zs:
            # ramp in passes along the centreline, then cut the whole level at z
            dz = z_prev - z
            passes = int(math.ceil(dz / (length * tan) - 1e-9)) if length > 1e-9 else 0
            if 0 < passes <= 2 * RAMP_LAPS:
                for k in range(passes):
                    za, zb = z_prev - dz * k / passes, z_prev - dz * (k + 1) / passes
                    run = np.concatenate([[0.0], np.cumsum(np.hypot(*np.diff(seq, axis=0).T))])
                    for p, d in zip(seq[1:], run[1:]):
                        tp.line(p[0], p[1], za + (zb - za) * d / length, plunge_feed)
                    seq = seq[::-1]
            else:
                tp.line(seq[0][0], seq[0][1], z, plunge_feed)
            for p in seq[1:]:
                tp.line(p[0], p[1], z, feed)
            seq = seq[::-1]
            z_prev = z
        end = tp.moves[-1].end
        tp.rapid(end[0], end[1], h.z_safe)
        return
    rings = _rings(centre_region, stepover)
    if not rings:
        raise ValueError("the tool does not fit in the region")
    start = rings[0][0]
    tp.rapid(start[0], start[1], h.z_safe)
    tp.rapid(start[0], start[1], h.r_plane)
    tp.line(start[0], start[1], z_top, plunge_feed)
    z_prev = z_top
    for z in zs:
        ramp_ring(tp, rings[0], z_prev, z, plunge_feed)
        z_prev = z
        cur = start
        for ring in rings:
            ring = _start_at(ring, cur)
            tp.line(ring[0][0], ring[0][1], z, feed)
            for p in ring[1:]:
                tp.line(p[0], p[1], z, feed)
            tp.line(ring[0][0], ring[0][1], z, feed)
            cur = ring[0]
        if z != zs[-1]:
            tp.line(start[0], start[1], z, feed)
    if finish_region is not None and not finish_region.equals(centre_region):
        from shapely.geometry.polygon import orient
        fin = np.asarray(orient(finish_region, 1.0).exterior.coords)[:-1]
        fin = _start_at(fin, np.asarray(tp.moves[-1].end[:2]))
        tp.line(fin[0][0], fin[0][1], zs[-1], feed)
        for k, z in enumerate(reversed(zs)):      # bottom up: each level's wall
            if k:
                tp.line(fin[0][0], fin[0][1], z, feed)
            for p in fin[1:]:
                tp.line(p[0], p[1], z, feed)
            tp.line(fin[0][0], fin[0][1], z, feed)
    end = tp.moves[-1].end
    tp.rapid(end[0], end[1], h.z_safe)
