"""The contours a profile cuts, each on its side, and the part they bound.

A drawing's regions (:func:`millpath.plan.twod.geometry.load_regions`: an outline with
the holes inside it) are the part's material for ``side = "outside"``: every outline is
cut with the tool outside it, every hole, slot or bore with the tool inside it. For
``side = "inside"`` the regions are openings in the material: outlines are cut from
inside, the islands in them from outside. Either way the tool is on the air side of
every contour.

A pocket clears inside the chosen contours (:func:`pocket_regions`); by default every
region of the drawing, an outline less its islands.

Contours are chosen by role (``contours``: the outlines or the holes/islands), by kind
(``kinds``: circle, slot, other; recognised within the operation's tolerance), by
width (``min_size``, ``max_size``: a circle's diameter, a slot's width, else twice
the radius of the largest circle inside the contour) and by DXF layer
(``contour_layer``). Job units.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import shapely
from shapely.geometry import LineString, Polygon, box as shp_box
from shapely.geometry.polygon import orient
from shapely.ops import unary_union

from millpath.errors import JobError
from millpath.io.schema import Param

KINDS = ("circle", "slot", "other")


def _kinds(v) -> str | None:
    if not v or not all(isinstance(k, str) and k in KINDS for k in v):
        return f"expected a list of {', '.join(KINDS)}, got {v!r}"
    return None


SELECT_PARAMS = {
    "contours": Param("str", "all", choices=("all", "outer", "inner"),
          doc="which contours: all, the outer ones (outlines) or the inner ones (holes, "
              "slots, bores; islands of an opening)"),
    "kinds": Param("list", None, check=_kinds,
          doc="only contours of these kinds: circle, slot (two lines and two half "
              "circles), other (default: all)"),
    "min_size": Param("float", None, positive=True, unit="length",
          doc="only contours at least this wide (a circle's diameter, a slot's width, "
              "else twice the radius of the largest circle inside)"),
    "max_size": Param("float", None, positive=True, unit="length",
          doc="only contours at most this wide (measured as min_size)"),
    "contour_layer": Param("str", None,
          doc="only the contours drawn on this DXF layer (the part, and so each "
              "contour's side, is every contour read from `layer`)"),
}


@dataclass
class Contour:
    """One closed contour: ``polygon`` its inside (counter-clockwise, no holes),
    ``outer`` a region's outline (else a hole or island), ``tool_outside`` the side
    the tool cuts it from, ``kind``, ``width`` and ``centre`` (see the module
    docstring)."""

    polygon: Polygon
    outer: bool
    tool_outside: bool
    name: str
    kind: str
    width: float
    centre: tuple[float, float]

    def describe(self, tol: float) -> str:
        """"entity 3A (a circle 6.6 wide round (10.000, 10.000))": the width to the
        tolerance's decimals."""
        return (f"{self.name} (a {self.kind} {_about(self.width, tol):g} wide round "
                f"({self.centre[0]:.3f}, {self.centre[1]:.3f}))")

    def to_json(self, tol: float) -> dict:
        return {"name": self.name, "kind": self.kind, "width": _about(self.width, tol),
                "centre": [round(self.centre[0], 6), round(self.centre[1], 6)],
                "role": "outer" if self.outer else "inner",
                "side": "outside" if self.tool_outside else "inside"}


def _about(v: float, tol: float) -> float:
    """``v`` rounded to the decimals of ``tol`` (0.01: 2)."""
    return round(v, max(0, -math.floor(math.log10(tol))))


def _boundary_points(poly: Polygon) -> np.ndarray:
    """Vertices and edge midpoints of the exterior (n, 2)."""
    c = np.asarray(poly.exterior.coords)[:, :2]
    return np.vstack([c[:-1], (c[:-1] + c[1:]) / 2])


def classify(poly: Polygon, tol: float) -> tuple[str, float, tuple[float, float]]:
    """(kind, width, centre) of a contour: a circle if every vertex and edge midpoint
    is within ``tol`` of one circle round the centroid; a slot if they are all within
    ``tol`` of half the width from the long axis of the smallest rectangle round it;
    else other, its width twice the radius of the largest circle inside."""
    p = _boundary_points(poly)
    c = poly.centroid
    rho = np.hypot(p[:, 0] - c.x, p[:, 1] - c.y)
    r = 0.5 * (rho.max() + rho.min())
    if rho.max() - rho.min() <= 2 * tol:
        return "circle", 2 * r, (c.x, c.y)
    rect = np.asarray(poly.minimum_rotated_rectangle.exterior.coords)[:4]
    e1, e2 = rect[1] - rect[0], rect[2] - rect[1]
    if np.hypot(*e1) < np.hypot(*e2):
        e1, e2 = e2, e1
        rect = np.roll(rect, -1, axis=0)
    w, L = float(np.hypot(*e2)), float(np.hypot(*e1))
    mid = rect.mean(axis=0)
    u = e1 / L
    half = 0.5 * (L - w)
    if half > tol:
        axis = LineString([mid - half * u, mid + half * u])
        d = shapely.distance(shapely.points(p), axis)
        if np.all(np.abs(d - w / 2) <= tol):
            return "slot", w, (float(mid[0]), float(mid[1]))
    mic = shapely.maximum_inscribed_circle(poly, max(tol, 1e-6))
    (x, y), _ = mic.coords
    return "other", 2 * mic.length, (x, y)


def _rings(reg):
    """(ring, outer, name) of a region: its outline, then its islands."""
    p = orient(reg.polygon, 1.0)
    names = list(reg.island_names) + [f"{reg.name} island {k}"
                                     for k in range(len(reg.island_names), len(p.interiors))]
    return [(p.exterior, True, reg.name)] + [(r, False, n) for r, n in zip(p.interiors, names)]


