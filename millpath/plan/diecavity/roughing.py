"""Contour-parallel roughing rings of a cavity, cut from the inside out.

The tool centre may go anywhere in ``region`` eroded by (tool radius + allowance);
rings are that area's boundary and its inward offsets by ``stepover``. Rings are
returned innermost first, each counter-clockwise (climb milling with M3 inside a
cavity), as (n, 2) arrays with the first point not repeated. Job units.
"""

from __future__ import annotations

import numpy as np
from shapely.geometry import MultiPolygon, Polygon
from shapely.geometry.polygon import orient


def _parts(g) -> list[Polygon]:
    if g.is_empty:
        return []
    if isinstance(g, Polygon):
        return [g]
    if isinstance(g, MultiPolygon):
        return list(g.geoms)
    return [p for p in getattr(g, "geoms", []) if isinstance(p, Polygon)]


def roughing_area(region: Polygon, radius: float, allowance: float,
                  simplify: float) -> list[Polygon]:
    """Where the tool centre may go while leaving ``allowance`` on the wall."""
    coarse = region.simplify(simplify, preserve_topology=True) if simplify > 0 else region
    # the simplified outline may stand up to `simplify` outside the region: erode more
    area = coarse.buffer(-(radius + allowance + simplify), quad_segs=16)
    return _parts(area)


def rings(area: list[Polygon], stepover: float, max_rings: int = 10_000) -> list[np.ndarray]:
    """Boundary rings of ``area`` and its inward offsets, innermost first."""
    out: list[np.ndarray] = []
    level = [p for p in area]
    k = 0
    while level and k < max_rings:
        for p in level:
            ring = np.asarray(orient(p, 1.0).exterior.coords)[:-1]
            if len(ring) >= 3:
                out.append(ring)
        nxt = []
        for p in level:
            nxt.extend(_parts(p.buffer(-stepover, quad_segs=16)))
        level = [p for p in nxt if p.area > 1e-12]
        k += 1
    out.reverse()
    return out
