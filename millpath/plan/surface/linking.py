"""Join finishing passes into a toolpath (job units; feeds in units per minute).

Neighbouring pieces closer than ``link_max`` in XY are joined by a feed move that
follows the surface (drop-cutter points along the straight XY link, verified at every
midpoint like the passes, holder clearance included); otherwise the tool retracts to
``safe_z``, rapids over, rapids down to ``clearance`` above the next start, or above
``approach_z`` if that is higher (the stock top: material the operation has not yet
cut may stand anywhere below it, so no rapid goes lower), and feeds down at
``plunge_feed`` - straight down to ``approach_z``, then by a helix (millpath.plan.entry)
where that start lies below ``approach_z`` (material may stand there) and a helix clear
of the surface fits.
``approach_z`` may also be a function of the start point (x, y, z): the highest
material near it (rest machining on the in-process stock), or the stock top only where
the tool at the start overlaps the stock (:func:`stock_approach`): beside the stock the
tool rapids down to ``clearance`` above the start and feeds straight in. With ``stock``
given, a start outside the stock's footprint whose tool overlaps it is entered from the
side instead of by a helix: down beside the stock, then straight in at the start's Z,
where that line stays clear of the surface.

With a ``material`` bound (:class:`millpath.plan.material.MaterialBound`, holder
included) of the stock before the passes, each pass is cut into it as it is added; a
link lifts only to ``clearance`` over the bound between the pieces (not to ``safe_z``)
and an entry starts ``clearance`` over the bound at its start, so a re-entry where
earlier passes cleared the material descends one layer, not from the stock top.
"""

from __future__ import annotations

import math

import numpy as np

from millpath.model.toolpath import Toolpath
from millpath.plan.entry import helix_entry, ramp_entry
from millpath.plan.surface.sampler import Sampler
from millpath.plan.surface.zigzag import Pass, refine_chords_many


def surface_links(sampler: Sampler, pairs: list[tuple[np.ndarray, np.ndarray]], tol: float,
                  step: float, silhouette: bool = False) -> list[np.ndarray | None]:
    """Tip points from ``a`` to ``b`` (x, y, z) following the surface, both ends
    included, for every pair ``(a, b)`` (one drop-cutter batch per refinement round for
    all of them); None with ``silhouette`` where the tool would leave the part."""
    if not pairs:
        return []
    runs = []
    for a, b in pairs:
        ua = sampler.uw(a[0], a[1])
        ub = sampler.uw(b[0], b[1])
        n = max(1, int(math.ceil(float(np.hypot(*(ub - ua))) / step)))
        t = np.linspace(0.0, 1.0, n + 1)
        runs.append(ua[None, :] + (ub - ua)[None, :] * t[:, None])
    uw = np.concatenate(runs)
    z, _ = sampler.z_safe(uw[:, 0], uw[:, 1])
    Ps = []
    for (a, b), Z, U in zip(pairs, np.split(z, np.cumsum([len(r) for r in runs])[:-1]), runs):
        Z[0], Z[-1] = a[2], b[2]
        Ps.append(np.column_stack([U, Z]))
    Ps = refine_chords_many(sampler, Ps, tol, tol, 1e-4)
    allp = np.concatenate(Ps)
    cut = np.cumsum([len(P) for P in Ps])[:-1]
    xy = sampler.xy(allp[:, 0], allp[:, 1])
    out = [np.column_stack([q, P[:, 2]]) for q, P in zip(np.split(xy, cut), Ps)]
    if silhouette:
        touch = np.split(sampler.touches(allp[:, 0], allp[:, 1]), cut)
        out = [L if t.all() else None for L, t in zip(out, touch)]
    return out


def stock_approach(stock, radius: float):
    """``approach_z`` for :func:`add_passes` on an uncut ``stock``: its top where a tool of
    ``radius`` at the start point overlaps the stock's footprint, else the start's own Z
    (the tool stands wholly beside the stock: there is nothing to enter)."""
    top = float(stock.zmax)

    def at(p) -> float:
        x, y = float(p[0]), float(p[1])
        near = math.hypot(*(np.subtract((x, y), stock.nearest_xy(x, y))))
        return top if near < radius else -math.inf
    return at


def _side_entry(stock, start, sampler: Sampler, allowance: float, margin: float,
                top: float, material=None):
    """Where to go down beside ``stock`` for a start outside its footprint (x, y): out
    from the footprint's nearest point until the tool clears it by ``margin``; None when
    the start is over the stock, the straight line in would come closer to the surface
    than ``allowance``, or (with ``material``) the move over to it at ``top`` or down
    to the start's Z there would meet material."""
    x, y, z = (float(v) for v in start)
    px, py = stock.nearest_xy(x, y)
    d = math.hypot(x - px, y - py)
    if d <= 1e-9:
        return None
    R = sampler.cutter.radius
    reach = max(R + margin - d, 0.0)
    sx, sy = x + (x - px) / d * reach, y + (y - py) / d * reach
    t = np.linspace(0.0, 1.0, max(2, int(math.ceil(reach / (0.1 * R))) + 1))
    uw = sampler.uw(sx + (x - sx) * t, sy + (y - sy) * t)
    if np.any(sampler.z_cut(uw[:, 0], uw[:, 1]) + allowance > z + 1e-9):
        return None
    if material is not None and (material.need_segment((x, y), (sx, sy)) + margin > top
                                 or material.need_at((sx, sy)) > z):
        return None
    return sx, sy


