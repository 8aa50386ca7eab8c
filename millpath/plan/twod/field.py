"""Where the tool meets material: a raster of the in-process stock at one Z.

Built from the planning context's ``remaining`` stock (``height(x, y)``: top of the
material left by earlier operations, job units) or, for the first operation, a full
block. ``material`` marks cells whose stock top is above ``z + threshold``;
``touch`` marks the tool-centre positions whose disk of radius ``R`` (plus one cell)
meets such a cell; ``within`` limits the material to cells the tool can reach (corners
it cannot enter are not worth a visit). Cells are ``h`` wide; lengths in job units.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np


@dataclass
class Raster:
    """Cell centres ``gx + (i + 0.5) h``, ``gy + (j + 0.5) h``; arrays are [j, i]."""

    gx: float
    gy: float
    h: float
    nx: int
    ny: int

    @classmethod
    def around(cls, bounds, h: float, margin: float) -> "Raster":
        x0, y0, x1, y1 = bounds
        gx, gy = x0 - margin, y0 - margin
        nx = int(math.ceil((x1 - x0 + 2 * margin) / h)) + 1
        ny = int(math.ceil((y1 - y0 + 2 * margin) / h)) + 1
        return cls(gx, gy, h, nx, ny)

    def centres(self) -> tuple[np.ndarray, np.ndarray]:
        xs = self.gx + (np.arange(self.nx) + 0.5) * self.h
        ys = self.gy + (np.arange(self.ny) + 0.5) * self.h
        return np.meshgrid(xs, ys)

    def index(self, x, y) -> tuple[np.ndarray, np.ndarray]:
        i = np.clip(np.floor((np.asarray(x) - self.gx) / self.h).astype(int), 0, self.nx - 1)
        j = np.clip(np.floor((np.asarray(y) - self.gy) / self.h).astype(int), 0, self.ny - 1)
        return i, j

    def inside(self, geom, margin: float = 0.0) -> np.ndarray:
        """Cells whose centre is inside ``geom`` shrunk by ``margin``."""
        import shapely
        g = geom.buffer(-margin) if margin > 0 else geom
        X, Y = self.centres()
        if g.is_empty:
            return np.zeros((self.ny, self.nx), bool)
        shapely.prepare(g)
        return shapely.contains_xy(g, X, Y)


def stock_heights(remaining, raster: Raster, full_top: float) -> np.ndarray:
    """Stock top at the raster's cells: ``remaining.height`` or a full block."""
    if remaining is None:
        return np.full((raster.ny, raster.nx), float(full_top))
    X, Y = raster.centres()
    return np.asarray(remaining.height(X, Y), float)


class MaterialField:
    """Material above one Z, and the tool positions that meet it."""

    def __init__(self, heights: np.ndarray, raster: Raster, z: float, threshold: float,
                 radius: float, within: np.ndarray | None = None):
        self.raster = raster
        self.heights = heights
        self.z = z
        self.material = heights > z + threshold
        if within is not None:            # material the tool can reach at all
            self.material &= within
        self.radius = radius
        if self.material.all():
            self.dist = np.zeros(self.material.shape)
        elif not self.material.any():
            self.dist = np.full(self.material.shape, np.inf)
        else:
            from scipy import ndimage      # (loaded only when a field is made)

            self.dist = ndimage.distance_transform_edt(~self.material) * raster.h
        self.touch = self.dist <= radius + raster.h

    def touches(self, pts: np.ndarray) -> np.ndarray:
        """True where a tool centre at ``pts`` (n, 2) meets material."""
        i, j = self.raster.index(pts[:, 0], pts[:, 1])
        return self.touch[j, i]

    def top_near(self, x: float, y: float, reach: float) -> float:
        """Highest stock top within ``reach`` of (x, y)."""
        r = self.raster
        i0, j0 = r.index(x - reach - r.h, y - reach - r.h)
        i1, j1 = r.index(x + reach + r.h, y + reach + r.h)
        return float(self.heights[int(j0):int(j1) + 1, int(i0):int(i1) + 1].max())


def densify(pts: np.ndarray, step: float) -> np.ndarray:
    """Polyline ``pts`` (n, 2) with extra points so no piece is longer than ``step``."""
    out = [pts[:1]]
    for a, b in zip(pts[:-1], pts[1:]):
        n = max(1, int(math.ceil(math.hypot(*(b - a)) / step)))
        t = np.linspace(0, 1, n + 1)[1:, None]
        out.append(a + (b - a) * t)
    return np.vstack(out)


def cutting_runs(pts: np.ndarray, touches: np.ndarray, pad: int = 2) -> list[tuple[int, int]]:
    """Index ranges [a, b] of ``pts`` where the tool meets material, each grown by
    ``pad`` points (so a run starts and ends in air where it can)."""
    if not touches.any():
        return []
    t = touches.copy()
    idx = np.flatnonzero(t)
    for k in range(1, pad + 1):
        t[np.clip(idx - k, 0, len(t) - 1)] = True
        t[np.clip(idx + k, 0, len(t) - 1)] = True
    runs = []
    edges = np.flatnonzero(np.diff(np.concatenate([[0], t.astype(int), [0]])))
    for a, b in zip(edges[::2], edges[1::2]):
        runs.append((int(a), int(b) - 1))
    return runs
