"""The simulated stock for display: a Z-map brought down to a few hundred thousand cells.

Lengths in program units. The display grid takes the middle cell of each ``step`` x ``step``
block of the Z-map (``step`` the smallest making at most ``max_cells`` blocks), so each display vertex is a true cell centre with its simulated
height. Deviation from the design (:func:`millpath.simulate.deviation`: positive =
material left, negative = gouge) is computed on the full Z-map and each display vertex
takes the extreme of its ``step`` x ``step`` block (the one of larger magnitude), so no
gouge or leftover disappears by decimation. The design is sampled at the display
vertices (``-inf`` and NaN: the stock bottom). The worst gouge and worst leftover are
the places the simulator reports (:class:`millpath.simulate.SimResult`), to one cell.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from millpath.simulate import ZMap, deviation
from millpath.simulate.designgrid import DesignGrid, grid_of

MAX_CELLS = 300_000


@dataclass
class DisplaySurface:
    """A decimated Z-map: ``heights[j, i]`` at ``(xs[i], ys[j])`` (cell centres)."""

    xs: np.ndarray                        # (nx,) float64
    ys: np.ndarray                        # (ny,) float64
    zmin: float
    ztop: float
    step: int
    heights: np.ndarray                   # (ny, nx) float32
    deviation: np.ndarray | None          # (ny, nx) float32, or None without a design
    design: np.ndarray | None             # (ny, nx) float32 design heights, or None
    max_gouge: float = 0.0
    max_left: float = 0.0
    gouge_at: tuple[float, float, float] | None = None
    left_at: tuple[float, float, float] | None = None


def _block_extreme(a: np.ndarray, step: int) -> np.ndarray:
    """Per ``step`` x ``step`` block: the value of larger magnitude (ties: the maximum)."""
    if step == 1:
        return a
    ny, nx = a.shape
    pad = np.pad(a, ((0, (-ny) % step), (0, (-nx) % step)))
    blk = pad.reshape(pad.shape[0] // step, step, pad.shape[1] // step, step)
    mx = blk.max(axis=(1, 3))
    mn = blk.min(axis=(1, 3))
    return np.where(-mn > mx, mn, mx)


def display_surface(zmap: ZMap, design=None, *, gouge_at=None, left_at=None,
                    max_cells: int = MAX_CELLS, grid: DesignGrid | None = None
                    ) -> DisplaySurface:
    """Decimate ``zmap`` (and its deviation from ``design``) for the page.

    ``gouge_at`` / ``left_at``: the ``(x, y)`` cell centres of the simulator's largest
    gouge and leftover (``SimResult.gouge_at`` / ``left_at``); their Z is the simulated
    height there. ``grid``: the design already sampled on ``zmap``
    (``SimResult.design_grid``), used when it is that of ``design``."""
    H = zmap.heights
    ny, nx = H.shape
    step = max(1, int(math.ceil(math.sqrt(nx * ny / max_cells))))
    while math.ceil(nx / step) * math.ceil(ny / step) > max_cells:
        step += 1
    off = (step - 1) // 2
    ii = np.minimum(np.arange(math.ceil(nx / step)) * step + off, nx - 1)
    jj = np.minimum(np.arange(math.ceil(ny / step)) * step + off, ny - 1)
    xs = zmap.x0 + (ii + 0.5) * zmap.dx
    ys = zmap.y0 + (jj + 0.5) * zmap.dy
    heights = H[np.ix_(jj, ii)].astype(np.float32)
    dev = des = None
    gmax = lmax = 0.0
    g_at = l_at = None
    if design is not None:
        grid = grid_of(zmap, design, grid)
        full = deviation(zmap, grid)
        gmax = max(float(-full.min()), 0.0) + 0.0
        lmax = max(float(full.max()), 0.0) + 0.0
        dev = _block_extreme(full, step).astype(np.float32)
        d = grid.centre[np.ix_(jj, ii)]          # the design at the display vertices
        d = np.where(np.isfinite(d), d, zmap.zmin)
        des = np.maximum(d, zmap.zmin).astype(np.float32)

        def where(at):
            if at is None:
                return None
            i = min(max(int((at[0] - zmap.x0) / zmap.dx), 0), nx - 1)
            j = min(max(int((at[1] - zmap.y0) / zmap.dy), 0), ny - 1)
            return (float(at[0]), float(at[1]), float(H[j, i]))
        g_at = where(gouge_at) if gmax > 0 else None
        l_at = where(left_at) if lmax > 0 else None
    return DisplaySurface(
        xs=xs, ys=ys,
        zmin=float(zmap.zmin), ztop=float(zmap.ztop), step=step, heights=heights,
        deviation=dev, design=des, max_gouge=gmax, max_left=lmax,
        gouge_at=g_at, left_at=l_at)
