"""Write the cuts of one level as moves: links through cleared space, safe entries,
and (with an in-process stock) only the stretches where the tool meets material.

Entry moves (helices, ramps, plunges in air) are recorded as index ranges of the
toolpath's moves in ``Emitter.entry_ranges``: the engagement measure leaves them out
(an entry's cut is axial, not radial).
"""

from __future__ import annotations

import math

import numpy as np
import shapely
from shapely.geometry import Point

from millpath.plan.pocket.passes import Cut, segment_inside
from millpath.plan.twod.field import MaterialField, cutting_runs, densify
from millpath.plan.twod.offsets import closed as close_ring
from millpath.plan.twod.writer import PathWriter


class Emitter:
    def __init__(self, w: PathWriter, *, radius: float, helix_radius: float, entry: str,
                 clearance: float):
        self.w = w
        self.R = radius
        self.helix_radius = helix_radius
        self.entry = entry
        self.clearance = clearance
        self.entry_ranges: list[tuple[int, int]] = []

    def mark_entry(self, i0: int) -> None:
        i1 = len(self.w.tp.moves)
        if i1 > i0:
            self.entry_ranges.append((i0, i1))

    def _z_from(self, z_from: float, field: MaterialField | None, x: float, y: float,
                reach: float) -> float:
        if field is None:
            return z_from
        return min(z_from, max(field.top_near(x, y, reach), field_z(field)) + self.clearance)

    def level(self, cuts: list[Cut], z: float, z_from: float,
              field: MaterialField | None) -> None:
        """Cut ``cuts`` at ``z``; ``z_from``: highest Z an entry starts from (material
        above it was removed by the previous level or is not there)."""
        for cut in cuts:
            pts = cut.pts
            if cut.closed:
                dense = close_ring(pts)
            else:
                dense = pts
            runs: list[tuple[np.ndarray, bool]]
            if field is None:
                runs = [(pts, cut.closed)]
            else:
                step = max(field.raster.h, 1e-6)
                dense = densify(dense, step)
                t = field.touches(dense)
                if t.all():
                    runs = [(pts, cut.closed)]
                else:
                    runs = [(dense[a:b + 1], False) for a, b in cutting_runs(dense, t)]
                    runs = [(r, c) for r, c in runs if len(r) >= 2]
            for run, is_closed in runs:
                self._run(run, is_closed, cut.room, z, z_from, field)

    def _run(self, run: np.ndarray, is_closed: bool, room, z: float, z_from: float,
             field: MaterialField | None) -> None:
        w = self.w
        p0 = run[0]
        at_level = w.pos is not None and abs(w.pos[2] - z) < 1e-9
        if at_level and segment_inside(room, w.pos[:2], p0):
            w.polyline(run[:1], z)
        else:
            i0 = len(w.tp.moves)
            zf = self._z_from(z_from, field, p0[0], p0[1], self.R + self.helix_radius)
            if field is not None and not field.touches(run[:1])[0]:
                w.plunge_air(p0[0], p0[1], z, zf)
            elif is_closed:
                self._enter_closed(run, room, z, zf)
            else:
                w.ramp_open(run, zf, z)
            self.mark_entry(i0)
        w.polyline(close_ring(run)[1:] if is_closed else run[1:], z)

    def _enter_closed(self, ring: np.ndarray, room, z: float, zf: float) -> None:
        w = self.w
        if self.entry == "helix":
            mic = shapely.maximum_inscribed_circle(room, self.R * 0.01)
            c = mic.coords[0]
            rad = Point(c).distance(room.boundary)
            rh = min(self.helix_radius, rad - 1e-3 * self.R)
            start = (c[0] + rh, c[1])
            if rh >= 0.1 * self.R and segment_inside(room, start, ring[0]):
                w.helix(c[0], c[1], rh, zf, z)
                w.polyline(ring[:1], z)
                return
        w.ramp_closed(ring, zf, z)


def field_z(field: MaterialField) -> float:
    return getattr(field, "z", -math.inf)
