"""Test drawings of 2.5D parts written with ezdxf, with their analytic truth (test
support: used by tests/profile and tests/pocket).

Millimetres, ``$INSUNITS = 4``. Each drawing is a list of *contours*, each a list of
pieces that are exact geometry: ``("line", (x0, y0), (x1, y1))``, ``("arc", (cx, cy),
r, a0, a1)`` (degrees, counter-clockwise from a0 to a1), ``("circle", (cx, cy), r)``,
``("ellipse", (cx, cy), a, b)`` (semi-axes along X and Y). :func:`signed_distance`
measures points against them: positive on the contour's outside.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np


@dataclass
class Contour:
    name: str
    kind: str                   # "outline", "circle", "slot", "oval"
    pieces: list[tuple]
    width: float                # a circle's diameter, a slot's width, ...
    layer: str = "0"

    def area(self) -> float:
        return polygon(self, 0.001).area


def _slot(name: str, a, b, w: float, layer: str = "0") -> Contour:
    """A slot (two lines, two half arcs) of width ``w`` between centres ``a`` and ``b``."""
    a, b = np.asarray(a, float), np.asarray(b, float)
    d = (b - a) / np.hypot(*(b - a))
    n = np.array([-d[1], d[0]]) * w / 2
    ang = math.degrees(math.atan2(d[1], d[0]))
    return Contour(name, "slot", [("line", tuple(a - n), tuple(b - n)),
                                  ("arc", tuple(b), w / 2, ang - 90, ang + 90),
                                  ("line", tuple(b + n), tuple(a + n)),
                                  ("arc", tuple(a), w / 2, ang + 90, ang + 270)], w, layer)


def _rounded_rect(name: str, x0, y0, x1, y1, r, layer: str = "0") -> Contour:
    p = [("line", (x0 + r, y0), (x1 - r, y0)), ("arc", (x1 - r, y0 + r), r, -90, 0),
         ("line", (x1, y0 + r), (x1, y1 - r)), ("arc", (x1 - r, y1 - r), r, 0, 90),
         ("line", (x1 - r, y1), (x0 + r, y1)), ("arc", (x0 + r, y1 - r), r, 90, 180),
         ("line", (x0, y1 - r), (x0, y0 + r)), ("arc", (x0 + r, y0 + r), r, 180, 270)]
    return Contour(name, "outline", p, min(x1 - x0, y1 - y0), layer)


def plate() -> list[Contour]:
    """A 120 x 80 plate with 6 mm corner radii (layer OUTLINE): four 6.6 holes and two
    10 mm holes (layer HOLES), a 19 mm bore (BORE), three slots 8 wide with 16 between
    centres and an oval, an ellipse 10 x 16 (SLOTS)."""
    out = [_rounded_rect("outline", 0, 0, 120, 80, 6, "OUTLINE")]
    for k, (x, y) in enumerate([(10, 10), (110, 10), (10, 70), (110, 70)]):
        out.append(Contour(f"hole6.6-{k}", "circle", [("circle", (x, y), 3.3)], 6.6, "HOLES"))
    for k, (x, y) in enumerate([(35, 62), (85, 62)]):
        out.append(Contour(f"hole10-{k}", "circle", [("circle", (x, y), 5.0)], 10.0, "HOLES"))
    out.append(Contour("bore19", "circle", [("circle", (60, 40), 9.5)], 19.0, "BORE"))
    out.append(_slot("slot-0", (30, 18), (46, 18), 8.0, "SLOTS"))
    out.append(_slot("slot-1", (74, 18), (90, 18), 8.0, "SLOTS"))
    out.append(_slot("slot-2", (100, 34), (100, 50), 8.0, "SLOTS"))
    out.append(Contour("oval", "oval", [("ellipse", (22, 42), 5.0, 8.0)], 10.0, "SLOTS"))
    return out


def island_pocket() -> list[Contour]:
    """An 80 x 50 pocket (corners sharp) round a 16 mm round island at its centre."""
    box = [("line", (0, 0), (80, 0)), ("line", (80, 0), (80, 50)),
           ("line", (80, 50), (0, 50)), ("line", (0, 50), (0, 0))]
    return [Contour("pocket", "outline", box, 50.0),
            Contour("island", "circle", [("circle", (40, 25), 8.0)], 16.0)]


def write(contours: list[Contour], path: Path) -> Path:
    """The contours as DXF entities (LINE, ARC, CIRCLE, ELLIPSE) on their layers."""
    import ezdxf
    doc = ezdxf.new("R2010")
    doc.header["$INSUNITS"] = 4
    msp = doc.modelspace()
    for c in contours:
        a = {"layer": c.layer}
        for p in c.pieces:
            if p[0] == "line":
                msp.add_line(p[1], p[2], dxfattribs=a)
            elif p[0] == "arc":
                msp.add_arc(p[1], p[2], p[3], p[4], dxfattribs=a)
            elif p[0] == "circle":
                msp.add_circle(p[1], p[2], dxfattribs=a)
            else:
                (cx, cy), ax, by = p[1], p[2], p[3]
                major, ratio = ((ax, 0), by / ax) if ax >= by else ((0, by), ax / by)
                msp.add_ellipse((cx, cy), major, ratio, dxfattribs=a)
    doc.saveas(path)
    return path


def _piece_points(p, step: float) -> np.ndarray:
    if p[0] == "line":
        a, b = np.asarray(p[1], float), np.asarray(p[2], float)
        n = max(1, int(math.ceil(np.hypot(*(b - a)) / step)))
        return a + np.linspace(0, 1, n + 1)[:, None] * (b - a)
    if p[0] == "arc":
        (cx, cy), r, a0, a1 = p[1], p[2], p[3], p[4]
        sw = (a1 - a0) % 360 or 360
        t = np.radians(a0 + sw * np.linspace(0, 1, max(8, int(r * math.radians(sw) / step)) + 1))
        return np.column_stack([cx + r * np.cos(t), cy + r * np.sin(t)])
    if p[0] == "circle":
        (cx, cy), r = p[1], p[2]
        t = np.linspace(0, 2 * math.pi, max(16, int(2 * math.pi * r / step)) + 1)
        return np.column_stack([cx + r * np.cos(t), cy + r * np.sin(t)])
    (cx, cy), a, b = p[1], p[2], p[3]
    t = np.linspace(0, 2 * math.pi, max(16, int(2 * math.pi * max(a, b) / step)) + 1)
    return np.column_stack([cx + a * np.cos(t), cy + b * np.sin(t)])


def polygon(c: Contour, step: float):
    """The contour as a shapely polygon with vertices on the curves ``step`` apart."""
    from shapely.geometry import Polygon
    pts = np.vstack([_piece_points(p, step) for p in c.pieces])
    return Polygon(pts).buffer(0)


def signed_distance(c: Contour, pts: np.ndarray) -> np.ndarray:
    """Distance (n,) of points (n, 2) to the contour ``c``, positive outside it.
    Lines, arcs and circles exactly; an ellipse by Newton's method on its parameter."""
    pts = np.asarray(pts, float)
    best = np.full(len(pts), np.inf)
    for p in c.pieces:
        best = np.minimum(best, _distance(p, pts))
    inside = _inside(c, pts)
    return np.where(inside, -best, best)


