"""Machining features of a B-rep solid, for 3-axis milling from +Z.

:func:`recognise` turns a solid (mm, turned to its setup) into the feature model of
the AP224 reader (:class:`~millpath.part.step.ap224.Feature` records with their faces)
and the machinable shapes of :mod:`millpath.part.step.shapes`:

- round holes (:mod:`.holes`): ``ROUND_HOLE`` (:class:`HoleShape`); counterbored and
  countersunk holes are ``COMPOSITE_HOLE`` features whose children are the holes of
  each diameter (a countersink is a conical hole of its top diameter, cut by a drill of
  that point angle); holes of one size are noted as a pattern;
- every floor (planar faces looking up, joined when they touch at one height) is a
  ``POCKET`` (closed or open), ``SLOT`` (long, narrow, between two parallel walls),
  ``STEP`` (mostly open) or, at the part's top, a ``PLANAR_FACE``; its shape is a
  general :class:`PocketShape`: the floor's plan-view region (floor fillets included,
  islands as holes) and the part's material above the floor (the tool must not enter
  it; sides where that material does not border the floor are open). Corner radius:
  the smallest concave vertical cylinder along its walls, 0 at a sharp corner; floor
  radius: the concave fillet between floor and walls;
- the outer profile (stock box minus the part's outline) and through openings of the
  outline that are not holes: ``GENERAL_OUTSIDE_PROFILE`` / through ``POCKET``;
- faces no feature explains that are free-form, inclined, or face down above the part's
  bottom are listed as unmachinable with advice (surface operations / another setup).

Shapes and feature parameters are in the file's length unit (``scale`` = file units
per mm); coordinates are the file's (turned to the setup).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import shapely
from shapely import affinity
from shapely.geometry import Point, box as sbox

from millpath.model.units import MM_PER_INCH
from millpath.part.brep.faces import FaceInfo, face_table
from millpath.part.brep.holes import CAVITY_BELOW, HoleStack, find_holes
from millpath.part.brep.regions import Shadows, edges_region
from millpath.part.brep.removal import overlap, removal_solid
from millpath.part.step.ap224 import Component, Feature, Placement
from millpath.part.step.shapes import HoleShape, PocketShape, ShapeSet, Unmachinable

Z_TOL = 1e-3            # mm: faces at one height
SURFACE_ADVICE = "use surface operations (surface-rough / surface-finish) on it"


@dataclass
class Recognition:
    features: list[Feature]
    shapes: ShapeSet
    box: tuple[float, float, float, float, float, float]   # part bounds (file units)
    faces: int
    mesh_source: Any = field(default=None, repr=False)    # the solid (mm)


def _placement(x: float, y: float, z: float, k: float) -> Placement:
    return Placement((x * k, y * k, z * k), (0.0, 0.0, -1.0), (1.0, 0.0, 0.0))


class _Ids:
    def __init__(self) -> None:
        self.n = 0

    def __call__(self) -> int:
        self.n += 1
        return self.n


def recognise(solid, stock_box=None, scale: float = 1.0) -> Recognition:
    """Features of ``solid`` (mm). ``stock_box`` (xmin, ymin, zmin, xmax, ymax, zmax, mm):
    the raw material, default the part's bounding box. ``scale``: file units per mm."""
    faces = face_table(solid)
    lo = np.min([f.box[:3] for f in faces], axis=0)
    hi = np.max([f.box[3:] for f in faces], axis=0)
    zmin, zmax = float(lo[2]), float(hi[2])
    sb = tuple(stock_box) if stock_box is not None else (*lo, *hi)
    k = scale
    feats: list[Feature] = []
    out = ShapeSet()
    new_id = _Ids()
    claimed: set[int] = set()

    # holes ------------------------------------------------------------------------------
    stacks = find_holes(faces, zmin)
    hole_disks = []
    sizes: dict[tuple, int] = {}
    for st in stacks:
        for s in st.segments:
            key = (round(s.diameter, 4), round(s.depth, 4), s.bottom)
            sizes[key] = sizes.get(key, 0) + 1
    for st in stacks:
        if st.problem == CAVITY_BELOW:
            _through_into_air(st, solid, sb[5], zmin)
        claimed.update(st.faces)
        _hole_features(st, feats, out, new_id, k, sizes)
        if st.segments and st.segments[-1].bottom == "through":
            hole_disks.append(Point(st.x, st.y).buffer(st.segments[-1].diameter / 2.0 + 0.01))

    # floors -----------------------------------------------------------------------------
    by_id = {f.id: f for f in faces}
    ups = [f for f in faces if f.horizontal() == 1 and f.id not in claimed]
    levels = sorted({round(f.zmin, 6) for f in ups if f.zmin < zmax - Z_TOL}
                    | {round(zmin, 6)})      # nothing is above the top: no section there
    shadows = Shadows(solid, levels, critical=[v for f in faces for v in (f.zmin, f.zmax)])
    corners = [f for f in faces if f.kind == "cylinder" and f.concave and f.vertical_axis()
               and f.uspan < 2 * math.pi - 1e-3]
    for group in _floor_groups(ups):
        z = float(np.mean([f.zmin for f in group]))
        ids = [f.id for f in group]
        claimed.update(ids)
        if z >= zmax - Z_TOL:
            fid = new_id()
            depth = sb[5] - zmax
            cx = (min(f.box[0] for f in group) + max(f.box[3] for f in group)) / 2.0
            cy = (min(f.box[1] for f in group) + max(f.box[4] for f in group)) / 2.0
            feats.append(Feature(fid, "PLANAR_FACE", "top face", "faced from the stock top"
                                 if depth > Z_TOL else "at the stock top: nothing to face", 0,
                                 _placement(cx, cy, z, k), {"removal depth": depth * k},
                                 faces=ids))
            continue
        region = shapely.union_all([edges_region(f.face) for f in group])
        _floor_feature(group, z, region, corners, by_id, shadows, zmax, feats, out, new_id,
                       k, claimed)

    # outer profile and through openings -------------------------------------------------
    outline = shadows.above(zmin - 2 * shadows.eps)
    stock_rect = sbox(sb[0], sb[1], sb[3], sb[4])
    outside = stock_rect.difference(shapely.Polygon(outline.exterior) if outline.geom_type
                                    == "Polygon" else shapely.union_all(
                                        [shapely.Polygon(p.exterior) for p in outline.geoms]))
    if outside.area > 1e-3:
        fid = new_id()
        feats.append(Feature(fid, "GENERAL_OUTSIDE_PROFILE", "outer profile",
                             "the part contoured out of the stock", 0,
                             _placement(*_centre(outside), sb[5], k),
                             {"depth": (sb[5] - zmin) * k}))
        out.shapes.append(_general(fid, outside, outline, sb[5], sb[5] - zmin, "through",
                                   0.0, 1e9, k, name="outer profile"))
    polys = [outline] if outline.geom_type == "Polygon" else list(outline.geoms)
    disk_tree = shapely.STRtree(hole_disks)
    for p in polys:
        for ring in p.interiors:
            hole = shapely.Polygon(ring)
            near = [hole_disks[i] for i in disk_tree.query(hole)] if hole_disks else []
            rest = hole.difference(shapely.union_all(near)) if near else hole
            if rest.area < 1e-2:
                continue
            fid = new_id()
            feats.append(Feature(fid, "POCKET", "through pocket", "through the part", 0,
                                 _placement(*_centre(hole), zmax, k),
                                 {"depth": (zmax - zmin) * k}))
            out.shapes.append(_general(fid, hole, outline, zmax, zmax - zmin, "through",
                                       0.0, _corner_radius(hole, outline, corners), k,
                                       name="through pocket"))

    # what no feature explains -----------------------------------------------------------
    for f in faces:
        if f.id in claimed:
            continue
        reason = _unexplained(f, zmin)
        if reason:
            out.skipped.append(Unmachinable(f.id, f"FACE #{f.id}", reason, kind="face"))
    _check_removal(solid, out, k, max(sb[5], zmax), zmin, {f.id: f for f in feats})
    box = tuple(v * k for v in (*lo, *hi))
    return Recognition(feats, out, box, len(faces), solid)


