"""Round holes of a solid, from its faces: coaxial stacks of vertical concave cylinders
(whole turns) with their bottoms, counterbores and countersinks.

A hole is reachable from +Z when its top is open. Its stack, from the top: an optional
countersink cone (widening upward), cylinders of decreasing radius joined by flat
shoulders (counterbores) or cones, and a bottom: a flat disk (with or without a corner
torus), a drill-point cone, a sphere, or nothing when it leaves the part's bottom
(through). Lengths in mm.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

from millpath.part.brep.faces import FaceInfo

TOL = 1e-4          # mm: coincidence of centres, radii and heights
CAVITY_BELOW = "the hole opens into a cavity below: not planned"


@dataclass
class Segment:
    """One machinable hole of a stack: diameter, entry top, depth to the lowest point,
    bottom ('through', 'flat', 'conical', 'spherical', 'flat with radius')."""

    x: float
    y: float
    z_top: float
    diameter: float
    depth: float
    bottom: str
    bottom_radius: float = 0.0
    tip_angle: float = 118.0
    role: str = "hole"            # hole | counterbore | countersink
    faces: list[int] = field(default_factory=list)


@dataclass
class HoleStack:
    x: float
    y: float
    segments: list[Segment]
    faces: list[int]
    problem: str = ""             # why it is not machinable from +Z ('' if it is)


def _key(f: FaceInfo) -> tuple[float, float]:
    return (round(f.centre[0] / TOL) * TOL, round(f.centre[1] / TOL) * TOL)


def find_holes(faces: list[FaceInfo], zmin: float) -> list[HoleStack]:
    """Hole stacks of the faces (vertical axis only)."""
    by_id = {f.id: f for f in faces}
    groups: dict[tuple[float, float], list[FaceInfo]] = {}
    for f in faces:
        if f.kind in ("cylinder", "cone", "sphere", "torus") and f.concave \
                and f.vertical_axis():
            groups.setdefault(_key(f), []).append(f)
    stacks = []
    for (x, y), fs in groups.items():
        cyl = [f for f in fs if f.kind == "cylinder"]
        # whole turns: cylinders of one radius and height range adding up to 2 pi
        rings: dict[tuple[float, float, float], list[FaceInfo]] = {}
        for f in cyl:
            k = (round(f.radius, 4), round(f.zmin, 4), round(f.zmax, 4))
            rings.setdefault(k, []).append(f)
        full = [(k, v) for k, v in rings.items()
                if sum(f.uspan for f in v) >= 2 * math.pi - 1e-3]
        if not full:
            continue
        full.sort(key=lambda kv: -kv[0][2])
        stacks.append(_stack(x, y, full, fs, by_id, zmin))
    return stacks


def _near_axis(f: FaceInfo, x: float, y: float, r: float) -> bool:
    b = f.box
    return (b[0] >= x - r - TOL and b[3] <= x + r + TOL and b[1] >= y - r - TOL
            and b[4] <= y + r + TOL)


def _stack(x, y, full, fs, by_id, zmin) -> HoleStack:
    faces: list[int] = []
    segs: list[Segment] = []
    used = set()
    cones = [f for f in fs if f.kind == "cone"]
    spheres = [f for f in fs if f.kind == "sphere"]
    tori = [f for f in fs if f.kind == "torus"]
    problem = ""
    (r0, _, top0), first = full[0]
    # countersink: a cone above the top cylinder, widening upward
    for c in cones:
        if abs(c.zmin - top0) < 1e-3 and c.zmax > top0 + TOL:
            r_top = r0 + (c.zmax - c.zmin) * math.tan(c.half_angle)
            depth = r_top / math.tan(c.half_angle)
            segs.append(Segment(x, y, c.zmax, 2 * r_top, depth, "conical",
                                tip_angle=math.degrees(2 * c.half_angle), role="countersink",
                                faces=[c.id]))
            used.add(c.id)
            break
    # is the top closed by a face looking down (a hole from below)?
    for f in first:
        for n in f.neighbours:
            g = by_id[n]
            if g.horizontal() == -1 and abs(g.zmin - top0) < 1e-3 and _near_axis(g, x, y, r0):
                problem = ("the hole is closed at the top (drilled from below): "
                           "not reachable from +Z")
    for i, ((r, zb, zt), ring) in enumerate(full):
        ids = [f.id for f in ring]
        nxt = full[i + 1] if i + 1 < len(full) else None
        below = [by_id[n] for f in ring for n in f.neighbours]
        if nxt is not None and abs(nxt[0][2] - zb) < 1e-3 and nxt[0][0] < r - TOL:
            shoulder = [g for g in below if g.horizontal() == 1 and abs(g.zmin - zb) < 1e-3
                        and _near_axis(g, x, y, r)]
            cone = [g for g in below if g.kind == "cone" and g.concave and abs(g.zmin - zb) < 1e-3]
            seg = Segment(x, y, zt, 2 * r, zt - zb, "flat", role="counterbore",
                          faces=ids + [g.id for g in shoulder])
            if not shoulder and cone:
                problem = problem or "a cone joins the hole's diameters: not planned"
            segs.append(seg)
            continue
        if nxt is not None:
            problem = problem or "the hole's diameters are not stacked top to bottom"
        # the bottom of the last cylinder
        floor = [g for g in below if g.horizontal() == 1 and abs(g.zmin - zb) < 1e-3
                 and _near_axis(g, x, y, r)]
        cone = [c for c in cones if c.id not in used and abs(c.zmax - zb) < 1e-3]
        sph = [s for s in spheres if abs(s.zmax - zb) < 1e-2]
        tor = [t for t in tori if abs(t.zmax - zb - t.radius) < 1e-2 or abs(t.zmax - zb) < 1e-2]
        seg = Segment(x, y, zt, 2 * r, zt - zb, "flat", faces=list(ids))
        if cone:
            c = cone[0]
            seg.bottom = "conical"
            seg.tip_angle = math.degrees(2 * c.half_angle)
            seg.depth = zt - (zb - r / math.tan(c.half_angle))
            seg.faces.append(c.id)
        elif sph:
            s = sph[0]
            seg.bottom = "spherical"
            seg.bottom_radius = s.radius
            seg.depth = zt - (s.centre[2] - s.radius)
            seg.faces.append(s.id)
        elif tor:
            t = tor[0]
            zf = t.zmin
            seg.bottom = "flat with radius"
            seg.bottom_radius = t.radius
            seg.depth = zt - zf
            seg.faces.append(t.id)
            seg.faces += [g.id for g in (by_id[n] for n in t.neighbours)
                          if g.horizontal() == 1 and abs(g.zmin - zf) < 1e-3]
        elif floor:
            seg.faces += [g.id for g in floor]
        elif zb <= zmin + 1e-3:
            seg.bottom = "through"
        else:
            problem = problem or CAVITY_BELOW
        segs.append(seg)
        break
    for s in segs:
        faces += s.faces
    return HoleStack(x, y, segs, sorted(set(faces)), problem)
