"""Arc and spline fitting: runs of G1 moves become G2/G3 arcs and G5 cubics.

Two entry points:

- :func:`fit_toolpath` rewrites a :class:`~millpath.model.Toolpath` (``millpath run``
  calls it between planning and posting when the job sets ``fit``);
- :func:`fit_program` rewrites an existing RS274NGC program (``millpath fit``, which
  reads the result back with the interpreter before writing it:
  :func:`millpath.fit.readback.read_back`).

Only runs of consecutive linear feed moves of one operation at one feed are rewritten;
rapids, drilling cycles, arcs already present, and everything under cutter radius
compensation (``G41``/``G42`` up to and including the move after ``G40``) stay as they
are. ``tolerance`` is an absolute length in the job's (program's) units: every point of
the fitted path is within it of the original path and every point of the original
within it of the fitted path, after rounding to the post-processor's decimals (4 in mm,
5 in inch). Arcs: XY, XZ, YZ, helical (normal travel linear in the angle); their radius
lies between ``max(min_radius, 4 tolerance, 200 grid steps)`` and :data:`MAX_RADIUS_MM`
(longer radii are written as lines, shorter ones keep the points); they never reverse
the turning direction of an original corner sharper than :data:`CORNER_DEG`. Cubics
(mode ``"arcs+cubics"``): XY at constant Z, G1-continuous at smooth vertices.
"""

from __future__ import annotations

import math

import numpy as np

from millpath.fit.arcs import LINUXCNC_ARC_ABS_INCH, LINUXCNC_ARC_ABS_MM
from millpath.fit.segment import PLANE_NAMES, PLANES, segment
from millpath.model.toolpath import Move, Toolpath
from millpath.model.units import as_written, default, length_scale

__all__ = ["fit_toolpath", "fit_program", "fit_points", "FitSettings", "MODES"]

MODES = ("none", "arcs", "arcs+cubics")
#: arcs with a larger radius (mm; converted for an inch program) are written as lines
MAX_RADIUS_MM = 1000.0
#: an original vertex turning more than this is a corner whose direction arcs keep
CORNER_DEG = 5.0
#: vertices turning less than this are smooth: cubics meeting there share a tangent
SMOOTH_DEG = 20.0


class FitSettings:
    """Derived numbers for one unit system and tolerance (all lengths in job units)."""

    def __init__(self, units: str, tolerance: float, mode: str = "arcs",
                 min_radius: float = 0.0, decimals: int | None = None):
        if mode not in MODES:
            raise ValueError(f"fit mode must be one of {', '.join(MODES)}, not {mode!r}")
        if not (isinstance(tolerance, (int, float)) and math.isfinite(tolerance)
                and tolerance > 0):
            raise ValueError(f"fit tolerance must be a positive length, not {tolerance!r}")
        if units not in ("mm", "inch"):
            raise ValueError(f"units must be mm or inch, not {units!r}")
        inch = units == "inch"
        self.units = units
        self.mode = mode
        self.decimals = decimals if decimals is not None else int(default("decimals", units))
        self.q = 10.0 ** -self.decimals
        # rounding every point to the grid moves it by up to sqrt(3)/2 grid steps
        self.tol = float(tolerance) - 0.8661 * self.q
        if self.tol <= 0.1 * tolerance:
            raise ValueError(f"fit tolerance {tolerance:g} is too small for "
                             f"{self.decimals} decimals")
        self.abs_lim = LINUXCNC_ARC_ABS_INCH if inch else LINUXCNC_ARC_ABS_MM
        self.rmin = max(float(min_radius), 4.0 * float(tolerance), 200.0 * self.q)
        self.rmax = MAX_RADIUS_MM * length_scale("mm", "inch" if inch else "mm")
        self.corner = math.radians(CORNER_DEG)
        self.smooth = math.radians(SMOOTH_DEG)
        self.cubics = mode == "arcs+cubics"


