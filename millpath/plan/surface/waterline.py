"""Waterline (constant-Z) finishing on the cutter-location surface.

At a level ``z`` the tool tip runs along the curve where the drop-cutter tip Z equals
``z`` (the CL surface's iso-contour). The contours come from a raster of drop-cutter
Z over the region (one batched :func:`.dropcutter.drop`, spacing ``spacing``), traced by
marching squares (``contourpy``); every vertex is then moved onto the exact level
along the raster gradient with the drop-cutter (a bracket narrowed by secant guesses
and halvings to ``width``), keeping the bracket end on the low side, so the tip at
``z`` is never below the drop-cutter Z there. Segments are verified at their midpoints
with the drop-cutter (split where the CL surface rises above the chord by more than
``tolerance``, measured vertically, or falls away from it by more than
``material_tolerance``, measured along the surface normal), collinear points merged,
and verified again. Job units throughout; angles in degrees.

Levels go down from the top of the CL surface. The step between two levels is set so
that the scallop, **measured along the surface normal**, stays under ``scallop`` on
slopes of at least ``min_slope``: on a slope ``a`` (from horizontal) the CL points of
two levels ``dz`` apart are ``dz / sin a`` apart along the slope, and that chord is
limited by the published side-step formula (:func:`.steps.side_step`) with the
curvature of the CL surface along its gradient (from the raster). The step is the
smallest over the contour's points at the level and at the candidate next level
(look-ahead), checked against the measured distance between the two contours (the
nearest point of the level above), and never more than ``stepdown_max``. A Z-map
simulation sees the scallop vertically: ``h / cos a`` on a slope ``a``. Shallower
areas get the levels the steep ones need, nothing more; their scallops are not held
(use the ``steep-shallow`` strategy, :mod:`.steep_shallow`).

Direction: ``climb = True`` (default) runs every contour with the rising surface on the
tool's right, i.e. climb milling with a clockwise spindle (M3): clockwise around
islands, counter-clockwise inside cavities, seen from +Z. ``climb = False`` reverses.

Points are removed (the contour is split there, nothing is cut) where the cutter's
contact lies on the mesh's open boundary (the tool would roll over the surface's edge,
not finish it), where the shank or a holder cylinder would come within
``holder_clearance`` of the mesh at that level (:meth:`.sampler.Sampler.holder_lift`),
and outside the ``keep`` mask (used by :mod:`.steep_shallow`). Each count is reported.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Callable

import numpy as np

from millpath.errors import PlanningError
from millpath.geometry.rows import unique_rows
from millpath.geometry.spacing import points_along
from millpath.model.limits import MAX_LEVELS
from millpath.plan.surface.dropcutter import drop
from millpath.plan.surface.sampler import Sampler
from millpath.plan.surface.steps import flat_side_step, side_step
from millpath.plan.surface.polyline import densify, merge_collinear
from millpath.plan.surface.zigzag import Pass, PassStats, effective_radius


@dataclass
class Raster:
    """Drop-cutter tip Z ``z[j, i]`` at ``x[i]``, ``y[j]`` (job units) and derived fields.

    ``valid``: the cutter touches the mesh and its contact is not on the mesh's open
    boundary; ``gx``, ``gy``: gradient of the CL surface; ``slope``: its angle from
    horizontal in degrees (equal to the part surface's slope at the contact for a ball);
    ``rho``: signed radius of curvature of the part surface along the gradient
    (positive convex, see :mod:`.steps`). Invalid nodes hold ``z_low`` (below
    every valid node) so that contours close around the surface.
    """

    x: np.ndarray
    y: np.ndarray
    z: np.ndarray
    valid: np.ndarray
    gx: np.ndarray
    gy: np.ndarray
    slope: np.ndarray
    rho: np.ndarray
    z_low: float

    @property
    def spacing(self) -> float:
        return float(self.x[1] - self.x[0])

    def nearest(self, field: np.ndarray, xy: np.ndarray) -> np.ndarray:
        """Value of ``field`` at the raster node nearest each point ``(n, 2)``."""
        h = self.spacing
        i = np.clip(np.rint((xy[:, 0] - self.x[0]) / h).astype(np.int64), 0, len(self.x) - 1)
        j = np.clip(np.rint((xy[:, 1] - self.y[0]) / h).astype(np.int64), 0, len(self.y) - 1)
        return field[j, i]

    def bilinear(self, field: np.ndarray, xy: np.ndarray) -> np.ndarray:
        """``field`` interpolated bilinearly at the points ``(n, 2)`` (clamped inside)."""
        h = self.spacing
        fx = np.clip((xy[:, 0] - self.x[0]) / h, 0.0, len(self.x) - 1.000001)
        fy = np.clip((xy[:, 1] - self.y[0]) / h, 0.0, len(self.y) - 1.000001)
        i = fx.astype(np.int64)
        j = fy.astype(np.int64)
        tx = fx - i
        ty = fy - j
        return ((1 - tx) * (1 - ty) * field[j, i] + tx * (1 - ty) * field[j, i + 1]
                + (1 - tx) * ty * field[j + 1, i] + tx * ty * field[j + 1, i + 1])


def boundary_segments(sampler: Sampler) -> np.ndarray:
    """XY segments ``(m, 2, 2)`` of the mesh's open boundary (edges of one triangle)."""
    t = sampler.index.tri
    e = np.concatenate([t[:, [0, 1]], t[:, [1, 2]], t[:, [2, 0]]])       # (3n, 2, 3)
    scale = max(1.0, float(np.abs(t).max()))
    key = np.round(e / (1e-9 * scale)).astype(np.int64).reshape(len(e), 6)
    a, b = key[:, :3], key[:, 3:]
    first = (a[:, 0] < b[:, 0]) | ((a[:, 0] == b[:, 0]) & ((a[:, 1] < b[:, 1])
                                    | ((a[:, 1] == b[:, 1]) & (a[:, 2] <= b[:, 2]))))
    k = np.where(first[:, None], key, np.concatenate([b, a], axis=1))
    _, inv, cnt = unique_rows(k)
    once = cnt[inv] == 1
    return e[once][:, :, :2]


def on_boundary(segments: np.ndarray, pts: np.ndarray, eps: float) -> np.ndarray:
    """Whether each XY point ``(n, 2)`` lies within ``eps`` of a boundary segment."""
    out = np.zeros(len(pts), bool)
    if len(segments) == 0 or len(pts) == 0:
        return out
    import shapely
    lines = shapely.linestrings(segments)
    tree = shapely.STRtree(lines)
    ok = np.isfinite(pts).all(axis=1)
    idx = np.nonzero(ok)[0]
    hit = tree.query(shapely.points(pts[idx]), predicate="dwithin", distance=eps)
    out[idx[np.unique(hit[0])]] = True
    return out


#: degrees: a rise between two neighbouring raster nodes this steep is a vertical wall
JUMP_SLOPE = 85.0


def make_raster(sampler: Sampler, region, spacing: float) -> Raster:
    """Drop-cutter Z over ``region`` (tool tip box) on a square grid of ``spacing``."""
    x0, y0, x1, y1 = region
    nx = max(3, int(math.ceil((x1 - x0) / spacing)) + 1)
    ny = max(3, int(math.ceil((y1 - y0) / spacing)) + 1)
    h = max((x1 - x0) / (nx - 1), (y1 - y0) / (ny - 1))
    x = x0 + h * np.arange(nx)
    y = y0 + h * np.arange(ny)
    X, Y = np.meshgrid(x, y)
    xy = np.column_stack([X.ravel(), Y.ravel()])
    r = drop(sampler.index, sampler.cutter, xy)
    z = r.z.reshape(ny, nx)
    fin = np.isfinite(z)
    if not fin.any():
        raise PlanningError("waterline: the cutter touches the surface nowhere in the region")
    scale = max(1.0, float(np.abs(sampler.index.tri).max()))
    edge = on_boundary(boundary_segments(sampler), r.cc[:, :2], 1e-7 * scale).reshape(ny, nx)
    valid = fin & ~edge
    if not valid.any():
        valid = fin
    zlo = float(z[fin].min())
    z_low = zlo - max(1.0, 4.0 * sampler.cutter.radius)
    zf = np.where(fin, z, z_low)
    gy, gx = np.gradient(zf, h)
    gyy, gyx = np.gradient(gy, h)
    gxy, gxx = np.gradient(gx, h)
    g2 = gx * gx + gy * gy
    with np.errstate(divide="ignore", invalid="ignore"):
        d2 = (gx * gx * gxx + gx * gy * (gxy + gyx) + gy * gy * gyy) / g2
        rho_cl = np.where(np.abs(d2) < 1e-12, np.inf, -(1.0 + g2) ** 1.5 / d2)
    rho_cl = np.where(g2 > 0, rho_cl, np.inf)
    # a vertical CL wall (a vertical part wall) is a jump between two nodes, steeper
    # than JUMP_SLOPE: its finite-difference curvature is an artefact (a spurious
    # crease either side); the wall is taken as planar there
    lim = h * math.tan(math.radians(JUMP_SLOPE))
    jump = np.zeros(zf.shape, bool)
    jx = np.abs(np.diff(zf, axis=1)) > lim
    jy = np.abs(np.diff(zf, axis=0)) > lim
    jump[:, 1:] |= jx
    jump[:, :-1] |= jx
    jump[1:, :] |= jy
    jump[:-1, :] |= jy
    rho_cl = np.where(jump & fin, np.inf, rho_cl)
    r_eff = sampler.cutter.corner if sampler.cutter.corner > 0 else sampler.cutter.radius
    slope = np.degrees(np.arctan(np.sqrt(g2)))
    return Raster(x, y, zf, valid, gx, gy, slope, rho_cl - r_eff, z_low)


@dataclass
class WaterlineSettings:
    """Tolerances and steps (job units; angles in degrees). ``region`` is the tool-tip
    box ``(xmin, ymin, xmax, ymax)``; ``spacing`` the raster step (default an eighth of
    the cutter radius); ``stepdown_max`` the largest step between levels (default the
    effective cutter radius); ``min_slope``: the scallop is held on slopes at least this
    steep. ``z_range`` limits the levels (tip Z) if given."""

    tolerance: float
    scallop: float
    region: tuple[float, float, float, float]
    material_tolerance: float | None = None
    spacing: float | None = None
    stepdown_max: float | None = None
    min_slope: float = 45.0
    climb: bool = True
    holder_clearance: float = 0.0
    max_levels: int = MAX_LEVELS
    z_range: tuple[float, float] | None = None
    on_level: Callable[[int, float], None] | None = None   # progress: levels so far, z


@dataclass
class WaterlineResult(PassStats):
    passes: list[Pass]
    levels: list[float]                          # tip Z of each level, top down
    n_contours: int = 0                          # closed or open pieces cut
    removed: dict = field(default_factory=dict)  # points not cut, by reason
    max_chord_ratio: float = 0.0                 # measured CL chord / allowed (<= 1)
    raster: Raster | None = None


class _Level:
    """Contour tracing and refinement at constant Z for one raster and sampler."""

    def __init__(self, sampler: Sampler, R: Raster, s: WaterlineSettings):
        import contourpy
        self.sampler = sampler
        self.R = R
        self.s = s
        self.gen = contourpy.contour_generator(R.x, R.y, R.z)
        self.tol_g = s.tolerance
        self.tol_m = s.material_tolerance if s.material_tolerance is not None else s.tolerance
        self.width = min(1e-3 * sampler.cutter.radius, 0.1 * min(self.tol_g, self.tol_m))

    def zc(self, xy: np.ndarray) -> np.ndarray:
        z = drop(self.sampler.index, self.sampler.cutter, xy).z
        return np.where(np.isfinite(z), z, self.R.z_low)

    def uphill(self, xy: np.ndarray, fallback: np.ndarray | None = None) -> np.ndarray:
        g = np.column_stack([self.R.bilinear(self.R.gx, xy), self.R.bilinear(self.R.gy, xy)])
        n = np.linalg.norm(g, axis=1)
        ok = n > 1e-12
        out = np.zeros_like(g)
        out[ok] = g[ok] / n[ok, None]
        if fallback is not None:
            out[~ok] = fallback[~ok]
        return out

    def onto(self, xy: np.ndarray, z: float, d: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Move points onto the level ``z`` along the unit directions ``d`` (uphill), to
        within ``width`` of where the tip crosses it; returns the low-side points (tip Z
        at or below ``z``) and a mask of points that could be bracketed."""
        h = self.R.spacing
        lo = xy - h * d
        hi = xy + h * d
        flo = self.zc(lo) - z
        fhi = self.zc(hi) - z
        bad = (flo > 0) | (fhi < 0)
        if bad.any():                                   # widen once
            lo2 = xy - 3 * h * d
            hi2 = xy + 3 * h * d
            lo = np.where(bad[:, None] & (flo > 0)[:, None], lo2, lo)
            hi = np.where(bad[:, None] & (fhi < 0)[:, None], hi2, hi)
            flo = self.zc(lo) - z
            fhi = self.zc(hi) - z
        ok = (flo <= 0) & (fhi >= 0)
        L, H = lo[ok], hi[ok]
        fL, fH = flo[ok], fhi[ok]
        w = np.linalg.norm(H - L, axis=1)
        # secant and bisection: each round two points straddle the guess (the secant's,
        # or the middle when the last round did not halve the bracket), 0.9 width
        # apart, and the bracket becomes the part between them where the tip crosses z
        # (f(L) <= 0 < f(H), as bisection keeps): a smooth CL wall is bracketed within
        # the width in two or three rounds instead of a dozen halvings
        halve = np.zeros(len(L), bool)
        cap = int(math.ceil(math.log2(max(w.max(initial=0.0), 1e-12) / self.width))) + 1
        for _ in range(2 * cap + 2):      # a round that does not halve: the next does
            act = np.nonzero(w > self.width)[0]
            if len(act) == 0:
                break
            Lp, Hp, fl, fh, wa = L[act], H[act], fL[act], fH[act], w[act]
            with np.errstate(divide="ignore", invalid="ignore"):
                t = np.where(fh > fl, fl / (fl - fh), 0.5)
            t = np.where(halve[act], 0.5, np.clip(t, 0.0, 1.0))
            e = 0.45 * self.width / wa
            ta = np.clip(t - e, 0.0, 1.0)
            tb = np.clip(t + e, 0.0, 1.0)
            Xa = Lp + (Hp - Lp) * ta[:, None]
            Xb = Lp + (Hp - Lp) * tb[:, None]
            f = self.zc(np.concatenate([Xa, Xb])) - z
            fa, fb = f[:len(act)], f[len(act):]
            a_up, b_up = fa > 0, fb > 0
            nL = np.where(a_up[:, None], Lp, np.where(b_up[:, None], Xa, Xb))
            nH = np.where(a_up[:, None], Xa, np.where(b_up[:, None], Xb, Hp))
            fL[act] = np.where(a_up, fl, np.where(b_up, fa, fb))
            fH[act] = np.where(a_up, fa, np.where(b_up, fb, fh))
            L[act], H[act] = nL, nH
            nw = np.linalg.norm(nH - nL, axis=1)
            halve[act] = nw > 0.5 * wa
            w[act] = nw
        out = xy.copy()
        out[ok] = L
        return out, ok

    def refine(self, P: np.ndarray, z: float) -> np.ndarray:
        """Insert level points where a segment's midpoint leaves the tolerance band."""
        min_len = 1e-3 * self.sampler.cutter.radius
        frozen = np.zeros(max(len(P) - 1, 0), bool)
        for _ in range(20):
            if len(P) < 2:
                return P
            mid = 0.5 * (P[1:] + P[:-1])
            zm = self.zc(mid)
            seg = np.linalg.norm(P[1:] - P[:-1], axis=1)
            g = np.hypot(self.R.bilinear(self.R.gx, mid), self.R.bilinear(self.R.gy, mid))
            cos = 1.0 / np.sqrt(1.0 + g * g)
            # a midpoint over nothing (the tool beside the part's outer wall) is not
            # split: no level point exists there
            bad = (((zm - z > self.tol_g) | ((z - zm) * cos > self.tol_m)) & (seg > min_len)
                   & ~frozen & (zm > self.R.z_low))
            if not bad.any():
                break
            idx = np.nonzero(bad)[0]
            t = P[idx + 1] - P[idx]
            nrm = np.column_stack([t[:, 1], -t[:, 0]]) / np.maximum(seg[idx], 1e-300)[:, None]
            d = self.uphill(mid[idx], nrm)
            q, ok = self.onto(mid[idx], z, d)
            # a midpoint that cannot be bracketed is not split again (halving the chord
            # does not bring it onto the level); the chord is kept only if it does not
            # gouge (:func:`_gouge_split` removes it otherwise)
            # material side: the level point found is an upper bound of the distance
            # to the CL surface (it lies on it); at a vertical CL wall the raster's
            # slope says nothing, this does
            near = ok & (zm[idx] < z) & (np.linalg.norm(q - mid[idx], axis=1) <= self.tol_m)
            frozen[idx[~ok | near]] = True
            use = ok & ~near
            ins = idx[use]
            P = np.insert(P, ins + 1, q[use], axis=0)
            frozen = np.insert(frozen, ins + 1, False)
        return P

    def contours(self, z: float, keep: np.ndarray | None = None) -> list[np.ndarray]:
        """``(points, bracketed, valid, closed)`` of every contour at level ``z``: XY
        points moved onto the level (closed contours repeat their first point), whether
        each could be bracketed, and whether its raster node is valid (others are left
        where marching squares put them and are never cut). Points whose node is
        outside ``keep`` (a mask on the raster) are not moved (never cut either)."""
        out = []
        for L in self.gen.lines(z):
            L = np.asarray(L, float)
            if len(L) < 2:
                continue
            closed = bool(np.allclose(L[0], L[-1]))
            t = np.gradient(L, axis=0) if len(L) > 2 else np.repeat(L[1:] - L[:1], len(L), 0)
            nrm = np.column_stack([t[:, 1], -t[:, 0]])
            nrm /= np.maximum(np.linalg.norm(nrm, axis=1), 1e-300)[:, None]
            d = self.uphill(L, nrm)
            # nodes whose contact is on the mesh's open boundary are not cut: skip them
            valid = self.R.nearest(self.R.valid, L)
            move = valid if keep is None else valid & self.R.nearest(keep, L)
            Q = L.copy()
            ok = np.zeros(len(L), bool)
            if move.any():
                Q[move], ok[move] = self.onto(L[move], z, d[move])
                # nothing under the tool on the low side: the level runs down the
                # part's outer wall (the tool beside the part), not over the surface
                beside = ~np.isfinite(drop(self.sampler.index, self.sampler.cutter,
                                           Q[move]).z)
                valid[np.nonzero(move)[0][beside]] = False
            if closed:
                Q[-1] = Q[0]
                ok[-1] = ok[0]
                valid[-1] = valid[0]
            out.append((Q, ok, valid, closed))
        return out


def index_runs(good: np.ndarray, closed: bool = False) -> list[np.ndarray]:
    """Index runs where ``good`` holds; a closed polyline (last = first) wraps around."""
    n = len(good)
    if good.all():
        return [np.arange(n)]
    idx = np.nonzero(good)[0]
    if len(idx) == 0:
        return []
    runs = np.split(idx, np.nonzero(np.diff(idx) > 1)[0] + 1)
    if closed and len(runs) > 1 and runs[0][0] == 0 and runs[-1][-1] == n - 1:
        runs = [np.concatenate([runs[-1][:-1], runs[0]])] + runs[1:-1]
    return runs


def _orient(P: np.ndarray, R: Raster, climb: bool) -> np.ndarray:
    """Reverse ``P`` unless the rising surface is on the right (climb) / left."""
    if len(P) < 2:
        return P
    t = np.gradient(P, axis=0)
    g = np.column_stack([R.bilinear(R.gx, P), R.bilinear(R.gy, P)])
    right = t[:, 1] * g[:, 0] - t[:, 0] * g[:, 1]          # (ty, -tx) . g
    on_right = float(right.sum()) >= 0.0
    return P if on_right == climb else P[::-1]


def _allowed_dz(R: Raster, pts: np.ndarray, r: float, h: float, min_slope: float,
                keep: np.ndarray | None) -> np.ndarray:
    """Largest level step at each point (inf where the scallop is not held there)."""
    if len(pts) == 0:
        return np.zeros(0)
    slope = R.bilinear(R.slope, pts)
    use = (slope >= min_slope) & R.nearest(R.valid, pts)
    if keep is not None:
        use &= R.nearest(keep, pts)
    rho_cl = R.nearest(R.rho, pts) + r
    # convex CL surface (a bump, or the rounding over a convex crease): the flat step,
    # which is smaller than the formula's; concave: the formula (smaller than flat)
    eps = np.where(rho_cl > 0, flat_side_step(r, h),
                   np.asarray(side_step(r, rho_cl - r, h), float))
    return np.where(use, eps * np.sin(np.radians(slope)), np.inf)


def waterline(sampler: Sampler, s: WaterlineSettings, raster: Raster | None = None,
              keep: np.ndarray | None = None) -> WaterlineResult:
    """Plan the waterline passes (see the module docstring); tip points in XY.

    ``keep`` is an optional boolean mask on the raster's nodes: points whose nearest
    node is outside it are not cut (and do not set the level step)."""
    r = effective_radius(sampler)
    h = s.scallop
    target = max(0.9 * h - min(s.material_tolerance or s.tolerance, 0.25 * h), 0.25 * h)
    spacing = s.spacing or sampler.cutter.radius / 8.0
    R = raster if raster is not None else make_raster(sampler, s.region, spacing)
    lv = _Level(sampler, R, s)
    zmax = float(R.z[R.valid].max())
    zmin = float(R.z[R.valid].min())
    top = zmax - s.tolerance
    bottom = zmin + s.tolerance
    if s.z_range is not None:
        bottom = max(bottom, s.z_range[0])
        top = min(top, s.z_range[1])
    dz_max = s.stepdown_max or r
    flat = flat_side_step(r, target)
    far = 2.0 * r                                 # beyond: no contour above to compare

    def allowed(C) -> float:
        pts = np.concatenate([Q[ok] for Q, ok, _, _ in C]) if C else np.zeros((0, 2))
        a = _allowed_dz(R, pts, r, target, s.min_slope, keep)
        return float(min(dz_max, a.min(initial=np.inf)))

    def chord_ratio(C_up, C, dz: float) -> float:
        """Largest measured chord between the level and the one above over the allowed
        one, at points where the scallop is held and the level above is near."""
        from scipy.spatial import cKDTree
        up = np.concatenate([Q[ok] for Q, ok, _, _ in C_up]) if C_up else np.zeros((0, 2))
        pts = np.concatenate([Q[ok] for Q, ok, _, _ in C]) if C else np.zeros((0, 2))
        if len(up) < 2 or len(pts) == 0:
            return 0.0
        a = _allowed_dz(R, pts, r, target, s.min_slope, keep)
        sel = np.isfinite(a)
        if not sel.any():
            return 0.0
        # nearest distance to the polylines above, on densified vertices
        segs = [densify(Q, 0.1 * flat) for Q, _, _, _ in C_up]
        tree = cKDTree(np.concatenate(segs))
        dxy, _ = tree.query(pts[sel])
        slope = np.radians(R.bilinear(R.slope, pts[sel]))
        eps = a[sel] / np.maximum(np.sin(slope), 1e-9)
        near = dxy < far
        if not near.any():
            return 0.0
        c = np.sqrt(dxy[near] ** 2 + dz * dz)
        return float((c / eps[near]).max())

    levels: list[float] = []
    contours: list[list] = []
    worst = 0.0
    z = top
    C = lv.contours(z, keep)
    while True:
        levels.append(z)
        contours.append(C)
        if s.on_level is not None:
            s.on_level(len(levels), z)
        if z <= bottom + 1e-12:
            break
        if len(levels) >= s.max_levels:
            raise PlanningError(f"waterline: more than {s.max_levels} levels: scallop {h} "
                                "is too small for this surface and cutter")
        dz = allowed(C)
        for _ in range(6):
            z2 = max(z - dz, bottom)
            C2 = lv.contours(z2, keep)
            a2 = allowed(C2)
            ratio = chord_ratio(C, C2, z - z2)
            new = min(dz, a2, dz / ratio if ratio > 1.0 else dz)
            if new >= dz * 0.999 or z2 <= bottom and new >= z - bottom:
                break
            dz = 0.95 * new
        worst = max(worst, chord_ratio(C, C2, z - z2))
        z, C = z2, C2

    # cut: split where points are unbracketed, off the keep mask or the holder is lifted
    removed = {"unbracketed": 0, "edge": 0, "holder": 0, "outside_mask": 0}
    passes: list[Pass] = []
    cur = None
    n_cont = 0
    for z, C in zip(levels, contours):
        pieces = []
        for Q, ok, valid, closed in C:
            good = ok & valid
            removed["edge"] += int((~valid).sum())
            inside = R.nearest(keep, Q) if keep is not None else np.ones(len(Q), bool)
            removed["unbracketed"] += int((valid & ~ok & inside).sum())
            if keep is not None:
                removed["outside_mask"] += int((valid & ~inside).sum())
                good &= inside
            for run in index_runs(good, closed):
                if len(run) < 2:
                    continue
                P = Q[run]
                is_closed = closed and len(run) >= len(Q) - 1 and good.all()
                P = lv.refine(P, z)
                P3 = np.column_stack([P, np.full(len(P), z)])
                P3 = merge_collinear(P3, 0.2 * min(lv.tol_g, lv.tol_m))
                P = lv.refine(P3[:, :2], z)
                if is_closed:
                    P[-1] = P[0]
                for Pc in _gouge_split(lv, P, z, is_closed, removed):
                    pieces.extend(_holder_split(sampler, Pc, z, is_closed and Pc is P,
                                                removed))
        pieces = [_orient(P, R, s.climb) for P in pieces]
        # order: nearest first; closed loops start nearest the current position
        while pieces:
            if cur is None:
                k = 0
            else:
                dist = [float(np.min(np.linalg.norm(P - cur, axis=1))) if _closed(P)
                        else float(np.linalg.norm(P[0] - cur)) for P in pieces]
                k = int(np.argmin(dist))
            P = pieces.pop(k)
            if _closed(P) and cur is not None:
                i = int(np.argmin(np.linalg.norm(P - cur, axis=1)))
                P = np.concatenate([P[i:-1], P[:i + 1]])
            cur = P[-1]
            passes.append(Pass(np.column_stack([P, np.full(len(P), z)]),
                               np.zeros(len(P), bool)))
            n_cont += 1
    return WaterlineResult(passes, levels, n_cont, removed, worst, R)


def _closed(P: np.ndarray) -> bool:
    return len(P) > 3 and bool(np.all(P[0] == P[-1]))


def _gouge_split(lv: _Level, P: np.ndarray, z: float, closed: bool,
                 removed: dict) -> list[np.ndarray]:
    """``P`` without the points below the drop-cutter Z and the segments a point of which
    (the middle, and every tenth of the tool radius along a long one) is more than the
    tolerance below it (left only where refinement could not bracket the level);
    returns ``[P]`` itself when nothing is removed."""
    if len(P) < 2:
        return []
    zp = lv.zc(P)
    # each segment sampled at its middle, and a long one every tenth of the tool radius
    # (near the part's edge the drop-cutter height changes fast along a segment)
    d = P[1:] - P[:-1]
    n = np.maximum(1, np.ceil(np.hypot(d[:, 0], d[:, 1])
                              / (0.1 * lv.sampler.cutter.radius)).astype(np.int64))
    Q, which = points_along(P[:-1], P[1:], n)
    zm = lv.zc(Q)
    seg = np.zeros(len(d), bool)
    np.logical_or.at(seg, which, zm > z + lv.tol_g)
    bad = zp > z + 1e-9
    removed["unbracketed"] += int(bad.sum())
    if not (bad.any() or seg.any()):
        return [P]
    bad[:-1] |= seg
    bad[1:] |= seg
    return [P[run] for run in index_runs(~bad, closed) if len(run) >= 2]


def _holder_split(sampler: Sampler, P: np.ndarray, z: float, closed: bool,
                  removed: dict) -> list[np.ndarray]:
    """Pieces of ``P`` where neither the shank nor a holder cylinder reaches the mesh
    with the tip at ``z`` (points and segment midpoints checked)."""
    if not sampler.holder or len(P) < 2:
        return [P] if len(P) >= 2 else []
    mid = 0.5 * (P[1:] + P[:-1])
    allp = np.concatenate([P, mid])
    uw = sampler.uw(allp[:, 0], allp[:, 1])
    lift = sampler.holder_lift(uw[:, 0], uw[:, 1], below=np.full(len(uw), z)) > z + 1e-9
    bad_p = lift[:len(P)].copy()
    bad_m = lift[len(P):]
    bad_p[:-1] |= bad_m
    bad_p[1:] |= bad_m
    removed["holder"] += int(lift[:len(P)].sum())
    if not bad_p.any():
        return [P]
    out = []
    for run in index_runs(~bad_p, closed):
        if len(run) >= 2:
            out.append(P[run])
    return out
