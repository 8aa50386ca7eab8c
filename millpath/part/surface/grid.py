"""Surfaces measured as (x, y, z) points on a regular or near-regular grid.

Typical sources are a CMM or a probing routine (reverse engineering). The samples must
form ``nx`` columns of roughly equal x by ``ny`` rows of roughly equal y (in any order);
"near-regular" means each sample may sit off its ideal node by less than a tenth of
the node spacing. Coordinates are in the job's units.

Between samples the surface is interpolated bilinearly (``method="linear"``) or with an
interpolating bicubic spline (``"cubic"``). Linear: on a near-regular grid each grid
cell is a bilinear quadrilateral through its four real samples, so the surface passes
exactly through every measured point. Cubic: the spline is built on the mean X of each
column and mean Y of each row (exact at the samples of a regular grid; on a
near-regular one, off by the samples' displacement times the local slope). Outside
the grid the nearest edge value is used.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from millpath.errors import GeometryError
from millpath.part.surface.bezier import point_grid_triangles
from millpath.io.text import read_number_rows


def _levels(values: np.ndarray, what: str, file) -> tuple[np.ndarray, np.ndarray]:
    """Cluster coordinates into grid levels; return (level index of each, level means)."""
    order = np.argsort(values)
    sv = values[order]
    gaps = np.diff(sv)
    if gaps.size == 0 or gaps.max() <= 0:
        raise GeometryError(f"measured grid: all points have the same {what}", file)
    # a new level starts where the gap is large compared with the largest gap
    big = gaps > 0.5 * gaps.max()
    level_sorted = np.concatenate([[0], np.cumsum(big)])
    idx = np.empty(values.size, int)
    idx[order] = level_sorted
    nlev = int(level_sorted[-1]) + 1
    means = np.bincount(idx, values, nlev) / np.bincount(idx, None, nlev)
    return idx, means


class MeasuredGrid:
    """A height field through measured points ``(x, y, z)`` (job units)."""

    def __init__(self, points: np.ndarray, method: str = "linear", file: str | Path | None = None):
        pts = np.asarray(points, dtype=float)
        if pts.ndim != 2 or pts.shape[1] != 3:
            raise GeometryError(f"measured grid: expected (x, y, z) rows, got shape {pts.shape}",
                                file)
        if not np.all(np.isfinite(pts)):
            bad = int(np.argwhere(~np.isfinite(pts).all(axis=1))[0, 0])
            raise GeometryError(f"measured grid: point {bad + 1} has a NaN or infinite value",
                                file)
        if method not in ("linear", "cubic"):
            raise GeometryError(f"measured grid: method must be linear or cubic, not {method!r}",
                                file)
        ix, xs = _levels(pts[:, 0], "x", file)
        iy, ys = _levels(pts[:, 1], "y", file)
        nx, ny = xs.size, ys.size
        if nx < 2 or ny < 2:
            raise GeometryError("measured grid: need at least 2 x 2 points", file)
        if pts.shape[0] != nx * ny:
            raise GeometryError(f"measured grid: {pts.shape[0]} points do not fill a grid of "
                                f"{nx} x {ny} (missing or extra samples)", file)
        cell = np.full((nx, ny), -1)
        cell[ix, iy] = np.arange(pts.shape[0])
        if np.any(cell < 0):
            i, j = np.argwhere(cell < 0)[0]
            raise GeometryError(f"measured grid: no sample near x={xs[i]:g} y={ys[j]:g} "
                                "(two samples share a node)", file)
        self.X = pts[cell, 0]          # (nx, ny) sample coordinates
        self.Y = pts[cell, 1]
        self.Z = pts[cell, 2]
        self.xs, self.ys = xs, ys      # mean level of each column / row
        self.method = method
        hx, hy = np.diff(xs).min(), np.diff(ys).min()
        dev = max(np.abs(self.X - xs[:, None]).max(), np.abs(self.Y - ys[None, :]).max())
        if dev > 0.1 * min(hx, hy):
            raise GeometryError("measured grid: samples are too far from a regular grid "
                                f"(off by {dev:g}, spacing {min(hx, hy):g})", file)
        self.regular = dev <= 1e-9 * max(1.0, abs(xs).max(), abs(ys).max())
        self._spline = None
        if method == "cubic":
            from scipy.interpolate import RectBivariateSpline
            k = 3 if min(nx, ny) >= 4 else 1
            self._spline = RectBivariateSpline(xs, ys, self.Z, kx=k, ky=k, s=0)

    @classmethod
    def from_csv(cls, path: str | Path, method: str = "linear") -> "MeasuredGrid":
        """Read ``x,y,z`` rows (comma, semicolon or whitespace separated; a header line
        and ``#`` comments are allowed). Errors name the file and line."""
        p = Path(path)
        rows = read_number_rows(p, "x, y, z", GeometryError)
        return cls(rows, method=method, file=p)

    @property
    def bounds(self) -> tuple[float, float, float, float]:
        """xmin, ymin, xmax, ymax of the samples."""
        return (float(self.X.min()), float(self.Y.min()), float(self.X.max()), float(self.Y.max()))

    def _locate(self, x: np.ndarray, y: np.ndarray):
        """Cell indices (i, j) and local coordinates (s, t) in [0, 1] of clamped points."""
        xs, ys = self.xs, self.ys
        xc = np.clip(x, xs[0], xs[-1])
        yc = np.clip(y, ys[0], ys[-1])
        i = np.clip(np.searchsorted(xs, xc, side="right") - 1, 0, xs.size - 2)
        j = np.clip(np.searchsorted(ys, yc, side="right") - 1, 0, ys.size - 2)
        s = (xc - xs[i]) / (xs[i + 1] - xs[i])
        t = (yc - ys[j]) / (ys[j + 1] - ys[j])
        return i, j, s, t, xc, yc

    def height(self, x, y) -> np.ndarray:
        """Interpolated Z at (x, y), vectorized; clamped to the grid outside it."""
        x, y = np.broadcast_arrays(np.asarray(x, float), np.asarray(y, float))
        if self._spline is not None:
            xc = np.clip(x, self.xs[0], self.xs[-1])
            yc = np.clip(y, self.ys[0], self.ys[-1])
            return self._spline.ev(xc, yc)
        i, j, s, t, xc, yc = self._locate(x, y)
        if not self.regular:
            for _ in range(2):   # a point may sit in a neighbour of its mean-level cell
                s, t = self._invert_quads(i, j, s, t, x, y)
                di = np.where((s < -1e-9) & (i > 0), -1, 0) + np.where(
                    (s > 1 + 1e-9) & (i < self.xs.size - 2), 1, 0)
                dj = np.where((t < -1e-9) & (j > 0), -1, 0) + np.where(
                    (t > 1 + 1e-9) & (j < self.ys.size - 2), 1, 0)
                if not (di.any() or dj.any()):
                    break
                i, j = i + di, j + dj
                s, t = np.where(di != 0, 0.5, s), np.where(dj != 0, 0.5, t)
            s, t = np.clip(s, 0.0, 1.0), np.clip(t, 0.0, 1.0)
        Z = self.Z
        return ((1 - s) * (1 - t) * Z[i, j] + s * (1 - t) * Z[i + 1, j]
                + (1 - s) * t * Z[i, j + 1] + s * t * Z[i + 1, j + 1])

    def _invert_quads(self, i, j, s, t, x, y, iterations: int = 8):
        """Local coordinates of (x, y) in the bilinear quadrilateral of the real samples
        of cell (i, j), by Newton iteration started at the regular-grid guess (may fall
        outside [0, 1] when the point lies in a neighbouring quadrilateral)."""
        X, Y = self.X, self.Y
        x00, x10, x01, x11 = X[i, j], X[i + 1, j], X[i, j + 1], X[i + 1, j + 1]
        y00, y10, y01, y11 = Y[i, j], Y[i + 1, j], Y[i, j + 1], Y[i + 1, j + 1]
        for _ in range(iterations):
            px = (1 - s) * (1 - t) * x00 + s * (1 - t) * x10 + (1 - s) * t * x01 + s * t * x11
            py = (1 - s) * (1 - t) * y00 + s * (1 - t) * y10 + (1 - s) * t * y01 + s * t * y11
            a = (1 - t) * (x10 - x00) + t * (x11 - x01)
            b = (1 - s) * (x01 - x00) + s * (x11 - x10)
            c = (1 - t) * (y10 - y00) + t * (y11 - y01)
            d = (1 - s) * (y01 - y00) + s * (y11 - y10)
            det = a * d - b * c
            rx, ry = px - x, py - y
            s = np.clip(s - (d * rx - b * ry) / det, -0.5, 1.5)
            t = np.clip(t - (-c * rx + a * ry) / det, -0.5, 1.5)
        return s, t

    def to_mesh(self, nu: int | None = None, nv: int | None = None) -> np.ndarray:
        """Triangles ``(k, 3, 3)``: through the samples themselves by default, or over an
        even ``nu x nv`` resampling of the bounding box."""
        if nu is None and nv is None:
            return point_grid_triangles(np.stack([self.X, self.Y, self.Z], axis=-1))
        xmin, ymin, xmax, ymax = self.bounds
        gx, gy = np.meshgrid(np.linspace(xmin, xmax, (nu or self.xs.size - 1) + 1),
                             np.linspace(ymin, ymax, (nv or self.ys.size - 1) + 1), indexing="ij")
        return point_grid_triangles(np.stack([gx, gy, self.height(gx, gy)], axis=-1))