def _descend(tp: Toolpath, start, safe_z: float, clearance: float, approach_z: float,
             plunge_feed: float, sampler: Sampler | None = None,
             allowance: float = 0.0, stock=None, material=None) -> bool:
    """From ``safe_z`` above ``start``: rapid to the approach height, then feed to
    ``start``: when ``start`` is below ``approach_z``, from the side (see the module) or
    down a helix (else a zigzag ramp) whose every point stays ``allowance`` above the
    surface, else straight. True if a side entry, helix or ramp was used.
    ``approach_z`` may be a function of ``start``."""
    if callable(approach_z):
        approach_z = approach_z(start)
    if stock is not None and sampler is not None and start[2] < approach_z - 1e-9:
        side = _side_entry(stock, start, sampler, allowance, clearance, safe_z, material)
        if side is not None:
            tp.rapid(side[0], side[1], safe_z)
            if start[2] + clearance < safe_z - 1e-9:
                tp.rapid(side[0], side[1], float(start[2]) + clearance)
            tp.line(side[0], side[1], float(start[2]), plunge_feed)
            tp.line(*start, plunge_feed)
            return True
    z = min(safe_z, max(start[2], approach_z) + clearance)
    if z < safe_z - 1e-9:
        tp.rapid(start[0], start[1], z)
    if sampler is not None and start[2] < approach_z - 1e-9:
        if approach_z < z - 1e-9:           # through air to the material, then the helix
            tp.line(start[0], start[1], approach_z, plunge_feed)
            z = approach_z

        def floor(xs, ys):
            uw = sampler.uw(xs, ys)
            return sampler.z_cut(uw[:, 0], uw[:, 1]) + allowance
        # the circle's centre downhill from the start first: a start on a steep flank
        # (the tool touching an edge near its equator) has its floor rise fast uphill
        e = 0.02 * sampler.cutter.radius
        sx, sy = float(start[0]), float(start[1])
        f = floor(np.array([sx + e, sx - e, sx, sx]), np.array([sy, sy, sy + e, sy - e]))
        gx, gy = float(f[0] - f[1]), float(f[2] - f[3])
        down = math.atan2(-gy, -gx) if math.hypot(gx, gy) > 1e-12 else None
        hx = helix_entry(start, z, sampler.cutter.radius, centre_ok=lambda xs, ys: True,
                         floor=floor, samples=192, first=down)
        if hx is not None:
            tp.arc(tuple(float(v) for v in start), (hx.center[0], hx.center[1],
                                                    float(start[2])),
                   False, plunge_feed, turns=hx.turns)
            return True
        rp = ramp_entry(start, z, sampler.cutter.radius, centre_ok=lambda xs, ys: True,
                        floor=floor)
        if rp is not None:
            for q in rp.points(z):
                tp.line(*q, plunge_feed)
            return True
    tp.line(*start, plunge_feed)
    return False


def add_passes(tp: Toolpath, sampler: Sampler, passes: list[Pass], *, feed: float,
               plunge_feed: float, safe_z: float, clearance: float, link_max: float,
               tolerance: float, approach_z: float = -math.inf,
               allowance: float = 0.0, silhouette: bool = False, stock=None,
               material=None) -> dict:
    """Append the passes to ``tp`` (its operation already begun); return link counts.
    ``allowance``: stock the passes leave on the surface (entries leave it too).
    ``silhouette``: a link whose tool would leave the part (touch nothing, see
    :meth:`.sampler.Sampler.touches`) retracts instead of following the surface.
    ``stock``: the uncut stock, for entries from its side; ``material``: a bound of the
    stock before the passes, for low links and entries (see the module)."""
    links = {"surface": 0, "retract": 0, "helix": 0}
    passes = [p for p in passes if len(p.points)]
    near = [k for k in range(1, len(passes))
            if math.hypot(*(passes[k].points[0, :2] - passes[k - 1].points[-1, :2])) <= link_max]
    found = surface_links(sampler, [(passes[k - 1].points[-1], passes[k].points[0])
                                    for k in near],
                          tolerance, 0.25 * sampler.cutter.radius, silhouette)
    link_to = dict(zip(near, found))
    if material is not None:
        # the cutter clear at the start; its shank and holder over the whole square the
        # entry helix may circle in (radius <= R / 2): the helix cuts, the holder must not
        h = 0.5 * sampler.cutter.radius

        def approach_z(p) -> float:
            x, y = float(p[0]), float(p[1])
            c = [(x - h, y - h), (x + h, y - h), (x + h, y + h), (x - h, y + h)]
            return max([material.need_at((x, y))]
                       + [material.need_segment(c[i], c[(i + 1) % 4], cutter=False)
                          for i in range(4)])
    cur = None
    for k, p in enumerate(passes):
        P = p.points
        start = P[0]
        if cur is None:
            tp.rapid(start[0], start[1], safe_z)
            links["helix"] += _descend(tp, start, safe_z, clearance, approach_z,
                                       plunge_feed, sampler, allowance, stock, material)
        elif (L := link_to.get(k)) is not None:
            tp.lines(L[1:], feed)
            links["surface"] += 1
        else:
            top = safe_z
            if material is not None:
                need = material.need_segment(cur, start) + clearance
                top = min(safe_z, max(need, float(cur[2]), float(start[2]) + clearance))
                links["low"] = links.get("low", 0) + (top < safe_z - 1e-9)
            tp.rapid(cur[0], cur[1], top)
            tp.rapid(start[0], start[1], top)
            links["helix"] += _descend(tp, start, top, clearance, approach_z,
                                       plunge_feed, sampler, allowance, stock, material)
            links["retract"] += 1
        tp.lines(P[1:], feed)
        if material is not None:
            material.cut(P)
        cur = P[-1]
    if cur is not None:
        tp.rapid(cur[0], cur[1], safe_z)
    return links
