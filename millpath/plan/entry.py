"""Entries into material: a helix instead of a straight plunge of an end mill.

:func:`helix_entry` finds a helix that ends at a cutting start point, descending from a
height above the material at no more than a ramp angle, whose tool centre circle stays
where the tool centre may go and never below the lowest allowed tip height. Lengths
in job units, angles in degrees. Strategies append it with :meth:`Toolpath.arc` (one
arc move, ``turns`` full turns about the Z axis, start = end in XY).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Callable

import numpy as np


@dataclass
class Helix:
    center: tuple[float, float]
    radius: float
    turns: int
    end: tuple[float, float, float]


def helix_entry(target, z_from: float, tool_radius: float, *,
                centre_ok: Callable[[np.ndarray, np.ndarray], bool],
                floor: Callable[[np.ndarray, np.ndarray], np.ndarray],
                angle: float = 3.0, radii=(0.5, 0.35, 0.25, 0.15), directions: int = 8,
                samples: int = 48, first: float | None = None) -> Helix | None:
    """A helix from ``z_from`` down to ``target`` (x, y, z), or None if none fits.

    ``centre_ok(xs, ys)``: True when the tool centre may pass through all those points;
    ``floor(xs, ys)``: the lowest tip Z allowed at each point. The helix circle has a
    radius of ``radii`` times the tool radius (largest first), its centre in one of
    ``directions`` around the target; the descent per turn is at most
    ``2 pi r tan(angle)``. ``first``: a direction of the centre from the target
    (radians) tried before the others, for example downhill from the target, where the
    circle bends away from the material the target touches.
    """
    tx, ty, tz = map(float, target)
    depth = z_from - tz
    if depth <= 0:
        return None
    t = np.linspace(0.0, 2 * math.pi, samples, endpoint=False)
    for k in radii:
        rh = k * tool_radius
        if rh <= 0:
            continue
        per_turn = 2 * math.pi * rh * math.tan(math.radians(angle))
        turns = max(1, math.ceil(depth / per_turn - 1e-9))
        angles = [2 * math.pi * j / directions for j in range(directions)]
        for a in ([first] if first is not None else []) + angles:
            cx, cy = tx + rh * math.cos(a), ty + rh * math.sin(a)
            # the target is on the circle at angle a + pi seen from the centre
            xs, ys = cx + rh * np.cos(t), cy + rh * np.sin(t)
            if not centre_ok(xs, ys):
                continue
            # the lowest the helix gets at each angle is on its last turn; the last
            # turn runs counter-clockwise from the target back to it
            phase = np.mod(t - (a + math.pi), 2 * math.pi) / (2 * math.pi)
            z_last = tz + depth / turns * (1.0 - phase)
            if np.all(z_last >= np.asarray(floor(xs, ys)) - 1e-9):
                return Helix((cx, cy), rh, turns, (tx, ty, tz))
    return None


@dataclass
class Ramp:
    far: tuple[float, float]
    legs: int                          # even: the last leg ends at the target
    end: tuple[float, float, float]

    def points(self, z_from: float) -> list[tuple[float, float, float]]:
        """End points of the legs, alternately at ``far`` and at the target."""
        tx, ty, tz = self.end
        out = []
        for k in range(1, self.legs + 1):
            z = z_from - (z_from - tz) * k / self.legs
            out.append((self.far[0], self.far[1], z) if k % 2 else (tx, ty, z))
        return out


def ramp_entry(target, z_from: float, tool_radius: float, *,
               centre_ok: Callable[[np.ndarray, np.ndarray], bool],
               floor: Callable[[np.ndarray, np.ndarray], np.ndarray],
               angle: float = 5.0, lengths=(2.0, 1.0, 0.5, 0.25), directions: int = 16,
               samples: int = 24) -> Ramp | None:
    """A zigzag ramp from ``z_from`` down to ``target`` along a straight leg of
    ``lengths`` times the tool radius (longest first) in one of ``directions``, at most
    ``angle`` steep, where the whole leg is allowed for the tool centre and the last
    (lowest) leg stays above ``floor``; None if none fits."""
    tx, ty, tz = map(float, target)
    depth = z_from - tz
    if depth <= 0:
        return None
    s = np.linspace(0.0, 1.0, samples)
    for k in lengths:
        L = k * tool_radius
        legs = max(2, math.ceil(depth / (L * math.tan(math.radians(angle))) - 1e-9))
        legs += legs % 2
        for j in range(directions):
            a = 2 * math.pi * j / directions
            fx, fy = tx + L * math.cos(a), ty + L * math.sin(a)
            xs, ys = tx + (fx - tx) * s, ty + (fy - ty) * s
            if not centre_ok(xs, ys):
                continue
            z_last = tz + depth / legs * s          # last leg: far (s=1) -> target (s=0)
            if np.all(z_last >= np.asarray(floor(xs, ys)) - 1e-9):
                return Ramp((fx, fy), legs, (tx, ty, tz))
    return None


def ring_segments(ring: np.ndarray) -> tuple[np.ndarray, np.ndarray, float]:
    """The closed ring ``(n, 2)`` as ``(closed points (n + 1, 2), segment lengths (n,),
    perimeter)``."""
    closed = np.vstack([ring, ring[:1]])
    seg = np.hypot(*np.diff(closed, axis=0).T)
    return closed, seg, float(seg.sum())


def ramp_laps(tp, closed: np.ndarray, seg: np.ndarray, laps: int, z_from: float,
              z_to: float, feed: float) -> None:
    """Append to the toolpath ``tp`` a descent from ``z_from`` to ``z_to`` along
    ``laps`` laps of a ring (``closed``, ``seg`` from :func:`ring_segments`), Z falling
    in proportion to the length walked, ending at the ring's first point."""
    total = laps * float(seg.sum())
    walked = 0.0
    for _ in range(laps):
        for p, L in zip(closed[1:], seg):
            walked += L
            tp.line(p[0], p[1], z_from - (z_from - z_to) * walked / total, feed)
