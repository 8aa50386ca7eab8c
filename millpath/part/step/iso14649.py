"""ISO 14649 (STEP-NC ARM) workpieces: the same features as AP224, as simple instances.

ISO 14649-10/11 files (schema ``COMBINED_SCHEMA`` or ``MACHINING_SCHEMA``) carry the
features with positional attributes instead of AP224's named representation items::

    ROUND_HOLE(id, workpiece, operations, placement, depth, diameter, change_in_diameter,
               bottom_condition)
    SLOT(id, workpiece, operations, placement, depth, course_of_travel, swept_shape,
         end_conditions)
    CLOSED_POCKET(id, workpiece, operations, placement, depth, bosses, slope,
                  bottom_condition, planar_radius, orthogonal_radius, feature_boundary)
    BLOCK(name, position, x, y, z)        MATERIAL(standard, name, properties)

This module maps them onto the AP224 records of :mod:`millpath.part.step.ap224`
(:class:`Feature` with the components AP224 would have), so listing, shapes and
planning work unchanged. Conventions mapped: the ARM placement's Z points out of the
material, AP224's into it (the axis is reversed); ``depth`` is a plane whose
location, in the feature's placement, is at ``z = -depth``; a rectangular profile's
``profile_width`` runs along the placement's X; wall angles are radians from the
vertical (AP224: degrees between floor and wall, 90 = vertical). Lengths are taken
as millimetres (ISO 14649 files carry no unit context).
"""

from __future__ import annotations

import math

import numpy as np

from millpath.part.step.ap224 import (Component, Feature, Part, Placement, Stock, Units,
                                      GeometryReader)
from millpath.part.step.p21 import Instance, Ref, StepFile

ARM_SCHEMAS = ("COMBINED_SCHEMA", "MACHINING_SCHEMA", "INTEGRATED_CNC_SCHEMA_ARM")
_HOLE_BOTTOMS = {"THROUGH_BOTTOM_CONDITION": "through", "FLAT_HOLE_BOTTOM": "flat",
                 "CONICAL_HOLE_BOTTOM": "conical", "SPHERICAL_HOLE_BOTTOM": "spherical",
                 "FLAT_WITH_RADIUS_HOLE_BOTTOM": "flat with radius",
                 "FLAT_WITH_TAPER_HOLE_BOTTOM": "flat with taper"}
_SLOT_ENDS = {"OPEN_SLOT_END_TYPE": "open", "RADIUSED_SLOT_END_TYPE": "radiused",
              "FLAT_SLOT_END_TYPE": "flat", "WOODRUFF_SLOT_END_TYPE": "woodruff",
              "LOOP_SLOT_END_TYPE": "loop"}
ARM_FEATURES = ("ROUND_HOLE", "SLOT", "CLOSED_POCKET", "OPEN_POCKET", "STEP", "PLANAR_FACE",
                "GENERAL_OUTSIDE_PROFILE", "BOSS", "THREAD", "CHAMFER", "EDGE_ROUND")


def is_iso14649(sf: StepFile) -> bool:
    """True for an ARM file: an ARM schema name, or WORKPIECE without AP224 features."""
    if any(s.upper() in ARM_SCHEMAS for s in sf.schemas):
        return True
    return bool(sf.by_type("WORKPIECE")) and not sf.by_type("MACHINING_FEATURE")


