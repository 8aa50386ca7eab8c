"""Steep/shallow finishing: waterline on the steep slopes, zigzag on the shallow ones.

The slope is that of the cutter-location surface (the drop-cutter raster of
:mod:`.waterline`), which for a ball equals the part surface's slope at the contact
point; it is measured in degrees from horizontal, its magnitude only (the pass direction
does not matter). Raster nodes at or above ``steep_angle`` are *steep*. Both strategies
overlap by ``overlap`` (job units, default half the cutter's effective radius, at least
two raster cells) across the border:

- waterline (:func:`.waterline.waterline`) cuts where a steep node lies within
  ``overlap``, and holds its scallop (along the normal) on slopes of ``steep_angle`` and
  more;
- zigzag (:func:`.zigzag.zigzag`) passes are kept where a shallow node lies within
  ``overlap``, and hold their scallop there on ground less steep than
  :data:`HOLD_MAX_SLOPE` (80 degrees; on vertical walls the XY side step would shrink
  towards zero: 1,589 pass lines instead of 146 on ktoolcav at scallop 0.005 in). A kept piece's ends are carried along their segment up to the border
  (the new end is a drop-cutter point, the segment verified like the passes), so
  the coverage does not depend on how far apart the pass points are. Pieces shorter
  than the cutter radius are dropped.

Every point of either comes from the drop-cutter (holder clearance included); pieces are
joined by :func:`.linking.add_passes`.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from millpath.plan.surface.sampler import Sampler
from millpath.plan.surface.waterline import (Raster, WaterlineResult, WaterlineSettings,
                                             index_runs, make_raster, waterline)
from millpath.plan.surface.zigzag import (Pass, PassStats, ZigzagResult, ZigzagSettings,
                                           refine_chords_many, zigzag)


#: degrees: the zigzag of a steep-shallow holds no scallop on ground this steep
HOLD_MAX_SLOPE = 80.0


@dataclass
class SteepShallowResult(PassStats):
    passes: list[Pass]                 # waterline pieces first (top down), then zigzag
    waterline: WaterlineResult
    zigzag: ZigzagResult
    zigzag_pieces: int                 # kept zigzag pieces
    steep_fraction: float              # of the valid raster nodes
    overlap: float


def masks(R: Raster, steep_angle: float, overlap: float) -> tuple[np.ndarray, np.ndarray]:
    """(waterline mask, zigzag mask) on the raster nodes (see the module docstring)."""
    from scipy.ndimage import distance_transform_edt     # (loaded only when planning)

    steep = R.valid & (R.slope >= steep_angle)
    h = R.spacing
    far = np.full(steep.shape, np.inf)
    to_steep = distance_transform_edt(~steep) * h if steep.any() else far
    to_shallow = distance_transform_edt(steep) * h if (~steep).any() else far
    return to_steep <= overlap, to_shallow <= overlap


def _border(R: Raster, mask: np.ndarray, a: np.ndarray, b: np.ndarray) -> np.ndarray | None:
    """The last point from ``a`` (kept) toward ``b`` (not kept), half a raster spacing
    apart, whose nearest raster node is in ``mask``; None if the first is not."""
    L = float(np.hypot(*(b[:2] - a[:2])))
    k = max(2, int(np.ceil(L / (0.5 * R.spacing))))
    t = np.linspace(0.0, 1.0, k + 1)[1:]
    xy = a[None, :2] + (b[:2] - a[:2])[None, :] * t[:, None]
    inside = R.nearest(mask, xy)
    if not inside[0]:
        return None
    n = int(np.argmin(inside)) if not inside.all() else len(inside)
    return xy[n - 1]


def _extend_all(sampler: Sampler, R: Raster, mask: np.ndarray,
                ends: list[tuple[np.ndarray, np.ndarray]], tol: float, tol_m: float
                ) -> list[np.ndarray | None]:
    """For each ``(a, b)``: points after ``a`` (kept) toward ``b`` (not kept) up to the
    mask's border, the tip point there from the drop-cutter, the segment refined (all
    segments in one batch); None if nothing to add."""
    out: list[np.ndarray | None] = [None] * len(ends)
    todo, segs = [], []
    for i, (a, b) in enumerate(ends):
        end = _border(R, mask, a, b)
        if end is not None:
            todo.append(i)
            segs.append((a, end))
    if not todo:
        return out
    A = np.array([a for a, _ in segs])
    E = np.array([e for _, e in segs])
    uwa = sampler.uw(A[:, 0], A[:, 1])
    uwe = sampler.uw(E[:, 0], E[:, 1])
    z, _ = sampler.z_safe(uwe[:, 0], uwe[:, 1])
    ok = np.isfinite(z)
    Ps = [np.array([[uwa[k, 0], uwa[k, 1], A[k, 2]], [uwe[k, 0], uwe[k, 1], z[k]]])
          for k in range(len(todo)) if ok[k]]
    Ps = refine_chords_many(sampler, Ps, tol, tol_m, 1e-3 * sampler.cutter.radius)
    for i, P in zip([i for i, good in zip(todo, ok) if good], Ps):
        back = sampler.xy(P[1:, 0], P[1:, 1])
        out[i] = np.column_stack([back, P[1:, 2]])
    return out


def mask_passes(sampler: Sampler, R: Raster, mask: np.ndarray, passes: list[Pass],
                min_length: float, tol: float, tol_m: float) -> list[Pass]:
    """The pieces of ``passes`` whose points' nearest raster node is in ``mask``, each
    carried up to the border along its end segments; pieces shorter than
    ``min_length`` (XY) dropped."""
    pieces = []                 # (pass, run, index of its forward and backward extension)
    ends: list[tuple[np.ndarray, np.ndarray]] = []
    for p in passes:
        P = p.points
        inside = R.nearest(mask, P[:, :2])
        if inside.all():
            pieces.append((p, None, -1, -1))
            continue
        for run in index_runs(inside, False):
            i0, i1 = run[0], run[-1]
            fwd = back = -1
            if i1 + 1 < len(P):
                fwd = len(ends)
                ends.append((P[i1], P[i1 + 1]))
            if i0 > 0:
                back = len(ends)
                ends.append((P[i0], P[i0 - 1]))
            pieces.append((p, run, fwd, back))
    ext = _extend_all(sampler, R, mask, ends, tol, tol_m)
    out: list[Pass] = []
    for p, run, fwd, back in pieces:
        if run is None:
            out.append(p)
            continue
        Q = p.points[run]
        lifted = p.lifted[run]
        if fwd >= 0 and (e := ext[fwd]) is not None:
            Q = np.concatenate([Q, e])
            lifted = np.concatenate([lifted, np.zeros(len(e), bool)])
        if back >= 0 and (e := ext[back]) is not None:
            Q = np.concatenate([e[::-1], Q])
            lifted = np.concatenate([np.zeros(len(e), bool), lifted])
        if len(Q) < 2 or np.hypot(*np.diff(Q[:, :2], axis=0).T).sum() < min_length:
            continue
        out.append(Pass(Q, lifted))
    return out


def steep_shallow(sampler: Sampler, design, zs: ZigzagSettings, ws: WaterlineSettings,
                  steep_angle: float, overlap: float | None = None) -> SteepShallowResult:
    """Plan both and keep each on its side of ``steep_angle`` (degrees); tip points in XY."""
    spacing = ws.spacing or sampler.cutter.radius / 8.0
    R = make_raster(sampler, ws.region, spacing)
    r_eff = sampler.cutter.corner or sampler.cutter.radius
    d = overlap if overlap is not None else max(0.5 * r_eff, 2.0 * R.spacing)
    wl_mask, zz_mask = masks(R, steep_angle, d)
    ws = WaterlineSettings(**{**ws.__dict__, "min_slope": steep_angle})
    wres = waterline(sampler, ws, raster=R, keep=wl_mask)
    # the zigzag is planned on the shallow side only: steep stations neither set the
    # side step nor get points
    # (holding it on the shallow nodes only, without the overlap band, left 1.3 to 2 %
    # of test_waterline's cells over the scallop: the waterline's border is soft)
    # the zigzag holds its scallop on its side and the overlap band, except on ground
    # steeper than HOLD_MAX_SLOPE (near-vertical walls, finished by the waterline),
    # where its XY side step would shrink towards zero
    hold_mask = zz_mask & (R.slope < max(HOLD_MAX_SLOPE, steep_angle))
    zs = ZigzagSettings(**{**zs.__dict__, "keep": lambda xy: R.nearest(zz_mask, xy),
                           "hold": lambda xy: R.nearest(hold_mask, xy)})
    zres = zigzag(sampler, design, zs)
    tol_m = zs.material_tolerance if zs.material_tolerance is not None else zs.tolerance
    zp = mask_passes(sampler, R, zz_mask, zres.passes, sampler.cutter.radius,
                     zs.tolerance, tol_m)
    steep = R.valid & (R.slope >= steep_angle)
    frac = float(steep.sum() / max(1, R.valid.sum()))
    return SteepShallowResult(wres.passes + zp, wres, zres, len(zp), frac, d)
