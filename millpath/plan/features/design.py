"""The finished part as a height field: the stock top minus the feature volumes.

:class:`FeatureDesign` implements the :class:`millpath.plan.base.Design` protocol:
``height(x, y)`` is the Z of the part's top surface (job units), ``-inf`` inside
through holes and through pockets. Shapes are those of
:mod:`millpath.part.step.shapes`, already scaled to job units.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
import shapely

from millpath.part.step.shapes import FaceShape, HoleShape, PocketShape, SlotShape


def slot_outline(s: SlotShape, reach: float):
    """The slot's plan outline; open ends are extended by ``reach`` (they leave the part)."""
    from shapely.geometry import LineString, Point

    d = np.asarray(s.direction)
    a = np.asarray(s.start, float)
    b = a + d * s.length
    a2 = a - d * reach if s.ends[0] == "open" else a
    b2 = b + d * reach if s.ends[1] == "open" else b
    poly = LineString([a2, b2]).buffer(s.width / 2.0, cap_style="flat")
    for e, p in zip(s.ends, (a, b)):
        if e == "radiused":
            poly = poly.union(Point(p).buffer(s.width / 2.0, quad_segs=32))
    return poly


def hole_floor(h: HoleShape, r: np.ndarray) -> np.ndarray:
    """Floor Z of a hole at radial distances ``r`` (all < D/2)."""
    zb = h.z_bottom
    if h.bottom == "through":
        return np.full_like(r, -np.inf)
    if h.bottom == "conical":
        return np.minimum(zb + r / math.tan(math.radians(h.tip_angle) / 2.0), h.z_top)
    if h.bottom == "spherical":
        rho = h.bottom_radius
        return np.minimum(zb + rho - np.sqrt(np.maximum(rho * rho - r * r, 0.0)), h.z_top)
    if h.bottom == "flat with taper":
        half = math.radians(h.tip_angle) / 2.0
        d = np.maximum(r - h.final_diameter / 2.0, 0.0)
        return np.minimum(zb + d / math.tan(half), h.z_top)
    if h.bottom == "flat with radius":
        rc = h.bottom_radius
        R = h.diameter / 2.0
        d = np.maximum(r - (R - rc), 0.0)
        return np.minimum(zb + rc - np.sqrt(np.maximum(rc * rc - d * d, 0.0)), h.z_top)
    return np.full_like(r, zb)


@dataclass
class FeatureDesign:
    """Stock top ``z_top`` minus the feature volumes (``shapes`` in job units)."""

    z_top: float
    shapes: list = field(default_factory=list)
    reach: float = 1e3            # how far open slot ends extend

    def __post_init__(self) -> None:
        self._polys = []                  # (shape, outline, its bounds, its boundary)
        for s in self.shapes:
            if isinstance(s, SlotShape):
                poly = slot_outline(s, self.reach)
            elif isinstance(s, (PocketShape, FaceShape)):
                poly = s.outline(32)
            else:
                continue
            shapely.prepare(poly)
            self._polys.append((s, poly, poly.bounds, poly.boundary))

    def height(self, x: np.ndarray, y: np.ndarray) -> np.ndarray:
        x = np.asarray(x, float)
        y = np.asarray(y, float)
        out = np.full(np.broadcast(x, y).shape, self.z_top, dtype=float)
        xb, yb = np.broadcast_arrays(x, y)
        for s in self.shapes:
            if isinstance(s, HoleShape):
                R = s.diameter / 2.0
                box = (np.abs(xb - s.x) < R) & (np.abs(yb - s.y) < R)
                if not box.any():
                    continue
                r = np.hypot(xb[box] - s.x, yb[box] - s.y)
                inside = r <= R                      # closed: the wall belongs to the cut
                sub = out[box]
                sub[inside] = np.minimum(sub[inside], hole_floor(s, r[inside]))
                out[box] = sub
        for s, poly, (x0, y0, x1, y1), edge in self._polys:
            box = (xb >= x0) & (xb <= x1) & (yb >= y0) & (yb <= y1)
            if not box.any():
                continue
            inside = shapely.intersects_xy(poly, xb[box], yb[box])   # boundary included
            floor = -np.inf if getattr(s, "bottom", "") == "through" else s.z_top - s.depth
            sub = out[box]
            fr = getattr(s, "floor_radius", 0.0)
            if fr > 0 and inside.any():
                # floor fillet: rises along a quarter circle within fr of the wall
                px, py = xb[box][inside], yb[box][inside]
                dist = s.wall_distance(px, py) if isinstance(s, PocketShape) else None
                if dist is None:                  # other profiles: to the outline
                    dist = shapely.distance(edge, shapely.points(px, py))
                d = np.clip(fr - dist, 0.0, fr)
                z = np.minimum(floor + fr - np.sqrt(np.maximum(fr * fr - d * d, 0.0)), s.z_top)
                sub[inside] = np.minimum(sub[inside], z)
            else:
                sub[inside] = np.minimum(sub[inside], floor)
            out[box] = sub
        return out

    def volume(self, cell: float, box: tuple[float, float, float, float],
               z_bottom: float) -> float:
        """Removed volume integrated on a grid of ``cell`` spacing over ``box`` (xmin,
        ymin, xmax, ymax), with through regions cut down to ``z_bottom``."""
        x0, y0, x1, y1 = box
        xs = np.arange(x0 + cell / 2.0, x1, cell)
        ys = np.arange(y0 + cell / 2.0, y1, cell)
        return self.volume_on_grid(xs, ys, cell * cell, z_bottom)

    def volume_on_grid(self, xs: np.ndarray, ys: np.ndarray, cell_area: float,
                       z_bottom: float) -> float:
        """Removed volume summed on the cells centred at ``xs`` x ``ys`` (e.g. a Z-map's,
        for a comparison without discretisation noise), down to ``z_bottom``."""
        X, Y = np.meshgrid(xs, ys)
        hgt = np.clip(self.height(X, Y), z_bottom, self.z_top)
        return float((self.z_top - hgt).sum() * cell_area)