def _through_into_air(st: HoleStack, solid, z_stock: float, zmin: float) -> None:
    """A hole whose last cylinder ends above the part's bottom with nothing under it
    (a through hole in a flange or a plate raised off the part's lowest face) is a
    through hole: its cylinder run down below the part cuts no material (checked on
    the solid)."""
    seg = st.segments[-1]
    probe = HoleShape(0, seg.x, seg.y, seg.z_top, seg.diameter, seg.depth, "through")
    if overlap(solid, removal_solid(probe, 1.0, z_stock, zmin)) is None:
        seg.bottom = "through"
        st.problem = ""


def _check_removal(solid, out: ShapeSet, k: float, z_stock: float, zmin: float,
                   feats: dict[int, Feature]) -> None:
    """Drop every shape whose removal volume holds material of the solid (it would
    gouge the part): it moves to ``out.skipped`` with the figures
    (:mod:`millpath.part.brep.removal`)."""
    keep = []
    unit = ("mm" if abs(k - 1.0) < 1e-9 else "in" if abs(k * MM_PER_INCH - 1.0) < 1e-9
            else "file units")
    for s in out.shapes:
        o = overlap(solid, removal_solid(s, k, z_stock, zmin))
        if o is None:
            keep.append(s)
            continue
        f = feats.get(s.id)
        what = f"{f.type} '{f.name}'" if f is not None else f"#{s.id}"
        out.skipped.append(Unmachinable(
            s.id, f.type if f is not None else "FEATURE",
            f"not a feature of the solid: {o.describe(k, unit)}; machining {what} "
            "would cut into the part", kind="gouge"))
    out.shapes[:] = keep


