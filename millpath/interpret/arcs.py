"""Arc centers from I/J/K or R and LinuxCNC's arc checks.

All functions work in a plane's (first, second) coordinates: XY=(X, Y), XZ=(Z, X),
YZ=(Y, Z), as RS274NGC. ``turn`` is the signed turn count: +P counter-clockwise (G3),
-P clockwise (G2). Tolerances are lengths in program units (LinuxCNC's: 0.00005 in /
0.00127 mm minimum radius, 0.002*sqrt(2) in / 0.02*sqrt(2) mm spiral, 0.1 % relative;
rs274 2.9 refuses an arc only when both spiral limits are exceeded).
"""

from __future__ import annotations

import math
from math import asin, atan2, cos, hypot, sin

from millpath.interpret.errors import GCodeError
from millpath.model.units import MM_PER_INCH

AXIS_NAMES = {"XY": ("X", "Y"), "XZ": ("Z", "X"), "YZ": ("Y", "Z")}
RADIUS_TOLERANCE = {"inch": 0.00005, "mm": 0.00005 * MM_PER_INCH}
SPIRAL_TOLERANCE = {"inch": 2 * 0.001 * math.sqrt(2.0), "mm": 2 * 0.01 * math.sqrt(2.0)}
SPIRAL_RELATIVE = 0.001
TINY = 1e-12
ONE_MINUS_TINY = 1.0 - TINY
HALF_PI = math.pi / 2.0
TWO_PI = 2.0 * math.pi


def _fmt(plane: str, sx, sy, cx, cy, ex, ey, r1, r2) -> str:
    a, b = AXIS_NAMES[plane]
    return (f"start=({a}{sx:.4f},{b}{sy:.4f}) center=({a}{cx:.4f},{b}{cy:.4f}) "
            f"end=({a}{ex:.4f},{b}{ey:.4f}) r1={r1:.4f} r2={r2:.4f}")


def _g_fmt(v: float) -> str:
    """C's %.4g."""
    s = f"{v:.4g}"
    if "e" in s:
        m, e = s.split("e")
        sign = e[0]
        digits = e[1:].lstrip("0").rjust(2, "0")
        s = f"{m}e{sign}{digits}"
    return s


def check_arc(plane: str, sx: float, sy: float, ox: float, oy: float, ex: float, ey: float,
              rtol: float, stol: float) -> float:
    """Raise LinuxCNC's zero-radius / spiral errors for an arc from (sx, sy) about
    (ox, oy) to (ex, ey) (``rtol``, ``stol``: the units' RADIUS_TOLERANCE and
    SPIRAL_TOLERANCE); return its start radius."""
    r1 = hypot(ox - sx, oy - sy)
    r2 = hypot(ox - ex, oy - ey)
    if r1 < rtol or r2 < rtol:
        raise GCodeError("Zero-radius arc: " + _fmt(plane, sx, sy, ox, oy, ex, ey, r1, r2))
    abs_err = abs(r1 - r2)
    if abs_err > stol and abs_err / max(r1, r2) > SPIRAL_RELATIVE:
        rel_err = abs_err / max(r1, r2)
        raise GCodeError("Radius to end of arc differs from radius to start: "
                         + _fmt(plane, sx, sy, ox, oy, ex, ey, r1, r2)
                         + f" abs_err={_g_fmt(abs_err)} rel_err={rel_err * 100:.4f}%")
    return r1


def arc_center_ijk(plane: str, units: str, cx: float, cy: float, ex: float, ey: float,
                   absolute: bool, i: float, j: float) -> tuple[float, float, float]:
    """Center and start radius of an I/J/K arc; raises LinuxCNC's zero-radius / spiral
    errors (:func:`check_arc`). Returns (center1, center2, r_start)."""
    if absolute:
        ox, oy = i, j
    else:
        ox, oy = cx + i, cy + j
    r1 = check_arc(plane, cx, cy, ox, oy, ex, ey, RADIUS_TOLERANCE[units],
                   SPIRAL_TOLERANCE[units])
    return ox, oy, r1


def arc_center_r(clockwise: bool, units: str, cx: float, cy: float, ex: float, ey: float,
                 radius: float) -> tuple[float, float]:
    """Center of an R-format arc (negative R: more than half a circle)."""
    if ex == cx and ey == cy:
        raise GCodeError("Current point same as end point of arc")
    abs_r = abs(radius)
    mx = (ex + cx) / 2.0
    my = (ey + cy) / 2.0
    half = hypot(mx - ex, my - ey)
    if half - abs_r > RADIUS_TOLERANCE[units]:
        raise GCodeError("Arc radius too small to reach end point")
    if abs_r == 0.0 or half / abs_r > ONE_MINUS_TINY:
        half = abs_r
    base = atan2(ey - cy, ex - cx)
    if (clockwise and radius > 0) or (not clockwise and radius < 0):
        theta = base - HALF_PI
    else:
        theta = base + HALF_PI
    turn2 = asin(half / abs_r) if abs_r else 0.0
    off = abs_r * cos(turn2)
    return mx + off * cos(theta), my + off * sin(theta)


def find_turn(x1: float, y1: float, cx: float, cy: float, turn: int, x2: float,
              y2: float) -> float:
    """Signed sweep angle (radians) from (x1, y1) to (x2, y2) about the center."""
    if turn == 0:
        return 0.0
    alpha = atan2(y1 - cy, x1 - cx)
    beta = atan2(y2 - cy, x2 - cx)
    if turn > 0:
        if beta <= alpha:
            beta += TWO_PI
        return (beta - alpha) + (turn - 1) * TWO_PI
    if alpha <= beta:
        alpha += TWO_PI
    return (beta - alpha) + (turn + 1) * TWO_PI
