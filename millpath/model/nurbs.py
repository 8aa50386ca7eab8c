"""NURBS curves in the XY plane as LinuxCNC's G5.2/G5.3 define them.

A curve of ``order`` k (degree k - 1) has control points ``points`` (n + 1, 3) as rows
(x, y, weight), program units. Its knot vector is LinuxCNC's clamped uniform one:
k zeros, then 1, 2, ..., n - k + 1, then k times n - k + 2; the parameter runs over
``[0, umax]`` with ``umax = n - k + 2``. The curve starts at the first control point and
ends at the last one.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class Nurbs:
    """A G5.2 NURBS: ``order`` k >= 2 and control points (x, y, w) with w > 0."""

    order: int
    points: tuple[tuple[float, float, float], ...]

    @property
    def umax(self) -> float:
        return float(len(self.points) - self.order + 1)

    def knots(self) -> np.ndarray:
        return knot_vector(len(self.points) - 1, self.order)

    def evaluate(self, u) -> np.ndarray:
        """Points (m, 2) at parameters ``u`` (m,) in [0, umax]."""
        return evaluate(self, np.atleast_1d(np.asarray(u, float)))

    def sample(self, chord_tol: float, max_points: int = 1 << 16) -> np.ndarray:
        """Points (m, 2) from the first to the last control point, uniform in the
        parameter, dense enough that each chord's mid-parameter point lies within
        ``chord_tol`` of the chord (doubling from 8 points per control point)."""
        m = 8 * len(self.points)
        while True:
            u = np.linspace(0.0, self.umax, 2 * m + 1)
            p = self.evaluate(u)
            a, mid, b = p[0:-1:2], p[1::2], p[2::2]
            d = b - a
            ln = np.hypot(d[:, 0], d[:, 1])
            cross = np.abs(d[:, 0] * (mid[:, 1] - a[:, 1]) - d[:, 1] * (mid[:, 0] - a[:, 0]))
            dev = np.where(ln > 1e-12, cross / np.maximum(ln, 1e-300),
                           np.hypot(mid[:, 0] - a[:, 0], mid[:, 1] - a[:, 1]))
            if float(dev.max(initial=0.0)) <= chord_tol or 2 * m + 1 >= max_points:
                out = p[::2] if float(dev.max(initial=0.0)) <= chord_tol else p
                out = out.copy()
                out[0] = self.points[0][:2]
                out[-1] = self.points[-1][:2]
                return out
            m *= 2

    def length(self) -> float:
        p = self.sample(1e-6 * max(1e-3, self.extent()))
        return float(np.hypot(*np.diff(p, axis=0).T).sum())

    def extent(self) -> float:
        c = np.asarray(self.points, float)[:, :2]
        return float(np.ptp(c, axis=0).max()) if len(c) else 0.0


def knot_vector(n: int, k: int) -> np.ndarray:
    """LinuxCNC's knot vector for n + 1 control points of order k (length n + k + 1)."""
    i = np.arange(n + k + 1)
    return np.where(i < k, 0, np.where(i <= n, i - k + 1, n - k + 2)).astype(float)


def basis(n: int, k: int, u: np.ndarray) -> np.ndarray:
    """B-spline basis values (m, n + 1) of order k at parameters ``u`` (m,), by the
    Cox-de Boor recursion on half-open spans (the last span closed at umax)."""
    t = knot_vector(n, k)
    umax = t[-1]
    u = np.clip(u, 0.0, umax)
    nb = n + k                          # order-1 functions: one per knot span
    N = ((t[None, :nb] <= u[:, None]) & (u[:, None] < t[None, 1:nb + 1])).astype(float)
    last = np.nonzero(t[:nb] < t[1:nb + 1])[0][-1]      # last non-empty span
    N[u >= umax, :] = 0.0
    N[u >= umax, last] = 1.0
    for q in range(2, k + 1):
        cnt = nb - q + 1
        left = t[q - 1:q - 1 + cnt] - t[:cnt]
        right = t[q:q + cnt] - t[1:1 + cnt]
        a = np.divide(u[:, None] - t[None, :cnt], left[None, :],
                      out=np.zeros((len(u), cnt)), where=left[None, :] != 0)
        b = np.divide(t[None, q:q + cnt] - u[:, None], right[None, :],
                      out=np.zeros((len(u), cnt)), where=right[None, :] != 0)
        N = a * N[:, :cnt] + b * N[:, 1:cnt + 1]
    return N


def evaluate(curve: Nurbs, u: np.ndarray) -> np.ndarray:
    """Rational curve points (m, 2) at parameters ``u``."""
    c = np.asarray(curve.points, float)
    N = basis(len(c) - 1, curve.order, u) * c[None, :, 2]
    den = N.sum(axis=1)
    return (N @ c[:, :2]) / den[:, None]