def _centre(g) -> tuple[float, float]:
    c = g.centroid
    return (float(c.x), float(c.y)) if not c.is_empty else (0.0, 0.0)


def _hole_features(st: HoleStack, feats, out: ShapeSet, new_id, k, sizes) -> None:
    ids = []
    for s in st.segments:
        fid = new_id()
        ids.append(fid)
        params = {"diameter": s.diameter * k, "depth": s.depth * k}
        comps = [Component(fid, "CIRCULAR_CLOSED_PROFILE", "", "diameter", "",
                           {"diameter": s.diameter * k})]
        if s.bottom != "through":
            b = {"radius": s.bottom_radius * k} if s.bottom_radius else {}
            if s.bottom == "conical":
                b = {"tip angle": s.tip_angle}
            comps.append(Component(fid, "HOLE_BOTTOM", s.bottom, "bottom condition", "", b))
        n = sizes.get((round(s.diameter, 4), round(s.depth, 4), s.bottom), 1)
        texts = {"bottom": s.bottom}
        if n > 1:
            texts["pattern"] = f"one of {n} holes of this size"
        f = Feature(fid, "ROUND_HOLE", s.role, f"{s.bottom} bottom", 0,
                    _placement(s.x, s.y, s.z_top, k), params, texts, comps, faces=s.faces)
        feats.append(f)
        if st.problem:
            out.skipped.append(Unmachinable(fid, "ROUND_HOLE", st.problem))
            continue
        out.shapes.append(HoleShape(fid, s.x * k, s.y * k, s.z_top * k, s.diameter * k,
                                    s.depth * k, s.bottom, s.bottom_radius * k, s.tip_angle,
                                    kind=s.role if s.role != "hole" else "hole"))
    if len(st.segments) > 1:
        roles = {s.role for s in st.segments}
        name = "countersunk hole" if "countersink" in roles else "counterbored hole"
        feats.append(Feature(new_id(), "COMPOSITE_HOLE", name, "", 0,
                             _placement(st.x, st.y, st.segments[0].z_top, k),
                             children=ids, faces=st.faces))


def _floor_groups(ups: list[FaceInfo]) -> list[list[FaceInfo]]:
    """Up-facing faces joined when they are neighbours at one height."""
    left = {f.id: f for f in ups}
    groups = []
    while left:
        _, f = left.popitem()
        g, todo = [f], [f]
        while todo:
            a = todo.pop()
            for n in a.neighbours:
                b = left.get(n)
                if b is not None and abs(b.zmin - a.zmin) < Z_TOL:
                    del left[n]
                    g.append(b)
                    todo.append(b)
        groups.append(g)
    return groups


