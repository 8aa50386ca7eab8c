"""Moves of 2.5D operations with safe entries.

Z heights (job units, tool tip): ``safe_z`` for rapids between places, ``clear_z``
(just above the stock top) where a descent changes from rapid to feed. Material is
never entered by a straight plunge: a descent into material is a helix (counter-
clockwise, climb for a clockwise spindle) or a ramp along the path at ``ramp_angle``
degrees; straight feeds down are used only where the caller knows the column is
empty (``plunge_air``).
"""

from __future__ import annotations

import math

import numpy as np

from millpath.model import Toolpath


class PathWriter:
    def __init__(self, tp: Toolpath, *, safe_z: float, clear_z: float, feed: float,
                 plunge_feed: float, ramp_angle: float):
        self.tp = tp
        self.safe_z = safe_z
        self.clear_z = clear_z
        self.feed = feed
        self.plunge_feed = plunge_feed
        self.slope = math.tan(math.radians(ramp_angle))
        self.pos: tuple[float, float, float] | None = None
        self.entries = {"helix": 0, "ramp": 0, "air": 0}

    # --- low level ---------------------------------------------------------------
    def _line(self, x, y, z, feed=None):
        self.tp.line(x, y, z, feed or self.feed)
        self.pos = (float(x), float(y), float(z))

    def retract(self) -> None:
        if self.pos is not None and self.pos[2] < self.safe_z:
            self.tp.rapid(self.pos[0], self.pos[1], self.safe_z)
            self.pos = (self.pos[0], self.pos[1], self.safe_z)

    def above(self, x: float, y: float) -> None:
        """Retract and rapid to (x, y) at ``safe_z``."""
        if self.pos is not None and abs(self.pos[0] - x) < 1e-9 and abs(self.pos[1] - y) < 1e-9:
            return
        self.retract()
        self.tp.rapid(x, y, self.safe_z)
        self.pos = (float(x), float(y), self.safe_z)

    def down_to(self, z: float) -> None:
        """Rapid down to ``z`` (above the stock: at most ``clear_z``)."""
        assert self.pos is not None
        if z < self.pos[2] - 1e-12:
            self.tp.rapid(self.pos[0], self.pos[1], z)
            self.pos = (self.pos[0], self.pos[1], z)

    def at(self, x, y, z) -> bool:
        return self.pos is not None and math.dist(self.pos, (x, y, z)) < 1e-7

    # --- entries -------------------------------------------------------------------
    def plunge_air(self, x: float, y: float, z: float, z_from: float) -> None:
        """Straight feed down at (x, y) where no material is above ``z``."""
        self.above(x, y)
        self.down_to(max(z_from, z))
        if self.pos[2] > z + 1e-12:
            self._line(x, y, z, self.plunge_feed)
        self.entries["air"] += 1

    def helix(self, cx: float, cy: float, r: float, z_from: float, z: float) -> None:
        """Helix of radius ``r`` round (cx, cy) from ``z_from`` down to ``z``, then a full
        circle at ``z``; ends at (cx + r, cy, z). Counter-clockwise."""
        x0, y0 = cx + r, cy
        self.above(x0, y0)
        self.down_to(z_from)
        pitch = max(2 * math.pi * r * self.slope, 1e-6)
        zc = self.pos[2]
        half = 0
        while zc > z + 1e-9:
            zn = max(z, zc - pitch / 2)
            ex, ey = (cx - r, cy) if half % 2 == 0 else (cx + r, cy)
            self.tp.arc((ex, ey, zn), (cx, cy, zn), False, self.plunge_feed)
            self.pos = (ex, ey, zn)
            zc = zn
            half += 1
        if half % 2 == 1:      # finish the turn so the circle starts at (cx + r, cy)
            self.tp.arc((cx + r, cy, z), (cx, cy, z), False, self.feed)
        self.tp.arc((cx - r, cy, z), (cx, cy, z), False, self.feed)
        self.tp.arc((cx + r, cy, z), (cx, cy, z), False, self.feed)
        self.pos = (x0, y0, z)
        self.entries["helix"] += 1

    def ramp_closed(self, ring: np.ndarray, z_from: float, z: float) -> None:
        """Descend along the closed polyline ``ring`` (n, 2; start not repeated) in
        whole laps from ``z_from`` to ``z`` at no more than the ramp angle; ends at
        ``ring[0]`` at ``z``."""
        pts = np.vstack([ring, ring[:1]])
        seg = np.hypot(*np.diff(pts, axis=0).T)
        L = float(seg.sum())
        self.above(*pts[0])
        self.down_to(z_from)
        zc = self.pos[2]
        if zc <= z + 1e-12:
            return
        laps = max(1, int(math.ceil((zc - z) / (L * self.slope) - 1e-9)))
        total = laps * L
        s = 0.0
        for _ in range(laps):
            for k in range(1, len(pts)):
                s += seg[k - 1]
                self._line(pts[k][0], pts[k][1], zc - (zc - z) * s / total, self.plunge_feed)
        self.entries["ramp"] += 1

    def ramp_open(self, pts: np.ndarray, z_from: float, z: float) -> None:
        """Descend back and forth along the start of the open polyline ``pts`` (at
        most its first 2 x ``span``) at no more than the ramp angle; ends at
        ``pts[0]`` at ``z``."""
        seg = np.hypot(*np.diff(pts, axis=0).T)
        cum = np.concatenate([[0], np.cumsum(seg)])
        span = min(float(cum[-1]), 50.0 * max(seg.max(initial=0), 1e-3))
        k = int(np.searchsorted(cum, span)) + 1
        path = pts[:max(2, k)]
        self.above(*pts[0])
        self.down_to(z_from)
        zc = self.pos[2]
        if zc <= z + 1e-12:
            return
        fwd = np.hypot(*np.diff(path, axis=0).T)
        L = float(fwd.sum())
        if L < 1e-6:
            raise ValueError("no room to ramp")
        trips = max(1, int(math.ceil((zc - z) / (2 * L * self.slope) - 1e-9)))
        total = trips * 2 * L
        s = 0.0
        there_back = np.vstack([path[1:], path[-2::-1]])
        steps = np.concatenate([fwd, fwd[::-1]])
        for _ in range(trips):
            for p, d in zip(there_back, steps):
                s += d
                self._line(p[0], p[1], zc - (zc - z) * s / total, self.plunge_feed)
        self.entries["ramp"] += 1

    # --- cutting -------------------------------------------------------------------
    def polyline(self, pts: np.ndarray, z: float, feed: float | None = None) -> None:
        """Feed along ``pts`` (n, 2) at ``z``, from the current position."""
        for p in pts:
            if self.pos is not None and abs(p[0] - self.pos[0]) < 1e-9 \
                    and abs(p[1] - self.pos[1]) < 1e-9 and abs(z - self.pos[2]) < 1e-9:
                continue
            self._line(p[0], p[1], z, feed)
