"""The pocket's walls and its grid of cells.

The pocket is a simple polygon (convex or concave) in XY, job units. Its cells are
``dx`` by ``dy`` rectangles tiling the polygon's bounding box from its lower-left
corner (or, given an ``anchor`` cell centre, from the last cell corner of the lattice
through that centre at or below the box's lower-left corner); cell ``(i, j)`` has its
centre at ``(x0 + (i + 1/2) dx, y0 + (j + 1/2) dy)``.
The tool centre must stay one tool radius inside every wall, so only cells whose
centres lie inside (or on) the polygon offset inward by the radius are machined.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import shapely
from shapely.geometry import LineString, MultiPolygon, Polygon
from shapely.validation import explain_validity

from millpath.errors import GeometryError, PlanningError
from millpath.model.limits import MAX_GRID_CELLS


def polygon_problem(points) -> str | None:
    """Why ``points`` (a list of [x, y]) is not a usable pocket outline, or None."""
    try:
        pts = np.asarray(points, dtype=float)
    except (TypeError, ValueError):
        return "expected a list of [x, y] points"
    if pts.ndim != 2 or pts.shape[1] != 2:
        return "expected a list of [x, y] points"
    if not np.all(np.isfinite(pts)):
        return "a point has a NaN or infinite coordinate"
    if len(pts) > 1 and np.allclose(pts[0], pts[-1]):
        pts = pts[:-1]                      # an explicitly closed outline
    if len(pts) < 3:
        return f"a pocket outline needs at least 3 points, got {len(pts)}"
    poly = Polygon(pts)
    span = np.abs(pts - pts.mean(axis=0)).max()
    if span == 0 or np.linalg.matrix_rank(pts - pts.mean(axis=0), tol=1e-12 * span) < 2:
        return "the outline encloses no area (all points on one line)"
    if not poly.is_valid:
        why = explain_validity(poly)
        if "Self-intersection" in why or "Ring Self-intersection" in why:
            return f"the outline intersects itself ({why.lower()})"
        return f"the outline is not a simple polygon ({why})"
    if poly.area <= 0:
        return "the outline encloses no area"
    return None


def pocket_polygon(points, file=None, key: str = "polygon") -> Polygon:
    """A counter-clockwise shapely Polygon from ``[[x, y], ...]``; GeometryError naming
    ``file`` and ``key`` when it is self-intersecting, degenerate or not finite."""
    msg = polygon_problem(points)
    if msg:
        raise GeometryError(f"{key}: {msg}", file)
    pts = np.asarray(points, dtype=float)
    if np.allclose(pts[0], pts[-1]):
        pts = pts[:-1]
    return shapely.geometry.polygon.orient(Polygon(pts), 1.0)


def inward_offset(poly: Polygon, distance: float, quad_segs: int = 16) -> Polygon | MultiPolygon:
    """The polygon shrunk by ``distance`` (round joins at concave corners); may be empty
    or split into several parts where the pocket has narrow necks."""
    off = poly.buffer(-distance, quad_segs=quad_segs, join_style="round")
    if off.is_empty:
        return off
    parts = [g for g in getattr(off, "geoms", [off]) if g.area > 0]
    parts = [shapely.geometry.polygon.orient(g, 1.0) for g in parts]
    return parts[0] if len(parts) == 1 else MultiPolygon(parts)


def _clear_of_corners(poly: Polygon, region, radius: float, segs: int = 64):
    """``region`` less a disc of ``radius`` about each reflex corner of ``poly``: the
    round joins of the offset are chords inside their arcs (nearer the corner than the
    radius); the discs' own chords (``segs`` per quarter) lie outside the radius."""
    ring = np.asarray(shapely.geometry.polygon.orient(poly, 1.0).exterior.coords)[:-1]
    a, b = ring - np.roll(ring, 1, axis=0), np.roll(ring, -1, axis=0) - ring
    reflex = ring[(a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0]) < 0]
    if region.is_empty or not len(reflex):
        return region
    grown = radius / math.cos(math.pi / (4 * segs)) * (1 + 1e-9)
    discs = shapely.MultiPoint(reflex).buffer(grown, quad_segs=segs)
    out = region.difference(discs)
    parts = [shapely.geometry.polygon.orient(g, 1.0)
             for g in getattr(out, "geoms", [out]) if g.area > 0]
    if not parts:
        return shapely.geometry.Polygon()
    return parts[0] if len(parts) == 1 else MultiPolygon(parts)