class _Arm:
    def __init__(self, sf: StepFile):
        self.sf = sf
        self.geo = GeometryReader(sf)

    def length(self, v) -> float | None:
        """A length given as a number or a TOLERANCED_LENGTH_MEASURE."""
        if isinstance(v, Ref):
            p = self.sf[v].get("TOLERANCED_LENGTH_MEASURE")
            if p is not None and isinstance(p[0], (int, float)) and not isinstance(p[0], Ref):
                return float(p[0])
            return None
        if isinstance(v, (int, float)) and not isinstance(v, bool):
            return float(v)
        return None

    def placement(self, v) -> Placement | None:
        if isinstance(v, Ref) and self.sf[v].has("AXIS2_PLACEMENT_3D"):
            return self.geo.placement(self.sf[v])
        return None

    def depth(self, v) -> float | None:
        """Depth from an ELEMENTARY_SURFACE (PLANE) located at z = -depth."""
        if not isinstance(v, Ref):
            return None
        p = self.sf[v].params
        pl = self.placement(p[1]) if len(p) > 1 else None
        return -pl.origin[2] if pl is not None else None

    def feature(self, inst: Instance, ftype: str) -> Feature:
        p = inst.params
        name = p[0] if isinstance(p[0], str) else ""
        pl = self.placement(p[3])
        f = Feature(inst.id, ftype, name, "", self.sf.line_of(inst))
        if pl is not None:      # ARM: Z out of the material; AP224: into it
            f.placement = Placement(pl.origin, tuple(-a for a in pl.axis), pl.ref, pl.id)
        depth = self.depth(p[4]) if len(p) > 4 else None
        into = f.placement.axis if f.placement else (0.0, 0.0, -1.0)
        if ftype == "ROUND_HOLE":
            d = self.length(p[5])
            if d is not None:
                f.components.append(Component(inst.id, "CIRCULAR_CLOSED_PROFILE", "",
                                              "diameter occurrence", "", {"diameter": d}))
            if depth is not None:
                f.components.append(Component(inst.id, "PATH_FEATURE_COMPONENT", "linear",
                                              "hole depth occurrence", "",
                                              {"distance": depth}, direction=into))
            if isinstance(p[7], Ref):
                f.components.append(self.hole_bottom(self.sf[p[7]]))
        elif ftype == "SLOT":
            self.slot(f, p, depth)
        elif ftype in ("CLOSED_POCKET", "OPEN_POCKET"):
            f.type = "POCKET"
            f.description = "closed" if ftype == "CLOSED_POCKET" else "open"
            self.pocket(f, p, depth, into)
        return f

    def hole_bottom(self, b: Instance) -> Component:
        kind = _HOLE_BOTTOMS.get(b.records[0][0], b.records[0][0].lower())
        c = Component(b.id, "HOLE_BOTTOM", kind, "bottom condition occurrence", "")
        bp = b.params
        if kind == "conical" and bp and isinstance(bp[0], float):
            c.params["tip angle"] = math.degrees(float(bp[0]))
        elif kind in ("spherical", "flat with radius") and bp:
            r = self.length(bp[0])
            if r is not None:
                c.params["radius" if kind == "spherical" else "corner radius"] = r
        return c

    def slot(self, f: Feature, p: list, depth: float | None) -> None:
        path = self.sf[p[5]] if isinstance(p[5], Ref) else None
        if path is not None and path.has("LINEAR_PATH"):
            lp = path.get("LINEAR_PATH")
            dist = self.length(lp[1])
            direction = self.geo.direction(lp[2], (1.0, 0.0, 0.0))
            # the direction is given in the feature's placement
            direction = tuple(float(v) for v in _in_parent(self.placement(p[3]), direction))
            f.components.append(Component(path.id, "PATH_FEATURE_COMPONENT", "linear",
                                          "course of travel occurrence", "",
                                          {"distance": dist or 0.0}, direction=direction))
        elif path is not None:
            f.components.append(Component(path.id, "PATH_FEATURE_COMPONENT",
                                          path.records[0][0].lower(),
                                          "course of travel occurrence", ""))
        prof = self.sf[p[6]] if isinstance(p[6], Ref) else None
        if prof is not None and prof.has("SQUARE_U_PROFILE"):
            sp = prof.get("SQUARE_U_PROFILE")
            params = {"width": self.length(sp[1]) or 0.0}
            if depth is not None:
                params["depth"] = depth
            for k, (rad, ang) in enumerate(((sp[2], sp[3]), (sp[4], sp[5]))):
                which = ("first", "second")[k]
                params[f"{which} radius"] = self.length(rad) or 0.0
                a = float(ang) if isinstance(ang, float) else 0.0
                params[f"{which} angle"] = 90.0 + math.degrees(a)
            f.components.append(Component(prof.id, "SQUARE_U_PROFILE", "sweep",
                                          "swept shape occurrence", "", params))
        elif prof is not None:
            f.components.append(Component(prof.id, prof.records[0][0], "",
                                          "swept shape occurrence", ""))
        for e in (p[7] if len(p) > 7 and isinstance(p[7], list) else []):
            if isinstance(e, Ref):
                end = self.sf[e]
                f.components.append(Component(end.id, "SLOT_END",
                                              _SLOT_ENDS.get(end.records[0][0], "open"),
                                              "end condition occurrence", ""))

    def pocket(self, f: Feature, p: list, depth: float | None, into) -> None:
        if depth is not None:
            f.components.append(Component(f.id, "PATH_FEATURE_COMPONENT", "linear",
                                          "pocket depth occurrence", "", {"distance": depth},
                                          direction=into))
        if len(p) > 7 and isinstance(p[7], Ref):
            b = self.sf[p[7]]
            kind = "through" if "THROUGH" in b.records[0][0] else "planar"
            c = Component(b.id, "POCKET_BOTTOM", kind, "bottom condition occurrence", "")
            pr = self.length(p[8]) if len(p) > 8 else None
            if pr:
                c.params["radius"] = pr
            f.components.append(c)
        corner = self.length(p[9]) if len(p) > 9 else None
        boundary = self.sf[p[10]] if len(p) > 10 and isinstance(p[10], Ref) else None
        if boundary is None:
            return
        name = boundary.records[0][0]
        bp = boundary.params
        c = Component(boundary.id, name, "", "closed boundary occurrence", "")
        c.placement = self.placement(bp[0])
        if name == "RECTANGULAR_CLOSED_PROFILE":
            c.params = {"length": self.length(bp[1]) or 0.0, "width": self.length(bp[2]) or 0.0,
                        "corner radius": corner or 0.0}
        elif name == "CIRCULAR_CLOSED_PROFILE":
            c.params = {"diameter": self.length(bp[1]) or 0.0}
        f.components.append(c)


