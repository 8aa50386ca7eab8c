"""Machinable shapes of AP224 features, in the stock frame, for 3-axis milling from +Z.

:func:`feature_shapes` turns the generic :class:`~millpath.part.step.ap224.Feature`
records into :class:`HoleShape`, :class:`SlotShape` and :class:`PocketShape` (or an
:class:`Unmachinable` with the reason). Conventions (lengths in the file's unit,
angles in degrees):

- Frame: coordinates are in the stock's placement frame (a block's corner of least
  coordinates is the origin, its top face at ``z = height``).
- A hole's or pocket's depth runs from its placement origin along its depth direction
  (the depth path's direction, else the placement axis), whichever side the origin is
  on: the published AP224 sample puts the origin on the face the feature opens into
  with the axis -Z; RAMP files put a bore's origin at its bottom with the axis +Z (out
  of the material) and a hole at the bottom of that bore at the bore's floor with the
  axis -Z. The span found is then checked against the stock and the other features:
  it must lie in the stock and open upward, at the stock top or into the floor of a
  wider feature above it (machined from there); one that opens only at the stock bottom
  or nowhere is listed as unmachinable. A hole reaching the stock bottom is a through
  hole. Slots and planar faces follow the same rule with the placement axis as the
  depth direction (their path component is the course of travel): axis -Z with the
  origin on the face they are cut from, or axis +Z with the origin on their floor (the
  finished face), as RAMP files write features; their span is checked the same way.
  A slot placed as ISO 10303-224 defines it (ISO/TS 10303-1814): origin at one end of
  the course of travel on the slot's floor, placement Z along the course, Y away from
  the part (the U profile opens towards +Y), X across the slot, the width centred on
  the origin; its placement Z is then horizontal and it rises ``depth`` from its floor.
- Hole depth is measured from the entry to the lowest point of the hole (the floor of a
  flat bottom, the tip of a conical one, the lowest point of a spherical one).
- A slot's course of travel starts at the placement origin and runs ``length`` along
  the path direction (default: placement X). Open and flat ends are at the ends of that
  centreline; radiused ends are half circles centred there (overall length + width).
  An open end means the slot leaves the part there.
- A pocket's profile is centred on the placement origin; a rectangle's ``length`` runs
  along the profile's X direction, ``width`` along its Y.
- A planar face's course of travel starts at the placement origin (like a slot's); its
  removal boundary (a LINEAR_PROFILE's 'profile length') is centred across it; it is
  lowered by its 'removal depth'.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from millpath.part.step.ap224 import Feature, Part, Placement

MACHINABLE_TYPES = ("ROUND_HOLE", "SLOT", "POCKET", "PLANAR_FACE", "FLAT_FACE")


@dataclass
class HoleShape:
    id: int
    x: float
    y: float
    z_top: float
    diameter: float
    depth: float
    bottom: str                   # through | flat | spherical | conical | flat with radius
                                  # | flat with taper
    bottom_radius: float = 0.0    # spherical radius or flat-with-radius corner radius
    tip_angle: float = 118.0      # conical bottom or taper: included angle (degrees)
    final_diameter: float = 0.0   # flat with taper: diameter of the flat at the bottom
    kind: str = "hole"

    @property
    def z_bottom(self) -> float:
        return self.z_top - self.depth


@dataclass
class SlotShape:
    id: int
    start: tuple[float, float]
    direction: tuple[float, float]       # unit vector in XY
    length: float                        # course of travel (centreline)
    width: float
    depth: float
    z_top: float
    ends: tuple[str, str]                # 'open' | 'radiused' | 'flat' at start, end
    kind: str = "slot"

    @property
    def end(self) -> tuple[float, float]:
        return (self.start[0] + self.direction[0] * self.length,
                self.start[1] + self.direction[1] * self.length)

    def outline(self, segments_per_quarter: int = 16):
        """The slot in plan view (shapely): the centreline widened by half the width,
        with half circles at radiused ends."""
        from shapely.geometry import LineString, Point
        a, b = np.asarray(self.start, float), np.asarray(self.end, float)
        r = self.width / 2.0
        if self.length <= 0:
            poly = Point(*a).buffer(r, quad_segs=segments_per_quarter)
        else:
            poly = LineString([a, b]).buffer(r, cap_style="flat")
        for e, p in zip(self.ends, (a, b)):
            if e == "radiused":
                poly = poly.union(Point(*p).buffer(r, quad_segs=segments_per_quarter))
        return poly


@dataclass
class PocketShape:
    id: int
    center: tuple[float, float]
    angle: float                         # profile X direction from +X, degrees
    profile: str                         # rectangular | circular | ngon
    depth: float
    z_top: float
    bottom: str = "planar"               # planar | through
    length: float = 0.0
    width: float = 0.0
    diameter: float = 0.0                # circular; circumscribed for an n-gon
    sides: int = 0
    corner_radius: float = 0.0
    floor_radius: float = 0.0            # fillet between walls and floor
    kind: str = "pocket"
    # profile 'general' (recognised from a solid): the floor's plan-view ``region``
    # (shapely, islands as holes, absolute coordinates) and ``keep``, the part's
    # material above the floor that the tool must not enter (open sides are where
    # ``keep`` does not border the region)
    region: Any = None
    keep: Any = None

    def outline(self, segments_per_quarter: int = 16):
        """The profile as a shapely Polygon (corner radii included)."""
        from shapely import affinity
        from shapely.geometry import Point, Polygon, box

        if self.profile == "general":
            return self.region
        if self.profile == "circular":
            poly = Point(0.0, 0.0).buffer(self.diameter / 2.0, quad_segs=segments_per_quarter)
        elif self.profile == "rectangular":
            rc = min(self.corner_radius, self.length / 2.0, self.width / 2.0)
            poly = box(-self.length / 2.0 + rc, -self.width / 2.0 + rc,
                       self.length / 2.0 - rc, self.width / 2.0 - rc)
            if rc > 0:
                poly = poly.buffer(rc, quad_segs=segments_per_quarter)
        else:
            r = self.diameter / 2.0
            a = np.linspace(0.0, 2 * math.pi, self.sides, endpoint=False)
            poly = Polygon(np.column_stack([r * np.cos(a), r * np.sin(a)]))
            if self.corner_radius > 0:
                poly = poly.buffer(-self.corner_radius, join_style="mitre").buffer(
                    self.corner_radius, quad_segs=segments_per_quarter)
        poly = affinity.rotate(poly, self.angle, origin=(0.0, 0.0))
        return affinity.translate(poly, self.center[0], self.center[1])

    def wall_distance(self, x: np.ndarray, y: np.ndarray) -> np.ndarray | None:
        """How far points inside a circular or rectangular profile (corner radii
        included) lie from its wall, exactly (negative outside); None for other
        profiles."""
        dx, dy = np.asarray(x, float) - self.center[0], np.asarray(y, float) - self.center[1]
        if self.profile == "circular":
            return self.diameter / 2.0 - np.hypot(dx, dy)
        if self.profile != "rectangular":
            return None
        a = math.radians(self.angle)
        u = np.abs(dx * math.cos(a) + dy * math.sin(a))
        v = np.abs(-dx * math.sin(a) + dy * math.cos(a))
        rc = min(self.corner_radius, self.length / 2.0, self.width / 2.0)
        qx, qy = u - (self.length / 2.0 - rc), v - (self.width / 2.0 - rc)
        outside = np.hypot(np.maximum(qx, 0.0), np.maximum(qy, 0.0)) + np.minimum(
            np.maximum(qx, qy), 0.0)
        return rc - outside


@dataclass
class FaceShape:
    """A planar face lowered by ``depth``: a rectangle whose centreline runs from
    ``start`` along ``direction`` for ``length`` (course of travel), ``width`` across
    (the removal boundary's profile length). Its sides on or beyond the stock's
    boundary are open."""

    id: int
    start: tuple[float, float]
    direction: tuple[float, float]
    length: float
    width: float
    depth: float
    z_top: float
    kind: str = "face"

    def outline(self, segments_per_quarter: int = 16):
        from shapely.geometry import LineString
        d = np.asarray(self.direction)
        a = np.asarray(self.start, float)
        return LineString([a, a + d * self.length]).buffer(self.width / 2.0, cap_style="flat")


@dataclass
class Unmachinable:
    id: int
    type: str
    reason: str
    kind: str = "unmachinable"


Shape = HoleShape | SlotShape | PocketShape | FaceShape


@dataclass
class ShapeSet:
    shapes: list[Shape] = field(default_factory=list)
    skipped: list[Unmachinable] = field(default_factory=list)


_NOT_PLANNED = {
    "STEP": "STEP features are not planned (AP224 gives the vee profile and the course "
            "of travel, not the step's width and depth)",
}


class _Missing(Exception):
    pass


def _need(d: dict, *names: str, what: str) -> float:
    for n in names:
        if n in d:
            return float(d[n])
    raise _Missing(f"{what} has no {names[0]!r}")


def _frame(part: Part) -> Placement:
    if part.stock is not None:
        return part.stock.placement
    return Placement()


def _local(frame: Placement, pl: Placement) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    m = frame.matrix().T
    return frame.to_local(pl.origin), m @ np.asarray(pl.axis), m @ np.asarray(pl.ref)


def _hole(f: Feature, o, depth_dir) -> HoleShape:
    prof = f.component("CIRCULAR_CLOSED_PROFILE")
    path = f.component("PATH_FEATURE_COMPONENT")
    if prof is None:
        raise _Missing("no CIRCULAR_CLOSED_PROFILE (diameter)")
    if path is None:
        raise _Missing("no PATH_FEATURE_COMPONENT (hole depth)")
    d = _need(prof.params, "diameter", what="hole profile")
    depth = _need(path.params, "distance", "length", what="hole depth path")
    b = f.component("HOLE_BOTTOM")
    bottom = (b.description or "flat") if b is not None else "through"
    h = HoleShape(f.id, float(o[0]), float(o[1]), float(o[2]), d, depth, bottom)
    if b is not None:
        if bottom == "spherical":
            h.bottom_radius = float(b.params.get("radius", d / 2.0))
            if h.bottom_radius < d / 2.0 - 1e-9:
                raise _Missing("spherical bottom radius smaller than the hole radius")
        elif bottom == "flat with radius":
            h.bottom_radius = _need(b.params, "corner radius", "radius", what="hole bottom")
        elif bottom == "conical":
            h.tip_angle = float(b.params.get("tip angle", 118.0))
        elif bottom == "flat with taper":
            # AP224's parameters: 'final diameter' (the flat) and the taper's angle, which
            # the schema names 'taper diameter' (a plane angle measure); read as the
            # cone's included angle, like a conical bottom's tip angle
            h.final_diameter = _need(b.params, "final diameter", what="hole bottom")
            h.tip_angle = _need(b.params, "taper angle", "taper diameter",
                                what="hole bottom")
            if not (0.0 < h.final_diameter < d and 0.0 < h.tip_angle < 180.0):
                raise _Missing("a 'flat with taper' bottom needs 0 < final diameter < "
                               "diameter and 0 < taper angle < 180 degrees")
        elif bottom not in ("flat", "through"):
            raise _Missing(f"unknown hole bottom {bottom!r}")
    if not (d > 0 and depth > 0):
        raise _Missing("hole diameter and depth must be positive")
    return h


def _slot(f: Feature, o, axis, ref, course=None) -> SlotShape:
    prof = f.component("SQUARE_U_PROFILE")
    if prof is None:
        raise _Missing("slot without a SQUARE_U_PROFILE (only square U slots are planned)")
    w = _need(prof.params, "width", what="slot profile")
    depth = _need(prof.params, "depth", "profile limit", what="slot profile")
    for a in ("first angle", "second angle"):
        if abs(prof.params.get(a, 90.0) - 90.0) > 1e-6:
            raise _Missing(f"slot wall {a} is not 90 degrees")
    for r in ("first radius", "second radius"):
        if prof.params.get(r, 0.0) > 1e-9:
            raise _Missing(f"slot floor {r} is not 0")
    path = f.component("PATH_FEATURE_COMPONENT")
    if path is None:
        raise _Missing("slot without a course of travel (PATH_FEATURE_COMPONENT)")
    if path.description not in ("", "linear"):
        raise _Missing(f"slot course of travel {path.description!r} is not linear")
    length = _need(path.params, "distance", "length", what="slot course of travel")
    d = np.asarray(course if course is not None else
                   path.direction if path.direction is not None else ref, float)
    if abs(d[2]) > 1e-6:
        raise _Missing("slot course of travel is not horizontal")
    d = d[:2] / np.linalg.norm(d[:2])
    ends = [c.description for c in f.components if c.type == "SLOT_END"]
    while len(ends) < 2:
        ends.append("open")
    for e in ends:
        if e not in ("open", "radiused", "flat"):
            raise _Missing(f"slot end {e!r} is not planned")
    if not (w > 0 and depth > 0 and length >= 0):
        raise _Missing("slot width and depth must be positive")
    return SlotShape(f.id, (float(o[0]), float(o[1])), (float(d[0]), float(d[1])), length, w,
                     depth, float(o[2]), (ends[0], ends[1]))


def _pocket(f: Feature, o, ref, frame: Placement) -> PocketShape:
    path = f.component("PATH_FEATURE_COMPONENT")
    if path is None:
        raise _Missing("pocket without a depth (PATH_FEATURE_COMPONENT)")
    depth = _need(path.params, "distance", "length", what="pocket depth")
    b = f.component("POCKET_BOTTOM")
    bottom = (b.description or "planar") if b is not None else "planar"
    if bottom not in ("planar", "through"):
        raise _Missing(f"pocket bottom {bottom!r} is not planned")
    floor_radius = float(b.params.get("radius", 0.0)) if b is not None else 0.0
    if floor_radius > 1e-9 and bottom == "through":
        raise _Missing("a through pocket has no floor fillet")
    prof = f.component("RECTANGULAR_CLOSED_PROFILE", "CIRCULAR_CLOSED_PROFILE",
                       "NGON_CLOSED_PROFILE")
    if prof is None:
        kinds = [c.type for c in f.components if c.type.endswith("PROFILE")]
        raise _Missing(f"pocket profile {kinds[0] if kinds else 'missing'} is not planned")
    r = ref
    if prof.placement is not None:
        r = frame.matrix().T @ np.asarray(prof.placement.ref)
    angle = math.degrees(math.atan2(r[1], r[0]))
    p = PocketShape(f.id, (float(o[0]), float(o[1])), angle, "", depth, float(o[2]), bottom,
                    floor_radius=floor_radius)
    if prof.type == "RECTANGULAR_CLOSED_PROFILE":
        p.profile = "rectangular"
        p.length = _need(prof.params, "length", what="rectangular profile")
        p.width = _need(prof.params, "width", what="rectangular profile")
        p.corner_radius = float(prof.params.get("corner radius", 0.0))
        if not (p.length > 0 and p.width > 0):
            raise _Missing("pocket length and width must be positive")
    elif prof.type == "CIRCULAR_CLOSED_PROFILE":
        p.profile = "circular"
        p.diameter = _need(prof.params, "diameter", what="circular profile")
    else:
        p.profile = "ngon"
        p.diameter = _need(prof.params, "circumscribed diameter", "diameter",
                           what="n-gon profile")
        p.sides = int(round(_need(prof.params, "number of sides", what="n-gon profile")))
        p.corner_radius = float(prof.params.get("corner radius", 0.0))
        if p.sides < 3:
            raise _Missing("an n-gon needs at least 3 sides")
    if not depth > 0:
        raise _Missing("pocket depth must be positive")
    return p


def _face(f: Feature, o, ref) -> FaceShape:
    depth = f.params.get("removal depth")
    if depth is None:
        c = next((c for c in f.components if "removal depth" in c.params), None)
        depth = c.params["removal depth"] if c is not None else None
    if depth is None:
        raise _Missing("face without a 'removal depth'")
    path = f.component("PATH_FEATURE_COMPONENT")
    if path is None or path.description not in ("", "linear"):
        raise _Missing("face without a linear course of travel")
    length = _need(path.params, "distance", "length", what="face course of travel")
    prof = f.component("LINEAR_PROFILE")
    if prof is None:
        raise _Missing("face without a LINEAR_PROFILE removal boundary")
    width = _need(prof.params, "profile length", what="face removal boundary")
    d = np.asarray(path.direction if path.direction is not None else ref, float)
    if abs(d[2]) > 1e-6:
        raise _Missing("face course of travel is not horizontal")
    d = d[:2] / np.linalg.norm(d[:2])
    if not (depth > 0 and length > 0 and width > 0):
        raise _Missing("face depth, length and width must be positive")
    return FaceShape(f.id, (float(o[0]), float(o[1])), (float(d[0]), float(d[1])), length,
                     width, float(depth), float(o[2]))


def feature_shapes(part: Part) -> ShapeSet:
    """Machinable shapes of a part's features, and the features left out (with reasons).

    Composite features (e.g. ``COMPOSITE_HOLE``) are covered by their components.
    """
    out = ShapeSet()
    frame = _frame(part)
    children = {c for f in part.features for c in f.children}
    for f in part.features:
        if f.children and all(c in children for c in f.children):
            continue      # composite: its components are features of their own
        if f.type not in MACHINABLE_TYPES:
            out.skipped.append(Unmachinable(f.id, f.type, _NOT_PLANNED.get(
                f.type, f"{f.type} features are not planned")))
            continue
        if f.placement is None:
            out.skipped.append(Unmachinable(f.id, f.type, "no placement ('orientation')"))
            continue
        o, axis, ref = _local(frame, f.placement)
        path = f.component("PATH_FEATURE_COMPONENT")
        if f.type == "SLOT" and abs(axis[2]) < 1e-6:
            # ISO 10303-224 (ISO/TS 10303-1814) slot frame: origin at one end on the
            # floor, Z along the course of travel, Y away from the part (the U profile
            # opens towards +Y): the slot rises from its floor along Y
            up = np.cross(axis, ref)
            if up[2] < 1 - 1e-6:
                out.skipped.append(Unmachinable(f.id, f.type, (
                    "the slot opens towards -Z: machine it from the other side"
                    if up[2] < -1 + 1e-6 else "the slot's open side (its placement's "
                    "Y) is not along Z: not reachable from the top")))
                continue
            try:
                out.shapes.append(_raised(_slot(f, o, axis, ref, course=axis), True))
            except _Missing as e:
                out.skipped.append(Unmachinable(f.id, f.type, str(e)))
            continue
        depth_dir = axis
        if f.type in ("ROUND_HOLE", "POCKET") and path is not None \
                and path.direction is not None:
            depth_dir = frame.matrix().T @ np.asarray(path.direction)
        upward = depth_dir[2] > 1 - 1e-6
        if depth_dir[2] > -1 + 1e-6 and not upward:
            out.skipped.append(Unmachinable(
                f.id, f.type, "depth direction is not along Z (not reachable from the top)"))
            continue
        try:
            if f.type == "ROUND_HOLE":
                out.shapes.append(_raised(_hole(f, o, depth_dir), upward))
            elif f.type == "SLOT":
                out.shapes.append(_raised(_slot(f, o, axis, ref), upward))
            elif f.type in ("PLANAR_FACE", "FLAT_FACE"):
                out.shapes.append(_raised(_face(f, o, ref), upward))
            else:
                out.shapes.append(_raised(_pocket(f, o, ref, frame), upward))
        except _Missing as e:
            out.skipped.append(Unmachinable(f.id, f.type, str(e)))
    if part.stock is not None:
        _check_openings(out, part.stock.box())
    return out


def _raised(shape, upward: bool):
    """A feature whose depth runs up from its origin: its top is origin + depth."""
    if upward:
        shape.z_top = shape.z_top + shape.depth
    return shape


def _footprint(shape):
    from shapely.geometry import Point
    if isinstance(shape, HoleShape):
        return Point(shape.x, shape.y).buffer(shape.diameter / 2.0, quad_segs=32)
    return shape.outline()


def _check_openings(out: "ShapeSet", box) -> None:
    """Keep the features whose span lies in the stock and opens upward (stock top or
    the floor of a wider feature above); mark holes reaching the stock bottom as
    through; move the others to ``skipped`` with the reason."""
    zmin, zmax = box[2], box[5]
    eps = 1e-6 * max(1.0, zmax - zmin)
    keep = []
    for s in out.shapes:
        lo, hi = s.z_top - s.depth, s.z_top
        name = {"hole": "ROUND_HOLE", "pocket": "POCKET", "slot": "SLOT"}.get(
            s.kind, "PLANAR_FACE")
        if hi > zmax + eps or lo < zmin - eps:
            out.skipped.append(Unmachinable(s.id, name, f"spans z {lo:g} .. {hi:g}, outside "
                                                        f"the stock's z {zmin:g} .. {zmax:g}"))
            continue
        opens = hi >= zmax - eps
        if not opens:
            fp = _footprint(s)
            for t in out.shapes:
                if t is s:
                    continue
                if abs((t.z_top - t.depth) - hi) <= eps and \
                        _footprint(t).buffer(eps).covers(fp):
                    opens = True
                    break
        if not opens:
            where = ("opens only at the stock bottom (z {:g}): machine it from the other "
                     "side".format(lo) if lo <= zmin + eps
                     else f"its top z {hi:g} opens neither at the stock top nor into a wider "
                          f"feature")
            out.skipped.append(Unmachinable(s.id, name, where))
            continue
        if isinstance(s, HoleShape) and lo <= zmin + eps and s.bottom != "through":
            s.bottom = "through"
        keep.append(s)
    out.shapes = keep
