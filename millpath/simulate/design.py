"""Designs for verification: the finished part's top surface as ``height(x, y) -> z``.

Any object with that method will do (see :class:`millpath.plan.base.Design`): arrays in,
array of the same shape out, job units, ``-inf`` where the part has no material. This
module supplies a triangle mesh (STL), a sampled height field, a plane and a set of
rectangular steps.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
from numba import njit

from millpath.errors import MillpathError
from millpath.threads import over_range


class PlaneDesign:
    """A flat part top at ``z`` everywhere."""

    def __init__(self, z: float):
        self.z = float(z)

    def height(self, x, y):
        return np.full(np.broadcast(np.asarray(x), np.asarray(y)).shape, self.z)


class BoxDesign:
    """A flat top at ``base`` with rectangular steps ``(xmin, ymin, xmax, ymax, z)``
    (pockets when ``z`` is below ``base``, bosses above, ``-inf`` for through openings);
    later boxes win where they overlap. Box edges belong to the box."""

    def __init__(self, base: float, boxes: list[tuple[float, float, float, float, float]]):
        self.base = float(base)
        self.boxes = [tuple(map(float, b)) for b in boxes]

    def height(self, x, y):
        x = np.asarray(x, float)
        y = np.asarray(y, float)
        out = np.full(np.broadcast(x, y).shape, self.base)
        for x0, y0, x1, y1, z in self.boxes:
            out[(x >= x0) & (x <= x1) & (y >= y0) & (y <= y1)] = z
        return out


class HeightFieldDesign:
    """Heights ``z[j, i]`` sampled at ``x[i]``, ``y[j]`` (increasing), interpolated
    bilinearly; nearest sample where a neighbour is ``-inf``; ``outside`` beyond the
    samples (default ``-inf``: no part there)."""

    def __init__(self, x, y, z, outside: float = -np.inf):
        self.x = np.asarray(x, float)
        self.y = np.asarray(y, float)
        self.z = np.asarray(z, float)
        if self.z.shape != (len(self.y), len(self.x)):
            raise ValueError(f"height field z must be (len(y), len(x)) = "
                             f"{(len(self.y), len(self.x))}, not {self.z.shape}")
        if len(self.x) < 2 or len(self.y) < 2:
            raise ValueError("height field needs at least 2 samples in X and Y")
        self.outside = float(outside)

    def height(self, x, y):
        x = np.asarray(x, float)
        y = np.asarray(y, float)
        shape = np.broadcast(x, y).shape
        xb = np.broadcast_to(x, shape).ravel()
        yb = np.broadcast_to(y, shape).ravel()
        xs, ys, z = self.x, self.y, self.z
        i = np.clip(np.searchsorted(xs, xb) - 1, 0, len(xs) - 2)
        j = np.clip(np.searchsorted(ys, yb) - 1, 0, len(ys) - 2)
        tx = np.clip((xb - xs[i]) / (xs[i + 1] - xs[i]), 0.0, 1.0)
        ty = np.clip((yb - ys[j]) / (ys[j + 1] - ys[j]), 0.0, 1.0)
        z00, z10, z01, z11 = z[j, i], z[j, i + 1], z[j + 1, i], z[j + 1, i + 1]
        with np.errstate(invalid="ignore"):
            out = ((1 - tx) * (1 - ty) * z00 + tx * (1 - ty) * z10
                   + (1 - tx) * ty * z01 + tx * ty * z11)
        bad = ~np.isfinite(out)
        if bad.any():
            ii = np.where(tx[bad] < 0.5, i[bad], i[bad] + 1)
            jj = np.where(ty[bad] < 0.5, j[bad], j[bad] + 1)
            out[bad] = z[jj, ii]
        eps = 1e-9 * max(1.0, float(np.abs(xs).max()), float(np.abs(ys).max()))
        outside = ((xb < xs[0] - eps) | (xb > xs[-1] + eps)
                   | (yb < ys[0] - eps) | (yb > ys[-1] + eps))
        out[outside] = self.outside
        return out.reshape(shape)


@njit(cache=True, nogil=True)
def _mesh_heights(lo, hi, px, py, tri, start, items, bx0, by0, bs, nbx, nby, out):
    n = px.shape[0]
    for q in range(lo, hi):
        x = px[q]
        y = py[q]
        best = -np.inf
        i = int(math.floor((x - bx0) / bs))
        j = int(math.floor((y - by0) / bs))
        if 0 <= i < nbx and 0 <= j < nby:
            b = j * nbx + i
            for p in range(start[b], start[b + 1]):
                t = items[p]
                ax = tri[t, 0, 0]
                ay = tri[t, 0, 1]
                bxx = tri[t, 1, 0] - ax
                byy = tri[t, 1, 1] - ay
                cx = tri[t, 2, 0] - ax
                cy = tri[t, 2, 1] - ay
                det = bxx * cy - byy * cx
                if det == 0.0:
                    continue
                rx = x - ax
                ry = y - ay
                u = (rx * cy - ry * cx) / det
                v = (bxx * ry - byy * rx) / det
                tol = 1e-9
                if u < -tol or v < -tol or u + v > 1.0 + tol:
                    continue
                z = (tri[t, 0, 2] + u * (tri[t, 1, 2] - tri[t, 0, 2])
                     + v * (tri[t, 2, 2] - tri[t, 0, 2]))
                if z > best:
                    best = z
        out[q] = best


class MeshDesign:
    """The top surface of a triangle mesh (``(n, 3, 3)`` vertices, job units): at each
    (x, y) the highest triangle above it; ``-inf`` where no triangle covers the point.
    Vertical triangles are ignored by ``height`` (they have no top surface) but kept in
    ``mesh()``, the reference of the exact gouge / material-left check."""

    def __init__(self, triangles):
        tri = np.ascontiguousarray(np.asarray(triangles, float).reshape(-1, 3, 3))
        self.all_triangles = tri
        e1 = tri[:, 1, :2] - tri[:, 0, :2]
        e2 = tri[:, 2, :2] - tri[:, 0, :2]
        area = np.abs(e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0])
        keep = area > 1e-14 * max(1.0, float(np.abs(tri).max(initial=1.0))) ** 2
        self.triangles = np.ascontiguousarray(tri[keep])
        if len(self.triangles) == 0:
            raise ValueError("mesh has no triangle with a top surface")
        lo = self.triangles[:, :, :2].min(axis=1)
        hi = self.triangles[:, :, :2].max(axis=1)
        gx0, gy0 = lo.min(axis=0)
        gx1, gy1 = hi.max(axis=0)
        span = max(gx1 - gx0, gy1 - gy0, 1e-9)
        n = len(self.triangles)
        bs = max(span / 1024.0, math.sqrt((gx1 - gx0 + 1e-9) * (gy1 - gy0 + 1e-9) / n) * 1.5)
        nbx = max(1, int(math.ceil((gx1 - gx0) / bs)) + 1)
        nby = max(1, int(math.ceil((gy1 - gy0) / bs)) + 1)
        i0 = np.floor((lo[:, 0] - gx0) / bs).astype(np.int64)
        i1 = np.minimum(np.floor((hi[:, 0] - gx0) / bs).astype(np.int64), nbx - 1)
        j0 = np.floor((lo[:, 1] - gy0) / bs).astype(np.int64)
        j1 = np.minimum(np.floor((hi[:, 1] - gy0) / bs).astype(np.int64), nby - 1)
        cnt = (i1 - i0 + 1) * (j1 - j0 + 1)
        owner = np.repeat(np.arange(n), cnt)
        k = np.arange(int(cnt.sum())) - np.repeat(np.cumsum(cnt) - cnt, cnt)
        w = np.repeat(i1 - i0 + 1, cnt)
        bi = np.repeat(i0, cnt) + k % w
        bj = np.repeat(j0, cnt) + k // w
        bucket = bj * nbx + bi
        order = np.argsort(bucket, kind="stable")
        self._items = np.ascontiguousarray(owner[order])
        self._start = np.searchsorted(bucket[order], np.arange(nbx * nby + 1)).astype(np.int64)
        self._grid = (float(gx0), float(gy0), float(bs), nbx, nby)

    @classmethod
    def from_stl(cls, path: str | Path) -> "MeshDesign":
        """Read an STL file (ASCII or binary) in job units."""
        from stl import mesh as stl_mesh
        p = Path(path)
        if not p.is_file():
            raise MillpathError("design file not found", p)
        try:
            m = stl_mesh.Mesh.from_file(str(p))
        except Exception as e:                       # numpy-stl raises several kinds
            raise MillpathError(f"cannot read STL: {e}", p) from None
        try:
            return cls(np.asarray(m.vectors, float))
        except ValueError as e:
            raise MillpathError(str(e), p) from None

    def mesh(self) -> np.ndarray:
        """All triangles (n, 3, 3), vertical walls included (the exact check's
        reference)."""
        return self.all_triangles

    def bounds(self) -> tuple[np.ndarray, np.ndarray]:
        t = self.triangles.reshape(-1, 3)
        return t.min(axis=0), t.max(axis=0)

    def height(self, x, y):
        x = np.asarray(x, float)
        y = np.asarray(y, float)
        shape = np.broadcast(x, y).shape
        px = np.ascontiguousarray(np.broadcast_to(x, shape).ravel())
        py = np.ascontiguousarray(np.broadcast_to(y, shape).ravel())
        out = np.empty(px.shape[0])
        gx0, gy0, bs, nbx, nby = self._grid
        over_range(_mesh_heights, px.shape[0], px, py, self.triangles, self._start, self._items, gx0, gy0, bs,
                      nbx, nby, out)
        return out.reshape(shape)
