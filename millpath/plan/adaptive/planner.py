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
   in it, otherwise by a retract and a feed down where the column is clear.

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
                margin: float = 0.08, max_passes: int = 2000) -> LevelResult:
    """Walker passes clearing the material raster ``M`` (modified: cleared) with the tool
    centre kept in ``A``. ``S`` (default: ``M``): the part of ``M`` passes are started
    for (material the clean-up rings would otherwise take); engagement is always
    counted on ``M``. ``start``: the tool's (x, y) before the level, if known."""
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
            if pos is not None and segment_clear(M, A, gx, gy, h, R + h, pos[0], pos[1], x, y):
                kind = "link"
            n = walk(M, S, A, gx, gy, h, R, x, y, heading, ds, amax, len(buf) - 1,
                     int(2 * math.pi * R / ds) + 4, buf)
            if n <= 1:
                tried[max(cj - 1, 0):cj + 2, max(ci - 1, 0):ci + 2] = True
                continue
            passes.append(Pass(kind, buf[:n, :2].copy()))
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
        pos = (float(buf[max(n, 1) - 1, 0]), float(buf[max(n, 1) - 1, 1]))
    return LevelResult(passes, int(S.sum()))
