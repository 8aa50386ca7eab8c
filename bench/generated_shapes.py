"""Random simple polygons and islands a user could draw, for generated jobs.

Millimetres; polygons are lists of [x, y] (counter-clockwise, no repeated closing
point), rounded to 3 decimals and valid (simple) after rounding. Every draw comes from
the ``numpy.random.Generator`` passed in, so a seed gives the same shapes.
"""

from __future__ import annotations

import math

import numpy as np
import shapely
from shapely import affinity
from shapely.geometry import Point, Polygon, box
from shapely.geometry.polygon import orient

KINDS = ("convex", "star", "u", "l", "neck", "rounded")


def _coords(p: Polygon) -> list[list[float]]:
    return [[round(float(x), 3), round(float(y), 3)] for x, y in p.exterior.coords[:-1]]


def _valid(pts: list[list[float]]) -> Polygon | None:
    if len(pts) < 3:
        return None
    p = Polygon(pts)
    return p if p.is_valid and p.area > 1.0 else None


def _convex(rng: np.random.Generator, w: float, h: float) -> Polygon:
    pts = rng.uniform([0, 0], [w, h], size=(int(rng.integers(5, 12)), 2))
    return shapely.convex_hull(shapely.multipoints(pts))


def _star(rng: np.random.Generator, w: float, h: float) -> Polygon:
    n = int(rng.integers(5, 13))
    ang = np.sort(rng.uniform(0, 2 * math.pi, n))
    r = rng.uniform(0.45, 1.0, n)
    return Polygon(np.column_stack([w / 2 * (1 + r * np.cos(ang)),
                                    h / 2 * (1 + r * np.sin(ang))]))


def _u(rng: np.random.Generator, w: float, h: float, tool_d: float) -> Polygon:
    slot_w = rng.uniform(0.15, 0.5) * w
    slot_d = rng.uniform(0.2, 0.7) * h
    x0 = rng.uniform(0.2 * w, 0.8 * w - slot_w)
    return box(0, 0, w, h).difference(box(x0, h - slot_d, x0 + slot_w, h + 1))


def _l(rng: np.random.Generator, w: float, h: float, tool_d: float) -> Polygon:
    cw, ch = rng.uniform(0.3, 0.7) * w, rng.uniform(0.3, 0.7) * h
    return box(0, 0, w, h).difference(box(w - cw, h - ch, w + 1, h + 1))


def _neck(rng: np.random.Generator, w: float, h: float, tool_d: float) -> Polygon:
    a = rng.uniform(0.3, 0.45) * w
    neck = min(rng.uniform(1.05, 3.0) * tool_d, 0.7 * h)   # the tool's width, or most of h
    y0 = rng.uniform(0.1 * h, 0.9 * h - neck)
    return shapely.union_all([box(0, 0, a, h), box(w - a, 0, w, h),
                              box(a - 1, y0, w - a + 1, y0 + neck)])


def _rounded(rng: np.random.Generator, w: float, h: float, tool_d: float) -> Polygon:
    base = (_u if rng.random() < 0.5 else _l)(rng, w, h, tool_d)
    r = rng.uniform(0.3, 3.0)
    p = base.buffer(r, quad_segs=4).buffer(-r, quad_segs=4)   # concave corners rounded
    return p.buffer(-r, quad_segs=4).buffer(r, quad_segs=4)   # convex corners rounded


def polygon(rng: np.random.Generator, kind: str, origin: tuple[float, float], w: float,
            h: float, tool_d: float) -> list[list[float]]:
    """A simple polygon of ``kind`` (see KINDS) in the box ``origin`` + (w, h), turned by
    a random angle about its centre (and kept in the box's bounding circle); the box
    itself if 50 draws give none wide enough for the tool."""
    for _ in range(50):
        if kind == "convex":
            p = _convex(rng, w, h)
        elif kind == "star":
            p = _star(rng, w, h)
        else:
            p = {"u": _u, "l": _l, "neck": _neck, "rounded": _rounded}[kind](rng, w, h, tool_d)
        if rng.random() < 0.5:
            p = affinity.rotate(p, float(rng.uniform(0, 360)), origin=(w / 2, h / 2))
            s = min(w / (p.bounds[2] - p.bounds[0]), h / (p.bounds[3] - p.bounds[1]), 1.0)
            p = affinity.scale(p, s, s, origin=(w / 2, h / 2))
            p = affinity.translate(p, -p.bounds[0], -p.bounds[1])
        p = orient(affinity.translate(p, *origin).simplify(0.01), 1.0)
        if p.geom_type != "Polygon" or p.interiors:
            continue
        pts = _coords(p)
        q = _valid(pts)
        if q is not None and q.buffer(-0.6 * tool_d).area > 0.1 * q.area:
            return pts
    # (a tool too large for this kind of shape at this size): the box
    return _coords(orient(box(origin[0], origin[1], origin[0] + w, origin[1] + h), 1.0))


