"""Tensor-product Bezier patches of any degree.

A patch has a control net ``control`` of shape ``(m + 1, n + 1, 3)``: ``control[i, j]``
is the (x, y, z) control point of Bernstein index ``i`` in ``u`` and ``j`` in ``v``
(both parameters in [0, 1]). Coordinates are in the job's units (mm or inch).

A net of Z values over an XY box (:meth:`BezierPatch.from_heights`) places the control
points on a regular grid, so that x depends on ``u`` only and y on ``v`` only, both
linearly; :meth:`BezierPatch.height` then maps (x, y) to (u, v) directly. For a general
net it inverts the XY mapping by Newton iteration.
"""

from __future__ import annotations

from math import comb

import numpy as np

from millpath.errors import GeometryError


def bernstein(degree: int, t: np.ndarray) -> np.ndarray:
    """Bernstein basis values, shape ``t.shape + (degree + 1,)``."""
    t = np.asarray(t, float)
    out = np.empty(t.shape + (degree + 1,))
    s = 1.0 - t
    # powers by repeated multiplication (much faster than ** on arrays)
    tp = [np.ones_like(t)]
    sp = [np.ones_like(t)]
    for _ in range(degree):
        tp.append(tp[-1] * t)
        sp.append(sp[-1] * s)
    for i in range(degree + 1):
        out[..., i] = comb(degree, i) * tp[i] * sp[degree - i]
    return out


def _contract(bu: np.ndarray, net: np.ndarray, bv: np.ndarray) -> np.ndarray:
    """sum_ij bu[..., i] net[i, j, :] bv[..., j] -> (..., d), by two matrix products."""
    a, b, d = net.shape
    tmp = (bu.reshape(-1, a) @ net.reshape(a, b * d)).reshape(-1, b, d)
    out = np.einsum("kjd,kj->kd", tmp, bv.reshape(-1, b))
    return out.reshape(bu.shape[:-1] + (d,))


def _diff_net(net: np.ndarray, axis: int, order: int) -> np.ndarray:
    """Control net of the ``order``-th partial derivative along ``axis`` (0: u, 1: v)."""
    for _ in range(order):
        deg = net.shape[axis] - 1
        if deg == 0:
            shape = list(net.shape)
            shape[axis] = 1
            return np.zeros(shape)
        net = deg * np.diff(net, axis=axis)
    return net


