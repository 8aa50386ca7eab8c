"""Clearing passes of one level for the offset and zigzag strategies.

A :class:`Cut` is a polyline of tool-centre positions (job units) with the area in
which the tool may link to it by a straight feed at the level (``room``) and, for
closed rings, the polygon it encloses (for a helix entry), and how far inside the
free area's boundary it runs (``inset``: the offset of its ring; 0 for lines).

- offset: rings of the free area (the pocket shrunk by ``R + allowance``) at
  ``stepover`` apart, cut from the innermost out: exteriors counter-clockwise, islands
  clockwise (climb with a clockwise spindle), all reversed for conventional milling.
  Inside the innermost rings of a branch, more rings at ``0.95 reach`` apart where
  the stepover is wider (``reach``: how far from a pass the tool cuts the level), and
  out-and-back spurs into the lunes wide rings leave at corners: no core is left
  standing.
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
    inset: float = 0.0


def offset_cuts(free, stepover: float, climb: bool = True,
                reach: float | None = None) -> list[Cut]:
    """Offset rings of ``free``, each branch of the offset tree from its innermost ring
    out (depth first), so a branch is entered once and its rings link through the
    space it has cleared; inside a branch's innermost ring, rings ``0.95 reach`` apart
    while that is closer than ``stepover`` (see the module doc)."""
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
    inner = 0.95 * reach if reach is not None else stepover
    if inner < stepover:
        # the cores: rings inside each innermost ring, until none fits
        nodes: dict[tuple[int, int], Polygon] = {(k, i): p for k, ps in enumerate(levels)
                                                 for i, p in enumerate(ps)}
        insets = {nd: nd[0] * stepover for nd in nodes}
        todo = [nd for nd in nodes if nd not in children]
        extra = 0
        while todo and extra < 10000:
            nd = todo.pop()
            for p in polygons(offset(nodes[nd], -inner)):
                extra += 1
                ch = (-extra, 0)
                nodes[ch] = p
                insets[ch] = insets[nd] + inner
                children.setdefault(nd, []).append(ch)
                todo.append(ch)
        at = nodes.__getitem__
        inset = insets.__getitem__
    else:
        def at(nd):
            return levels[nd[0]][nd[1]]

        def inset(nd):
            return nd[0] * stepover
    cuts: list[Cut] = []

    def visit(node: tuple[int, int]) -> None:
        stack = [(node, False)]
        while stack:
            nd, done = stack.pop()
            if done:
                poly = at(nd)
                for r in rings(poly):
                    if len(r) >= 3:
                        cuts.append(Cut(r if climb else r[::-1], True, poly, inset(nd)))
                continue
            stack.append((nd, True))
            for ch in reversed(children.get(nd, [])):
                stack.append((ch, False))

    for j in range(len(levels[0]) if levels else 0):
        visit((0, j))
    if reach is not None and stepover > reach and cuts:
        cuts += spurs(free, cuts, reach)
    return cuts


def spurs(free, cuts: list[Cut], reach: float, rounds: int = 30) -> list[Cut]:
    """Short out-and-back cuts into what ``cuts`` leave of ``free`` when each sweeps
    ``reach`` around it: rings wider apart than ``reach`` leave lunes at the convex
    corners of the inner ones. Each goes from the nearest point of a cut to the lune's
    point farthest from the cuts, and back; a few rounds, until nothing is left wider
    than a hundredth of ``reach``."""
    from shapely.ops import nearest_points
    out: list[Cut] = []
    paths = [LineString(np.vstack([c.pts, c.pts[:1]]) if c.closed else c.pts)
             for c in cuts]
    rooms = polygons(free)
    for _ in range(rounds):
        swept = shapely.union_all([p.buffer(reach, quad_segs=8) for p in paths])
        left = [g for g in polygons(free.difference(swept))
                if g.buffer(-0.01 * reach).area > 0.0]
        if not left:
            break
        every = shapely.MultiLineString([list(p.coords) for p in paths])
        for g in left:
            pts = np.asarray(g.exterior.coords)
            far = pts[int(np.argmax(shapely.distance(shapely.points(pts), every)))]
            base = np.asarray(nearest_points(every, shapely.Point(far))[0].coords)[0, :2]
            room = next((q for q in rooms if q.buffer(1e-7).covers(shapely.Point(far))),
                        rooms[0])
            line = np.array([base, far[:2], base])
            out.append(Cut(line, False, room))
            paths.append(LineString(line[:2]))
            every = shapely.MultiLineString([list(p.coords) for p in paths])
    return out


def order_nearest(cuts: list[Cut], start) -> list[Cut]:
    """Cuts of equal rank visited nearest first is left to the caller; this keeps the
    inside-out order and only rotates each ring to start nearest the previous end."""
    from millpath.plan.twod.offsets import start_at
    out = []
    pos = start
    for c in cuts:
        pts = start_at(c.pts, pos) if (c.closed and pos is not None) else c.pts
        out.append(Cut(pts, c.closed, c.room, c.inset))
        pos = pts[0] if c.closed else pts[-1]
    return out


def cusp(stepover: float, tool) -> float:
    """Height of the ridge a bull-nose or ball ``tool`` leaves on the floor between
    passes ``stepover`` apart (0 where the flat bottoms overlap)."""
    rc = tool.corner_radius
    gap = stepover - 2.0 * (tool.radius - rc)
    if gap <= 0.0 or rc <= 0.0:
        return 0.0
    return rc - math.sqrt(max(rc * rc - 0.25 * gap * gap, 0.0))


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
