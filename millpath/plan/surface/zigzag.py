"""Zigzag finishing on the cutter-location surface.

Passes run along ``u`` (at ``angle`` from +X, see :mod:`.sampler`) and step across in
``w``. Every pass is a polyline of tool-tip points (job units) that

- is sampled by constant CL arc length (denser where steep), the step from the chord
  tolerance and the local curvature along the pass (:func:`.steps.feed_step`);
- is verified at evenly spaced points of every segment (three, or more for a ball so
  that they are at most ``sqrt(0.4 r tolerance)`` apart, see :func:`_refine_many`): the
  drop-cutter Z there may exceed the chord by at most ``tolerance`` (the gouge side)
  and fall below it by at most ``material_tolerance`` (the material side); failing
  segments are split, collinear points merged, and the merged chords verified again;
- never lets the shank or the holder touch the surface (points are lifted, counted).

Side step, ``side_step = "published"``: every pass is a straight line; the step to the
next is the smallest, over the pass, of the published scallop formula with the local
curvature across the passes, projected on XY by the cross slope.
``side_step = "variable"``: the same formula at each station along the pass, each station
keeping its own step (held also to the step found halfway to each neighbour), so the
next pass is a curve ``w(u)`` and no station pays for the worst one.
In both, the scallop is held under ``h`` measured vertically (the formula gets the
normal height ``h cos(slope)``), less an allowance for the feed chords on the material
side, so a Z-map simulation measures at most ``h``. The formula is local: over a
convex crease (or the surface's edge, which the tool rolls over) it allows up to a
cutter diameter that the surface beyond cannot take, so each step is also limited by
the step the formula gives at the candidate next line (:func:`_look_ahead`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Callable

import numpy as np

from millpath.errors import PlanningError
from millpath.geometry.spacing import points_along
from millpath.model.limits import MAX_PASS_LINES
from millpath.plan.surface.polyline import chord_offsets, collinear_keep
from millpath.plan.surface.sampler import Sampler
from millpath.plan.surface.steps import curvature_radius, feed_step, flat_side_step, side_step


#: job units: a merged chord through points this near it needs no new check
ON_CHORD = 1e-9


@dataclass
class ZigzagSettings:
    """Tolerances and steps (job units). ``region`` is ``(xmin, ymin, xmax, ymax)``
    of the tool tip; ``station`` the spacing of the stations along the passes where
    side steps are computed. ``trim_edges``: the region is the surface grown by the
    cutter radius; the first and last pass at each station are moved in to where the
    contact point just reaches the surface's edge (see :func:`edge_lines`). ``keep``:
    XY points ``(n, 2)`` -> where passes are wanted (steep-shallow's shallow side and
    the overlap), no points are planned elsewhere; ``hold``: where the scallop sets the
    side step (default ``keep``; steep-shallow: the overlap band below
    :data:`.steep_shallow.HOLD_MAX_SLOPE`). With ``hold`` given, a line station off the
    held ground advances to where it is held again (at most the flat step), one on it
    stops at its border, and a slope is measured one-sided beside it. ``silhouette``:
    passes are cut where the cutter touches nothing (its tip farther than its radius
    from the part's silhouette, see :func:`beside_part`), so the tool never runs down
    the outside of the part to ``z_floor``."""

    tolerance: float
    scallop: float
    region: tuple[float, float, float, float]
    side_step: str = "variable"
    material_tolerance: float | None = None
    station: float | None = None
    max_step: float | None = None
    max_passes: int = MAX_PASS_LINES
    trim_edges: bool = False
    keep: Callable[[np.ndarray], np.ndarray] | None = None
    hold: Callable[[np.ndarray], np.ndarray] | None = None
    on_line: Callable[[int], None] | None = None      # progress: pass lines so far
    silhouette: bool = False    # split passes where the tool is beside the part


@dataclass
class Pass:
    points: np.ndarray          # (n, 3) tool tip x, y, z
    lifted: np.ndarray          # (n,) bool: raised to clear the shank or holder


def passes_length(passes: list[Pass]) -> float:
    """Cutting length along ``passes`` (job units, links excluded)."""
    return float(sum(np.linalg.norm(np.diff(p.points, axis=0), axis=1).sum() for p in passes))


def passes_points(passes: list[Pass]) -> int:
    """Number of CL points in ``passes``."""
    return int(sum(len(p.points) for p in passes))


class PassStats:
    """Mixin for results holding ``passes``: cutting length (job units, links
    excluded) and CL point count."""

    passes: list[Pass]

    @property
    def length(self) -> float:
        return passes_length(self.passes)

    @property
    def n_points(self) -> int:
        return passes_points(self.passes)


@dataclass
class ZigzagResult(PassStats):
    passes: list[Pass]
    steps: list[float] = field(default_factory=list)   # XY side step per pass (mean)
    min_step: float = 0.0
    n_lines: int = 0                                    # pass lines across the region

    @property
    def n_lifted(self) -> int:
        return int(sum(int(p.lifted.sum()) for p in self.passes))


def effective_radius(sampler: Sampler) -> float:
    """Radius of the cutter part that leaves the scallops: the ball, or a bull's corner."""
    c = sampler.cutter
    if c.corner <= 0.0:
        raise PlanningError("scallop-driven finishing needs a ball or bull-nose cutter, "
                            "not a flat end mill")
    return c.corner


def _frame_box(sampler: Sampler, region) -> tuple[float, float, float, float]:
    x0, y0, x1, y1 = region
    uw = sampler.uw(np.array([x0, x1, x1, x0]), np.array([y0, y0, y1, y1]))
    return uw[:, 0].min(), uw[:, 0].max(), uw[:, 1].min(), uw[:, 1].max()


def in_region(sampler: Sampler, region, u, w) -> np.ndarray:
    x0, y0, x1, y1 = region
    xy = sampler.xy(u, w)
    e = 1e-9
    return ((xy[..., 0] >= x0 - e) & (xy[..., 0] <= x1 + e)
            & (xy[..., 1] >= y0 - e) & (xy[..., 1] <= y1 + e))


def _runmin(a: np.ndarray, k: int = 1) -> np.ndarray:
    out = a.copy()
    for s in range(1, k + 1):
        out[s:] = np.minimum(out[s:], a[:-s])
        out[:-s] = np.minimum(out[:-s], a[s:])
    return out


class StepMemo:
    """Station steps already computed, per station: a station's step depends on its own
    point ``(u, w)`` only, so a look-ahead round that moves a few stations recomputes
    those alone. Keyed by the stations' ``u`` array (the pass stations, or the halfway
    points between them); ``slots`` recent ``w`` per station are kept."""

    def __init__(self, slots: int = 8):
        self.slots = slots
        self.rows: dict[bytes, tuple[np.ndarray, np.ndarray, np.ndarray]] = {}

    def lookup(self, u: np.ndarray, W: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(step, known) at each station: ``known`` where ``(u, W)`` was stored."""
        key = u.tobytes()
        if key not in self.rows:
            n = len(u)
            self.rows[key] = (np.full((n, self.slots), np.nan), np.full((n, self.slots), np.nan),
                              np.zeros(n, np.int64))
        Wc, Ec, _ = self.rows[key]
        hit = Wc == W[:, None]
        known = hit.any(axis=1)
        step = Ec[np.arange(len(u)), np.argmax(hit, axis=1)]
        return np.where(known, step, np.nan), known

    def store(self, u: np.ndarray, W: np.ndarray, step: np.ndarray, where: np.ndarray) -> None:
        Wc, Ec, nxt = self.rows[u.tobytes()]
        i = np.nonzero(where)[0]
        Wc[i, nxt[i]] = W[i]
        Ec[i, nxt[i]] = step[i]
        nxt[i] = (nxt[i] + 1) % self.slots


def _station_steps(sampler: Sampler, u, W, r, h, fd, keep=None, need=None,
                   memo: StepMemo | None = None) -> np.ndarray:
    """XY side step at each station from the published formula with the local curvature
    and slope across the passes. The scallop is limited to ``h`` measured vertically:
    the normal height used in the formula is ``h cos(slope)``. NaN where unknown (no
    surface, or outside ``keep``) or not ``need``-ed. One drop-cutter batch for the
    three rows. ``memo`` (one per ``sampler, r, h, fd, keep``): steps of stations
    already computed at the same point are reused."""
    u = np.asarray(u, float)
    W = np.asarray(W, float)
    want = np.ones(len(u), bool) if need is None else np.asarray(need, bool)
    if memo is not None:
        out, known = memo.lookup(u, W)
        todo = want & ~known
        if todo.any():
            out[todo] = _station_steps(sampler, u[todo], W[todo], r, h, fd, keep)
            memo.store(u, W, out, todo)
        return np.where(want, out, np.nan)
    if not np.all(want):
        out = np.full(len(u), np.nan)
        if np.any(want):
            out[want] = _station_steps(sampler, u[want], W[want], r, h, fd, keep)
        return out
    n = len(u)
    uu, ww = np.concatenate([u, u, u]), np.concatenate([W - fd, W, W + fd])
    z = sampler.z_cut(uu, ww)
    zm, z0, zp = z[:n], z[n:2 * n], z[2 * n:]
    if keep is None:
        ok = np.isfinite(zm) & np.isfinite(z0) & np.isfinite(zp)
    else:
        # a neighbour row off the held ground (a wall the waterline finishes, or no
        # surface) does not set the slope: one-sided difference from the other row
        held = np.isfinite(z) & np.asarray(keep(sampler.xy(uu, ww)), bool)
        hm, h0, hp = held[:n], held[n:2 * n], held[2 * n:]
        zm0 = zm
        zm = np.where(hm, zm, np.where(hp, 2.0 * z0 - zp, z0))
        zp = np.where(hp, zp, np.where(hm, 2.0 * z0 - zm0, z0))
        ok = h0
    out = np.full(n, np.nan)
    rho_cl, slope = curvature_radius(zm[ok], z0[ok], zp[ok], fd)
    cos = 1.0 / np.sqrt(1.0 + slope * slope)
    out[ok] = side_step(r, rho_cl - r, h * cos) * cos
    return out


def edge_lines(sampler: Sampler, design, u: np.ndarray, wmin: float, wmax: float,
               slack: float, iterations: int = 14) -> tuple[np.ndarray, np.ndarray]:
    """First and last pass line ``w(u)`` for a region grown beyond the surface.

    At each station the surface spans ``[e0, e1]`` in ``w`` (where the design is
    finite). The first line is the largest ``w <= e0`` at which the cutter's contact
    point lies within ``slack`` of ``e0`` (so the edge is finished), found by
    bisection; likewise the last line from ``e1``. Between there and the grown
    region's bound the tool would only roll over the edge. Stations with no surface take
    the lines of the nearest station with surface if it is within a cutter radius (the
    pass runs on over the edge), else an empty span (first line = last line).
    """
    n = len(u)
    k = 257
    ws = np.linspace(wmin, wmax, k)
    uu = np.repeat(u, k)
    xy = sampler.xy(uu, np.tile(ws, n))
    fin = np.isfinite(design.height(xy[:, 0], xy[:, 1])).reshape(n, k)
    has = fin.any(axis=1)
    i0 = np.where(has, np.argmax(fin, axis=1), 0)
    i1 = np.where(has, k - 1 - np.argmax(fin[:, ::-1], axis=1), 0)
    e0, e1 = ws[i0], ws[i1]

    def reaches(w, lower: bool) -> np.ndarray:
        _, _, cw = sampler.cut(u, w)
        ok = (cw <= e0 + slack) if lower else (cw >= e1 - slack)
        return ok | ~np.isfinite(cw)

    def search(edge, bound, lower: bool) -> np.ndarray:
        good = np.where(reaches(edge, lower), edge, bound)      # known to reach
        bad = edge.copy()                                         # known not to
        todo = good != edge
        for _ in range(iterations):
            mid = 0.5 * (good + bad)
            ok = reaches(mid, lower)
            good = np.where(todo & ok, mid, good)
            bad = np.where(todo & ~ok, mid, bad)
        return good

    W0 = search(e0, np.full(n, wmin), True)
    W1 = np.maximum(search(e1, np.full(n, wmax), False), W0)
    if not has.any():
        return np.full(n, wmin), np.full(n, wmin)
    # beyond the surface's ends along the passes the lines run straight on, one cutter
    # radius (the tool rolls over the edge there); further out nothing is cut
    W0 = np.interp(u, u[has], W0[has])
    W1 = np.interp(u, u[has], W1[has])
    uh = u[has]
    gap = np.min(np.abs(u[:, None] - uh[None, :]), axis=1) if n * len(uh) < 4_000_000 \
        else np.abs(u - np.interp(u, uh, uh))
    far = gap > sampler.cutter.radius + 1e-9
    W1 = np.where(far, W0, W1)
    return W0, W1


def pass_lines(sampler: Sampler, design, s: ZigzagSettings) -> tuple[np.ndarray, list[np.ndarray], list[float]]:
    """Stations ``u`` and the ``w(u)`` of every pass, with the XY step taken after each."""
    r = effective_radius(sampler)
    h = s.scallop
    umin, umax, wmin, wmax = _frame_box(sampler, s.region)
    st = s.station or min(0.5, sampler.cutter.radius / 4.0)
    n = max(2, int(math.ceil((umax - umin) / st)) + 1)
    u = np.linspace(umin, umax, n)
    flat = flat_side_step(r, h)
    fd = min(0.25 * r, max(4.0 * flat, 1e-3))
    if s.trim_edges:
        W, wmax = edge_lines(sampler, design, u, wmin, wmax, 0.5 * flat_side_step(r, h))
    else:
        W = np.full(n, wmin)
    lines = [W.copy()]
    memo = StepMemo()                     # station steps at recent points
    steps: list[float] = []
    target = 0.9 * h - min(s.material_tolerance or s.tolerance, 0.25 * h)
    target = max(target, 0.25 * h)
    while np.any(W < wmax - 1e-9):
        if len(lines) >= s.max_passes:
            raise PlanningError(f"more than {s.max_passes} passes: scallop {h} is too small "
                                f"for this surface and cutter")
        inside = in_region(sampler, s.region, u, W)
        hold = s.hold or s.keep
        eps = _station_steps(sampler, u, W, r, target, fd, hold, memo=memo)
        known = inside & np.isfinite(eps)
        if not known.any():
            dW = np.full(n, flat_side_step(r, target))
        elif s.side_step == "published":
            dW = np.full(n, float(eps[known].min()))        # the worst station, whole pass
        else:
            e = np.where(known, eps, np.inf)
            if hold is None:
                e = np.where(np.isfinite(e), e, float(eps[known].min()))
            else:
                # a station where the scallop is not held (the waterline's side of a
                # steep-shallow) runs on to where it is held again, at most the flat step
                e = np.where(np.isfinite(e), e, _to_held(sampler, u, W, hold,
                                                         flat_side_step(r, target)))
            dW = _between(sampler, u, W, e, r, target, fd, hold,  # each station its own
                          memo=memo)
        dW = _look_ahead(sampler, u, W, dW, wmax, r, target, fd, s.side_step == "published",
                         hold, memo=memo)
        if hold is not None and s.side_step != "published":
            dW = _held_end(sampler, u, W, dW, hold)
        Wn = np.minimum(W + dW, wmax)
        steps.append(float(np.mean(Wn - W)))
        W = Wn
        lines.append(W.copy())
        if s.on_line is not None:
            s.on_line(len(lines))
    return u, lines, steps


def _held_end(sampler: Sampler, u, W, dW, hold, k: int = 16) -> np.ndarray:
    """``dW`` shortened, at stations on held ground, to the last of ``k`` samples ahead
    before the held ground ends: the next line lies at its border (a wall's foot), so
    the held ground up to it is finished by the zigzag, not left to the waterline."""
    t = np.arange(1, k + 1) / k
    uu = np.repeat(u, k)
    ww = (W[:, None] + dW[:, None] * t[None, :]).ravel()
    h = np.asarray(hold(sampler.xy(uu, ww)), bool).reshape(len(u), k)
    here = np.asarray(hold(sampler.xy(u, W)), bool)
    ends = here & ~h.all(axis=1)
    first_off = np.argmin(h, axis=1)                  # first sample off the held ground
    last_on = np.where(first_off > 0, t[np.maximum(first_off - 1, 0)], 0.0)
    out = dW.copy()
    cut = ends & (first_off > 0)
    out[cut] = dW[cut] * last_on[cut]
    return out


def _to_held(sampler: Sampler, u, W, hold, cap: float, k: int = 16) -> np.ndarray:
    """Step in ``w`` from each line point ``(u, W)`` to the first of ``k`` samples
    ``cap / k`` apart ahead where ``hold`` holds (``cap`` if none): a line crossing
    ground where the scallop is not held does not jump over held ground beyond."""
    d = cap * np.arange(1, k + 1) / k
    uu = np.repeat(u, k)
    ww = (W[:, None] + d[None, :]).ravel()
    h = np.asarray(hold(sampler.xy(uu, ww)), bool).reshape(len(u), k)
    first = np.where(h.any(axis=1), np.argmax(h, axis=1), k - 1)
    return d[first]


def _between(sampler: Sampler, u, W, step, r: float, target: float, fd: float,
             keep=None, need=None, memo: StepMemo | None = None) -> np.ndarray:
    """Each station's step, also held to the steps found halfway to its neighbours (on
    the chord between their points): the passes are straight between stations, so the
    surface there counts too, but not what a neighbour meets farther along w."""
    if len(u) < 2:
        return np.asarray(step, float)
    um, wm = 0.5 * (u[1:] + u[:-1]), 0.5 * (W[1:] + W[:-1])
    em = _station_steps(sampler, um, wm, r, target, fd, keep,
                        None if need is None else need[1:] | need[:-1], memo)
    em = np.where(np.isfinite(em), em, np.inf)
    out = np.asarray(step, float).copy()
    out[1:] = np.minimum(out[1:], em)
    out[:-1] = np.minimum(out[:-1], em)
    return out


def _look_ahead(sampler: Sampler, u, W, dW, wmax, r: float, target: float,
                fd: float, uniform: bool, keep=None, rounds: int = 4,
                memo: StepMemo | None = None) -> np.ndarray:
    """Shrink the step ``dW`` to the published step found at the candidate next line:
    the formula is local, and over a convex crease (or the edge the tool rolls over)
    it allows up to a cutter diameter that the surface beyond cannot take. Each round
    takes ``min(dW, step at W + dW)`` (the whole pass for ``uniform``)."""
    dW = np.asarray(dW, float).copy()
    for _ in range(rounds):
        Wn = np.minimum(W + dW, wmax)
        live = Wn < wmax - 1e-9               # stations at the last line need no step
        ahead = _station_steps(sampler, u, Wn, r, target, fd, keep, live, memo)
        ok = np.isfinite(ahead) & live
        if not ok.any():
            break
        new = np.where(ok, np.minimum(dW, ahead), dW)
        if uniform:
            new = np.full_like(dW, float(new.min()))
        else:
            new = _between(sampler, u, Wn, new, r, target, fd, keep, live, memo)
        if np.allclose(new[live], dW[live], rtol=1e-3, atol=0.0):
            break
        dW = new
    return dW


def refine_chords_many(sampler: Sampler, Ps: list[np.ndarray], tol_g: float, tol_m: float,
                       min_len: float, checks: int = 3) -> list[np.ndarray]:
    """Split the segments of every polyline in ``Ps`` (rows u, w, z) that deviate beyond
    tolerance at any of ``checks`` evenly spaced interior points (the midpoint alone
    misses a bump of the CL surface narrower than half a segment), and for a ball or
    bull cutter at points close enough that no CL cap rises over the tolerance between
    them (see :func:`_refine_many`), inserting the worst point, until none does: one
    drop-cutter batch per round for all of them (numba's parallel loop), and a segment
    found within tolerance is not checked again (its ends do not change)."""
    return _refine_many(sampler, Ps, tol_g, tol_m, min_len, checks,
                        r=max(sampler.cutter.corner, 0.0))[0]


def _refine_many(sampler: Sampler, Ps: list[np.ndarray], tol_g: float, tol_m: float,
                 min_len: float, checks: int = 3, good: list[np.ndarray] | None = None,
                 r: float = 0.0) -> tuple[list[np.ndarray], list[np.ndarray]]:
    """:func:`refine_chords_many`, skipping the segments ``good`` marks (per polyline,
    per segment: checked before at these same ends); also returns the segments found
    within tolerance (or too short to split).

    With ``r > 0`` (the ball's radius, or the bull's corner) a chord is also checked on
    the gouge side at points ``s = sqrt(0.4 r tol_g)`` apart (3D; at least ``checks``
    evenly spaced points): where the CL curves along the pass with a radius of at least
    ``r`` (a ball over a convex edge or surface), it rises above the chord between two
    such points by at most ``s^2 / (8 r) = tol_g / 20`` more than at them, so each point
    is held to ``0.95 tol_g``. Three checks per chord alone let a CL cap between them
    through (surface-cavity: 0.0107 mm for 0.01)."""
    if not Ps:
        return [], []
    s = math.sqrt(0.4 * r * tol_g) if r > 0.0 else math.inf
    lim_g = 0.95 * tol_g if r > 0.0 else tol_g
    P = np.concatenate(Ps)
    pid = np.repeat(np.arange(len(Ps)), [len(Q) for Q in Ps])
    todo = pid[:-1] == pid[1:]                      # segments still to check
    if good is not None:
        todo &= ~np.concatenate([np.append(g, False) for g in good])[:-1]
    for _ in range(20):
        idx = np.nonzero(todo)[0]
        if len(idx) == 0:
            break
        A, B = P[idx], P[idx + 1]
        n = np.full(len(idx), checks, np.int64)
        if r > 0.0:
            dense = np.ceil(np.linalg.norm(B - A, axis=1) / s).astype(np.int64) - 1
            n = np.maximum(n, dense)
        Q, row = points_along(A, B, n)
        zt, _ = sampler.z_safe(Q[:, 0], Q[:, 1])
        dev = zt - Q[:, 2]
        over = np.maximum(dev - lim_g, -dev - tol_m)             # > 0: outside
        # the worst check point of each chord (its first, on a tie; NaN counts least)
        first = np.cumsum(n) - n
        top = np.fmax.reduceat(over, first)
        pos = np.where(over == top[row], np.arange(len(over)), len(over))
        worst = np.minimum.reduceat(pos, first)
        worst = np.where(worst < len(over), worst, first)
        seg = np.hypot(B[:, 0] - A[:, 0], B[:, 1] - A[:, 1])
        bad = (over[worst] > 0) & (seg > min_len)
        todo[idx[~bad]] = False
        if not bad.any():
            break
        new = Q[worst[bad]].copy()
        new[:, 2] = zt[worst[bad]]
        at = idx[bad]
        P = np.insert(P, at + 1, new, axis=0)
        pid = np.insert(pid, at + 1, pid[at])
        todo = np.insert(todo, at + 1, True)          # both halves are checked next
    counts = np.bincount(pid, minlength=len(Ps))
    ends = np.cumsum(counts)
    ok = ~todo
    return (np.split(P, ends[:-1]),
            [ok[e - c:e - 1] for e, c in zip(ends, counts)])


def sample_passes(sampler: Sampler, runs: list[tuple[np.ndarray, np.ndarray]],
                  s: ZigzagSettings, r: float) -> list[np.ndarray | None]:
    """:func:`sample_pass` of every ``(u, W)`` run, with one drop-cutter batch per step
    for all of them."""
    runs = [(u[m], W[m]) for u, W in runs
            for m in [in_region(sampler, s.region, u, W)]]
    keep = [i for i, (u, _) in enumerate(runs) if len(u) >= 2]
    out: list[np.ndarray | None] = [None] * len(runs)
    if not keep:
        return out
    Us = np.concatenate([runs[i][0] for i in keep])
    Ws = np.concatenate([runs[i][1] for i in keep])
    Zs, _ = sampler.z_safe(Us, Ws)
    ends = np.cumsum([len(runs[i][0]) for i in keep])
    tol_g = s.tolerance
    tol_m = s.material_tolerance if s.material_tolerance is not None else s.tolerance
    max_step = s.max_step or 2.0 * sampler.cutter.radius
    samples, owners = [], []
    for i, u, W, Z in zip(keep, np.split(Us, ends[:-1]), np.split(Ws, ends[:-1]),
                          np.split(Zs, ends[:-1])):
        uw = _arc_samples(u, W, Z, r, min(tol_g, tol_m), max_step)
        if uw is not None:
            samples.append(uw)
            owners.append(i)
    if not samples:
        return out
    allp = np.concatenate(samples)
    z, _ = sampler.z_safe(allp[:, 0], allp[:, 1])
    Ps = np.split(np.column_stack([allp, z]), np.cumsum([len(q) for q in samples])[:-1])
    min_len = 1e-3 * max(r, 1e-3)
    Ps, good = _refine_many(sampler, Ps, tol_g, tol_m, min_len, r=r)
    # after merging, a segment between two points that were neighbours is one already
    # checked, and so is a chord through points it passes within ON_CHORD of (straight
    # stretches: the chords it replaces were checked at the same points, to within
    # that): only the other merged chords are checked again
    merged, good_m = [], []
    for P, g in zip(Ps, good):
        k = collinear_keep(P, 0.2 * min(tol_g, tol_m))
        merged.append(P[k])
        bad = np.concatenate([[0], np.cumsum(~g)])          # unchecked chords so far
        all_good = bad[k[1:]] == bad[k[:-1]]
        good_m.append(all_good & (chord_offsets(P, k) <= ON_CHORD))
    Ps, _ = _refine_many(sampler, merged, tol_g, tol_m, min_len, good=good_m, r=r)
    for i, P in zip(owners, Ps):
        out[i] = P
    return out


def _arc_samples(u: np.ndarray, W: np.ndarray, Z: np.ndarray, r: float, tol: float,
                 max_step: float) -> np.ndarray | None:
    """(u, w) rows sampled by constant CL arc length along one pass (see
    :func:`sample_pass`), from its stations' tip Z; None if under two stations."""
    ok = np.isfinite(Z)
    if not ok.all():
        u, W, Z = u[ok], W[ok], Z[ok]
    if len(u) < 2:
        return None
    seg = np.sqrt(np.diff(u) ** 2 + np.diff(W) ** 2 + np.diff(Z) ** 2)
    if len(u) >= 3:
        sxy = np.concatenate([[0.0], np.cumsum(np.hypot(np.diff(u), np.diff(W)))])
        ds = np.gradient(sxy)
        d1 = np.gradient(Z, sxy)
        d2 = np.gradient(d1, sxy)
        with np.errstate(divide="ignore", invalid="ignore"):
            rho_cl = np.where(np.abs(d2) < 1e-12, np.inf, -(1.0 + d1 * d1) ** 1.5 / d2)
        delta = feed_step(r, rho_cl - r, tol, max_step)
        delta = _runmin(np.maximum(delta, ds.min() * 0.5), 1)
    else:
        delta = np.full(len(u), max_step)
    N = np.concatenate([[0.0], np.cumsum(seg / np.minimum(delta[1:], delta[:-1]))])
    k = max(1, int(math.ceil(N[-1])))
    Ns = np.linspace(0.0, N[-1], k + 1)
    us = np.union1d(np.interp(Ns, N, u), u)
    return np.column_stack([us, np.interp(us, u, W)])


def sample_pass(sampler: Sampler, u: np.ndarray, W: np.ndarray, s: ZigzagSettings,
                r: float) -> np.ndarray | None:
    """Tolerance-driven CL points (rows u, w, z in the pass frame) along one pass: the
    stations inside the region, sampled by constant CL arc length with the feed step
    from the chord tolerance and the curvature along the pass (:func:`.steps.feed_step`),
    the stations kept too (``w(u)`` is piecewise linear between them, and a chord across
    a kink would leave the next pass's scallop wider than planned; collinear ones are
    merged), every chord verified (:func:`refine_chords_many`)."""
    return sample_passes(sampler, [(u, W)], s, r)[0]


def beside_part(sampler: Sampler, P: np.ndarray, touch: np.ndarray | None = None
                ) -> list[np.ndarray]:
    """The runs of ``P`` (rows u, w, z) where the cutter touches the part (at least two
    points each). The chord verification (:func:`refine_chords_many`) has already put points
    down the cliff where the drop-cutter falls to ``z_floor`` beside the part, so a run
    ends within the minimum segment length of the tool's last contact."""
    if touch is None:
        touch = sampler.touches(P[:, 0], P[:, 1])
    if touch.all():
        return [P]
    cut = np.nonzero(np.diff(touch.astype(np.int8)))[0] + 1
    return [Q for Q, t in zip(np.split(P, cut), np.split(touch, cut)) if t[0] and len(Q) > 1]


def zigzag(sampler: Sampler, design, s: ZigzagSettings) -> ZigzagResult:
    """Plan the zigzag passes (see module docstring); points are returned in XY."""
    if s.side_step not in ("published", "variable"):
        raise PlanningError(f"side_step must be published or variable, not {s.side_step!r}")
    r = effective_radius(sampler)
    u, lines, steps = pass_lines(sampler, design, s)
    wmax = lines[-1]
    passes: list[Pass] = []
    runs: list[tuple[np.ndarray, np.ndarray]] = []
    line_of: list[int] = []
    for k, W in enumerate(lines):
        # a station already on the last line was finished by the pass before
        active = (lines[0] < wmax - 1e-9) if k == 0 else lines[k - 1] < wmax - 1e-9
        active = active | np.roll(active, 1) | np.roll(active, -1)
        if s.keep is not None:
            # only where passes are wanted, two stations beyond (the caller trims)
            want = s.keep(sampler.xy(u, W))
            for _ in range(2):
                want = want | np.roll(want, 1) | np.roll(want, -1)
            active &= want
        for run in np.split(np.arange(len(u)), np.nonzero(np.diff(active.astype(int)))[0] + 1):
            if not active[run[0]] or len(run) < 2:
                continue
            runs.append((u[run], W[run]))
            line_of.append(k)
    sampled = sample_passes(sampler, runs, s, r)
    by_line: dict[int, list[np.ndarray]] = {}
    for k, P in zip(line_of, sampled):
        if P is not None:
            by_line.setdefault(k, []).append(P)
    out: list[np.ndarray] = []
    for k in sorted(by_line):
        pieces = by_line[k]
        if k % 2 == 1:
            pieces = [P[::-1] for P in pieces[::-1]]
        out.extend(pieces)
    if out and s.silhouette:
        allp = np.concatenate(out)
        touch = np.split(sampler.touches(allp[:, 0], allp[:, 1]),
                         np.cumsum([len(P) for P in out])[:-1])
        out = [Q for P, t in zip(out, touch) for Q in beside_part(sampler, P, t)]
    if out:
        allp = np.concatenate(out)
        _, lifted = sampler.z_safe(allp[:, 0], allp[:, 1])
        xy = sampler.xy(allp[:, 0], allp[:, 1])
        cut = np.cumsum([len(P) for P in out])[:-1]
        for P, xyp, lf in zip(out, np.split(xy, cut), np.split(lifted, cut)):
            passes.append(Pass(np.column_stack([xyp, P[:, 2]]), lf))
    return ZigzagResult(passes, steps, min(steps) if steps else 0.0, len(lines))
