"""The in-process stock: a Z-map carried from operation to operation.

After each operation is planned its motion is swept into the Z-map (the simulator's
kernel, :func:`millpath.simulate.simulator.sweep`) in short windows of consecutive
motion, each on the part of the map it can reach, which also measures per operation:

- ``feed_length``: length of the feed motion (lines, arcs, cubics);
- ``air_length``, ``air_time_s``, ``air_share``: feed motion in windows that removed
  nothing (less than ``1e-4`` of a cell's height times its area), its time and its
  share of the operation's time (machine model of :mod:`millpath.simulate.cycletime`);
- ``engagement``: for windows of horizontal feed motion (constant Z) that are not
  entries, the area (seen from above) of the cells whose height dropped, divided by
  the window's length and the tool diameter: the radial width of cut as a fraction of
  the diameter, measured on the stock. ``max`` and ``mean`` (length-weighted over
  the windows that cut) are reported. Windows are a quarter of the tool diameter
  long (or one longer move); shorter ones (the ends of passes) are not measured.

Heights are job units; ``height(x, y)`` returns the stock bottom outside the map.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numba
import numpy as np

from millpath.model.motion import Motion
from millpath.model.stock import Machine, Stock
from millpath.model.tool import Tool
from millpath.simulate.cycletime import motion_times
from millpath.simulate.path import motion_segments
from millpath.simulate.simulator import sweep
from millpath.simulate.zmap import ZMap


@dataclass
class OpStock:
    """What one operation did to the in-process stock (job units, seconds)."""

    feed_length: float = 0.0
    air_length: float = 0.0
    time_s: float = 0.0
    air_time_s: float = 0.0
    removed_volume: float = 0.0
    eng_max: float = 0.0
    eng_len: float = 0.0
    eng_sum: float = 0.0
    samples: list[tuple[float, float, float]] = field(default_factory=list)  # x, y, eng

    def to_json(self) -> dict:
        d = {"feed_length": round(self.feed_length, 3), "air_cut_length": round(self.air_length, 3),
             "air_cut_time_s": round(self.air_time_s, 3),
             "air_cut_share": round(self.air_time_s / self.time_s, 4) if self.time_s > 0 else 0.0,
             "removed_volume": round(self.removed_volume, 3)}
        if self.eng_len > 0:
            d["engagement"] = {"max": round(self.eng_max, 4),
                               "mean": round(self.eng_sum / self.eng_len, 4)}
        return d


def _length(mo: Motion) -> float:
    if mo.kind == "arc" and mo.center is not None:
        from millpath.simulate.path import arc_params
        r, _a0, sweep_, dn = arc_params(mo)
        return math.hypot(abs(sweep_) * r, dn)
    return math.dist(mo.start, mo.end)


class InProcessStock:
    """The stock left by the operations swept so far (read-only for planners:
    :class:`millpath.plan.base.Remaining`)."""

    def __init__(self, stock: Stock, resolution: float):
        self.zmap = ZMap.from_stock(stock, resolution)
        self.resolution = float(resolution)

    def height(self, x, y) -> np.ndarray:
        """Top of the material at (x, y) (nearest cell); the stock bottom outside."""
        z = self.zmap
        x = np.asarray(x, float)
        y = np.asarray(y, float)
        ny, nx = z.heights.shape
        i = np.floor((x - z.x0) / z.dx).astype(np.int64)
        j = np.floor((y - z.y0) / z.dy).astype(np.int64)
        ok = (i >= 0) & (i < nx) & (j >= 0) & (j < ny)
        out = np.full(x.shape, z.zmin)
        out[ok] = z.heights[j[ok], i[ok]]
        return out

    def _sweep_window(self, ms: list[Motion], tools: dict[int, Tool]) -> tuple[float, int]:
        """Sweep motions ``ms`` into the map; (volume removed, cells lowered)."""
        z = self.zmap
        segs = motion_segments(ms, self.resolution / 20.0)
        if not len(segs):
            return 0.0, 0
        R = max((tools[t].radius for t in set(segs.tool.tolist()) if t in tools), default=0.0)
        pts = np.vstack([segs.start, segs.end])
        ny, nx = z.heights.shape
        i0 = max(0, int(math.floor((pts[:, 0].min() - R - z.x0) / z.dx)) - 1)
        i1 = min(nx, int(math.ceil((pts[:, 0].max() + R - z.x0) / z.dx)) + 1)
        j0 = max(0, int(math.floor((pts[:, 1].min() - R - z.y0) / z.dy)) - 1)
        j1 = min(ny, int(math.ceil((pts[:, 1].max() + R - z.y0) / z.dy)) + 1)
        if i0 >= i1 or j0 >= j1:
            return 0.0, 0
        before = np.ascontiguousarray(z.heights[j0:j1, i0:i1])
        sub = ZMap(z.x0 + i0 * z.dx, z.y0 + j0 * z.dy, z.dx, z.dy, z.zmin, z.ztop,
                   before.copy(),
                   None if z.initial is None else z.initial[j0:j1, i0:i1].copy())
        threads = numba.get_num_threads()
        numba.set_num_threads(1)          # small maps: a parallel launch costs more
        try:
            sweep(sub, segs, tools, len(ms))
        finally:
            numba.set_num_threads(threads)
        drop = before - sub.heights
        z.heights[j0:j1, i0:i1] = sub.heights
        vol = float(drop.sum()) * z.cell_area
        cells = int(np.count_nonzero(drop > 1e-4 * min(z.dx, z.dy)))
        return vol, cells

    def cut(self, motions: list[Motion], op_of: list[int], entry: list[bool],
            tools: dict[int, Tool], machine: Machine, n_ops: int) -> list[OpStock]:
        """Sweep ``motions`` (``op_of[k]``: operation index of motion k; ``entry[k]``:
        part of an entry, left out of the engagement) and measure each operation."""
        stats = [OpStock() for _ in range(n_ops)]
        if not motions:
            return stats
        times = motion_times(motions, machine)
        cell_area = self.zmap.cell_area
        eps_v = 1e-4 * min(self.zmap.dx, self.zmap.dy) * cell_area
        k = 0
        n = len(motions)
        while k < n:
            mo = motions[k]
            op = op_of[k]
            if mo.kind in ("traverse", "dwell"):
                self._sweep_window([mo], tools)
                stats[op].time_s += float(times[k])
                k += 1
                continue
            horiz = abs(mo.end[2] - mo.start[2]) < 1e-9 and not entry[k]
            win = [mo]
            L = _length(mo)
            t = float(times[k])
            D = tools[mo.tool].diameter if mo.tool in tools else 0.0
            lim = 0.25 * D if D > 0 else 1.0
            k += 1
            while k < n and L < lim:
                m2 = motions[k]
                if m2.kind in ("traverse", "dwell") or op_of[k] != op or m2.tool != mo.tool:
                    break
                h2 = abs(m2.end[2] - m2.start[2]) < 1e-9 and not entry[k]
                if h2 != horiz:
                    break
                win.append(m2)
                L += _length(m2)
                t += float(times[k])
                k += 1
            vol, cells = self._sweep_window(win, tools)
            s = stats[op]
            s.time_s += t
            s.feed_length += L
            s.removed_volume += vol
            if vol <= eps_v:
                s.air_length += L
                s.air_time_s += t
            elif horiz and D > 0 and L >= 0.5 * lim:
                e = cells * cell_area / (L * D)
                s.eng_max = max(s.eng_max, e)
                s.eng_len += L
                s.eng_sum += e * L
                s.samples.append((win[-1].end[0], win[-1].end[1], e))
        return stats