def _floor_feature(group, z, region, corners, by_id, shadows: Shadows, zmax, feats, out,
                   new_id, k, claimed) -> None:
    ids = [f.id for f in group]
    # floor fillets: concave horizontal-axis cylinders / tori along the floor's edges
    fillets = []
    for f in group:
        for n in f.neighbours:
            g = by_id[n]
            if g.kind in ("cylinder", "torus") and g.concave and abs(g.zmin - z) < Z_TOL \
                    and (g.kind == "torus" or abs(g.axis[2]) < 1e-6):
                fillets.append(g)
    fr = min((g.radius for g in fillets), default=0.0)
    fillet_ids = sorted({g.id for g in fillets})
    claimed.update(fillet_ids)
    if fillets:
        region = shapely.union_all([region] + [edges_region(g.face) for g in fillets])
    keep = shadows.above(z + fr, _near(region))
    walls = [by_id[n] for f in group + fillets for n in f.neighbours
             if (by_id[n].vertical_wall() or by_id[n].kind in ("cylinder", "torus"))
             and by_id[n].zmax > z + Z_TOL]
    z_top = max([w.zmax for w in walls if w.zmax > z + Z_TOL], default=zmax)
    fid = new_id()
    covered = region.intersection(shadows.above(z, _near(region))).area
    if covered > 0.5 * region.area:
        feats.append(Feature(fid, "POCKET", "floor under material", "", 0,
                             _placement(*_centre(region), z, k), {}, faces=ids))
        out.skipped.append(Unmachinable(fid, "POCKET", "the floor is under material "
                                        "(an undercut): not reachable from +Z"))
        return
    local = shapely.clip_by_rect(keep, *region.buffer(1.0).bounds)    # walls near the floor
    corner = _corner_radius(region, local, corners)
    name, params = _classify(region, local, z_top - z)
    islands = _islands(region, local)
    texts = {}
    if "ends" in params:
        texts["ends"] = ", ".join(params.pop("ends"))
    params = {key: v * k for key, v in params.items()}
    params.update({"depth": (z_top - z) * k, "corner radius": min(corner, 1e6) * k,
                   "floor radius": fr * k})
    if islands:
        texts["islands"] = str(islands)
    if z_top < zmax - Z_TOL:
        texts["level"] = "below the part's top (nested in another feature or a step)"
    ftype = {"slot": "SLOT", "step": "STEP"}.get(name.split()[-1], "POCKET")
    feats.append(Feature(fid, ftype, name, f"floor at z {z * k:.6g}", 0,
                         _placement(*_centre(region), z_top, k), params, texts,
                         faces=ids + fillet_ids + sorted({w.id for w in walls}
                                                         - set(fillet_ids) - set(ids))))
    out.shapes.append(_general(fid, region, keep, z_top, z_top - z, "planar", fr, corner, k,
                               name=name))


#: how far around a floor the material above it is kept in its shape (mm): the tool
#: centre stays within a radius of the floor, so material beyond two radii of the floor
#: does not matter (tools up to 50 mm in diameter)
KEEP_MARGIN = 100.0


def _near(region) -> tuple[float, float, float, float]:
    """``region``'s bounds grown by :data:`KEEP_MARGIN`."""
    x0, y0, x1, y1 = region.bounds
    m = KEEP_MARGIN
    return (x0 - m, y0 - m, x1 + m, y1 + m)


def _general(fid, region, keep, z_top, depth, bottom, fr, corner, k, name) -> PocketShape:
    c = _centre(region)
    sc = (lambda g: affinity.scale(g, k, k, origin=(0, 0))) if k != 1.0 else (lambda g: g)
    p = PocketShape(fid, (c[0] * k, c[1] * k), 0.0, "general", depth * k, z_top * k, bottom,
                    corner_radius=min(corner, 1e6) * k, floor_radius=fr * k,
                    region=sc(region), keep=sc(keep))
    p.kind = name.split()[-1] if name.split()[-1] in ("slot", "step", "profile") else "pocket"
    return p


def _corner_radius(region, keep, corners: list[FaceInfo]) -> float:
    """Smallest concave corner of the walls around ``region`` (mm; 1e9: none):
    0 at a sharp corner of ``keep`` next to the region, else the smallest radius of the
    partial concave vertical cylinders (``corners``) beside it."""
    near = region.buffer(0.05)
    r = 1e9
    for g in (keep.geoms if hasattr(keep, "geoms") else [keep]):
        if g.is_empty:
            continue
        g = shapely.geometry.polygon.orient(g, 1.0)
        for ring in [g.exterior, *g.interiors]:
            p = np.asarray(ring.coords)[:-1]
            if len(p) < 3:
                continue
            a = p - np.roll(p, 1, axis=0)
            b = np.roll(p, -1, axis=0) - p
            cross = a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0]
            dot = (a * b).sum(axis=1)
            turn = np.degrees(np.arctan2(cross, dot))
            sharp = p[turn < -25.0]                # reflex for the material: a sharp corner
            if len(sharp) and shapely.intersects_xy(near, sharp[:, 0], sharp[:, 1]).any():
                return 0.0
    x0, y0, x1, y1 = near.bounds
    for f in corners:
        if f.box[0] >= x0 and f.box[3] <= x1 \
                and f.box[1] >= y0 and f.box[4] <= y1 \
                and near.intersects(Point(f.centre[0], f.centre[1]).buffer(f.radius + 0.01)):
            r = min(r, f.radius)
    return r


