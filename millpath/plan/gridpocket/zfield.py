"""Tool-tip Z over the pocket bottom, and adaptive sampling of Z along moves.

``z_mode = "tool"`` drops the real cutter onto the bottom surface: the tip Z at (x, y)
is the lowest at which the cutter profile (flat, ball or bull) is nowhere below the
surface under its footprint. The surface is triangulated finely enough that the
triangles stay within a quarter of the tolerance of it, lifted by their measured
largest error (so they are never below the true surface at the probe points), and the
exact drop-cutter of :mod:`millpath.plan.surface.dropcutter` is run on those triangles.
``z_mode = "surface"`` is the thesis's behaviour: the tip sits on the surface height
under the tool centre (a flat or bull cutter then gouges a sloped bottom).

All lengths are in the job's units.
"""

from __future__ import annotations

import math
from typing import Callable

import numpy as np

from millpath.errors import PlanningError
from millpath.model import Tool

HeightFn = Callable[[np.ndarray, np.ndarray], np.ndarray]


class ZField:
    """Memoized tip Z of ``tool`` above ``surface`` (anything with a vectorized
    ``height(x, y)``) for tool centres inside ``box = (xmin, ymin, xmax, ymax)``."""

    def __init__(self, surface, tool: Tool, mode: str, box, tolerance: float,
                 file=None):
        self.surface = surface
        self.tool = tool
        self.mode = mode
        self._cache: dict[tuple[float, float], float] = {}
        self.mesh_error = 0.0
        if mode == "tool":
            from millpath.part.surface.mesh import Mesh
            from millpath.plan.surface.dropcutter import build_index, surface_cutter
            if tool.type == "drill":
                raise PlanningError(f"tool {tool.number}: a drill cannot mill a pocket "
                                    "(use a flat, ball or bull end mill)", file)
            self._cutter = surface_cutter(tool)
            xmin, ymin, xmax, ymax = box
            pad = 1.05 * tool.radius
            h = min(tool.radius / 4.0, max(xmax - xmin, ymax - ymin) / 64.0)
            for _ in range(4):
                nu = max(2, int(math.ceil((xmax - xmin) / h)))
                nv = max(2, int(math.ceil((ymax - ymin) / h)))
                # nodes on the box edges; one padding column/row outside for the
                # footprint of a tool touching the walls
                xs = np.concatenate([[xmin - pad], np.linspace(xmin, xmax, nu + 1), [xmax + pad]])
                ys = np.concatenate([[ymin - pad], np.linspace(ymin, ymax, nv + 1), [ymax + pad]])
                tri = self._mesh(xs, ys)
                inner = self._mesh(xs[1:-1], ys[1:-1])
                probe = np.concatenate([inner.mean(axis=1), (inner[:, 0] + inner[:, 1]) / 2.0,
                                        (inner[:, 1] + inner[:, 2]) / 2.0])
                err = float(np.abs(surface.height(probe[:, 0], probe[:, 1])
                                   - probe[:, 2]).max())
                if err <= tolerance / 4.0 or nu * nv > 250_000:
                    break
                h /= 2.0
            # lift the triangles by their largest error so the tool never dips below the
            # true surface between mesh nodes (costs at most 2 err of left-over)
            self.mesh_error = err
            tri = tri.copy()
            tri[:, :, 2] += err
            self._index = build_index(Mesh(tri, "pocket bottom"))

    def _mesh(self, xs: np.ndarray, ys: np.ndarray) -> np.ndarray:
        gx, gy = np.meshgrid(xs, ys, indexing="ij")
        P = np.stack([gx, gy, self.surface.height(gx, gy)], axis=-1)
        p00, p10, p01, p11 = P[:-1, :-1], P[1:, :-1], P[:-1, 1:], P[1:, 1:]
        return np.concatenate([np.stack([p00, p10, p11], -2).reshape(-1, 3, 3),
                               np.stack([p00, p11, p01], -2).reshape(-1, 3, 3)])

    def _compute(self, x: np.ndarray, y: np.ndarray) -> np.ndarray:
        if self.mode == "surface":
            return np.asarray(self.surface.height(x, y), float)
        from millpath.plan.surface.dropcutter import drop_z
        return drop_z(self._index, self._cutter, x, y)

    def z(self, x, y) -> np.ndarray:
        """Tip Z at points (x, y) (1-D arrays of equal length)."""
        x = np.atleast_1d(np.asarray(x, float))
        y = np.atleast_1d(np.asarray(y, float))
        keys = [(round(a, 9), round(b, 9)) for a, b in zip(x.tolist(), y.tolist())]
        missing = [k for k in dict.fromkeys(keys) if k not in self._cache]
        if missing:
            m = np.array(missing)
            vals = self._compute(m[:, 0], m[:, 1])
            self._cache.update(zip(missing, vals.tolist()))
        return np.array([self._cache[k] for k in keys])


