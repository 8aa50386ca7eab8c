"""Tool selection for features from the job's tool library (job units).

- Holes: a drill of the hole's diameter (within ``tol``) for through holes, conical
  bottoms (the drill's point angle within 1 degree of the tip angle) and flat bottoms
  (the planner then mills the drill point's cone flat with the end mill chosen here;
  without an end mill the cone is left and reported); otherwise
  helical interpolation with the largest flat end mill no wider than 0.9 x the hole
  (a bull nose of the bottom's corner radius for 'flat with radius'); a spherical bottom
  takes a ball end mill of the hole's diameter; a 'flat with taper' bottom takes the
  largest flat end mill no wider than 0.9 x its flat (final diameter), which mills the
  cone in steps (strategy 'taper').
- Slots: the largest flat end mill no wider than the slot.
- Faces: the largest flat end mill.
- Pockets: the largest flat end mill whose radius is no larger than the corner radius
  and that fits the pocket; without one, the smallest that fits (corners are left
  with the tool's radius and reported). A floor fillet takes a bull nose end mill of
  that corner radius instead.

Among equals, tools whose flute length reaches the feature's depth come first.
"""

from __future__ import annotations

import math

from millpath.model import Tool
from millpath.part.step.shapes import FaceShape, HoleShape, PocketShape, SlotShape


def _flute_ok(t: Tool, depth: float) -> bool:
    return t.flute_length >= depth - 1e-9


def _largest(cands: list[Tool], depth: float) -> Tool | None:
    if not cands:
        return None
    return max(cands, key=lambda t: (_flute_ok(t, depth), t.diameter, -t.number))


def matching_drill(h: HoleShape, tools: list[Tool], tol: float) -> Tool | None:
    """A drill of the hole's diameter (within ``tol``) whose flutes reach deepest."""
    drills = [t for t in tools if t.type == "drill" and abs(t.diameter - h.diameter) <= tol]
    return _largest(drills, h.depth)


def hole_tool(h: HoleShape, tools: list[Tool], tol: float) -> tuple[str, Tool | None, str]:
    """(strategy, tool, note): strategy 'drill', 'helical', 'plunge' or '' (none)."""
    drills = [t for t in tools if t.type == "drill" and abs(t.diameter - h.diameter) <= tol]
    drill = _largest(drills, h.depth)
    flats = [t for t in tools if t.type == "flat" and t.diameter <= 0.9 * h.diameter]
    if h.bottom == "through":
        if drill is not None:
            return "drill", drill, ""
        t = _largest(flats, h.depth)
        return ("helical", t, "") if t else ("", None, "no drill of the diameter and no end "
                                             "mill smaller than the hole")
    if h.bottom == "conical":
        ok = [d for d in drills if abs(d.point_angle - h.tip_angle) <= 1.0]
        if ok:
            return "drill", _largest(ok, h.depth), ""
        return "", None, (f"no drill of diameter {h.diameter:g} with a "
                          f"{h.tip_angle:g} degree point")
    if h.bottom == "spherical":
        balls = [t for t in tools if t.type == "ball" and abs(t.diameter - h.diameter) <= tol
                 and abs(h.bottom_radius - h.diameter / 2.0) <= tol]
        if balls:
            return "plunge", _largest(balls, h.depth), ""
        return "", None, f"no ball end mill of diameter {h.diameter:g} for the spherical bottom"
    if h.bottom == "flat with taper":
        t = _largest([f for f in flats if f.diameter <= 0.9 * h.final_diameter], h.depth)
        if t:
            return "taper", t, ""
        return "", None, (f"no flat end mill within 0.9 x the taper's flat "
                          f"({h.final_diameter:g})")
    if h.bottom == "flat with radius":
        bulls = [t for t in tools if t.type == "bull" and t.diameter <= 0.9 * h.diameter
                 and abs(t.corner_radius - h.bottom_radius) <= tol]
        t = _largest(bulls, h.depth)
        if t:
            return "helical", t, ""
        return "", None, f"no bull nose end mill with corner radius {h.bottom_radius:g}"
    t = _largest(flats, h.depth)           # flat bottom
    if t is not None:
        return "helical", t, ""
    if drill is not None:
        return "drill", drill, "flat bottom drilled: the drill point's cone is left"
    return "", None, "no end mill smaller than the hole and no drill of its diameter"


def slot_tool(s: SlotShape, tools: list[Tool], tol: float) -> tuple[str, Tool | None, str]:
    flats = [t for t in tools if t.type == "flat" and t.diameter <= s.width + tol]
    t = _largest(flats, s.depth)
    if t is None:
        return "", None, f"no flat end mill no wider than the slot ({s.width:g})"
    if "flat" in s.ends:
        return "slot", t, (f"flat slot end: its square corners are left at the tool "
                           f"radius {t.radius:g}")
    return "slot", t, ""


def pocket_tool(p: PocketShape, tools: list[Tool], tol: float) -> tuple[str, Tool | None, str]:
    if p.floor_radius > 0:       # a bull nose whose corner radius is the floor fillet
        tools = [t for t in tools if t.type == "bull"
                 and abs(t.corner_radius - p.floor_radius) <= tol]
        if not tools:
            return "", None, (f"no bull nose end mill with corner radius {p.floor_radius:g} "
                              f"for the floor fillet")
        kind = "bull"
    else:
        kind = "flat"
    if p.profile == "circular":
        flats = [t for t in tools if t.type == kind and t.diameter <= 0.9 * p.diameter]
        t = _largest(flats, p.depth)
        return ("circular", t, "") if t else ("", None, "no end mill smaller than the pocket")
    if p.profile == "rectangular":
        room = min(p.length, p.width)
    else:
        room = p.diameter * math.cos(math.pi / p.sides)       # inscribed diameter
    fits = [t for t in tools if t.type == kind and t.diameter < room - tol]
    if not fits:
        return "", None, f"no {kind} end mill fits the pocket ({room:g} wide)"
    corner = [t for t in fits if t.radius <= p.corner_radius + tol]
    if corner:
        return "pocket", _largest(corner, p.depth), ""
    t = min(fits, key=lambda t: (not _flute_ok(t, p.depth), t.diameter))
    return "pocket", t, (f"corner radius {p.corner_radius:g} is below the smallest tool "
                         f"radius {t.radius:g}: corners are left at the tool radius")


def face_tool(f: FaceShape, tools: list[Tool], tol: float) -> tuple[str, Tool | None, str]:
    """Face milling: the largest flat end mill."""
    t = _largest([t for t in tools if t.type == "flat"], f.depth)
    return ("face", t, "") if t else ("", None, "no flat end mill for face milling")