def _contour(ring, outer: bool, tool_outside: bool, name: str, tol: float) -> Contour:
    poly = orient(Polygon(ring.coords), 1.0)
    kind, width, centre = classify(poly, tol)
    return Contour(poly, outer, tool_outside, name, kind, width, centre)


def profile_contours(regions, side_outside: bool, tol: float) -> list["Contour"]:
    """Every contour of ``regions``: outlines first, each with its holes after it."""
    return [_contour(ring, outer, outer == side_outside, name, tol)
            for reg in regions for ring, outer, name in _rings(reg)]


def pocket_regions(regions, grown, params: dict, tol: float, layer_loops, file=None):
    """The areas a pocket clears inside the chosen contours, as regions: inside an
    outline its region (the outline less its islands, ``regions``: loaded with the air
    inside the outlines); inside a hole, slot or bore the hole less the regions drawn in
    it (``grown``: loaded with the air inside the holes, so each wall stays on its air
    side)."""
    from millpath.part.drawing import Region
    cands: list[tuple[Contour, object, list[str]]] = []
    for reg in regions:
        ring, _, name = _rings(reg)[0]
        cands.append((_contour(ring, True, False, name, tol), reg.polygon,
                      list(reg.island_names)))
    for reg in grown:
        for ring, outer, name in _rings(reg)[1:]:
            c = _contour(ring, False, False, name, tol)
            inside = [r for r in grown if r is not reg
                      and c.polygon.contains(r.polygon.representative_point())]
            area = c.polygon.difference(unary_union([Polygon(r.polygon.exterior)
                                                     for r in inside]))
            cands.append((c, area, [r.name for r in inside]))
    chosen = {id(c) for c in select([c for c, _, _ in cands], params, layer_loops, file)}
    out = []
    for c, area, islands in cands:
        if id(c) not in chosen:
            continue
        for k, poly in enumerate(getattr(area, "geoms", [area])):
            if isinstance(poly, Polygon) and not poly.is_empty:
                out.append(Region(orient(poly, 1.0), c.name if k == 0 else f"{c.name} ({k})",
                                  islands))
    return out


def select(contours: list[Contour], params: dict, layer_loops, file=None) -> list[Contour]:
    """The contours the keys of :data:`SELECT_PARAMS` choose; ``layer_loops``: the
    polygons drawn on ``contour_layer`` (None when not given), matched to the part's
    contours within ``tolerance``. JobError naming the keys when none is left."""
    tol = params["tolerance"]
    out = list(contours)
    if params["contours"] != "all":
        out = [c for c in out if c.outer == (params["contours"] == "outer")]
    if params["kinds"]:
        out = [c for c in out if c.kind in params["kinds"]]
    if params["min_size"] is not None:
        out = [c for c in out if c.width >= params["min_size"] - tol]
    if params["max_size"] is not None:
        out = [c for c in out if c.width <= params["max_size"] + tol]
    if layer_loops is not None:
        out = [c for c in out if any(_same(c.polygon, q, tol) for q in layer_loops)]
    if not out:
        seen = "; ".join(f"{'outer' if c.outer else 'inner'} {c.describe(tol)}"
                         for c in contours[:8])
        more = f" and {len(contours) - 8} more" if len(contours) > 8 else ""
        raise JobError("contours, kinds, min_size, max_size, contour_layer: no contour of "
                       f"the drawing is chosen (it has {len(contours)}: {seen}{more})", file)
    return out


def layer_polygons(params: dict, units: str, tol: float, file=None) -> list[Polygon] | None:
    """The closed contours drawn on ``contour_layer`` (None when it is not given), read
    as the part is (chords within a 40th of the tolerance), for :func:`select`."""
    if params["contour_layer"] is None:
        return None
    if params["dxf"] is None:
        raise JobError("contour_layer: needs a dxf drawing", file)
    from millpath.part.drawing import read_dxf
    from millpath.plan.twod.geometry import CURVE_FRACTION
    return [orient(Polygon(lp.points), 1.0) for lp in read_dxf(
        params["dxf"], units, 0.5 * CURVE_FRACTION * tol, layer=params["contour_layer"],
        join_tolerance=params["join_tolerance"] or 10.0 * tol)]


def selecting(params: dict) -> bool:
    """Whether any key of :data:`SELECT_PARAMS` narrows the choice of contours."""
    return (params["contours"] != "all" or bool(params["kinds"])
            or params["min_size"] is not None or params["max_size"] is not None
            or params["contour_layer"] is not None)


def _same(a: Polygon, b: Polygon, tol: float) -> bool:
    """Whether two contours are one (each point of either within ``tol`` of the other)."""
    if abs(a.area - b.area) > tol * max(a.length, b.length):
        return False
    if a.centroid.distance(b.centroid) > tol:
        return False
    return a.exterior.hausdorff_distance(b.exterior) <= tol


def material(regions, side_outside: bool, around) -> object:
    """The part's material seen from above: the regions (``side_outside``), or the
    rectangle ``around`` (xmin, ymin, xmax, ymax) less the regions (openings)."""
    u = unary_union([r.polygon for r in regions])
    if side_outside:
        return u
    return shp_box(*around).difference(u)


def order(contours: list[Contour], start=(0.0, 0.0)) -> list[Contour]:
    """Contours cut from inside first (the part stays held), then the others; within
    each, nearest to the previous one's centre first."""
    out, at = [], np.asarray(start, float)
    for group in ([c for c in contours if not c.tool_outside],
                  [c for c in contours if c.tool_outside]):
        left = list(group)
        while left:
            k = min(range(len(left)), key=lambda i: math.dist(left[i].centre, at))
            c = left.pop(k)
            out.append(c)
            at = np.asarray(c.centre)
    return out
