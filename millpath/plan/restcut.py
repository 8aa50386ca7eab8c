"""Rest machining of a planned toolpath: keep only the moves that meet material.

Used by operations whose planners know nothing of the in-process stock (``features``,
``grid-pocket``): the operation is planned as for a full block, then each motion move
(line, arc, cubic, canned cycle) is tested against the in-process stock left by the
earlier operations (``PlanContext.remaining``) and kept only where the tool meets
more than ``allowance`` of it; the kept runs are linked again.

The test, Z included: a tool-tip position (x, y, z) meets material when a stock cell
whose centre lies within ``R - allowance`` of (x, y) stands more than ``allowance``
above the tool's surface there (tip Z plus the cutter's profile at that distance:
flat, ball or bull; drills as flat). A move meets material when any of its points,
sampled half a stock cell apart, does; a canned cycle when its hole bottom does. The
stock is read on a raster of half the stock's cell width (every stock cell is seen).

Links between kept moves: a straight rapid move, kept down inside cleared space, when
the straight line meets no material at all (no cell within ``R`` plus one raster cell
above the tool's surface by more than a micrometre) and is shorter than ``link_max``
(default four tool diameters); otherwise up to ``safe_z``, across,
rapid down to ``clearance`` above the highest stock under the tool, then feed down to
the next kept move's start. That start is the end of a dropped move (tested: no more
than ``allowance`` of material under the tool) or of an original rapid, so the feed
down never plunges into material. Lengths in job units.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit
from scipy import ndimage

from millpath.geometry.cutter import Cutter, height
from millpath.model.toolpath import Move, Toolpath, sample_move

@njit(cache=True)
def meets_stock(P, H, gx, gy, h, kind, R, rc, k, thr, rin):
    """For each tip point of ``P`` (n, 3): a cell of the height raster ``H`` (origin
    ``gx, gy``, cell ``h``) within ``R - rin`` of it stands more than ``thr`` above the
    cutter's surface (``kind, R, rc, k`` a :class:`~millpath.geometry.cutter.Cutter`'s row)."""
    n = P.shape[0]
    ny, nx = H.shape
    out = np.zeros(n, np.bool_)
    rr = R - rin
    for k in range(n):
        x, y, z = P[k, 0], P[k, 1], P[k, 2]
        i0 = max(0, int(math.floor((x - rr - gx) / h)))
        i1 = min(nx - 1, int(math.floor((x + rr - gx) / h)))
        j0 = max(0, int(math.floor((y - rr - gy) / h)))
        j1 = min(ny - 1, int(math.floor((y + rr - gy) / h)))
        hit = False
        for j in range(j0, j1 + 1):
            yc = gy + (j + 0.5) * h
            for i in range(i0, i1 + 1):
                xc = gx + (i + 0.5) * h
                r = math.sqrt((xc - x) ** 2 + (yc - y) ** 2)
                if r > rr:
                    continue
                if H[j, i] > z + height(kind, R, rc, k, r) + thr:
                    hit = True
                    break
            if hit:
                break
        out[k] = hit
    return out


class StockRaster:
    """The in-process stock's heights on a raster of cell width ``h`` covering
    ``bounds`` (xmin, ymin, xmax, ymax) grown by ``margin``; with ``highest``, each cell
    takes the highest of its 3 x 3 neighbours (between samples the stock can stand
    higher, on a slope: a test that skips must err toward cutting)."""

    def __init__(self, remaining, bounds, margin: float, h: float, highest: bool = False):
        x0, y0, x1, y1 = bounds
        self.gx, self.gy, self.h = x0 - margin, y0 - margin, h
        nx = int(math.ceil((x1 - x0 + 2 * margin) / h)) + 1
        ny = int(math.ceil((y1 - y0 + 2 * margin) / h)) + 1
        X, Y = np.meshgrid(self.gx + (np.arange(nx) + 0.5) * h,
                           self.gy + (np.arange(ny) + 0.5) * h)
        H = remaining.height(X, Y)
        if highest:
            H = ndimage.maximum_filter(H, size=3)
        self.H = np.ascontiguousarray(H, dtype=float)

    def meets(self, P: np.ndarray, tool, thr: float, rin: float) -> np.ndarray:
        return meets_stock(np.ascontiguousarray(P, dtype=float), self.H, self.gx, self.gy,
                           self.h, *Cutter.of(tool).row, float(thr), float(rin))

    def top_near(self, x: float, y: float, reach: float) -> float:
        """Highest stock within ``reach`` (a square) of (x, y)."""
        h = self.h
        ny, nx = self.H.shape
        i0 = max(0, int(math.floor((x - reach - self.gx) / h)))
        i1 = min(nx - 1, int(math.floor((x + reach - self.gx) / h)))
        j0 = max(0, int(math.floor((y - reach - self.gy) / h)))
        j1 = min(ny - 1, int(math.floor((y + reach - self.gy) / h)))
        if i0 > i1 or j0 > j1:
            return -math.inf
        return float(self.H[j0:j1 + 1, i0:i1 + 1].max())


def _after(start, m: Move):
    """Where the tool is after move ``m`` begun at ``start``."""
    if m.kind == "drill":
        z = max(m.r_plane, start[2]) if m.retract_initial and start is not None else m.r_plane
        return (m.end[0], m.end[1], z)
    return m.end


def rest_filter(tp: Toolpath, remaining, tools: dict, allowance: float, safe_z: float,
                clearance: float, link_max: float | None = None) -> dict:
    """Keep, in place, the moves of ``tp`` that meet more than ``allowance`` of the
    in-process stock ``remaining``; relink them (see the module docstring). Returns
    figures for the report: moves and feed length before and after, links made."""
    moves = list(tp.moves)
    if not moves or any(m.kind == "comp" for m in moves):
        return {"applied": False}
    h = float(remaining.resolution) / 2.0
    ends = tp.ends()
    Rmax = max(tools[op.tool].radius for op in tp.ops if op.tool in tools)
    lo = ends[:, :2].min(axis=0)
    hi = ends[:, :2].max(axis=0)
    for m in moves:                       # arcs may bulge beyond their ends
        if m.kind == "arc" and m.center is not None:
            r = math.dist(m.center[:2], m.end[:2])
            lo = np.minimum(lo, np.array(m.center[:2]) - r)
            hi = np.maximum(hi, np.array(m.center[:2]) + r)
        if m.kind == "cubic":
            c = np.array([m.c1, m.c2])
            lo = np.minimum(lo, c.min(axis=0))
            hi = np.maximum(hi, c.max(axis=0))
    raster = StockRaster(remaining, (lo[0], lo[1], hi[0], hi[1]), Rmax + 2 * h, h)
    step = h
    keep: list[bool] = []
    starts: list = []
    split: list[Move] = []
    pos = None
    for m in moves:
        if m.kind == "rapid":
            split.append(m)
            starts.append(pos)
            keep.append(False)
            pos = m.end
            continue
        tool = tools[tp.ops[m.op].tool]
        if m.kind == "drill":
            P = np.array([m.end])
        else:
            P = sample_move(pos if pos is not None else m.end, m, step)
        t = raster.meets(P, tool, allowance, allowance)
        if m.kind == "line" and pos is not None and t.any() and not t.all():
            # a long line meeting material only in part: split it where the runs of
            # points that meet material (grown by the tool radius) begin and end
            pad = int(math.ceil(tool.radius / step)) + 1
            for a, b, on in _runs(t, pad):
                q = P[b]
                split.append(Move("line", (float(q[0]), float(q[1]), float(q[2])),
                                  m.feed, m.op))
                starts.append(pos)
                keep.append(on)
                pos = split[-1].end
            split[-1] = m                       # the exact end point
            pos = m.end
            continue
        split.append(m)
        starts.append(pos)
        keep.append(bool(t.any()))
        pos = _after(pos, m)
    moves = split

    feed_before = _feed_length(moves)
    out: list[Move] = []
    cur = None
    cur_op = None
    links = {"keep_down": 0, "retract": 0}
    eps = 1e-6
    for k, m in enumerate(moves):
        if not keep[k]:
            continue
        tool = tools[tp.ops[m.op].tool]
        if cur_op is not None and m.op != cur_op:          # tool change: leave high
            if cur is not None and cur[2] < safe_z:
                out.append(Move("rapid", (cur[0], cur[1], safe_z), op=cur_op))
            cur = None
        cur_op = m.op
        target = starts[k] if starts[k] is not None else (m.end[0], m.end[1], safe_z)
        if cur is None or math.dist(cur, target) > 1e-9:
            lmax = link_max if link_max is not None else 4.0 * tool.diameter
            if cur is not None and math.dist(cur, target) <= lmax and not raster.meets(
                    sample_move(cur, Move("line", target), step), tool, eps, -h).any():
                out.append(Move("rapid", tuple(target), op=m.op))
                links["keep_down"] += 1
            else:
                if cur is not None and cur[2] < safe_z:
                    out.append(Move("rapid", (cur[0], cur[1], safe_z), op=m.op))
                out.append(Move("rapid", (target[0], target[1], safe_z), op=m.op))
                zc = max(target[2], raster.top_near(target[0], target[1],
                                                    tool.radius + h) + clearance)
                if zc < safe_z - 1e-9:
                    out.append(Move("rapid", (target[0], target[1], zc), op=m.op))
                if target[2] < min(zc, safe_z) - 1e-9:
                    out.append(Move("line", tuple(target), 0.5 * _link_feed(moves, k), m.op))
                links["retract"] += 1
        out.append(m)
        cur = _after(target, m)
    if cur is not None and cur[2] < safe_z:
        out.append(Move("rapid", (cur[0], cur[1], safe_z), op=cur_op))
    kept = sum(keep)
    tp.moves[:] = out
    return {"applied": True, "allowance": allowance, "moves_kept": int(kept),
            "motion_moves": int(sum(m.kind != "rapid" for m in moves)),
            "feed_length_before": round(feed_before, 3),
            "feed_length": round(_feed_length(out), 3), "links": links}


def _runs(t: np.ndarray, pad: int) -> list[tuple[int, int, bool]]:
    """Index ranges (a, b, meets) covering sample points 0..n-1 of a move: the runs
    of ``t`` grown by ``pad`` points and the gaps between them."""
    g = t.copy()
    idx = np.flatnonzero(t)
    for k in range(1, pad + 1):
        g[np.clip(idx - k, 0, len(t) - 1)] = True
        g[np.clip(idx + k, 0, len(t) - 1)] = True
    n = len(g)
    cuts = [0]
    for c in range(1, n):
        if g[c] != g[c - 1]:
            cuts.append(c - 1 if g[c] else c)     # split at the clear point
    cuts.append(n - 1)
    cuts = [c for i, c in enumerate(cuts) if i == 0 or c != cuts[i - 1]]
    return [(p, q, bool(g[p:q + 1].any())) for p, q in zip(cuts[:-1], cuts[1:])]


def _link_feed(moves: list[Move], k: int) -> float:
    f = moves[k].feed
    return f if f > 0 else max((m.feed for m in moves if m.kind == "line"), default=1.0)


def _feed_length(moves: list[Move]) -> float:
    total, pos = 0.0, None
    for m in moves:
        if m.kind in ("line", "arc", "cubic") and pos is not None:
            if m.kind == "line":
                total += math.dist(pos, m.end)
            else:
                P = sample_move(pos, m, 0.5)
                total += float(np.linalg.norm(np.diff(P, axis=0), axis=1).sum())
        pos = _after(pos, m) if pos is not None or m.kind != "drill" else m.end
    return total
