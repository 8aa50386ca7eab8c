"""Read the contours of a DXF drawing (model space) with ezdxf.

Entities: LINE, ARC, CIRCLE, LWPOLYLINE (bulges), 2D POLYLINE (bulges), SPLINE and
ELLIPSE, and those inside INSERTed blocks. Arcs and bulges are flattened into chords
within ``tolerance`` of the true curve (sagitta), splines and ellipses by ezdxf's
adaptive flattening to the same distance. Entities in an OCS (extrusion not +Z) are
mapped to world X, Y. ``$INSUNITS`` (inch, foot, mm, cm, m, micron) converts to the
job's units; 0 (unitless) means the job's units. Z is ignored (the drawing is the XY
plane seen from +Z).

Work is bounded before it is done (:mod:`millpath.model.limits`): a circle, arc, bulge,
ellipse or spline larger than the job's ``max_extent`` is refused, the points each
curve needs at the tolerance are counted before it is cut, and a drawing needing more
than ``MAX_CURVE_POINTS`` in all is refused naming the entity (its handle).
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from millpath.errors import GeometryError
from millpath.model.limits import MAX_COORDINATE, MAX_CURVE_POINTS, Limits
from millpath.model.units import MM_PER_FOOT, MM_PER_INCH, length_scale
from millpath.part.drawing.chains import Loop, Piece, join_pieces

#: $INSUNITS code -> millimetres per drawing unit
INSUNITS_MM = {1: MM_PER_INCH, 2: MM_PER_FOOT, 4: 1.0, 5: 10.0, 6: 1000.0,
               8: 1e-6 * MM_PER_INCH, 9: 1e-3 * MM_PER_INCH,
               10: 914.4, 13: 1e-3, 14: 100.0}
SUPPORTED = ("LINE", "ARC", "CIRCLE", "LWPOLYLINE", "POLYLINE", "SPLINE", "ELLIPSE")


class _Budget:
    """What the drawing's curves may still take: radii and spans up to ``max_size`` (job
    units) and ``points`` points in all; ``scale`` turns drawing units into job units."""

    def __init__(self, max_size: float, scale: float, units: str, tolerance: float,
                 points: int = MAX_CURVE_POINTS):
        self.max_size, self.scale, self.units = max_size, scale, units
        self.tolerance, self.points = tolerance, points

    def size(self, value: float, what: str) -> None:
        """Refuse a radius or span (drawing units) larger than the job's extent."""
        if not (abs(value) * self.scale <= self.max_size):
            raise ValueError(f"{what}{abs(value) * self.scale:g} {self.units} is larger "
                             f"than the {self.max_size:g} {self.units} limit (wrong "
                             f"$INSUNITS?)")

    def take(self, n: float, what: str) -> None:
        """Spend ``n`` points; refuse when the drawing would need more than its share."""
        self.points -= n
        if self.points < 0:
            raise ValueError(f"{what}needs {n:.3g} points within "
                             f"{self.tolerance * self.scale:g} {self.units}: more than the "
                             f"{MAX_CURVE_POINTS} a drawing may be cut into (a coarser "
                             f"operation tolerance?)")


def arc_count(r: float, sweep: float, tolerance: float) -> int:
    """Chords :func:`arc_points` cuts an arc of radius ``r`` and ``sweep`` into."""
    if r <= tolerance:
        return max(3, int(math.ceil(abs(sweep) / (math.pi / 2))))
    step = 2.0 * math.acos(max(1.0 - tolerance / r, -1.0))
    return max(1, int(math.ceil(abs(sweep) / max(step, 1e-9) - 1e-9)))


def arc_points(cx: float, cy: float, r: float, a0: float, sweep: float,
               tolerance: float, budget: _Budget | None = None,
               what: str = "") -> np.ndarray:
    """Points on a circular arc from angle ``a0`` through signed ``sweep`` (radians,
    positive counter-clockwise), chords within ``tolerance`` of the arc; ``budget``
    refuses a radius or a count over the limits before any point is made."""
    if budget is not None:
        budget.size(r, f"{what}a radius of ")
    n = arc_count(r, sweep, tolerance)
    if budget is not None:
        budget.take(n + 1, what)
    t = a0 + sweep * np.linspace(0.0, 1.0, n + 1)
    return np.column_stack([cx + r * np.cos(t), cy + r * np.sin(t)])


