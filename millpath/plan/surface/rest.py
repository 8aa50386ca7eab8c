"""Rest machining for surface finishing: keep only where the tool meets material.

A tool-tip position (x, y, z) meets material when a cell of the in-process stock
(``ctx.remaining``, sampled on a raster of its own resolution, each sample raised to
the highest of its 3 x 3 neighbours so the test errs toward cutting) within the tool radius
stands more than ``threshold`` above the tool's surface there (tip Z plus the cutter's
profile height at that distance: flat, ball or bull). Passes are cut into the runs of
points that meet material, each grown by ``pad`` points so a run starts and ends in
air; the linking of :func:`millpath.plan.surface.linking.add_passes` joins them. Z is
part of the test: stock left high on a slope is found even where the XY spot was
cleared higher up. Lengths in job units.
"""

from __future__ import annotations

import numpy as np

from millpath.plan.restcut import StockRaster
from millpath.plan.surface.zigzag import Pass


def rest_passes(passes: list[Pass], remaining, tool, threshold: float,
                pad: int = 2) -> tuple[list[Pass], dict]:
    """The runs of ``passes`` where ``tool`` meets more than ``threshold`` of the
    in-process stock ``remaining``; and counts for the report."""
    pts = [p.points for p in passes if len(p.points)]
    if not pts:
        return [], {"points_kept": 0, "points": 0}
    allp = np.vstack(pts)
    R = tool.radius
    h = float(getattr(remaining, "resolution", R / 8))
    lo, hi = allp[:, :2].min(axis=0), allp[:, :2].max(axis=0)
    raster = StockRaster(remaining, (lo[0], lo[1], hi[0], hi[1]), R + h, h, highest=True)
    out: list[Pass] = []
    kept = total = 0
    for p in passes:
        P = np.ascontiguousarray(p.points, dtype=float)
        if not len(P):
            continue
        t = raster.meets(P, tool, threshold, 0.0)
        total += len(P)
        if not t.any():
            continue
        idx = np.flatnonzero(t)
        grow = t.copy()
        for k in range(1, pad + 1):
            grow[np.clip(idx - k, 0, len(t) - 1)] = True
            grow[np.clip(idx + k, 0, len(t) - 1)] = True
        edges = np.flatnonzero(np.diff(np.concatenate([[0], grow.astype(int), [0]])))
        for a, b in zip(edges[::2], edges[1::2]):
            if b - a >= 2:
                out.append(Pass(P[a:b].copy(), p.lifted[a:b].copy()))
                kept += b - a
    return out, {"points_kept": int(kept), "points": int(total)}
