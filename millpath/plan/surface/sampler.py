"""Cutter-location sampling in a rotated pass frame, with holder clearance.

The pass frame has ``u`` along the passes and ``w`` across them; the passes run at
``angle`` degrees from +X (counter-clockwise seen from +Z)::

    x = u cos(angle) - w sin(angle),   y = u sin(angle) + w cos(angle)

``z_cut`` is the drop-cutter tip Z of the cutter alone; ``z_safe`` also lifts the tool
so that the shank and every holder cylinder (flat profiles whose bottoms sit
``z_bottom`` above the tip, from :meth:`Tool.holder_cylinders`) clear the mesh by
``holder_clearance`` (material a roughing allowance left stands above the mesh).
Job units throughout.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from millpath.geometry.cutter import Cutter
from millpath.plan.surface.dropcutter import MeshIndex, build_index, drop


@dataclass
class Sampler:
    index: MeshIndex
    cutter: Cutter
    angle: float = 0.0                                   # degrees
    holder: tuple[tuple[float, float, float], ...] = ()  # (radius, z_bottom, z_top)
    z_floor: float = -np.inf
    holder_index: MeshIndex | None = None
    holder_clearance: float = 0.0                        # kept between holder and mesh

    def __post_init__(self) -> None:
        a = math.radians(self.angle)
        self._c, self._s = math.cos(a), math.sin(a)
        # a cylinder no wider than the cutter, whose bottom is above the cutter surface
        # at its radius, cannot touch anything the cutter does not
        c = self.cutter
        self.holder = tuple(h for h in self.holder
                            if h[0] > c.radius or h[1] < c.height(h[0]))
        if self.holder and self.holder_index is None:
            rmax = max(h[0] for h in self.holder)
            self.holder_index = build_index(self.index.mesh, cell=max(rmax / 3.0,
                                                                      self.index.cell))
        self._near_top = [self._top_within(h[0]) for h in self.holder]

    def _top_within(self, radius: float) -> np.ndarray:
        """Per cell of the holder index, an upper bound of the mesh's Z within ``radius``
        of any point of the cell (cells' highest triangle tops, dilated by a disc)."""
        ix = self.holder_index
        n = ix.nx * ix.ny
        has = ix.starts[1:] > ix.starts[:-1]
        top = np.full(n, -np.inf)
        top[has] = ix.ztop[ix.items[ix.starts[:-1][has]]]        # lists: highest first
        top = top.reshape(ix.ny, ix.nx)
        # a point of the cell and a triangle point within radius: their cells' centres
        # are at most radius + one cell diagonal apart
        k = int(math.ceil(radius / ix.cell + 1.5))
        j, i = np.mgrid[-k:k + 1, -k:k + 1]
        disc = np.hypot(i, j) <= radius / ix.cell + math.sqrt(2.0)
        from scipy.ndimage import maximum_filter
        return maximum_filter(top, footprint=disc, mode="nearest")

    def _cell_of(self, xy: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        ix = self.holder_index
        i = np.clip(np.floor((xy[:, 0] - ix.x0) / ix.cell), 0, ix.nx - 1).astype(np.int64)
        j = np.clip(np.floor((xy[:, 1] - ix.y0) / ix.cell), 0, ix.ny - 1).astype(np.int64)
        return j, i

    def xy(self, u, w) -> np.ndarray:
        u = np.asarray(u, float)
        w = np.asarray(w, float)
        return np.stack([u * self._c - w * self._s, u * self._s + w * self._c], axis=-1)

    def uw(self, x, y) -> np.ndarray:
        x = np.asarray(x, float)
        y = np.asarray(y, float)
        return np.stack([x * self._c + y * self._s, -x * self._s + y * self._c], axis=-1)

    def z_cut(self, u, w) -> np.ndarray:
        u, w = np.broadcast_arrays(np.asarray(u, float), np.asarray(w, float))
        xy = self.xy(u, w).reshape(-1, 2)
        return drop(self.index, self.cutter, xy, self.z_floor).z.reshape(u.shape)

    def cut(self, u, w) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Tip Z of the cutter alone and the contact point's (u, w), for 1-D arrays."""
        u = np.asarray(u, float)
        w = np.asarray(w, float)
        r = drop(self.index, self.cutter, self.xy(u, w), self.z_floor)
        cuw = self.uw(r.cc[:, 0], r.cc[:, 1])
        return r.z, cuw[:, 0], cuw[:, 1]

    def touches(self, u, w) -> np.ndarray:
        """Whether the cutter touches the mesh at all at ``(u, w)`` (1-D arrays): the tip
        lies within the cutter radius of the part's silhouette. Elsewhere the tool is
        beside the part and ``z_cut`` is only ``z_floor``."""
        r = drop(self.index, self.cutter, self.xy(u, w))
        return np.isfinite(r.z)

    def holder_lift(self, u, w, below=None) -> np.ndarray:
        """Lowest tip Z at which no holder cylinder touches the mesh (-inf if none).
        With ``below`` (tip Z per point), points where a cylinder cannot come within the
        clearance of the mesh with the tip at ``below`` (the mesh near it is lower than
        its bottom, :meth:`_top_within`) are not queried for it: -inf there (the lift
        would not exceed ``below``)."""
        u, w = np.broadcast_arrays(np.asarray(u, float), np.asarray(w, float))
        out = np.full(u.shape, -np.inf)
        if not self.holder:
            return out
        xy = self.xy(u, w).reshape(-1, 2)
        flat = out.reshape(-1)
        cells = self._cell_of(xy)
        zb_all = None if below is None else np.asarray(below, float).reshape(-1)
        for (r, zb, _zt), near in zip(self.holder, self._near_top):
            need = np.ones(len(xy), bool)
            if zb_all is not None:
                need = ~(near[cells] <= zb_all + zb - self.holder_clearance)   # NaN: query
            if not need.any():
                continue
            z = drop(self.holder_index, Cutter(r, 0.0), xy[need]).z - zb + self.holder_clearance
            flat[need] = np.maximum(flat[need], z)
        return out

    def z_safe(self, u, w) -> tuple[np.ndarray, np.ndarray]:
        """(tip Z clear of cutter and holder contact, mask where the holder lifted it)."""
        zc = self.z_cut(u, w)
        zh = self.holder_lift(u, w, below=zc)
        lifted = zh > zc + 1e-9
        return np.maximum(zc, zh), lifted
