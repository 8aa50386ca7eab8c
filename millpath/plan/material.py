"""An upper bound on the material a plan has left, for safe links and entries.

Job units (mm or inch); Z is the tool tip. The bound lives on a square lattice of
nodes ``g`` apart (``r0 = g / sqrt(2)``: every point of the plane is within ``r0`` of a
node). A node stands for the disc of radius ``r0`` around it: its value is a height no
material in that disc rises above. It starts at the stock top and is lowered only by
path points the tool has cut through whose cutter covers the node's whole disc (node
within ``R - r0`` of the point), to the cutter's surface over that disc (tip Z + the
profile height at ``distance + r0``) plus a lift for the fit's deviation. So the bound
never claims air that sampling has not proven: slivers between passes, the band along
the walls and cells no layer has visited stay at the stock top.

A tool whose tip is at ``z`` with its axis at ``p`` clears the bound when, at every node
within ``R + r0`` of ``p``, ``z + profile(max(0, d - r0)) >= bound``. Tool positions the
plan has cut through exactly (same XY) are clear above their lowest tip Z too: the cutter
there sweeps the very disc it swept before. With ``holder``, the shank and holder
cylinders (flat, lifted by their bottom height) must clear the bound too.

It starts from the stock top, or from a stock as it is (:meth:`MaterialBound.clip`:
nothing beside the stock's footprint, nothing above an in-process stock's heights).
"""

from __future__ import annotations

import math

import numpy as np

from millpath.geometry.cutter import Cutter
from millpath.model import Tool