def sample_chain(xy: np.ndarray, zfun: Callable[[np.ndarray, np.ndarray], np.ndarray],
                 spacing: float | None, gouge_tol: float, dense: int = 16,
                 ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """3D points along the XY polyline ``xy`` (``(n, 2)``) with Z from ``zfun``.

    With a ``spacing``, every segment is checked at points about ``spacing`` apart and
    the check point most below the straight line is inserted, repeatedly, until the
    line is nowhere more than ``gouge_tol`` below the required Z; then every piece is
    checked again at ``dense`` times that density (the required Z can peak between
    samples where the tool passes over a crest of the bottom), inserting the worst
    point of each piece still more than ``gouge_tol`` below, a few rounds. Without a
    spacing the polyline's own points are used (thesis behaviour).

    Returns ``(points (m, 3), their XY distance along the polyline (m,), check points
    (k, 3), their distance along (k,))``; the check points are every sample with its
    required Z, for fitters that must not dip below them.
    """
    xy = np.asarray(xy, float)
    z = zfun(xy[:, 0], xy[:, 1])
    seg = np.diff(xy, axis=0)
    length = np.hypot(seg[:, 0], seg[:, 1])
    cum = np.concatenate([[0.0], np.cumsum(length)])
    base = np.column_stack([xy, z])
    if spacing is None or len(xy) < 2:
        return base, cum, base.copy(), cum.copy()
    counts = np.maximum(0, np.ceil(length / spacing).astype(int) - 1)
    if counts.sum() == 0:
        if dense > 1:
            out_a, out_La, extra, extra_L = _refine_dense(base, cum, zfun, spacing / dense,
                                                          gouge_tol)
            checks = np.concatenate([base, extra])
            check_L = np.concatenate([cum, extra_L])
            order = np.argsort(check_L, kind="stable")
            return out_a, out_La, checks[order], check_L[order]
        return base, cum, base.copy(), cum.copy()
    t_all = np.concatenate([np.arange(1, c + 1) / (c + 1) for c in counts])
    s_all = np.repeat(np.arange(len(seg)), counts)
    pts = xy[s_all] + seg[s_all] * t_all[:, None]
    zs_all = zfun(pts[:, 0], pts[:, 1])
    L_all = cum[s_all] + length[s_all] * t_all
    out = [base[0]]
    out_L = [0.0]
    starts = np.concatenate([[0], np.cumsum(counts)])
    for k in range(len(seg)):
        a, b = starts[k], starts[k + 1]
        if b > a:
            t = t_all[a:b]
            zs = zs_all[a:b]
            kt = [0.0, 1.0]
            kz = [z[k], z[k + 1]]
            for _ in range(b - a):
                viol = zs - np.interp(t, kt, kz)
                w = int(np.argmax(viol))
                if viol[w] <= gouge_tol:
                    break
                pos = int(np.searchsorted(kt, t[w]))
                kt.insert(pos, float(t[w]))
                kz.insert(pos, float(zs[w]))
            for tk, zk in zip(kt[1:-1], kz[1:-1]):
                p = xy[k] + seg[k] * tk
                out.append(np.array([p[0], p[1], zk]))
                out_L.append(cum[k] + length[k] * tk)
        out.append(base[k + 1])
        out_L.append(cum[k + 1])
    out_a, out_La = np.array(out), np.array(out_L)
    extra = np.zeros((0, 3))
    extra_L = np.zeros(0)
    if dense > 1:
        out_a, out_La, extra, extra_L = _refine_dense(out_a, out_La, zfun, spacing / dense,
                                                      gouge_tol)
    checks = np.concatenate([base, np.column_stack([pts, zs_all]), extra])
    check_L = np.concatenate([cum, L_all, extra_L])
    order = np.argsort(check_L, kind="stable")
    return out_a, out_La, checks[order], check_L[order]


def _refine_dense(P: np.ndarray, L: np.ndarray, zfun, step: float, gouge_tol: float,
                  rounds: int = 6):
    """Insert into the 3D polyline ``P`` (XY distance along it ``L``) the worst point of
    each piece whose straight line runs more than ``gouge_tol`` below ``zfun`` at points
    about ``step`` apart; repeated up to ``rounds`` times. Returns the polyline, its
    distances and the inserted points with theirs."""
    added, added_L = [], []
    for _ in range(rounds):
        d = np.diff(L)
        n = np.maximum(0, np.ceil(d / step).astype(np.int64) - 1)
        if n.sum() == 0:
            break
        piece = np.repeat(np.arange(len(d)), n)
        first = np.concatenate([[0], np.cumsum(n)[:-1]])
        t = (np.arange(len(piece)) - first[piece] + 1) / (n[piece] + 1)
        q = P[piece] + (P[piece + 1] - P[piece]) * t[:, None]
        viol = np.asarray(zfun(q[:, 0], q[:, 1]), float) - q[:, 2]
        has = n > 0
        worst = np.full(len(d), -np.inf)
        worst[has] = np.maximum.reduceat(viol, first[has])
        bad = np.flatnonzero(worst > gouge_tol)
        if not len(bad):
            break
        new_pts, new_L = [], []
        for k in bad:
            a = first[k]
            w = a + int(np.argmax(viol[a:a + n[k]]))
            new_pts.append([q[w, 0], q[w, 1], q[w, 2] + viol[w]])
            new_L.append(L[k] + d[k] * t[w])
        at = bad + 1
        P = np.insert(P, at, np.array(new_pts), axis=0)
        L = np.insert(L, at, np.array(new_L))
        added += new_pts
        added_L += new_L
    return P, L, np.array(added).reshape(-1, 3), np.array(added_L)