def _in_parent(pl: Placement | None, d) -> np.ndarray:
    return np.asarray(d, float) if pl is None else pl.matrix() @ np.asarray(d, float)


def read_iso14649(sf: StepFile) -> Part:
    """A :class:`Part` from an ISO 14649 (ARM) file."""
    arm = _Arm(sf)
    stock = None
    for b in sf.by_type("BLOCK"):
        p = b.get("BLOCK")
        if len(p) >= 5 and all(isinstance(v, (int, float)) for v in p[2:5]):
            pl = arm.placement(p[1]) or Placement()
            stock = Stock("block", pl, {"length": float(p[2]), "width": float(p[3]),
                                        "height": float(p[4])}, b.id)
            break
    material = ""
    for w in sf.by_type("WORKPIECE"):
        m = w.params[1] if len(w.params) > 1 else None
        if isinstance(m, Ref) and sf[m].has("MATERIAL"):
            mp = sf[m].get("MATERIAL")
            material = " ".join(s for s in mp[:2] if isinstance(s, str) and s)
            break
    feats = []
    for inst in sf.instances.values():
        name = inst.records[0][0]
        if not inst.complex and name in ARM_FEATURES and len(inst.params) >= 5 \
                and isinstance(inst.params[1], Ref) and sf[inst.params[1]].has("WORKPIECE"):
            feats.append(arm.feature(inst, name))
    product = ""
    for pr in sf.by_type("PROJECT"):
        product = pr.params[0] if isinstance(pr.params[0], str) else ""
    return Part(file=sf.file, schema=sf.schemas, product=product, units=Units("mm", 1.0),
                stock=stock, material=material, features=feats, step=sf)