class BezierPatch:
    """A Bezier patch ``S(u, v) = sum_ij B_i^m(u) B_j^n(v) P_ij`` (job units)."""

    def __init__(self, control: np.ndarray):
        c = np.array(control, dtype=float)
        if c.ndim != 3 or c.shape[2] != 3 or c.shape[0] < 2 or c.shape[1] < 2:
            raise GeometryError("a Bezier control net needs shape (m+1, n+1, 3) with m, n >= 1, "
                                f"got {c.shape}")
        if not np.all(np.isfinite(c)):
            raise GeometryError("a Bezier control net has a NaN or infinite coordinate")
        self.control = c
        self._regular = self._box_mapping()

    # --- construction ---------------------------------------------------------------
    @classmethod
    def from_heights(cls, z: np.ndarray, box: tuple[float, float, float, float]) -> "BezierPatch":
        """Patch over ``box = (xmin, ymin, xmax, ymax)`` from Z values ``z[i, j]``.

        ``i`` runs along X (u) and ``j`` along Y (v); control points are evenly spaced,
        so the patch's XY mapping is the identity on the box.
        """
        z = np.array(z, dtype=float)
        if z.ndim != 2 or z.shape[0] < 2 or z.shape[1] < 2:
            raise GeometryError(f"a Bezier height net needs at least 2 x 2 values, got {z.shape}")
        xmin, ymin, xmax, ymax = map(float, box)
        if not (xmin < xmax and ymin < ymax):
            raise GeometryError("a Bezier box needs xmin < xmax and ymin < ymax")
        xs = np.linspace(xmin, xmax, z.shape[0])
        ys = np.linspace(ymin, ymax, z.shape[1])
        X, Y = np.meshgrid(xs, ys, indexing="ij")
        return cls(np.stack([X, Y, z], axis=-1))

    def _box_mapping(self) -> tuple[float, float, float, float] | None:
        """(xmin, ymin, xmax, ymax) if x is linear in u alone and y linear in v alone."""
        c = self.control
        m, n = c.shape[0] - 1, c.shape[1] - 1
        x0, x1 = c[0, 0, 0], c[-1, 0, 0]
        y0, y1 = c[0, 0, 1], c[0, -1, 1]
        if x1 == x0 or y1 == y0:
            return None
        xs = x0 + (x1 - x0) * np.arange(m + 1) / m
        ys = y0 + (y1 - y0) * np.arange(n + 1) / n
        scale = max(abs(x1 - x0), abs(y1 - y0))
        tol = 1e-12 * max(scale, 1.0) * 100
        if (np.all(np.abs(c[:, :, 0] - xs[:, None]) <= tol)
                and np.all(np.abs(c[:, :, 1] - ys[None, :]) <= tol)):
            return (x0, y0, x1, y1)
        return None

    # --- queries --------------------------------------------------------------------
    @property
    def degree(self) -> tuple[int, int]:
        return self.control.shape[0] - 1, self.control.shape[1] - 1

    @property
    def bounds(self) -> tuple[float, float, float, float]:
        """XY bounding box of the control net (contains the patch): xmin, ymin, xmax, ymax."""
        c = self.control
        return (float(c[..., 0].min()), float(c[..., 1].min()),
                float(c[..., 0].max()), float(c[..., 1].max()))

    def evaluate(self, u, v, du: int = 0, dv: int = 0) -> np.ndarray:
        """Point (or partial derivative d^(du+dv)S / du^du dv^dv) at (u, v).

        ``u`` and ``v`` broadcast against each other; returns shape ``broadcast + (3,)``.
        """
        u, v = np.broadcast_arrays(np.asarray(u, float), np.asarray(v, float))
        net = _diff_net(_diff_net(self.control, 0, du), 1, dv)
        bu = bernstein(net.shape[0] - 1, u)
        bv = bernstein(net.shape[1] - 1, v)
        return _contract(bu, net, bv)

    def derivatives(self, u, v) -> tuple[np.ndarray, np.ndarray]:
        """First partial derivatives (dS/du, dS/dv) at (u, v), each ``broadcast + (3,)``."""
        return self.evaluate(u, v, 1, 0), self.evaluate(u, v, 0, 1)

    def normal(self, u, v) -> np.ndarray:
        """Unit normal (dS/du x dS/dv, flipped to point up when possible)."""
        su, sv = self.derivatives(u, v)
        nrm = np.cross(su, sv)
        nrm = np.where(nrm[..., 2:3] < 0, -nrm, nrm)
        length = np.linalg.norm(nrm, axis=-1, keepdims=True)
        return nrm / np.where(length == 0, 1.0, length)

    def uv_of(self, x, y, iterations: int = 30) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Parameters (u, v) whose XY image is (x, y), and a mask of points found.

        Exact for box-mapped patches; Newton iteration from the nearest sample of a
        31 x 31 parameter grid otherwise. Points outside the patch get clamped
        parameters and ``found = False``.
        """
        x, y = np.broadcast_arrays(np.asarray(x, float), np.asarray(y, float))
        if self._regular is not None:
            x0, y0, x1, y1 = self._regular
            u = (x - x0) / (x1 - x0)
            v = (y - y0) / (y1 - y0)
            eps = 1e-9
            found = (u >= -eps) & (u <= 1 + eps) & (v >= -eps) & (v <= 1 + eps)
            return np.clip(u, 0, 1), np.clip(v, 0, 1), found
        shape = x.shape
        xf, yf = x.ravel(), y.ravel()
        s = np.linspace(0.0, 1.0, 31)
        U, V = np.meshgrid(s, s, indexing="ij")
        P = self.evaluate(U.ravel(), V.ravel())[:, :2]
        u = np.empty(xf.size)
        v = np.empty(xf.size)
        for k in range(0, xf.size, 4096):   # chunked nearest-sample search
            q = np.stack([xf[k:k + 4096], yf[k:k + 4096]], axis=1)
            d2 = ((q[:, None, :] - P[None, :, :]) ** 2).sum(-1)
            idx = d2.argmin(axis=1)
            u[k:k + 4096] = U.ravel()[idx]
            v[k:k + 4096] = V.ravel()[idx]
        for _ in range(iterations):
            p = self.evaluate(u, v)
            su, sv = self.derivatives(u, v)
            rx, ry = p[:, 0] - xf, p[:, 1] - yf
            a, b, c, d = su[:, 0], sv[:, 0], su[:, 1], sv[:, 1]
            det = a * d - b * c
            det = np.where(np.abs(det) < 1e-300, 1e-300, det)
            du = (d * rx - b * ry) / det
            dv = (-c * rx + a * ry) / det
            u = np.clip(u - du, 0.0, 1.0)
            v = np.clip(v - dv, 0.0, 1.0)
            if np.all(np.abs(du) + np.abs(dv) < 1e-13):
                break
        p = self.evaluate(u, v)
        size = max(np.ptp(P[:, 0]), np.ptp(P[:, 1]), 1e-300)
        found = np.hypot(p[:, 0] - xf, p[:, 1] - yf) <= 1e-9 * max(size, 1.0)
        return u.reshape(shape), v.reshape(shape), found.reshape(shape)

    def height(self, x, y, outside: str = "clamp") -> np.ndarray:
        """Z of the patch above (x, y) (vectorized, job units).

        Points outside the patch's XY image get the height at the nearest parameter
        (``outside="clamp"``) or NaN (``outside="nan"``).
        """
        u, v, found = self.uv_of(x, y)
        m, n = self.degree
        z = _contract(bernstein(m, u), self.control[:, :, 2:], bernstein(n, v))[..., 0]
        if outside == "nan":
            z = np.where(found, z, np.nan)
        return z

    def to_mesh(self, nu: int = 32, nv: int = 32) -> np.ndarray:
        """Triangles ``(2 * nu * nv, 3, 3)`` over an even (nu x nv) parameter grid,
        counter-clockwise seen from +Z for box-mapped patches."""
        return point_grid_triangles(self.evaluate(*np.meshgrid(np.linspace(0, 1, nu + 1),
                                                          np.linspace(0, 1, nv + 1),
                                                          indexing="ij")))


def point_grid_triangles(P: np.ndarray) -> np.ndarray:
    """Two triangles per cell of a ``(a, b, 3)`` point grid: ``(2 (a-1) (b-1), 3, 3)``."""
    p00, p10 = P[:-1, :-1], P[1:, :-1]
    p01, p11 = P[:-1, 1:], P[1:, 1:]
    t1 = np.stack([p00, p10, p11], axis=-2).reshape(-1, 3, 3)
    t2 = np.stack([p00, p11, p01], axis=-2).reshape(-1, 3, 3)
    return np.concatenate([t1, t2], axis=0)
