"""The material left's peaks, found between the sample points.

Sampled every ``spacing``, the material left reads a cusp between two passes low by up
to the cusp's slope times half the spacing (a ball's scallop about 10 % low at a
quarter of its radius). Around the highest samples the design is sampled again, on
each sample's own triangle, on grids each four times finer than the last, until the
step is under the accuracy; the figure is the highest found and where. Material
narrower than the sampling that no sample lands on (a thin ridge between two cuts) is
not seen: that width is the sample spacing, reported with the figure. Program units.
"""

from __future__ import annotations

from typing import Callable, Protocol

import numpy as np


class Measure(Protocol):
    """Measures material left at design points as the samples were measured."""

    def prepare(self, centres: np.ndarray, normals: np.ndarray, radius: float) -> None:
        """Every later point lies within ``radius`` of one of ``centres`` (on the
        triangle of that centre's normal)."""

    def __call__(self, points: np.ndarray, normals: np.ndarray,
                 owners: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(material left, bounding motion or -1) at each point."""


def closest_on_triangles(P: np.ndarray, T: np.ndarray) -> np.ndarray:
    """The point of triangle ``T[i]`` (n, 3, 3) nearest to ``P[i]`` (n, 3), for points in
    or near the triangle's plane."""
    A, B, C = T[:, 0], T[:, 1], T[:, 2]
    n = np.cross(B - A, C - A)
    nn = np.einsum("ij,ij->i", n, n)
    nn = np.where(nn > 0, nn, 1.0)
    Q = P - (np.einsum("ij,ij->i", P - A, n) / nn)[:, None] * n     # onto the plane
    # inside: each edge sees Q on its inner side
    inside = np.ones(len(P), bool)
    for a, b in ((A, B), (B, C), (C, A)):
        inside &= np.einsum("ij,ij->i", np.cross(b - a, Q - a), n) >= 0
    best = Q.copy()
    bestd = np.where(inside, 0.0, np.inf)
    for a, b in ((A, B), (B, C), (C, A)):
        e = b - a
        ee = np.einsum("ij,ij->i", e, e)
        t = np.clip(np.einsum("ij,ij->i", Q - a, e) / np.where(ee > 0, ee, 1.0), 0.0, 1.0)
        X = a + t[:, None] * e
        d = np.einsum("ij,ij->i", Q - X, Q - X)
        take = ~inside & (d < bestd)
        best[take] = X[take]
        bestd[take] = d[take]
    return best


def triangle_grids(points: np.ndarray, owners: np.ndarray, tri: np.ndarray,
                   half: float, n: int) -> tuple[np.ndarray, np.ndarray]:
    """An ``n`` x ``n`` grid ``2 * half`` wide around each point, in the plane of its
    triangle (axes along the triangle's longest edge and across it), each grid point
    moved to the nearest point of that triangle; returns (points, owners)."""
    T = tri[owners]
    e = np.stack([T[:, 1] - T[:, 0], T[:, 2] - T[:, 1], T[:, 0] - T[:, 2]], axis=1)
    k = np.argmax(np.linalg.norm(e, axis=2), axis=1)
    u = e[np.arange(len(T)), k]
    nrm = np.cross(T[:, 1] - T[:, 0], T[:, 2] - T[:, 0])
    u /= np.maximum(np.linalg.norm(u, axis=1), 1e-300)[:, None]
    v = np.cross(nrm, u)
    v /= np.maximum(np.linalg.norm(v, axis=1), 1e-300)[:, None]
    s = np.linspace(-half, half, n)
    a, b = (g.ravel() for g in np.meshgrid(s, s, indexing="ij"))
    G = (points[:, None, :] + a[None, :, None] * u[:, None, :]
         + b[None, :, None] * v[:, None, :]).reshape(-1, 3)
    own = np.repeat(owners, len(a))
    return closest_on_triangles(G, tri[own]), own


def peak_rounds(spacing: float, accuracy: float, n: int = 9) -> int:
    """How many grids :func:`refine_peaks` measures (the first ``spacing`` wide, each
    next ``(n - 1) / 2`` times finer, the last with steps of at most ``accuracy``)."""
    half, k = spacing, 1
    while 2.0 * half / (n - 1) > accuracy and k < 1000:
        half, k = 2.0 * half / (n - 1), k + 1
    return k


def refine_peaks(pts: np.ndarray, own: np.ndarray, left: np.ndarray, who: np.ndarray,
                 tri: np.ndarray, normals: np.ndarray, measure: Measure, spacing: float,
                 accuracy: float, top: int = 32, keep: int = 8, n: int = 9,
                 on_round: Callable[[], None] | None = None
                 ) -> tuple[float, np.ndarray | None, int]:
    """The highest material left near the ``top`` highest samples (those at least
    ``accuracy / 2``): (figure, design point or None, bounding motion). ``normals`` are
    the unit normals of ``tri``; ``measure`` measures points as the samples were.
    ``on_round()`` is called once the measure is prepared and after each of the
    :func:`peak_rounds` grids."""
    done = on_round or (lambda: None)
    if not len(left):
        return 0.0, None, -1
    q = int(np.argmax(left))
    best, at, bw = float(left[q]), pts[q].copy(), int(who[q])
    cand = np.flatnonzero(left >= accuracy / 2)
    if not len(cand) or spacing <= 0:
        return best, at, bw
    cand = cand[np.argsort(-left[cand], kind="stable")[:top]]
    P, O, L = pts[cand], own[cand], left[cand]
    half = spacing
    # later grids stay within half * (1 + 1/4 + 1/16 + ...) * sqrt(2) of the first centres
    measure.prepare(P, normals[O], 2.0 * half)
    done()
    while True:
        G, gown = triangle_grids(P, O, tri, half, n)
        gl, gw = measure(G, normals[gown], gown)
        done()
        if len(gl):
            j = int(np.argmax(gl))
            if gl[j] > best:
                best, at, bw = float(gl[j]), G[j].copy(), int(gw[j])
        step = 2.0 * half / (n - 1)
        if step <= accuracy:
            return best, at, bw
        # the next grids around the highest of each grid (and the old centres)
        per = gl.reshape(len(P), -1)
        arg = np.argmax(per, axis=1)
        hi = per[np.arange(len(P)), arg]
        better = hi > L
        P = np.where(better[:, None], G.reshape(len(P), -1, 3)[np.arange(len(P)), arg], P)
        L = np.maximum(L, hi)
        order = np.argsort(-L, kind="stable")[:keep]
        P, O, L = P[order], O[order], L[order]
        half = step
