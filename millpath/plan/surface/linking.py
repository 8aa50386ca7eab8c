"""Join finishing passes into a toolpath (job units; feeds in units per minute).

Neighbouring pieces closer than ``link_max`` in XY are joined by a feed move that
follows the surface (drop-cutter points along the straight XY link, verified at every
midpoint like the passes, holder clearance included); otherwise the tool retracts to
``safe_z``, rapids over, rapids down to ``clearance`` above the next start, or above
``approach_z`` if that is higher (the stock top: material the operation has not yet
cut may stand anywhere below it, so no rapid goes lower), and feeds down at
``plunge_feed`` - by a helix (millpath.plan.entry) where that start lies below
``approach_z`` (material may stand there) and a helix clear of the surface fits.
``approach_z`` may also be a function of the start point (x, y, z): the highest
material near it (rest machining on the in-process stock).
"""

from __future__ import annotations

import math

import numpy as np

from millpath.model.toolpath import Toolpath
from millpath.plan.entry import helix_entry, ramp_entry
from millpath.plan.surface.sampler import Sampler
from millpath.plan.surface.zigzag import Pass, refine_chords


def surface_link(sampler: Sampler, a: np.ndarray, b: np.ndarray, tol: float,
                 step: float) -> np.ndarray:
    """Tip points from ``a`` to ``b`` (x, y, z) following the surface, both ends included."""
    ua = sampler.uw(a[0], a[1])
    ub = sampler.uw(b[0], b[1])
    n = max(1, int(math.ceil(float(np.hypot(*(ub - ua))) / step)))
    t = np.linspace(0.0, 1.0, n + 1)
    uw = ua[None, :] + (ub - ua)[None, :] * t[:, None]
    z, _ = sampler.z_safe(uw[:, 0], uw[:, 1])
    z[0], z[-1] = a[2], b[2]
    P = refine_chords(sampler, np.column_stack([uw, z]), tol, tol, 1e-4)
    xy = sampler.xy(P[:, 0], P[:, 1])
    return np.column_stack([xy, P[:, 2]])


def _link_on_part(sampler: Sampler, a: np.ndarray, b: np.ndarray, tol: float,
                  silhouette: bool) -> np.ndarray | None:
    """:func:`surface_link`, or None with ``silhouette`` when the tool leaves the part."""
    L = surface_link(sampler, a, b, tol, 0.25 * sampler.cutter.radius)
    if silhouette:
        uw = sampler.uw(L[:, 0], L[:, 1])
        if not sampler.touches(uw[:, 0], uw[:, 1]).all():
            return None
    return L


def _descend(tp: Toolpath, start, safe_z: float, clearance: float, approach_z: float,
             plunge_feed: float, sampler: Sampler | None = None,
             allowance: float = 0.0) -> bool:
    """From ``safe_z`` above ``start``: rapid to the approach height, then feed to
    ``start``: down a helix (else a zigzag ramp) whose every point stays ``allowance``
    above the surface when ``start`` is below ``approach_z``, else straight. True if a
    helix or ramp was used. ``approach_z`` may be a function of ``start``."""
    if callable(approach_z):
        approach_z = approach_z(start)
    z = min(safe_z, max(start[2], approach_z) + clearance)
    if z < safe_z - 1e-9:
        tp.rapid(start[0], start[1], z)
    if sampler is not None and start[2] < approach_z - 1e-9:
        def floor(xs, ys):
            uw = sampler.uw(xs, ys)
            return sampler.z_cut(uw[:, 0], uw[:, 1]) + allowance
        hx = helix_entry(start, z, sampler.cutter.radius,
                         centre_ok=lambda xs, ys: True, floor=floor)
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
               allowance: float = 0.0, silhouette: bool = False) -> dict:
    """Append the passes to ``tp`` (its operation already begun); return link counts.
    ``allowance``: stock the passes leave on the surface (entries leave it too).
    ``silhouette``: a link whose tool would leave the part (touch nothing, see
    :meth:`.sampler.Sampler.touches`) retracts instead of following the surface."""
    links = {"surface": 0, "retract": 0, "helix": 0}
    cur = None
    for p in passes:
        P = p.points
        if len(P) == 0:
            continue
        start = P[0]
        if cur is None:
            tp.rapid(start[0], start[1], safe_z)
            links["helix"] += _descend(tp, start, safe_z, clearance, approach_z,
                                       plunge_feed, sampler, allowance)
        elif (math.hypot(start[0] - cur[0], start[1] - cur[1]) <= link_max
              and (L := _link_on_part(sampler, cur, start, tolerance, silhouette))
              is not None):
            for q in L[1:]:
                tp.line(*q, feed)
            links["surface"] += 1
        else:
            tp.rapid(cur[0], cur[1], safe_z)
            tp.rapid(start[0], start[1], safe_z)
            links["helix"] += _descend(tp, start, safe_z, clearance, approach_z,
                                       plunge_feed, sampler, allowance)
            links["retract"] += 1
        for q in P[1:]:
            tp.line(*q, feed)
        cur = P[-1]
    if cur is not None:
        tp.rapid(cur[0], cur[1], safe_z)
    return links