class MaterialBound:
    """Upper bound of the material over ``bounds`` = (xmin, ymin, xmax, ymax), widened
    by the tool radius; heights above ``top`` are never claimed below it."""

    def __init__(self, bounds, tool: Tool, top: float, spacing: float, lift: float,
                 decimals: int = 6, holder: bool = False):
        self.tool = tool
        self.cutter = Cutter.of(tool)
        self.top = float(top)
        self.g = float(spacing)
        self.r0 = self.g / math.sqrt(2.0)
        self.lift = float(lift)
        self.decimals = decimals
        self.holder = tool.holder_cylinders() if holder else []
        R = max([tool.radius] + [r for r, _, _ in self.holder])
        self.x0 = bounds[0] - R - self.g
        self.y0 = bounds[1] - R - self.g
        nx = int(math.ceil((bounds[2] - bounds[0] + 2 * R + 2 * self.g) / self.g)) + 1
        ny = int(math.ceil((bounds[3] - bounds[1] + 2 * R + 2 * self.g) / self.g)) + 1
        self.h = np.full((nx, ny), self.top)
        self.visits: dict[tuple[float, float], float] = {}

    def clip(self, stock=None, heights=None, step: float | None = None) -> None:
        """Lower the bound to the stock as it is: -inf at nodes whose disc lies wholly
        beside ``stock``'s footprint; at most the highest of ``heights(x, y)`` (an
        in-process stock) sampled ``step`` apart over each node's disc."""
        nx, ny = self.h.shape
        X, Y = np.meshgrid(self.x0 + np.arange(nx) * self.g, self.y0 + np.arange(ny) * self.g,
                           indexing="ij")
        if stock is not None:
            px, py = stock.nearest_xy(X, Y)
            self.h[np.hypot(X - px, Y - py) > self.r0] = -np.inf
        if heights is not None:
            s = min(step or self.r0, self.r0)
            m = int(math.ceil(self.r0 / s))
            top = np.full(self.h.shape, -np.inf)
            for a in range(-m, m + 1):
                for b in range(-m, m + 1):
                    ox, oy = a * s, b * s
                    if math.hypot(ox, oy) > self.r0 + s:
                        continue
                    top = np.maximum(top, np.asarray(heights(X + ox, Y + oy), float))
            np.minimum(self.h, top + self.lift, out=self.h)

    def _window(self, xs: np.ndarray, ys: np.ndarray, reach: float):
        """Node indices (i, j) of a square window of half-width ``reach`` around each
        point, shape (n, W), and whether each lies on the lattice."""
        m = int(math.ceil(reach / self.g)) + 1
        off = np.arange(-m, m + 1)
        di, dj = (a.ravel() for a in np.meshgrid(off, off, indexing="ij"))
        i0 = np.floor((xs - self.x0) / self.g).astype(int)
        j0 = np.floor((ys - self.y0) / self.g).astype(int)
        i = i0[:, None] + di[None, :]
        j = j0[:, None] + dj[None, :]
        ok = (i >= 0) & (i < self.h.shape[0]) & (j >= 0) & (j < self.h.shape[1])
        return np.clip(i, 0, self.h.shape[0] - 1), np.clip(j, 0, self.h.shape[1] - 1), ok

    def cut(self, pts: np.ndarray) -> None:
        """The tool has cut through the points ``pts`` (n, 3) (tip positions)."""
        pts = np.asarray(pts, float).reshape(-1, 3)
        for p in pts:
            key = (round(float(p[0]), self.decimals), round(float(p[1]), self.decimals))
            self.visits[key] = min(self.visits.get(key, math.inf), float(p[2]))
        R = self.tool.radius
        if R <= self.r0:
            return
        for a in range(0, len(pts), 2048):
            c = pts[a:a + 2048]
            i, j, ok = self._window(c[:, 0], c[:, 1], R)
            d = np.hypot(self.x0 + i * self.g - c[:, :1], self.y0 + j * self.g - c[:, 1:2])
            ok &= d <= R - self.r0
            v = c[:, 2:3] + self.cutter.height(d + self.r0) + self.lift
            np.minimum.at(self.h, (i[ok], j[ok]), v[ok])

    def need_segment(self, a, b, cutter: bool = True) -> float:
        """Lowest tip Z at which the tool moves from XY ``a`` to XY ``b`` clear of the
        bound (the stock top where the bound is the stock top); without ``cutter``, only
        its shank and holder (with ``holder``)."""
        a = np.asarray(a, float)[:2]
        b = np.asarray(b, float)[:2]
        R = max([self.tool.radius] + [r for r, _, _ in self.holder])
        length = float(np.hypot(*(b - a)))
        n = max(1, int(math.ceil(length / self.g)))
        t = np.linspace(0.0, 1.0, n + 1)
        s = a[None, :] + (b - a)[None, :] * t[:, None]
        i, j, ok = self._window(s[:, 0], s[:, 1], R + self.r0 + self.g)
        i, j = i[ok], j[ok]
        flat = np.unique(i * self.h.shape[1] + j)
        i, j = flat // self.h.shape[1], flat % self.h.shape[1]
        qx, qy = self.x0 + i * self.g, self.y0 + j * self.g
        ab = b - a
        L2 = float(ab @ ab)
        u = np.zeros_like(qx) if L2 == 0 else np.clip(((qx - a[0]) * ab[0] + (qy - a[1]) * ab[1])
                                                     / L2, 0.0, 1.0)
        d = np.hypot(qx - a[0] - u * ab[0], qy - a[1] - u * ab[1])
        near = d <= self.tool.radius + self.r0
        need = self.h[i[near], j[near]] - self.cutter.height(np.maximum(d[near] - self.r0, 0.0))
        out = float(need.max()) if near.any() and cutter else -math.inf
        for r, zb, _ in self.holder:
            near = d <= r + self.r0
            if near.any():
                out = max(out, float(self.h[i[near], j[near]].max()) - zb)
        return out

    def need_at(self, p) -> float:
        """Lowest tip Z of the tool standing at XY ``p`` clear of the material: the
        bound's, or lower where the plan has cut through that very XY."""
        x, y = float(p[0]), float(p[1])
        key = (round(x, self.decimals), round(y, self.decimals))
        return min(self.need_segment((x, y), (x, y)), self.visits.get(key, math.inf) + self.lift)
