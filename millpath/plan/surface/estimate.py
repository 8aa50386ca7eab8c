"""Estimates before planning: pass lines, waterline levels, CL points and CPU time of a
surface finishing operation, from a coarse drop-cutter raster and the step formulas
(:mod:`.steps`), in well under a second. Job units; angles in degrees.

- zigzag pass lines: along each station ``u`` the passes advance by the side step for
  the scallop measured vertically (the flat formula with ``h cos(slope)``, times
  ``cos(slope)`` on XY, never below a quarter of it as in :func:`.steps.side_step`), so
  the station needs ``sum(dw / step)`` lines; the operation needs the most any station
  needs (variable side step) or the width over the smallest step (published). Curvature
  is ignored (a lower bound on concave ground, an upper one on convex).
- waterline levels: the height over the level step ``min(stepdown_max, flat step x
  sin(the shallowest slope held))``; the contour length summed over all levels is the
  integral of the CL slope over the steep area (coarea formula).
- points: pass lines x stations per line (on the ground steep-shallow keeps: within
  the overlap of shallow ground); contour length over the length per point of the
  coarse raster's contours at the planners' merge tolerance (:func:`contour_spacing`),
  at most 0.6 r. Steep-shallow lines also count one line per border of the held ground
  a station crosses (the planner stops a line there).
- CPU time: drop-cutter queries (about 35 per zigzag point, from the side steps,
  look-ahead and verification rounds; 65 per raster spacing of contour length, from
  the level search and the bisection onto each level; one per waterline raster node)
  times the measured cost of one query on the coarse raster, times the measured
  overhead around the kernels (bench/real_meshes.py's jobs, within about 2x).
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass

import numpy as np

from millpath.model.limits import MAX_ROUGH_RASTER
from millpath.plan.surface.dropcutter import PARALLEL_MIN
from millpath.plan.surface.sampler import Sampler
from millpath.plan.surface.steep_shallow import HOLD_MAX_SLOPE
from millpath.plan.surface.steps import flat_side_step

#: drop-cutter queries per planned zigzag CL point and per waterline raster spacing of
#: contour length (measured on bench/real_meshes.py's jobs: 34, and 63 to 65)
DROPS_PER_ZIGZAG_POINT = 35
DROPS_PER_CONTOUR_SPACING = 65
#: CPU per query in the planners over CPU per query on the coarse raster (measured:
#: 1.4 to 1.5 us against 0.64 to 1.0 us; array handling between the kernels)
OVERHEAD = 1.8
#: CPU seconds of Python work per CL point (array handling between the kernels)
PYTHON_PER_POINT = 3e-5


@dataclass
class Estimate:
    """What an operation will take (rough figures, see the module docstring)."""

    pass_lines: int = 0         # zigzag pass lines (surface-rough: rows per layer)
    levels: int = 0             # waterline levels (surface-rough: layers)
    points: int = 0             # CL points planned
    drops: int = 0              # drop-cutter queries
    seconds: float = 0.0        # CPU seconds

    def to_json(self) -> dict:
        return {"pass_lines": self.pass_lines, "levels": self.levels, "points": self.points,
                "drop_queries": self.drops, "cpu_s": round(self.seconds, 1)}


@dataclass
class CoarseRaster:
    """Drop-cutter tip Z ``z[j, i]`` on a grid in the pass frame (``u[i]``, ``w[j]``)."""

    u: np.ndarray
    w: np.ndarray
    z: np.ndarray
    us_per_drop: float
    on_part: np.ndarray | None = None      # the cutter touches the part (not its floor)

    @staticmethod
    def build(sampler: Sampler, region, n: int = 160) -> "CoarseRaster":
        x0, y0, x1, y1 = region
        c = sampler.uw(np.array([x0, x1, x1, x0]), np.array([y0, y0, y1, y1]))
        u = np.linspace(c[:, 0].min(), c[:, 0].max(), n)
        w = np.linspace(c[:, 1].min(), c[:, 1].max(), n)
        U, W = np.meshgrid(u, w)
        # the compiled kernels (serial and parallel) are loaded before the timing
        sampler.z_cut(np.full(PARALLEL_MIN, u[0]), np.full(PARALLEL_MIN, w[0]))
        t = time.process_time()
        z = sampler.z_cut(U, W)
        dt = time.process_time() - t
        # beside the part the drop-cutter stops at the sampler's floor: not the surface
        on = np.isfinite(z) & (z > sampler.z_floor + 1e-9 * max(1.0, abs(sampler.z_floor)))
        return CoarseRaster(u, w, z, 1e6 * dt / z.size, on)

    def slopes(self) -> tuple[np.ndarray, np.ndarray]:
        """(slope across the passes dz/dw, slope magnitude in degrees); NaN off the part."""
        zf = np.where(np.isfinite(self.z), self.z, np.nan)
        hw = self.w[1] - self.w[0] if len(self.w) > 1 else 1.0
        hu = self.u[1] - self.u[0] if len(self.u) > 1 else 1.0
        gw, gu = np.gradient(zf, hw, hu)
        return gw, np.degrees(np.arctan(np.hypot(gw, gu)))


def _target(h: float, tol_m: float) -> float:
    return max(0.9 * h - min(tol_m, 0.25 * h), 0.25 * h)


def _dilate(mask: np.ndarray, distance: float, R: CoarseRaster) -> np.ndarray:
    """``mask`` grown by ``distance`` (job units) on the coarse raster, at least by
    nothing: whole cells, rounded."""
    from scipy.ndimage import binary_dilation
    k = int(round(distance / max(float(R.w[1] - R.w[0]), 1e-12))) if len(R.w) > 1 else 0
    return binary_dilation(mask, iterations=k) if k > 0 and mask.any() else mask


def zigzag_lines(R: CoarseRaster, r: float, h: float, tol_m: float, published: bool,
                 max_slope: float | None = None, overlap: float = 0.0) -> int:
    """Pass lines a zigzag needs (see the module docstring); ``max_slope``: only the
    shallower ground and the band ``overlap`` wide beyond it, up to
    :data:`.steep_shallow.HOLD_MAX_SLOPE`, are held (steep-shallow)."""
    gw, mag = R.slopes()
    cos = 1.0 / np.sqrt(1.0 + gw * gw)
    tgt = _target(h, tol_m)
    flat = 2.0 * np.sqrt(np.maximum(2.0 * r * tgt * cos - (tgt * cos) ** 2, 0.0))
    step = flat * cos
    held = np.isfinite(step) & (step > 0)
    if max_slope is not None:
        band = _dilate(mag < max_slope, overlap, R)
        held &= band & (mag < max(HOLD_MAX_SLOPE, max_slope))
    width = float(R.w[-1] - R.w[0])
    if not held.any():
        return max(1, int(math.ceil(width / flat_side_step(r, tgt)))) + 1
    if published:
        return int(math.ceil(width / float(step[held].min()))) + 1
    dw = R.w[1] - R.w[0] if len(R.w) > 1 else width
    free = flat_side_step(r, tgt)
    per = np.where(held, dw / np.where(held, step, 1.0), dw / free)
    need = per.sum(axis=0)
    if max_slope is not None:
        # a line stops at each border of the held ground (a wall's foot) and the next
        # starts at the held ground beyond: one more line per border crossed
        need = need + np.abs(np.diff(held.astype(np.int8), axis=0)).sum(axis=0)
    return int(math.ceil(float(need.max()))) + 1


def waterline_levels(R: CoarseRaster, r: float, h: float, tol_m: float, min_slope: float,
                     dz_max: float, steep_only: bool = False) -> tuple[int, float, float]:
    """(levels, contour length over all levels, level step) of a waterline holding the
    scallop on slopes of ``min_slope`` and more; ``steep_only``: contours are cut on
    that ground only (steep-shallow). Contours beside the part (the tool running down
    its outside, which the planner does not cut) are not counted."""
    _, mag = R.slopes()
    fin = np.isfinite(R.z) if R.on_part is None else R.on_part
    if not fin.any():
        return 0, 0.0, 0.0
    steep = fin & (mag >= min_slope)
    tgt = _target(h, tol_m)
    sl = float(mag[steep].min()) if steep.any() else 90.0
    dz = min(dz_max, flat_side_step(r, tgt) * math.sin(math.radians(max(sl, min_slope))))
    height = float(R.z[fin].max() - R.z[fin].min())
    levels = max(1, int(math.ceil(height / max(dz, 1e-12)))) + 1
    # coarea: the length of all contours is the integral of |grad z| over the area,
    # jumps included (the raster's differences between nodes on the part; with
    # steep_only, pairs with a steep node); divided by the level step
    zl = np.where(fin, R.z, 0.0)
    use = steep if steep_only else fin
    hu = float(R.u[1] - R.u[0])
    hw = float(R.w[1] - R.w[0])
    pu = fin[:, 1:] & fin[:, :-1] & (use[:, 1:] | use[:, :-1])
    pw = fin[1:, :] & fin[:-1, :] & (use[1:, :] | use[:-1, :])
    jump = (np.abs(np.diff(zl, axis=1))[pu].sum() * hw
            + np.abs(np.diff(zl, axis=0))[pw].sum() * hu)
    return levels, float(jump / max(dz, 1e-12)), dz


def contour_spacing(R: CoarseRaster, tol: float, min_slope: float | None,
                    samples: int = 12) -> float:
    """Mean length per planned point of waterline contours (job units): contours of the
    coarse raster at ``samples`` levels, each piece's points counted as the chords a
    tolerance ``tol`` allows on its turning (``sqrt(L theta / (8 tol))`` per
    polyline segment of length ``L`` turning by ``theta``), plus its two ends; on
    ground at least ``min_slope`` steep if given."""
    import contourpy
    fin = np.isfinite(R.z) if R.on_part is None else R.on_part
    if not fin.any():
        return 1.0
    _, mag = R.slopes()
    zl = np.where(fin, R.z, float(R.z[fin].min()) - 1.0)
    gen = contourpy.contour_generator(R.u, R.w, zl)
    lo, hi = float(R.z[fin].min()), float(R.z[fin].max())
    hu = float(R.u[1] - R.u[0])
    length = points = 0.0
    for z in np.linspace(lo, hi, samples + 2)[1:-1]:
        for L in gen.lines(z):
            L = np.asarray(L, float)
            if len(L) < 2:
                continue
            i = np.clip(np.rint((L[:, 0] - R.u[0]) / hu).astype(np.int64), 0, len(R.u) - 1)
            j = np.clip(np.rint((L[:, 1] - R.w[0]) / (R.w[1] - R.w[0])).astype(np.int64),
                        0, len(R.w) - 1)
            ok = fin[j, i] if min_slope is None else fin[j, i] & (mag[j, i] >= min_slope)
            seg = np.hypot(*np.diff(L, axis=0).T)
            oks = ok[1:] & ok[:-1]
            if not oks.any():
                continue
            d = np.diff(L, axis=0)
            a = np.arctan2(d[:, 1], d[:, 0])
            turn = np.abs(np.angle(np.exp(1j * np.diff(a))))        # at interior vertices
            theta = np.concatenate([[0.0], turn]) * 0.5 + np.concatenate([turn, [0.0]]) * 0.5
            length += float(seg[oks].sum())
            points += float(np.sqrt(seg[oks] * theta[oks] / (8.0 * tol)).sum()) + 2.0
    return length / points if points > 0 else 1.0


def estimate_finish(sampler: Sampler, region, *, strategy: str, scallop: float,
                    tolerance: float, material_tolerance: float, side_step: str,
                    steep_angle: float, stepdown_max: float | None,
                    raster: CoarseRaster | None = None) -> tuple[Estimate, CoarseRaster]:
    """Estimate of a ``surface-finish`` operation and the coarse raster it used."""
    R = raster or CoarseRaster.build(sampler, region)
    c = sampler.cutter
    r = c.corner if c.corner > 0 else c.radius
    e = Estimate()
    station = min(0.5, c.radius / 4.0)
    n_st = max(2, int(math.ceil(float(R.u[-1] - R.u[0]) / station)) + 1)
    zz_points = 0
    if strategy in ("zigzag", "steep-shallow"):
        e.pass_lines = zigzag_lines(R, r, scallop, material_tolerance,
                                    side_step == "published",
                                    steep_angle if strategy == "steep-shallow" else None,
                                    0.5 * r)
        zz_points = e.pass_lines * n_st
        if strategy == "steep-shallow":
            # the passes are kept within the overlap (half the radius) of shallow ground
            _, mag = R.slopes()
            fin = np.isfinite(R.z)
            kept = _dilate(fin & (mag < steep_angle), 0.5 * r, R)
            shallow = float((fin & kept).sum() / max(1, fin.sum()))
            zz_points = int(zz_points * max(shallow, 0.05))
    wl_points = wl_drops = 0
    if strategy in ("waterline", "steep-shallow"):
        ss = strategy == "steep-shallow"
        e.levels, length, _ = waterline_levels(R, r, scallop, material_tolerance,
                                               steep_angle, stepdown_max or r, ss)
        tol = 0.2 * min(tolerance, material_tolerance)       # the planners' merge
        # (at most 0.6 r per point: the bisection's jitter leaves points the merge
        # keeps; measured 0.42 r on the text box, 0.82 r on ktoolcav)
        per_point = min(contour_spacing(R, tol, steep_angle if ss else None), 0.6 * c.radius)
        wl_points = int(length / per_point)
        spacing = c.radius / 8.0                              # the waterline raster's
        x0, y0, x1, y1 = region
        wl_drops = int(DROPS_PER_CONTOUR_SPACING * length / spacing
                       + (x1 - x0) * (y1 - y0) / spacing ** 2)
    e.points = zz_points + wl_points
    e.drops = zz_points * DROPS_PER_ZIGZAG_POINT + wl_drops
    e.seconds = e.drops * R.us_per_drop * 1e-6 * OVERHEAD + e.points * PYTHON_PER_POINT
    return e, R


#: the most raster nodes a ``surface-rough`` plans (beyond: refused; about 1 GB)
ROUGH_MAX_RASTER = MAX_ROUGH_RASTER


@dataclass
class RoughEstimate(Estimate):
    """A ``surface-rough`` estimate: ``levels`` layers, ``pass_lines`` rows per layer,
    ``raster`` drop-cutter nodes of its two rasters (rows and the fine contour one)."""

    raster: int = 0

    def to_json(self) -> dict:
        return {**super().to_json(), "raster_nodes": self.raster}


def estimate_rough(region, top: float, bottom: float, stepdown: float, step_over: float,
                   station: float, angle: float, us_per_drop: float) -> RoughEstimate:
    """Layers, rows, raster nodes, points and CPU seconds of a ``surface-rough`` from the
    region (tool-tip box), the stock top and the lowest floor (surface bottom plus
    allowance) alone: every row of every layer is counted as cut (an upper bound)."""
    x0, y0, x1, y1 = region
    a = math.radians(angle)
    c, s = abs(math.cos(a)), abs(math.sin(a))
    lu = (x1 - x0) * c + (y1 - y0) * s            # extent along the passes
    lw = (x1 - x0) * s + (y1 - y0) * c            # and across them
    n_u = max(2, int(math.ceil(lu / station)) + 1)
    rows = max(1, int(math.ceil(lw / step_over))) + 1
    fine = max(2, int(math.ceil(lw / station)) + 1)
    e = RoughEstimate()
    e.levels = max(1, int(math.ceil(max(top - bottom, 0.0) / stepdown)))
    e.pass_lines = rows
    e.raster = n_u * (rows + fine)
    e.points = e.levels * rows * n_u
    e.drops = 2 * e.raster
    e.seconds = e.drops * us_per_drop * 1e-6 + e.points * PYTHON_PER_POINT
    return e