def bulge_points(vertices: list[tuple[float, float, float]], closed: bool,
                 tolerance: float, budget: _Budget | None = None) -> np.ndarray:
    """A polyline with bulges (x, y, bulge) as chords; bulge = tan(included angle / 4),
    positive counter-clockwise."""
    out: list[np.ndarray] = []
    n = len(vertices)
    last = n if closed else n - 1
    if budget is not None:
        budget.take(n, "")
    for i in range(last):
        x0, y0, b = vertices[i]
        x1, y1, _ = vertices[(i + 1) % n]
        if abs(b) < 1e-12 or (x0 == x1 and y0 == y1):
            out.append(np.array([[x0, y0], [x1, y1]]))
            continue
        theta = 4.0 * math.atan(b)
        chord = math.hypot(x1 - x0, y1 - y0)
        r = chord / (2.0 * math.sin(abs(theta) / 2.0))
        mx, my = (x0 + x1) / 2, (y0 + y1) / 2
        d = r * math.cos(theta / 2.0)          # signed: centre left of the chord if b > 0
        ux, uy = (x1 - x0) / chord, (y1 - y0) / chord
        cx, cy = mx - uy * d * math.copysign(1, b), my + ux * d * math.copysign(1, b)
        a0 = math.atan2(y0 - cy, x0 - cx)
        out.append(arc_points(cx, cy, r, a0, theta, tolerance, budget,
                              f"vertex {i + 1} (bulge {b:g}): "))
    if not out:
        return np.array([[v[0], v[1]] for v in vertices])
    return np.vstack([out[0]] + [o[1:] for o in out[1:]])


def _ocs_xy(e, pts: np.ndarray) -> np.ndarray:
    """Map OCS points (n, 2) of a 2D entity to world XY."""
    ext = e.dxf.get("extrusion", None)
    if ext is None or (abs(ext[0]) < 1e-12 and abs(ext[1]) < 1e-12 and ext[2] > 0):
        return pts
    from ezdxf.math import OCS
    ocs = OCS(ext)
    elev = float(e.dxf.get("elevation", 0.0) or 0.0) if e.dxftype() == "LWPOLYLINE" else 0.0
    w = [ocs.to_wcs((float(x), float(y), elev)) for x, y in pts]
    return np.array([[v.x, v.y] for v in w])


def _piece(e, tol: float, budget: _Budget) -> Piece | None:
    t = e.dxftype()
    h = _handle(e)
    if t == "LINE":
        s, f = e.dxf.start, e.dxf.end
        budget.take(2, "")
        return Piece(np.array([[s.x, s.y], [f.x, f.y]]), h)
    if t == "CIRCLE":
        c, r = e.dxf.center, float(e.dxf.radius)
        pts = arc_points(c.x, c.y, r, 0.0, 2 * math.pi, tol, budget)[:-1]
        return Piece(_ocs_xy(e, pts), h, closed=True)
    if t == "ARC":
        c, r = e.dxf.center, float(e.dxf.radius)
        a0, a1 = math.radians(e.dxf.start_angle), math.radians(e.dxf.end_angle)
        if not (math.isfinite(a0) and math.isfinite(a1)):
            raise ValueError("a non-finite angle")
        sweep = (a1 - a0) % (2 * math.pi) or 2 * math.pi
        return Piece(_ocs_xy(e, arc_points(c.x, c.y, r, a0, sweep, tol, budget)), h)
    if t == "LWPOLYLINE":
        v = [(float(x), float(y), float(b)) for x, y, b in e.get_points("xyb")]
        if len(v) < 2:
            return None
        return Piece(_ocs_xy(e, bulge_points(v, bool(e.closed), tol, budget)), h,
                     bool(e.closed))
    if t == "POLYLINE":
        if e.is_3d_polyline or e.is_poly_face_mesh or e.is_polygon_mesh:
            pts = np.array([[v.dxf.location.x, v.dxf.location.y] for v in e.vertices])
            return Piece(pts, h, bool(e.is_closed)) if len(pts) >= 2 else None
        v = [(float(q.dxf.location.x), float(q.dxf.location.y), float(q.dxf.get("bulge", 0.0)))
             for q in e.vertices]
        if len(v) < 2:
            return None
        return Piece(_ocs_xy(e, bulge_points(v, bool(e.is_closed), tol, budget)), h,
                     bool(e.is_closed))
    if t in ("SPLINE", "ELLIPSE"):
        if t == "ELLIPSE":
            budget.size(math.hypot(e.dxf.major_axis.x, e.dxf.major_axis.y), "a half axis of ")
        else:
            cps = [(float(p[0]), float(p[1])) for p in e.control_points] or [(0.0, 0.0)]
            budget.size(float(np.ptp(np.array(cps), axis=0).max()), "a span of ")
        pts = []
        for p in e.flattening(tol):
            pts.append((p.x, p.y))
            if not len(pts) & 1023:
                budget.take(1024, "")
        budget.take(len(pts) & 1023, "")
        pts = np.array(pts)
        closed = t == "SPLINE" and bool(e.closed)
        return Piece(pts, h, closed) if len(pts) >= 2 else None
    return None