def _distance(p, q: np.ndarray) -> np.ndarray:
    if p[0] == "line":
        a, b = np.asarray(p[1], float), np.asarray(p[2], float)
        d = b - a
        t = np.clip(((q - a) @ d) / (d @ d), 0.0, 1.0)
        return np.hypot(*(q - (a + t[:, None] * d)).T)
    if p[0] in ("arc", "circle"):
        c, r = np.asarray(p[1], float), p[2]
        v = q - c
        rho = np.hypot(*v.T)
        if p[0] == "circle":
            return np.abs(rho - r)
        a0, a1 = p[3], p[4]
        sw = (a1 - a0) % 360 or 360
        ang = np.degrees(np.arctan2(v[:, 1], v[:, 0]))
        on = (ang - a0) % 360 <= sw
        ends = [c + r * np.array([math.cos(math.radians(a)), math.sin(math.radians(a))])
                for a in (a0, a1)]
        off = np.minimum(np.hypot(*(q - ends[0]).T), np.hypot(*(q - ends[1]).T))
        return np.where(on, np.abs(rho - r), off)
    (cx, cy), a, b = p[1], p[2], p[3]
    x, y = q[:, 0] - cx, q[:, 1] - cy
    # nearest point by Newton on f(t) = d/dt |E(t) - q|^2 / 2, from the best of 64 starts
    t0 = np.linspace(0, 2 * math.pi, 64, endpoint=False)
    d2 = (a * np.cos(t0)[None] - x[:, None]) ** 2 + (b * np.sin(t0)[None] - y[:, None]) ** 2
    t = t0[np.argmin(d2, axis=1)]
    for _ in range(30):
        c_, s_ = np.cos(t), np.sin(t)
        f = (b * b - a * a) * s_ * c_ + a * x * s_ - b * y * c_
        df = (b * b - a * a) * (c_ * c_ - s_ * s_) + a * x * c_ + b * y * s_
        t = t - f / np.where(np.abs(df) > 1e-300, df, 1e-300)
    return np.hypot(a * np.cos(t) - x, b * np.sin(t) - y)


def _inside(c: Contour, q: np.ndarray) -> np.ndarray:
    if len(c.pieces) == 1 and c.pieces[0][0] == "circle":
        (cx, cy), r = c.pieces[0][1], c.pieces[0][2]
        return np.hypot(q[:, 0] - cx, q[:, 1] - cy) < r
    if len(c.pieces) == 1 and c.pieces[0][0] == "ellipse":
        (cx, cy), a, b = c.pieces[0][1], c.pieces[0][2], c.pieces[0][3]
        return ((q[:, 0] - cx) / a) ** 2 + ((q[:, 1] - cy) / b) ** 2 < 1
    import shapely
    return shapely.contains_xy(polygon(c, 0.01), q[:, 0], q[:, 1])
