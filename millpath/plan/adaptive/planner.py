"""Adaptive clearing of one level: passes of the walker, their entries and links.

Per level (job units; ``R`` tool radius, ``D`` diameter):

1. The material raster ``M``: cells inside the pocket shrunk by the allowance, within
   reach of the tool (``R`` of an allowed centre) and above the level in the
   in-process stock. Allowed centres ``A``: the pocket shrunk by ``R + allowance``
   and one more cell.
2. A pass starts in cleared space beside the material (the nearest such place, heading
   along the material's edge with it on the right); when there is none, a helix bores
   the roomiest spot still full of material (radius ``helix_radius`` or less).
3. The walker (:mod:`.walker`) runs until it cannot keep the engagement; the next
   pass is reached by a feed straight through cleared space when the whole tool stays
   in it, or by two such feeds by way of a place the tool has been at on this level
   (route no longer than ``link_max``), otherwise by a retract and a feed down where the column is clear, at the
   last step before the pass first cuts (the walker's idle steps before it are air).

The engagement limit per step is ``engagement * D * ds`` of area, less ``margin``
(default 8 %) for the raster's counting error.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy import ndimage

from millpath.plan.adaptive.walker import (allowed, block_any, crescent, cut_disk,
                                           segment_clear, walk)


@dataclass
class Pass:
    """One walker pass: ``kind`` "helix" (bore at ``center`` with ``radius`` first),
    "link" (feed from the previous pass's end), "jump" (retract, feed down in air);
    ``pts`` (n, 2) the centre positions."""

    kind: str
    pts: np.ndarray
    center: tuple[float, float] | None = None
    radius: float = 0.0


@dataclass
class LevelResult:
    passes: list[Pass]
    left_cells: int          # material cells the walker could not reach within the limit


def approach(M, A, gx, gy, h, R, x, y, ux, uy, limit):
    """Move from (x, y) along (ux, uy) in steps of ``h`` while the tool disk (one cell
    larger: cells are not points) stays free of material and the centre allowed; the
    last such position."""
    for _ in range(int(limit / h) + 1):
        qx, qy = x + ux * h, y + uy * h
        if not allowed(A, gx, gy, h, qx, qy):
            break
        if crescent(M, gx, gy, h, R + h, x, y, qx, qy, False) > 0:
            break
        x, y = qx, qy
    return x, y


def clear_level(M: np.ndarray, A: np.ndarray, gx: float, gy: float, h: float, R: float,
                engagement: float, *, helix_radius: float, start=None, S=None,
                margin: float = 0.08, max_passes: int = 2000,
                link_max: float = 0.0) -> LevelResult:
    """Walker passes clearing the material raster ``M`` (modified: cleared) with the tool
    centre kept in ``A``. ``S`` (default: ``M``): the part of ``M`` passes are started
    for (material the clean-up rings would otherwise take); engagement is always
    counted on ``M``. ``start``: the tool's (x, y) before the level, if known.
    ``link_max``: longest link by way of a point the tool has already been at (two
    straight feeds through cleared space) taken instead of a retract; 0: none."""
    if S is None:
        S = M.copy()
    D = 2 * R
    ds = R / 4.0
    amax = engagement * (1.0 - margin) * D * ds / (h * h)
    buf = np.zeros((200_000, 3))
    f = max(1, int(round(0.25 * R / h)))
    hc = f * h
    dist_A = ndimage.distance_transform_edt(A) * h      # room round allowed centres
    passes: list[Pass] = []
    visited: list[np.ndarray] = []       # centres the tool has been at on this level
    pos = start
    tried = np.zeros_like(block_any(S, f))
    for _ in range(max_passes):
        Mc = block_any(S, f)
        if not Mc.any():
            break
        dist = ndimage.distance_transform_edt(~Mc) * hc
        Ac = A[f // 2::f, f // 2::f][:Mc.shape[0], :Mc.shape[1]]
        Ac = np.pad(Ac, ((0, Mc.shape[0] - Ac.shape[0]), (0, Mc.shape[1] - Ac.shape[1])))
        lo = R + 1.5 * hc
        gyd, gxd = np.gradient(dist)
        band = (dist >= lo) & (dist <= lo + max(engagement * D, 2 * hc)) & Ac & ~tried
        cand = None
        jj, ii = np.nonzero(band)
        if len(jj):
            cx = gx + (ii * f + f // 2 + 0.5) * h
            cy = gy + (jj * f + f // 2 + 0.5) * h
            if pos is not None:
                order = np.argsort(np.hypot(cx - pos[0], cy - pos[1]))
            else:
                order = np.arange(len(cx))
            for k in order[:40]:
                x, y = float(cx[k]), float(cy[k])
                if crescent(M, gx, gy, h, R + h, x + 1e9, y, x, y, False) > 0:
                    tried[jj[k], ii[k]] = True
                    continue
                g = np.array([gxd[jj[k], ii[k]], gyd[jj[k], ii[k]]])
                if np.hypot(*g) < 1e-12:
                    tried[jj[k], ii[k]] = True
                    continue
                g = g / np.hypot(*g)
                x, y = approach(M, A, gx, gy, h, R, x, y, -g[0], -g[1], 3 * hc)
                cand = (x, y, math.atan2(-g[0], g[1]), jj[k], ii[k])
                break
        if cand is not None:
            x, y, heading, cj, ci = cand
            kind = "jump"
            via = None
            if pos is not None and segment_clear(M, A, gx, gy, h, R + h, pos[0], pos[1], x, y):
                kind = "link"
            elif pos is not None and link_max > 0 and visited:
                via = _via(M, A, gx, gy, h, R, pos, (x, y), np.vstack(visited), link_max)
                kind = "jump" if via is None else "link"
            M_before = M.copy() if kind == "jump" else M
            n = walk(M, S, A, gx, gy, h, R, x, y, heading, ds, amax, len(buf) - 1,
                     int(2 * math.pi * R / ds) + 4, buf)
            if n <= 1:
                tried[max(cj - 1, 0):cj + 2, max(ci - 1, 0):ci + 2] = True
                continue
            s0 = 0
            if kind == "jump":           # enter where the pass begins to cut: the idle
                cut_at = np.flatnonzero(buf[1:n, 2] > 0)   # steps before are in air
                s0 = int(cut_at[0]) if len(cut_at) else 0
                # ... at the last of them whose disk, one cell larger, held no material
                while s0 > 0 and crescent(M_before, gx, gy, h, R + h, buf[s0, 0] + 1e9,
                                          buf[s0, 1], buf[s0, 0], buf[s0, 1], False) > 0:
                    s0 -= 1
            pts = buf[s0:n, :2].copy()
            visited.append(pts[::2])
            if via is not None:
                pts = np.vstack([via[None, :], pts])
            passes.append(Pass(kind, pts))
            pos = (float(buf[n - 1, 0]), float(buf[n - 1, 1]))
            continue
        # no cleared space next to material: bore a new start with a helix
        full = A & S
        if not full.any():
            break
        score = np.where(full, dist_A, -1.0)
        j, i = np.unravel_index(int(np.argmax(score)), score.shape)
        room = float(dist_A[j, i]) - h
        rh = min(helix_radius, room)
        if rh < 0.05 * R:
            break
        cx, cy = gx + (i + 0.5) * h, gy + (j + 0.5) * h
        cut_disk(M, gx, gy, h, R + rh, cx, cy)
        cut_disk(S, gx, gy, h, R + rh, cx, cy)
        n = walk(M, S, A, gx, gy, h, R, cx + rh, cy, math.pi / 2, ds, amax, len(buf) - 1,
                 int(2 * math.pi * R / ds) + 4, buf)
        passes.append(Pass("helix", buf[:max(n, 1), :2].copy(), (cx, cy), rh))
        visited.append(buf[:max(n, 1):2, :2].copy())
        pos = (float(buf[max(n, 1) - 1, 0]), float(buf[max(n, 1) - 1, 1]))
    return LevelResult(passes, int(S.sum()))


def _via(M, A, gx, gy, h, R, a, b, pts: np.ndarray, link_max: float, tries: int = 12):
    """A point of ``pts`` (places the tool has been at) from which the tool feeds
    straight to ``a`` and to ``b`` through cleared space (disk radius ``R`` free of
    ``M``), the route a -> via -> b no longer than ``link_max``; the shortest of the
    ``tries`` shortest candidates that works, or None."""
    d = np.hypot(pts[:, 0] - a[0], pts[:, 1] - a[1]) + np.hypot(pts[:, 0] - b[0],
                                                                 pts[:, 1] - b[1])
    ok = np.flatnonzero(d <= link_max)
    if not len(ok):
        return None
    for k in ok[np.argsort(d[ok])][:tries]:
        v = pts[k]
        if segment_clear(M, A, gx, gy, h, R, a[0], a[1], v[0], v[1]) and \
                segment_clear(M, A, gx, gy, h, R, v[0], v[1], b[0], b[1]):
            return v.copy()
    return None
