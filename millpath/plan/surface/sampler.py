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

from millpath.plan.surface.cutter import Cutter
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

    def holder_lift(self, u, w) -> np.ndarray:
        """Lowest tip Z at which no holder cylinder touches the mesh (-inf if none)."""
        u, w = np.broadcast_arrays(np.asarray(u, float), np.asarray(w, float))
        out = np.full(u.shape, -np.inf)
        if not self.holder:
            return out
        xy = self.xy(u, w).reshape(-1, 2)
        for r, zb, _zt in self.holder:
            z = (drop(self.holder_index, Cutter(r, 0.0), xy).z.reshape(u.shape) - zb
                 + self.holder_clearance)
            np.maximum(out, z, out=out)
        return out

    def z_safe(self, u, w) -> tuple[np.ndarray, np.ndarray]:
        """(tip Z clear of cutter and holder contact, mask where the holder lifted it)."""
        zc = self.z_cut(u, w)
        zh = self.holder_lift(u, w)
        lifted = zh > zc + 1e-9
        return np.maximum(zc, zh), lifted
