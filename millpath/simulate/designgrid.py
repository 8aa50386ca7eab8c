"""The design's heights on the cells of a Z-map, computed once per simulation.

Sampling a design (a mesh through the drop-cutter, a solid's features) over every cell
is the costly part of comparing a Z-map with it; the comparison (report figures), the
deviation picture, its outline and the viewer's surface all read the same grid, so it
is computed once (:func:`design_grid`) and handed on (``SimResult.design_grid``).

Heights are in the Z-map's units. A cell's design height is taken at its centre and
four corners (see :mod:`millpath.simulate.simulator`): ``lo`` / ``hi`` are the lowest
and highest of the five, NaN and ``-inf`` (no part: through holes) counted as the stock
bottom, and never below it; ``centre`` keeps the design's own value at the centre.
A design with ``waste(x, y)`` (bool: nothing designed there, as a profile's scrap) marks
those cells ``free``: they are neither gouged nor left.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from millpath.simulate.zmap import ZMap

ROWS = 256                    # Z-map rows sampled at a time (bounds the sample arrays)


@dataclass
class DesignGrid:
    """Design heights over the cells of ``zmap`` (all arrays (ny, nx) float64)."""

    design: Any                 # what was sampled (an object with height(x, y))
    zmap: ZMap                  # on whose cells
    centre: np.ndarray          # the design's value at each cell centre, as it gave it
    lo: np.ndarray              # lowest of centre and corners, >= stock bottom
    hi: np.ndarray              # highest of centre and corners, >= stock bottom
    free: np.ndarray | None = None   # bool: the cell centre is in the design's waste

    def rows(self, j0: int, j1: int, h: np.ndarray
             ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """``(centre, lo, hi)`` of rows [j0, j1) for stock heights ``h`` there: the centre
        with NaN and below the stock bottom as the bottom; cells in the design's waste
        take ``h`` itself in all three (neither gouged nor left)."""
        c = self.centre[j0:j1]
        c = np.maximum(np.where(np.isnan(c), -np.inf, c), self.zmap.zmin)
        lo, hi = self.lo[j0:j1], self.hi[j0:j1]
        if self.free is not None:
            f = self.free[j0:j1]
            c, lo, hi = np.where(f, h, c), np.where(f, h, lo), np.where(f, h, hi)
        return c, lo, hi


def row_blocks(zmap: ZMap, rows: int = ROWS):
    """(j0, j1) of consecutive blocks of at most ``rows`` Z-map rows."""
    ny = zmap.heights.shape[0]
    for j0 in range(0, ny, rows):
        yield j0, min(ny, j0 + rows)


def design_grid(zmap: ZMap, design) -> DesignGrid:
    """Sample ``design`` (``height(X, Y)`` on arrays) at the centres and corners of every
    cell of ``zmap``, a block of rows at a time."""
    ny, nx = zmap.heights.shape
    centre = np.empty((ny, nx))
    lo = np.empty((ny, nx))
    hi = np.empty((ny, nx))
    xs = zmap.xs()
    ys = zmap.ys()
    xk = zmap.x0 + np.arange(nx + 1) * zmap.dx
    zf = zmap.zmin
    waste = getattr(design, "waste", None)
    free = np.zeros((ny, nx), bool) if waste is not None else None
    for j0, j1 in row_blocks(zmap):
        X, Y = np.meshgrid(xs, ys[j0:j1])
        dc = np.asarray(design.height(X, Y), float).reshape(X.shape)
        if waste is not None:
            free[j0:j1] = np.asarray(waste(X, Y), bool).reshape(X.shape)
        yk = zmap.y0 + np.arange(j0, j1 + 1) * zmap.dy
        XK, YK = np.meshgrid(xk, yk)
        dk = np.asarray(design.height(XK, YK), float).reshape(XK.shape)
        centre[j0:j1] = dc
        a = dc.copy()
        b = dc.copy()
        for c in (dk[:-1, :-1], dk[1:, :-1], dk[:-1, 1:], dk[1:, 1:]):
            np.fmin(a, c, out=a)
            np.fmax(b, c, out=b)
        lo[j0:j1] = np.maximum(np.where(np.isnan(a), -np.inf, a), zf)
        hi[j0:j1] = np.maximum(np.where(np.isnan(b), -np.inf, b), zf)
    return DesignGrid(design, zmap, centre, lo, hi, free)


def grid_of(zmap: ZMap, design, known: DesignGrid | None = None) -> DesignGrid:
    """``known`` if it samples this ``design`` on this ``zmap``, else a new grid."""
    if known is not None and known.design is design and known.zmap is zmap:
        return known
    return design_grid(zmap, design)
