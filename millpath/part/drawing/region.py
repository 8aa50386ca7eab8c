"""Loops nested into regions: an outer boundary with its islands.

Nesting is by containment: a loop inside an even number of others is an outer
boundary, inside an odd number an island of the smallest loop around it (a boundary
inside an island starts a new region). Loops that cross themselves or each other are
GeometryErrors naming their entities (or keys) and the place.

:func:`shift_region` moves a region's contours sideways by a small distance (mitred
corners): flattened contours within ``s`` of the drawn curves, moved by ``s`` toward one
side, lie wholly on that side of the drawing (see its docstring).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import shapely
from shapely.geometry import LinearRing, Polygon
from shapely.geometry.polygon import orient

from millpath.errors import GeometryError
from millpath.part.drawing.chains import Loop


@dataclass
class Region:
    """A pocket region: ``polygon`` (exterior counter-clockwise, islands clockwise, job
    units), the names of the loops behind it (``name``, ``island_names``)."""

    polygon: Polygon
    name: str = ""
    island_names: list[str] = field(default_factory=list)


def _ring_problem(pts: np.ndarray) -> tuple[float, float] | None:
    """The place where a closed polyline crosses itself, or None."""
    ring = LinearRing(pts)
    if ring.is_simple:
        return None
    # self-intersection points: nodes of the noded ring visited more than once
    noded = shapely.node(shapely.linestrings(np.vstack([pts, pts[:1]])))
    parts = list(getattr(noded, "geoms", [noded]))
    ends = np.array([[g.coords[0], g.coords[-1]] for g in parts]).reshape(-1, 2)
    key = np.round(ends, 6)
    uniq, counts = np.unique(key, axis=0, return_counts=True)
    multi = uniq[counts > 2]
    if len(multi):
        return float(multi[0][0]), float(multi[0][1])
    return float(pts[0][0]), float(pts[0][1])


def check_loop(loop: Loop, file=None) -> Polygon:
    """A valid polygon of ``loop``; GeometryError if it crosses itself or is empty."""
    if len(loop.points) < 3:
        raise GeometryError("a contour needs at least 3 points", file, entity=loop.name)
    at = _ring_problem(loop.points)
    if at is not None:
        raise GeometryError(f"the contour crosses itself at ({at[0]:.4f}, {at[1]:.4f})",
                            file, entity=loop.name)
    poly = Polygon(loop.points)
    if poly.area <= 0:
        raise GeometryError("the contour encloses no area", file, entity=loop.name)
    return orient(poly, 1.0)


def regions_from_loops(loops: list[Loop], file=None) -> list[Region]:
    """Regions (outer boundary with islands) of ``loops``, largest first."""
    polys = [check_loop(lp, file) for lp in loops]
    order = sorted(range(len(polys)), key=lambda i: -polys[i].area)
    for a in range(len(order)):
        for b in range(a + 1, len(order)):
            i, j = order[a], order[b]
            if polys[i].exterior.intersects(polys[j].exterior):
                x = polys[i].exterior.intersection(polys[j].exterior)
                p = x.representative_point() if not x.is_empty else polys[j].centroid
                raise GeometryError(f"contours cross or touch at ({p.x:.4f}, {p.y:.4f}) "
                                    f"({loops[j].name})", file, entity=loops[i].name)
    parent = {}
    depth = {}
    for a, i in enumerate(order):          # larger loops first: parents come before
        par = None
        for i2 in reversed(order[:a]):     # the smallest enclosing one
            if polys[i2].contains(polys[i]):
                par = i2
                break
        parent[i] = par
        depth[i] = 0 if par is None else depth[par] + 1
    out = []
    for i in order:
        if depth[i] % 2:
            continue
        holes = [j for j in order if parent[j] == i]
        poly = orient(Polygon(polys[i].exterior.coords,
                              [polys[j].exterior.coords for j in holes]), 1.0)
        out.append(Region(poly, loops[i].name, [loops[j].name for j in holes]))
    return out


def region_from_polygon(polygon, islands, file=None, key: str = "polygon",
                        islands_key: str = "islands") -> Region:
    """A region from job keys ``polygon = [[x, y], ...]`` and ``islands = [[[x, y],
    ...], ...]``; GeometryError naming the key for a crossing polygon, an island
    outside the polygon or islands crossing each other."""
    outer = check_loop(Loop(np.asarray([p[:2] for p in polygon], float), [key]), file)
    isl = []
    for k, q in enumerate(islands or []):
        name = f"{islands_key}[{k}]"
        pts = np.asarray([p[:2] for p in q], float)
        poly = check_loop(Loop(pts, [name]), file)
        if not outer.contains(poly):
            c = poly.representative_point()
            raise GeometryError(f"{name}: the island at ({c.x:.4f}, {c.y:.4f}) is not inside "
                                f"the pocket {key}", file)
        for m, other in enumerate(isl):
            if poly.intersects(other):
                c = poly.intersection(other).representative_point()
                raise GeometryError(f"{name}: the island meets {islands_key}[{m}] at "
                                    f"({c.x:.4f}, {c.y:.4f})", file)
        isl.append(poly)
    poly = orient(Polygon(outer.exterior.coords, [i.exterior.coords for i in isl]), 1.0)
    return Region(poly, key, [f"{islands_key}[{k}]" for k in range(len(isl))])


def shift_region(region: Region, distance: float) -> Region:
    """``region`` with every contour moved sideways by ``distance`` (job units): positive
    grows the region (outline outward, islands shrink), negative shrinks it; corners
    mitred (a mitred offset contains the round one, so nothing of it comes nearer the
    old contour than ``|distance|``).

    Use: contours whose vertices lie on the drawn curves with chords within ``s`` of
    them (so every point between a chord and its curve is within ``s`` of the chord)
    and moved by ``s`` lie wholly on the side they were moved to: shrunk by ``s`` the
    region is inside the drawn one, grown by ``s`` it contains it; each wall is then
    within ``2 s`` of the drawn one. A move that would split the region or close it up
    (a neck or a gap narrower than ``2 |distance|``) leaves it unchanged."""
    if distance == 0:
        return region
    moved = region.polygon.buffer(distance, join_style="mitre", mitre_limit=5.0)
    if (not isinstance(moved, Polygon) or moved.is_empty or not moved.is_valid
            or len(moved.interiors) != len(region.polygon.interiors)):
        return region
    # the buffer may list the islands in another order: keep each name with its island
    # (growing the region shrinks its islands: the new one lies in the old, and back)
    old = [Polygon(r) for r in region.polygon.interiors]
    order = []
    for ring in moved.interiors:
        n = Polygon(ring)
        k = next((i for i, o in enumerate(old) if i not in order and (
            o.contains(n.representative_point()) if distance > 0
            else n.contains(o.representative_point()))), None)
        if k is None:
            return region
        order.append(k)
    holes = [moved.interiors[j].coords for j in sorted(range(len(order)), key=order.__getitem__)]
    return Region(orient(Polygon(moved.exterior.coords, holes), 1.0), region.name,
                  list(region.island_names))
