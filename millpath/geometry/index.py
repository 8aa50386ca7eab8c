"""A uniform XY bucket grid over axis-aligned boxes (triangles, chords), for numba.

Each item is listed in every bucket its XY box overlaps. A query over a box visits
each item once by taking it only in the first bucket where its own bucket range and
the query's overlap (see :func:`first_bucket`). Lengths in any consistent unit.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numba import njit


MAX_ENTRIES = 8_000_000      # bucket entries of one index (8 bytes each, several arrays)


@dataclass
class BoxIndex:
    lo: np.ndarray          # (n, 3) box minima
    hi: np.ndarray          # (n, 3) box maxima
    start: np.ndarray       # (nbx * nby + 1,) CSR offsets into items
    items: np.ndarray       # item numbers, bucket by bucket
    bi0: np.ndarray         # (n,) first bucket column of each item
    bj0: np.ndarray         # (n,) first bucket row
    blo: np.ndarray         # (nbx * nby, 3) minima of the boxes listed in each bucket
    bhi: np.ndarray         # (nbx * nby, 3) their maxima (empty buckets: -inf)
    x0: float
    y0: float
    bs: float               # bucket size
    nbx: int
    nby: int

    @classmethod
    def build(cls, lo: np.ndarray, hi: np.ndarray, bucket: float | None = None) -> "BoxIndex":
        lo = np.ascontiguousarray(lo, float).reshape(-1, 3)
        hi = np.ascontiguousarray(hi, float).reshape(-1, 3)
        n = len(lo)
        if n == 0:
            return cls(lo, hi, np.zeros(2, np.int64), np.zeros(0, np.int64),
                       np.zeros(0, np.int64), np.zeros(0, np.int64), np.full((1, 3), np.inf),
                       np.full((1, 3), -np.inf), 0.0, 0.0, 1.0, 1, 1)
        gx0, gy0 = lo[:, 0].min(), lo[:, 1].min()
        gx1, gy1 = hi[:, 0].max(), hi[:, 1].max()
        span = max(gx1 - gx0, gy1 - gy0, 1e-9)
        if bucket is None:
            ext = np.maximum(hi[:, :2] - lo[:, :2], 0.0)
            bucket = max(float(np.median(ext.max(axis=1))) * 2.0,
                         math.sqrt((gx1 - gx0 + 1e-9) * (gy1 - gy0 + 1e-9) / n) * 1.5)
        bs = max(float(bucket), span / 2048.0, 1e-9)
        while True:
            nbx = max(1, int(math.ceil((gx1 - gx0) / bs)) + 1)
            nby = max(1, int(math.ceil((gy1 - gy0) / bs)) + 1)
            i0 = np.clip(np.floor((lo[:, 0] - gx0) / bs).astype(np.int64), 0, nbx - 1)
            i1 = np.clip(np.floor((hi[:, 0] - gx0) / bs).astype(np.int64), 0, nbx - 1)
            j0 = np.clip(np.floor((lo[:, 1] - gy0) / bs).astype(np.int64), 0, nby - 1)
            j1 = np.clip(np.floor((hi[:, 1] - gy0) / bs).astype(np.int64), 0, nby - 1)
            cnt = (i1 - i0 + 1) * (j1 - j0 + 1)
            # long thin items (slivers of a triangulated top) listed in thousands of
            # buckets each: coarser buckets keep the index within MAX_ENTRIES
            if int(cnt.sum()) <= max(MAX_ENTRIES, 4 * n) or bs >= span:
                break
            bs *= 2.0
        owner = np.repeat(np.arange(n), cnt)
        k = np.arange(int(cnt.sum())) - np.repeat(np.cumsum(cnt) - cnt, cnt)
        w = np.repeat(i1 - i0 + 1, cnt)
        bucket_of = (np.repeat(j0, cnt) + k // w) * nbx + np.repeat(i0, cnt) + k % w
        order = np.argsort(bucket_of, kind="stable")
        items = np.ascontiguousarray(owner[order])
        start = np.searchsorted(bucket_of[order], np.arange(nbx * nby + 1)).astype(np.int64)
        blo = np.full((nbx * nby, 3), np.inf)
        bhi = np.full((nbx * nby, 3), -np.inf)
        full = np.flatnonzero(np.diff(start) > 0)
        if len(full):
            blo[full] = np.minimum.reduceat(lo[items], start[full], axis=0)
            bhi[full] = np.maximum.reduceat(hi[items], start[full], axis=0)
        return cls(lo, hi, start, items, i0, j0, blo, bhi, float(gx0), float(gy0), bs,
                   nbx, nby)

    def arrays(self):
        """The index as one tuple for numba (see :func:`box_candidates`)."""
        return (self.lo, self.hi, self.start, self.items, self.bi0, self.bj0, self.blo,
                self.bhi, self.x0, self.y0, self.bs, self.nbx, self.nby)


@njit(cache=True, inline="always")
def bucket_range(x0, y0, bs, nbx, nby, qx0, qy0, qx1, qy1):
    """Bucket columns/rows (ia, ib, ja, jb) a query box overlaps (empty: ia > ib)."""
    ia = int(math.floor((qx0 - x0) / bs))
    ib = int(math.floor((qx1 - x0) / bs))
    ja = int(math.floor((qy0 - y0) / bs))
    jb = int(math.floor((qy1 - y0) / bs))
    ia = max(ia, 0)
    ja = max(ja, 0)
    ib = min(ib, nbx - 1)
    jb = min(jb, nby - 1)
    return ia, ib, ja, jb


@njit(cache=True, inline="always")
def first_bucket(i, j, it_i0, it_j0, ia, ja):
    """True when bucket (i, j) is the first one shared by an item starting at bucket
    (it_i0, it_j0) and a query starting at (ia, ja)."""
    return i == max(it_i0, ia) and j == max(it_j0, ja)


@njit(cache=True)
def box_candidates(ix, qx0, qy0, qz0, qx1, qy1, qz1, buf):
    """Items of the index ``ix`` (:meth:`BoxIndex.arrays`) whose box overlaps the query
    box, each once, bucket by bucket, written to ``buf`` (an int64 array, replaced by
    one twice as long when full; give ``qz0 = -inf, qz1 = inf`` for an XY query).
    Buckets whose items' boxes all miss the query box are passed over whole. Returns
    (count, buffer)."""
    lo, hi, start, items, bi0, bj0, blo, bhi, x0, y0, bs, nbx, nby = ix
    ia, ib, ja, jb = bucket_range(x0, y0, bs, nbx, nby, qx0, qy0, qx1, qy1)
    n = 0
    for bj in range(ja, jb + 1):
        for bi in range(ia, ib + 1):
            b = bj * nbx + bi
            if (bhi[b, 0] < qx0 or blo[b, 0] > qx1 or bhi[b, 1] < qy0 or blo[b, 1] > qy1
                    or bhi[b, 2] < qz0 or blo[b, 2] > qz1):
                continue
            for p in range(start[b], start[b + 1]):
                t = items[p]
                if not first_bucket(bi, bj, bi0[t], bj0[t], ia, ja):
                    continue
                if (hi[t, 0] < qx0 or lo[t, 0] > qx1 or hi[t, 1] < qy0 or lo[t, 1] > qy1
                        or hi[t, 2] < qz0 or lo[t, 2] > qz1):
                    continue
                n, buf = push(buf, n, t)
    return n, buf


@njit(cache=True, inline="always")
def push(buf, n, t):
    """``buf[n] = t``, ``buf`` (int64) replaced by one twice as long when full; returns
    (n + 1, buffer)."""
    if n == buf.shape[0]:
        grown = np.empty(2 * n + 16, np.int64)
        grown[:n] = buf[:n]
        buf = grown
    buf[n] = t
    return n + 1, buf