def _layer(e) -> str:
    """An entity's layer ("0" for an entity that has none, as a damaged file can hold)."""
    return _attribute(e, "layer", "0")


def _handle(e) -> str:
    return _attribute(e, "handle", "?")


def _attribute(e, name: str, default: str) -> str:
    from ezdxf.lldxf.const import DXFAttributeError
    try:
        return str(e.dxf.get(name, default))
    except DXFAttributeError:          # not an attribute of this kind of entity
        return default


def _entities(msp, layer: str | None):
    for e in msp:
        if e.dxftype() == "INSERT":
            if layer is not None and _layer(e).lower() != layer.lower():
                continue
            try:
                yield from e.virtual_entities()
            except Exception:           # ezdxf raises various errors on odd blocks
                continue
            continue
        if layer is not None and _layer(e).lower() != layer.lower():
            continue
        yield e


def read_dxf(path: str | Path, units: str, tolerance: float, *, layer: str | None = None,
             join_tolerance: float | None = None, limits: Limits | None = None
             ) -> list[Loop]:
    """Closed loops (job units) of the DXF at ``path`` on ``layer`` (all layers if None).

    ``tolerance``: chordal tolerance in job units; ``join_tolerance`` (default 10 x
    ``tolerance``): the largest gap closed between entity ends; ``limits``: the job's
    (its ``max_extent`` bounds every radius and span; default: the units' own).
    GeometryError for an unreadable file, no supported entity, a curve over the limits,
    or a chain left open.
    """
    import ezdxf
    path = Path(path)
    if not path.is_file():
        raise GeometryError("DXF file not found", path)
    try:
        doc = ezdxf.readfile(str(path))
    except Exception as e:  # noqa: BLE001 - any failure of the DXF parser is a bad file
        why = " ".join(str(e).split()) or type(e).__name__
        raise GeometryError(f"not a readable DXF file ({why})", path) from None
    try:
        code = int(doc.header.get("$INSUNITS", 0) or 0)
    except (TypeError, ValueError):
        raise GeometryError(f"$INSUNITS = {doc.header.get('$INSUNITS')!r} is not a unit code",
                            path) from None
    job_mm = length_scale(units, "mm")
    scale = INSUNITS_MM[code] / job_mm if code in INSUNITS_MM else 1.0
    if code not in INSUNITS_MM and code != 0:
        raise GeometryError(f"$INSUNITS = {code}: unsupported drawing unit", path)
    tol_d = tolerance / scale            # flatten in drawing units
    budget = _Budget((limits or Limits.default_for(units)).max_extent, scale, units, tol_d)
    pieces: list[Piece] = []
    layers = set()
    for e in _entities(doc.modelspace(), layer):
        layers.add(_layer(e))
        if e.dxftype() not in SUPPORTED:
            continue
        try:
            p = _piece(e, tol_d, budget)
        except (ValueError, ZeroDivisionError, AttributeError, OverflowError) as ex:
            raise GeometryError(f"{e.dxftype()}: {ex}", path,
                                entity=f"entity {_handle(e)}") from None
        if p is None:
            continue
        if not np.isfinite(p.points).all():
            raise GeometryError(f"{e.dxftype()} has a non-finite coordinate", path,
                                entity=f"entity {p.handle}")
        if len(p.points) and np.abs(p.points).max() * scale > MAX_COORDINATE:
            raise GeometryError(f"{e.dxftype()} has a coordinate larger than the "
                                f"{MAX_COORDINATE:g} limit", path,
                                entity=f"entity {p.handle}")
        p.points = p.points * scale
        pieces.append(p)
    if not pieces:
        where = f" on layer {layer!r}" if layer is not None else ""
        known = sorted({_layer(e) for e in doc.modelspace()})
        raise GeometryError(f"no LINE, ARC, CIRCLE, LWPOLYLINE, POLYLINE or SPLINE{where} "
                            f"(layers in the file: {', '.join(known) or 'none'})", path)
    jt = join_tolerance if join_tolerance is not None else 10.0 * tolerance
    loops = join_pieces(pieces, jt, path)
    if not loops:
        raise GeometryError("no closed contour in the drawing", path)
    return loops
