"""Offsets of regions and their boundary rings (shapely, round joins).

Orientation: rings are returned as (n, 2) arrays without the closing point; exteriors
counter-clockwise, interiors (islands) clockwise, so that following a ring keeps the
region on the left: with a clockwise (M3) spindle that is climb milling of the
material outside the ring, conventional milling when reversed.
"""

from __future__ import annotations

import numpy as np
from shapely.geometry import MultiPolygon, Polygon
from shapely.geometry.polygon import orient


def polygons(geom) -> list[Polygon]:
    """The non-empty polygons of a (multi)polygon or collection."""
    if geom is None or geom.is_empty:
        return []
    if isinstance(geom, Polygon):
        return [geom]
    if isinstance(geom, MultiPolygon):
        return [g for g in geom.geoms if not g.is_empty]
    return [g for g in getattr(geom, "geoms", []) if isinstance(g, Polygon) and not g.is_empty]


def offset(geom, distance: float, quad_segs: int = 32):
    """``geom`` grown by ``distance`` (negative: shrunk), round joins."""
    return geom.buffer(distance, quad_segs=quad_segs, join_style="round")


def rings(poly: Polygon) -> list[np.ndarray]:
    """Boundary rings of ``poly``: exterior counter-clockwise first, then islands
    clockwise; no repeated closing point."""
    p = orient(poly, 1.0)
    out = [np.asarray(p.exterior.coords)[:-1, :2]]
    out += [np.asarray(r.coords)[:-1, :2] for r in p.interiors]
    return out


def start_at(r: np.ndarray, p) -> np.ndarray:
    """The ring rotated to start at its vertex nearest ``p``."""
    k = int(np.argmin(np.hypot(r[:, 0] - p[0], r[:, 1] - p[1])))
    return np.roll(r, -k, axis=0)


def closed(r: np.ndarray) -> np.ndarray:
    return np.vstack([r, r[:1]])