@dataclass
class PocketGrid:
    """Cells of the pocket: ``inside[i, j]`` when cell (i, j)'s centre may be visited."""

    polygon: Polygon            # the walls (counter-clockwise)
    region: Polygon | MultiPolygon   # where the tool centre may go: walls offset by R
    x0: float
    y0: float
    dx: float
    dy: float
    inside: np.ndarray          # (nx, ny) bool

    @property
    def shape(self) -> tuple[int, int]:
        return self.inside.shape

    def centre(self, i, j) -> tuple[np.ndarray, np.ndarray]:
        """Centre (x, y) of cells (i, j) (scalars or arrays)."""
        return (self.x0 + (np.asarray(i) + 0.5) * self.dx,
                self.y0 + (np.asarray(j) + 0.5) * self.dy)

    def segment_inside(self, a, b) -> bool:
        """True when the straight XY segment a-b keeps the tool centre inside the region."""
        if np.allclose(a, b):
            return bool(shapely.covers(self.region, shapely.points(a[0], a[1])))
        seg = LineString([tuple(a[:2]), tuple(b[:2])])
        # a hair of slack: cell centres on the offset boundary count as inside
        return bool(self.region.buffer(1e-9 * max(self.dx, self.dy)).covers(seg))

    def rings(self) -> list[np.ndarray]:
        """The offset outline(s) the wall pass follows, each ``(n, 2)`` counter-clockwise,
        not repeating the first point."""
        out = []
        for g in getattr(self.region, "geoms", [self.region]):
            c = np.asarray(g.exterior.coords)[:-1]
            out.append(c)
        return out


def check_grid(dx: float, dy: float, diameter: float, force: bool = False,
               file=None, key: str = "grid") -> None:
    """Reject cells larger than D/sqrt(2): a tool at the centre would not cover the cell
    corners (uncut material in plan view) unless ``force``."""
    limit = diameter / math.sqrt(2.0)
    if not (dx > 0 and dy > 0 and math.isfinite(dx) and math.isfinite(dy)):
        raise GeometryError(f"{key}: cell sizes must be positive numbers", file)
    if not force and max(dx, dy) > limit * (1 + 1e-12):
        raise PlanningError(f"{key}: cell {dx:g} x {dy:g} is larger than D/sqrt(2) = {limit:.5g} "
                            f"for the {diameter:g} tool; it would leave uncut material "
                            "between cells", file)


def build_grid(poly: Polygon, tool_radius: float, dx: float, dy: float, file=None,
               key: str = "polygon", anchor: tuple[float, float] | None = None) -> PocketGrid:
    """Offset the walls by the tool radius and mark the cells whose centres lie inside.

    ``anchor``: an (x, y) the lattice of cell centres passes through (default: the
    cells tile the bounding box from its lower-left corner)."""
    region = _clear_of_corners(poly, inward_offset(poly, tool_radius), tool_radius)
    if region.is_empty:
        xmin, ymin, xmax, ymax = poly.bounds
        raise PlanningError(f"{key}: the tool (diameter {2 * tool_radius:g}) is too big for the "
                            f"pocket (bounding box {xmax - xmin:g} x {ymax - ymin:g}); nothing "
                            "can be cut", file)
    xmin, ymin, xmax, ymax = poly.bounds
    if anchor is not None:
        # cell corners of the anchored lattice at or below the lower-left corner
        cx, cy = anchor[0] - dx / 2.0, anchor[1] - dy / 2.0
        xmin = cx + math.floor((xmin - cx) / dx + 1e-9) * dx
        ymin = cy + math.floor((ymin - cy) / dy + 1e-9) * dy
    nx = max(1, int(math.ceil((xmax - xmin) / dx - 1e-9)))
    ny = max(1, int(math.ceil((ymax - ymin) / dy - 1e-9)))
    if nx * ny > MAX_GRID_CELLS:
        raise PlanningError(f"grid: {nx} x {ny} cells is too many; use larger cells", file)
    i, j = np.meshgrid(np.arange(nx), np.arange(ny), indexing="ij")
    x = xmin + (i + 0.5) * dx
    y = ymin + (j + 0.5) * dy
    slack = region.buffer(1e-9 * max(dx, dy))
    inside = shapely.contains_xy(slack, x, y)
    return PocketGrid(poly, region, xmin, ymin, dx, dy, inside)
