"""Contour start, lead-in and lead-out arcs of a profile (job units, XY).

The contour is followed with the tool on side ``s`` (+1: left, G41; -1: right, G42).
At the start point P0 (middle of the longest straight stretch) with unit tangent t
and tool-side normal n = s * rot90(t), the lead-in is a straight entry along -n
from S = A + d n to A = C - rho t, then a quarter arc about C = P0 + rho n onto P0
(counter-clockwise for s = +1); the lead-out mirrors it (arc from P0 to B = C + rho t,
exit along +n). ``rho`` is the programmed lead radius (> tool radius, so the tool
centre's arc has radius rho - R under control compensation) and ``d`` the entry length.
For CAM compensation the same leads are offset by R toward the tool side.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass
class Leads:
    S: np.ndarray          # entry start (tool-centre position: compensation starts here)
    A: np.ndarray          # arc start
    C: np.ndarray          # arc centre
    B: np.ndarray          # lead-out arc end
    E: np.ndarray          # exit end
    ccw: bool              # arc direction


def start_on_chord(ring: np.ndarray, k: int) -> np.ndarray:
    """``ring`` (n, 2, not closed) rotated to start at the middle of its chord ``k``
    (from vertex k to k + 1)."""
    nxt = np.roll(ring, -1, axis=0)
    mid = (ring[k] + nxt[k]) / 2
    return np.vstack([mid, np.roll(ring, -(k + 1), axis=0)])


def chords_by_length(ring: np.ndarray, n: int = 8) -> list[int]:
    """Indices of the ``n`` longest chords of ``ring`` (n, 2, not closed), longest first."""
    nxt = np.roll(ring, -1, axis=0)
    L = np.hypot(*(nxt - ring).T)
    return [int(k) for k in np.argsort(-L, kind="stable")[:n]]


def leads(P0: np.ndarray, t: np.ndarray, side: int, rho: float, d: float,
          offset: float = 0.0) -> Leads:
    """Leads at P0 (tangent ``t``) with the contour offset by ``offset`` to the tool side
    (0: the programmed contour; R: the tool-centre path)."""
    t = t / np.hypot(*t)
    n = side * np.array([-t[1], t[0]])
    C = P0 + rho * n
    r = rho - offset
    A = C - r * t
    B = C + r * t
    return Leads(A + d * n, A, C, B, B + d * n, ccw=side > 0)
