"""The stock as a height field (Z-map) over its XY box.

Cells tile the stock box exactly: ``nx = ceil(width / resolution)`` columns of width
``dx = width / nx`` (so ``dx <= resolution``), likewise rows. ``heights[j, i]`` is the
top of the material at the cell centre ``(x0 + (i + 0.5) dx, y0 + (j + 0.5) dy)``;
material fills each cell's column from the stock bottom ``zmin`` up to that height.
A height equal to ``zmin`` means no material is left. A cylindrical stock (a bar with a
vertical axis) starts with material only in the cells whose centres are inside its
circle (``initial``: the starting height of every cell). Lengths in job units.

A height field cannot represent undercuts; for 3-axis milling with the tool axis along
Z the tool's swept volume never makes one, so the model is exact at the cell centres.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from millpath.model.stock import Stock


@dataclass
class ZMap:
    x0: float
    y0: float
    dx: float
    dy: float
    zmin: float
    ztop: float
    heights: np.ndarray            # (ny, nx) float64
    initial: np.ndarray | None = None   # (ny, nx) starting heights; None: ztop everywhere

    @classmethod
    def from_stock(cls, stock: Stock, resolution: float) -> "ZMap":
        """The stock (a full block, or a bar's circle in its box) with cells at most
        ``resolution`` wide."""
        if not (resolution > 0 and math.isfinite(resolution)):
            raise ValueError(f"resolution must be a positive length, not {resolution!r}")
        w, h, _ = stock.size
        fx, fy = max(w / resolution, 1.0), max(h / resolution, 1.0)   # floats: may be inf
        if not fx * fy <= 400_000_000:
            raise ValueError(f"resolution {resolution} gives {fx:.3g} x {fy:.3g} cells: "
                             "too many")
        nx = max(1, int(math.ceil(w / resolution - 1e-9)))
        ny = max(1, int(math.ceil(h / resolution - 1e-9)))
        z = cls(stock.xmin, stock.ymin, w / nx, h / ny, stock.zmin, stock.zmax,
                np.full((ny, nx), float(stock.zmax)))
        if stock.cylinder is not None:
            X, Y = np.meshgrid(z.xs(), z.ys())
            z.heights[~stock.inside_xy(X, Y)] = stock.zmin
            z.initial = z.heights.copy()
        return z

    def start_heights(self) -> np.ndarray | float:
        """The heights the stock started with (an array, or ``ztop`` for a block)."""
        return self.ztop if self.initial is None else self.initial

    @property
    def shape(self) -> tuple[int, int]:
        return self.heights.shape          # (ny, nx)

    @property
    def cell_area(self) -> float:
        return self.dx * self.dy

    def xs(self) -> np.ndarray:
        """Cell centre X coordinates (nx,)."""
        return self.x0 + (np.arange(self.heights.shape[1]) + 0.5) * self.dx

    def ys(self) -> np.ndarray:
        """Cell centre Y coordinates (ny,)."""
        return self.y0 + (np.arange(self.heights.shape[0]) + 0.5) * self.dy

    def extent(self) -> tuple[float, float, float, float]:
        """(xmin, xmax, ymin, ymax) of the grid, for imshow."""
        ny, nx = self.heights.shape
        return (self.x0, self.x0 + nx * self.dx, self.y0, self.y0 + ny * self.dy)

    def material_volume(self) -> float:
        return float(np.sum(self.heights - self.zmin, dtype=np.float64) * self.cell_area)

    def removed_volume(self) -> float:
        """Volume removed from the full block (job units cubed)."""
        return float(np.sum(self.start_heights() - self.heights, dtype=np.float64)
                     * self.cell_area)

    def height_at(self, x: float, y: float) -> float:
        """Height of the cell containing (x, y); ValueError outside the grid."""
        ny, nx = self.heights.shape
        i = int(math.floor((x - self.x0) / self.dx))
        j = int(math.floor((y - self.y0) / self.dy))
        if not (0 <= i < nx and 0 <= j < ny):
            raise ValueError(f"({x}, {y}) is outside the stock")
        return float(self.heights[j, i])