def islands(rng: np.random.Generator, outer: list[list[float]], tool_d: float,
            count: int, gap: float) -> list[list[list[float]]]:
    """Up to ``count`` islands (circles of 16-64 chords or rectangles) inside ``outer``,
    each at least ``gap`` from the outline and from the others."""
    room = Polygon(outer)
    out: list[list[list[float]]] = []
    for _ in range(count * 20):
        if len(out) == count:
            break
        r = rng.uniform(0.6, 2.5) * tool_d
        free = room.buffer(-(gap + r))
        if free.is_empty:
            continue
        x0, y0, x1, y1 = free.bounds
        c = Point(rng.uniform(x0, x1), rng.uniform(y0, y1))
        if not free.contains(c):
            continue
        if rng.random() < 0.6:
            isl = c.buffer(r, quad_segs=int(rng.integers(4, 17)))
        else:
            isl = affinity.rotate(box(c.x - r, c.y - 0.6 * r, c.x + r, c.y + 0.6 * r),
                                  float(rng.uniform(0, 180)))
        isl = orient(isl, 1.0)
        pts = _coords(isl)
        if _valid(pts) is None:
            continue
        room = room.difference(Polygon(pts).buffer(gap))
        out.append(pts)
    return out


def heightfield(rng: np.random.Generator, w: float, h: float
                ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """A free-form part surface over [0, w] x [0, h]: heights ``z[j, i]`` at
    (xs[i], ys[j]), 0.4 to 1.2 mm apart, its highest point at z = 0. One to four
    features on a flat plate: smooth bumps and dips (Gaussian, 3-12 mm wide), and
    rectangular bosses and cavities with rounded corners whose walls rise over 0.3 to
    3 mm (up to about 85 degrees)."""
    step = float(rng.uniform(0.4, 1.2))
    xs = np.linspace(0.0, w, max(3, int(math.ceil(w / step)) + 1))
    ys = np.linspace(0.0, h, max(3, int(math.ceil(h / step)) + 1))
    X, Y = np.meshgrid(xs, ys)
    Z = np.zeros_like(X)
    for _ in range(int(rng.integers(1, 5))):
        cx, cy = rng.uniform(0.2, 0.8) * w, rng.uniform(0.2, 0.8) * h
        kind = rng.choice(["bump", "dip", "boss", "cavity"])
        if kind in ("bump", "dip"):
            a = float(rng.uniform(2.0, 10.0)) * (1 if kind == "bump" else -1)
            s = float(rng.uniform(3.0, 12.0))
            Z += a * np.exp(-((X - cx) ** 2 + (Y - cy) ** 2) / (2 * s * s))
        else:
            a = float(rng.uniform(2.0, 10.0)) * (1 if kind == "boss" else -1)
            hx, hy = rng.uniform(4.0, 0.3 * w), rng.uniform(4.0, 0.3 * h)
            rc = float(rng.uniform(0.5, min(hx, hy)))
            wall = float(rng.uniform(0.3, 3.0))
            qx = np.maximum(np.abs(X - cx) - (hx - rc), 0.0)
            qy = np.maximum(np.abs(Y - cy) - (hy - rc), 0.0)
            sd = np.hypot(qx, qy) - rc           # outside the rounded rectangle > 0
            t = np.clip(-sd / wall, 0.0, 1.0)
            Z += a * t * t * (3 - 2 * t)
    Z = np.round(Z - Z.max(), 4)
    return np.round(xs, 4), np.round(ys, 4), Z


def heightfield_triangles(xs: np.ndarray, ys: np.ndarray, z: np.ndarray) -> np.ndarray:
    """(n, 3, 3) triangles of the height field, two per cell, counter-clockwise seen
    from above (each cell split along its (i, j)-(i+1, j+1) diagonal)."""
    X, Y = np.meshgrid(xs, ys)
    P = np.stack([X, Y, z], axis=-1)
    a, b = P[:-1, :-1].reshape(-1, 3), P[:-1, 1:].reshape(-1, 3)
    c, d = P[1:, 1:].reshape(-1, 3), P[1:, :-1].reshape(-1, 3)
    return np.concatenate([np.stack([a, b, c], 1), np.stack([a, c, d], 1)])


def stl_bytes(tri: np.ndarray) -> bytes:
    """Binary STL of triangles (n, 3, 3), normals from the vertex order."""
    n = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    n /= np.maximum(np.linalg.norm(n, axis=1, keepdims=True), 1e-30)
    rec = np.zeros(len(tri), dtype=[("n", "<f4", 3), ("v", "<f4", (3, 3)), ("a", "<u2")])
    rec["n"], rec["v"] = n, tri
    return b"generated height field".ljust(80, b" ") + np.uint32(len(tri)).tobytes() \
        + rec.tobytes()
