"""Independent checks for pocket tests: the simulator's Z-map swept window by window.

The engagement of a window of horizontal feed lines is the area (seen from above) of
the cells whose height dropped, divided by the window's length and the tool diameter.
Arcs (helix entries and their closing circles) are not measured; vertical feed lines
(plunges) must remove nothing."""

from __future__ import annotations

import math

import numpy as np

from millpath.simulate.path import motion_segments, toolpath_motions
from millpath.simulate.simulator import sweep
from millpath.simulate.zmap import ZMap


def _sweep_part(zm: ZMap, ms, tools, R):
    segs = motion_segments(ms, zm.dx / 20)
    if not len(segs):
        return np.zeros((0, 0))
    pts = np.vstack([segs.start, segs.end])
    ny, nx = zm.heights.shape
    i0 = max(0, int((pts[:, 0].min() - R - zm.x0) / zm.dx) - 2)
    i1 = min(nx, int((pts[:, 0].max() + R - zm.x0) / zm.dx) + 3)
    j0 = max(0, int((pts[:, 1].min() - R - zm.y0) / zm.dy) - 2)
    j1 = min(ny, int((pts[:, 1].max() + R - zm.y0) / zm.dy) + 3)
    before = zm.heights[j0:j1, i0:i1].copy()
    sub = ZMap(zm.x0 + i0 * zm.dx, zm.y0 + j0 * zm.dy, zm.dx, zm.dy, zm.zmin, zm.ztop,
               before.copy())
    sweep(sub, segs, tools, len(ms))
    zm.heights[j0:j1, i0:i1] = sub.heights
    return before - sub.heights


def measure(tp, tools, stock, resolution, zmap: ZMap | None = None):
    """Sweep ``tp`` into ``zmap`` (default: a full block); returns (zmap, engagement
    samples [(x, y, e)], largest volume removed by a vertical feed line)."""
    zm = zmap or ZMap.from_stock(stock, resolution)
    motions, _ = toolpath_motions(tp)
    samples = []
    worst_plunge = 0.0
    k, n = 0, len(motions)
    while k < n:
        mo = motions[k]
        D = tools[mo.tool].diameter
        horiz = mo.kind == "feed" and abs(mo.end[2] - mo.start[2]) < 1e-9
        if not horiz:
            d = _sweep_part(zm, [mo], tools, D / 2)
            vertical = (mo.kind == "feed" and math.dist(mo.start[:2], mo.end[:2]) < 1e-9
                        and mo.end[2] < mo.start[2])
            if vertical and d.size:
                worst_plunge = max(worst_plunge, float(d.sum()) * zm.cell_area)
            k += 1
            continue
        win, L = [mo], math.dist(mo.start, mo.end)
        k += 1
        while k < n and L < D / 4:
            m2 = motions[k]
            if not (m2.kind == "feed" and abs(m2.end[2] - m2.start[2]) < 1e-9
                    and m2.tool == mo.tool):
                break
            win.append(m2)
            L += math.dist(m2.start, m2.end)
            k += 1
        d = _sweep_part(zm, win, tools, D / 2)
        if L >= D / 8 and d.size:
            cells = int(np.count_nonzero(d > 1e-4 * zm.dx))
            samples.append((win[-1].end[0], win[-1].end[1], cells * zm.cell_area / (L * D)))
    return zm, np.array(samples).reshape(-1, 3), worst_plunge


def cell_centres(zm: ZMap):
    return np.meshgrid(zm.xs(), zm.ys())


import pytest  # noqa: E402


@pytest.fixture
def sweep_measure():
    """:func:`measure` as a fixture (tests are imported by file, not as a package)."""
    return measure
