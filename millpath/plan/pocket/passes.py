"""Clearing passes of one level for the offset and zigzag strategies.

A :class:`Cut` is a polyline of tool-centre positions (job units) with the area in
which the tool may link to it by a straight feed at the level (``room``) and, for
closed rings, the polygon it encloses (for a helix entry).

- offset: rings of the free area (the pocket shrunk by ``R + allowance``) at
  ``stepover`` apart, cut from the innermost out: exteriors counter-clockwise, islands
  clockwise (climb with a clockwise spindle), all reversed for conventional milling.
- zigzag: lines at ``angle`` degrees ``stepover`` apart, alternate directions, then
  the free area's boundary rings (climb) to take off the scallops.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import shapely
from shapely import affinity
from shapely.geometry import LineString, Polygon

from millpath.plan.twod.offsets import offset, polygons, rings


@dataclass
class Cut:
    pts: np.ndarray
    closed: bool
    room: Polygon


def offset_cuts(free, stepover: float, climb: bool = True) -> list[Cut]:
    """Offset rings of ``free``, each branch of the offset tree from its innermost ring
    out (depth first), so a branch is entered once and its rings link through the
    space it has cleared."""
    levels: list[list[Polygon]] = []
    k = 0
    while k < 100000:
        comp = polygons(offset(free, -k * stepover)) if k else polygons(free)
        if not comp:
            break
        levels.append(comp)
        k += 1
    children: dict[tuple[int, int], list[tuple[int, int]]] = {}
    for k in range(1, len(levels)):
        for i, p in enumerate(levels[k]):
            pt = p.representative_point()
            for j, q in enumerate(levels[k - 1]):
                if q.covers(pt):
                    children.setdefault((k - 1, j), []).append((k, i))
                    break
    cuts: list[Cut] = []

    def visit(node: tuple[int, int]) -> None:
        stack = [(node, False)]
        while stack:
            nd, done = stack.pop()
            if done:
                poly = levels[nd[0]][nd[1]]
                for r in rings(poly):
                    if len(r) >= 3:
                        cuts.append(Cut(r if climb else r[::-1], True, poly))
                continue
            stack.append((nd, True))
            for ch in reversed(children.get(nd, [])):
                stack.append((ch, False))

    for j in range(len(levels[0]) if levels else 0):
        visit((0, j))
    return cuts


def order_nearest(cuts: list[Cut], start) -> list[Cut]:
    """Cuts of equal rank visited nearest first is left to the caller; this keeps the
    inside-out order and only rotates each ring to start nearest the previous end."""
    from millpath.plan.twod.offsets import start_at
    out = []
    pos = start
    for c in cuts:
        pts = start_at(c.pts, pos) if (c.closed and pos is not None) else c.pts
        out.append(Cut(pts, c.closed, c.room))
        pos = pts[0] if c.closed else pts[-1]
    return out


def zigzag_cuts(free, stepover: float, angle: float = 0.0, climb: bool = True) -> list[Cut]:
    """Raster lines across ``free`` then its boundary rings."""
    cuts: list[Cut] = []
    for poly in polygons(free):
        c = poly.centroid
        rot = affinity.rotate(poly, -angle, origin=c)
        x0, y0, x1, y1 = rot.bounds
        n = max(1, int(math.ceil((y1 - y0) / stepover)))
        ys = y0 + (np.arange(n) + 0.5) * (y1 - y0) / n
        flip = False
        for y in ys:
            line = LineString([(x0 - 1, y), (x1 + 1, y)])
            inter = rot.intersection(line)
            segs = [g for g in getattr(inter, "geoms", [inter])
                    if isinstance(g, LineString) and not g.is_empty and g.length > 1e-9]
            segs.sort(key=lambda g: g.bounds[0], reverse=flip)
            for g in segs:
                g2 = affinity.rotate(g, angle, origin=c)
                pts = np.asarray(g2.coords)[:, :2]
                if flip:
                    pts = pts[::-1]
                cuts.append(Cut(pts, False, poly))
            flip = not flip
        for r in rings(poly):
            cuts.append(Cut(r if climb else r[::-1], True, poly))
    return cuts


def segment_inside(room: Polygon, a, b) -> bool:
    """True if the straight segment a-b lies in ``room`` (covered, boundary included)."""
    if math.dist(a, b) < 1e-9:
        return True
    return bool(shapely.covers(room.buffer(1e-7), LineString([a, b])))
