"""One level of adaptive clearing: rasters from the region and the in-process stock,
walker passes (:mod:`millpath.plan.adaptive.planner`), their moves, and a clean-up
ring along the free area's boundary.

The raster is ``D / 80`` fine (coarser for very large regions: at most about 6 million
cells); the walker's step is ``R / 4``.
"""

from __future__ import annotations

import math

import numpy as np
from scipy import ndimage

from millpath.plan.adaptive.planner import clear_level
from millpath.plan.pocket.passes import Cut, order_nearest
from millpath.plan.twod.field import MaterialField, Raster, stock_heights
from millpath.plan.twod.offsets import offset, polygons, rings


def adaptive_level(w, em, ctx, pocket, free, tool, z: float, z_from: float,
                   threshold: float, allow: float, engagement: float, helix_radius: float,
                   climb: bool, full_top: float, rest: bool = False) -> int:
    """Clear ``pocket`` at ``z`` adaptively; returns the material cells left. Adaptive
    clearing is always climb milling (the walker keeps the material on its right):
    ``climb`` is accepted for a common signature only."""
    R = tool.radius
    D = tool.diameter
    x0, y0, x1, y1 = pocket.bounds
    h = D / 80.0
    cells = (x1 - x0 + 2 * R) * (y1 - y0 + 2 * R) / (h * h)
    if cells > 6e6:
        h *= math.sqrt(cells / 6e6)
    raster = Raster.around(pocket.bounds, h, R + 2 * h)
    heights = stock_heights(ctx.remaining, raster, full_top)
    A = raster.inside(free, margin=h)
    dist_A = ndimage.distance_transform_edt(~A) * h
    reach = dist_A <= R + h
    inner = raster.inside(offset(pocket, -allow) if allow > 0 else pocket)
    M = (heights > z + threshold) & reach & inner
    S = M & (dist_A <= R - 2 * h)      # passes are not started for the last cells: clean-up
    air = heights <= z + 1e-9 * max(1.0, abs(z))
    start = w.pos[:2] if (w.pos is not None and abs(w.pos[2] - z) < 1e-9) else None
    # a link by way of cleared space is worth taking when it is no longer than the
    # retract's feed down at half the feed (from z_from) counted twice
    res = clear_level(M, A, raster.gx, raster.gy, h, R, engagement,
                      helix_radius=helix_radius, start=start, S=S,
                      link_max=4.0 * max(z_from - z, 0.0))
    for p in res.passes:
        pts = p.pts
        i0 = len(w.tp.moves)
        if p.kind == "helix":
            zf = min(z_from, _top(heights, raster, p.center, R + p.radius) + em.clearance)
            w.helix(p.center[0], p.center[1], p.radius, max(zf, z), z)
        elif p.kind == "link" and w.pos is not None and abs(w.pos[2] - z) < 1e-9:
            pass
        else:
            x, y = pts[0]
            if not rest or _column_clear(air, raster, x, y, R):
                zf = min(z_from, _top(heights, raster, (x, y), R) + em.clearance)
                w.plunge_air(x, y, z, max(zf, z))
            else:
                w.ramp_open(pts, z_from, z)
        em.mark_entry(i0)
        w.polyline(pts, z)
    # clean-up rings toward the free area's boundary (the walker stops short of it, and
    # where it could not keep the engagement): from the inside out, 0.3 of the width of
    # cut apart, each only where it meets material the walker left
    left = np.where(M, np.maximum(heights, z + 1.0), z)
    field = MaterialField(left, raster, z, 0.5, R)
    if field.material.any():
        s = 0.3 * engagement * D
        k_max = int(math.ceil((2 * h + engagement * D) / s))
        for k in range(k_max, -1, -1):
            ring_area = offset(free, -k * s) if k else free
            cuts = [Cut(r, True, p) for p in polygons(ring_area) for r in rings(p)]
            cuts = order_nearest(cuts, w.pos[:2] if w.pos else None)
            em.level(cuts, z, z_from, field)
    return res.left_cells


def _top(heights, raster, c, reach) -> float:
    i0, j0 = raster.index(c[0] - reach, c[1] - reach)
    i1, j1 = raster.index(c[0] + reach, c[1] + reach)
    return float(heights[int(j0):int(j1) + 1, int(i0):int(i1) + 1].max())


def _column_clear(air, raster, x, y, R) -> bool:
    r = raster
    i0, j0 = r.index(x - R - r.h, y - R - r.h)
    i1, j1 = r.index(x + R + r.h, y + R + r.h)
    return bool(air[int(j0):int(j1) + 1, int(i0):int(i1) + 1].all())