def _classify(region, keep, depth: float) -> tuple[str, dict]:
    """('closed pocket' | 'open pocket' | 'slot' | 'step', parameters in mm)."""
    # openings in the floor (holes, deeper pockets) are not open sides: outer rings only
    boundary = shapely.union_all([shapely.LinearRing(g.exterior.coords)
                                  for g in getattr(region, "geoms", [region])])
    wall = keep.buffer(0.01)
    closed = boundary.intersection(wall).length
    total = boundary.length
    open_frac = 1.0 - closed / total if total > 0 else 1.0
    mrr = region.minimum_rotated_rectangle
    params: dict = {}
    if mrr.geom_type == "Polygon":
        c = np.asarray(mrr.exterior.coords)[:4]
        e = np.hypot(*np.diff(np.vstack([c, c[:1]]), axis=0).T)
        length, width = max(e[0], e[1]), min(e[0], e[1])
        if width > 0 and length >= 2.0 * width and region.area >= 0.75 * mrr.area \
                and not list(region.interiors if region.geom_type == "Polygon" else [1]):
            i = int(np.argmax(e[:2]))
            sides = [shapely.LineString([c[i], c[(i + 1) % 4]]),
                     shapely.LineString([c[(i + 2) % 4], c[(i + 3) % 4]])]
            if all(s.buffer(0.02).intersection(wall).area > 0 and
                   s.intersection(wall.buffer(0.02)).length > 0.6 * s.length for s in sides):
                params = {"width": width, "length": length}
                ends = [_slot_end(region, wall, c[(i + 1 + 2 * j) % 4], c[(i + 2 + 2 * j) % 4],
                                  c[(i + 2 * j) % 4], width) for j in (0, 1)]
                params["ends"] = ends
                return ("slot" if open_frac < 0.02 else "open slot"), params
    if open_frac < 0.02:
        return "closed pocket", params
    return ("step" if open_frac > 0.5 else "open pocket"), params


def _slot_end(region, wall, a, b, far, width: float) -> str:
    """'radiused', 'flat' or 'open': the slot's end along side ``a``-``b`` of its
    rectangle (``far``: the corner across from ``a``)."""
    a, b, far = np.asarray(a), np.asarray(b), np.asarray(far)
    inward = (far - a) / max(np.linalg.norm(far - a), 1e-12) * width / 2.0
    zone = shapely.Polygon([a, b, b + inward, a + inward])
    fill = region.intersection(zone).area / max(zone.area, 1e-12)
    if fill < 0.9:
        return "radiused"
    side = shapely.LineString([a, b])
    return "flat" if side.intersection(wall.buffer(0.02)).length > 0.6 * side.length \
        else "open"


def _islands(region, keep) -> int:
    """Material standing inside the floor's outline (islands)."""
    polys = region.geoms if hasattr(region, "geoms") else [region]
    n = 0
    for p in polys:
        for ring in p.interiors:
            hole = shapely.Polygon(ring)
            if hole.intersection(keep).area > 0.5 * hole.area:
                n += 1
    return n


def _unexplained(f: FaceInfo, zmin: float) -> str:
    if f.kind == "free-form":
        return f"free-form face: {SURFACE_ADVICE}"
    if f.kind == "plane":
        h = f.horizontal()
        if h == -1:
            return "" if f.zmax <= zmin + Z_TOL else \
                "faces down above the part's bottom: not reachable from +Z (another setup)"
        if h == 0 and abs(f.normal[2]) > 1e-6:
            if f.normal[2] > 0:
                return f"inclined plane: {SURFACE_ADVICE}"
            return "inclined plane facing down: not reachable from +Z (another setup)"
        return ""
    if f.kind == "cylinder" and f.vertical_axis():
        return ""
    if f.kind == "cylinder" and not f.concave:
        return f"rounded edge (convex cylinder, radius {f.radius:.6g}): {SURFACE_ADVICE}"
    if f.kind in ("cylinder", "cone") and not f.vertical_axis() and f.concave:
        return ("hole or round not along the setup axis: not reachable from +Z "
                "(another setup)")
    return f"{f.kind} face: {SURFACE_ADVICE}"