def _dedupe(P: np.ndarray) -> np.ndarray:
    """Indices of points that differ from their predecessor (the first is kept)."""
    if len(P) == 0:
        return np.zeros(0, dtype=np.int64)
    keep = np.ones(len(P), dtype=bool)
    keep[1:] = np.any(P[1:] != P[:-1], axis=1)
    return np.flatnonzero(keep)


def fit_points(points: np.ndarray, s: FitSettings):
    """Fit one polyline ``points`` ((n, 3), start point first, job units).

    Returns ``(P, idx, kinds, ends, params)``: the points as the post writes them
    (:func:`~millpath.model.units.as_written`), de-duplicated,
    the index of each in ``points``, and the primitives of
    :func:`millpath.fit.segment.segment` (ends index ``P``).
    """
    pts = np.asarray(points, dtype=float)
    R = as_written(pts, s.decimals)             # the grid as the post writes it
    idx = _dedupe(R)
    P = np.ascontiguousarray(R[idx])
    if len(P) < 2:
        return P, idx, np.zeros(0, np.int8), np.zeros(0, np.int64), np.zeros((0, 8))
    kinds, ends, par = segment(P, s.tol, s.q, s.abs_lim, s.rmin, s.rmax, s.corner,
                               s.cubics, s.smooth)
    return P, idx, kinds, ends, par


def _moves_for_run(start, lines: list[Move], s: FitSettings) -> list[Move]:
    pts = np.array([start] + [m.end for m in lines], dtype=float)
    P, idx, kinds, ends, par = fit_points(pts, s)
    if len(kinds) >= len(lines):
        return list(lines)
    feed, op = lines[0].feed, lines[0].op
    out: list[Move] = []
    prev = 0
    for k, e, p in zip(kinds.tolist(), ends.tolist(), par):
        end = tuple(float(v) for v in P[e])
        if k == 0:
            if e == prev + 1 and idx[e] == idx[prev] + 1:
                out.append(lines[idx[e] - 1])     # untouched original move
            else:
                out.append(Move("line", end, feed, op))   # merged: the checked chord
        elif k == 1:
            pl = int(p[0])
            a1, a2, an = (int(v) for v in PLANES[pl])
            c = [0.0, 0.0, 0.0]
            c[a1], c[a2], c[an] = float(p[1]), float(p[2]), float(P[prev][an])
            out.append(Move("arc", end, feed, op, center=tuple(c), plane=PLANE_NAMES[pl],
                            clockwise=bool(p[3] > 0.5)))
        else:
            out.append(Move("cubic", end, feed, op, c1=(float(p[0]), float(p[1])),
                            c2=(float(p[2]), float(p[3]))))
        prev = e
    return out


def fit_toolpath(toolpath: Toolpath, tolerance: float, mode: str = "arcs", *,
                 min_radius: float = 0.0) -> Toolpath:
    """A new toolpath with linear runs replaced by arcs (and cubics) within ``tolerance``.

    ``tolerance`` and ``min_radius`` are in the toolpath's units. ``mode``: ``"none"``
    (a copy), ``"arcs"`` or ``"arcs+cubics"``. ``min_radius`` (the largest tool radius
    in use): no fitted arc has a radius at or below it; since the side the material is
    on is not known here, this holds for convex and concave arcs alike.
    """
    s = FitSettings(toolpath.units, tolerance, mode, min_radius)
    out = Toolpath(units=toolpath.units, moves=[], ops=list(toolpath.ops))
    moves = toolpath.moves
    if mode == "none":
        out.moves = list(moves)
        return out
    from millpath.fit.collinear import rebuild_line_runs
    return rebuild_line_runs(toolpath, lambda start, run: _moves_for_run(start, run, s))


def fit_program(text: str, tolerance: float, mode: str = "arcs", *,
                min_radius: float = 0.0, file: str | None = None, stats=None) -> str:
    """Rewrite the runs of ``G1`` moves of an RS274NGC program within ``tolerance``
    (program units); see :mod:`millpath.fit.program` (``stats``: a ``FitStats``)."""
    from millpath.fit.program import fit_program as _fp
    return _fp(text, tolerance, mode, min_radius=min_radius, file=file, stats=stats)
