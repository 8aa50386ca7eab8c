"""The tool tip as the machine moves it: interpreted motion in the part's frame.

The interpreter records motion as LinuxCNC's canonical calls do: program coordinates in
the program units in force, with the frame that places them on the machine
(:class:`millpath.model.motion.Frame`). The machine moves the controlled point

    controlled (mm) = scale * (rotate_xy(program + G92/G52 offset, rotation) + work offset)
                      + tool length offset as applied (G43 H.., G43.1, G43.2)

and the cutter's tip is the controlled point minus the offsets of the tool really in the
spindle (its row of the tool table as written). A ``G43`` with another tool's ``H``, an
``M6`` with no ``G43`` after it, a ``G92``/``G52``/``G10 L2`` shift or rotation and a
``G20``/``G21`` switch in the middle of a program all move the tip accordingly.

The part's frame is the frame program coordinates have when the program starts (the
work system in force, G54 unless the machine's stored parameters say otherwise, with
its offsets and any stored G92 offset), in the part's units: a tip there is
``(rotate_xy(tip - reference origin, -reference rotation) - reference G92) / part scale``.
Arcs stay arcs (an XZ or YZ arc turned by an XY rotation other than a multiple of 90
degrees is cut into chords within ``CHORD_MM`` of it, a hundredth of the proof's accuracy); cubics and NURBS, XY
only, are carried with their control points. Feeds in units per minute are converted
to the part's units; inverse-time feeds are kept.
"""

from __future__ import annotations

import math
from dataclasses import replace

from millpath.model.motion import Frame, Motion
from millpath.model.nurbs import Nurbs
from millpath.model.units import length_scale
from millpath.simulate.path import motion_points

#: how far the chords of an arc that no plane of the part holds may stray (mm)
CHORD_MM = 1e-5
_ZERO = (0.0, 0.0, 0.0)


def _rot(x: float, y: float, c: float, s: float) -> tuple[float, float]:
    return x * c - y * s, x * s + y * c


class _Map:
    """Program point of one frame -> part point (affine: a rotation about Z, a scale and
    a shift)."""

    def __init__(self, f: Frame, ref: Frame, part_scale: float):
        s_f = f.scale
        t_f = math.radians(f.rotation)
        t_r = math.radians(ref.rotation)
        self.k = s_f / part_scale
        # controlled point: s_f * (R_f (p + ao) + origin) + tlo_mm; tip: minus tool_mm;
        # part: R_r^-1 (tip - s_r * origin_r) / part_scale
        self.c, self.s = math.cos(t_f - t_r), math.sin(t_f - t_r)
        cr, sr = math.cos(-t_r), math.sin(-t_r)
        ao = f.axis_offset
        ax, ay = _rot(ao[0], ao[1], math.cos(t_f), math.sin(t_f))
        sr_ = ref.scale
        sh = [s_f * (ax + f.origin[0]) + f.tlo_mm[0] - f.tool_mm[0] - sr_ * ref.origin[0],
              s_f * (ay + f.origin[1]) + f.tlo_mm[1] - f.tool_mm[1] - sr_ * ref.origin[1],
              s_f * (ao[2] + f.origin[2]) + f.tlo_mm[2] - f.tool_mm[2] - sr_ * ref.origin[2]]
        shx, shy = _rot(sh[0], sh[1], cr, sr)
        ra = ref.axis_offset
        self.shift = ((shx - sr_ * ra[0]) / part_scale, (shy - sr_ * ra[1]) / part_scale,
                      (sh[2] - sr_ * ra[2]) / part_scale)
        self.identity = (self.k == 1.0 and self.s == 0.0 and self.c == 1.0
                         and self.shift == _ZERO)
        self.quarter = abs(self.s) < 1e-15 or abs(self.c) < 1e-15

    def point(self, p) -> tuple[float, float, float]:
        if self.identity:
            return (p[0], p[1], p[2])
        x, y = _rot(p[0], p[1], self.c, self.s)
        k, sh = self.k, self.shift
        return (k * x + sh[0], k * y + sh[1], k * p[2] + sh[2])

    def xy(self, p) -> tuple[float, float]:
        x, y = _rot(p[0], p[1], self.c, self.s)
        return (self.k * x + self.shift[0], self.k * y + self.shift[1])


def _plane_after(plane: str, c: float, s: float) -> tuple[str, int]:
    """The plane an arc lies in after a quarter-turn rotation about Z, and the sign its
    turn direction takes (the plane's normal may flip)."""
    if plane == "XY" or abs(s) < 1e-15:
        return plane, (1 if plane == "XY" or c > 0 else -1)
    # a quarter turn swaps X and Y: XZ (normal +Y) <-> YZ (normal +X)
    if plane == "XZ":     # normal +Y turns to -X (s > 0) or +X (s < 0)
        return "YZ", (-1 if s > 0 else 1)
    return "XZ", (1 if s > 0 else -1)      # YZ: normal +X turns to +Y (s > 0)


def _arc_chords(m: Motion, mp: _Map, part_scale: float) -> list[Motion]:
    """An arc no plane of the part holds, as straight feeds within ``CHORD_MM`` of it."""
    tol = CHORD_MM / (part_scale * mp.k) if mp.k else CHORD_MM
    pts = motion_points(m, tol)
    out = []
    prev = mp.point(m.start)
    for i in range(1, len(pts)):
        q = mp.point(pts[i])
        out.append(replace(m, kind="feed", start=prev, end=q, center=None, rotation=0,
                           feed=m.feed * (mp.k if m.feed_mode != "inverse_time" else 1.0),
                           tool_offset=_ZERO, frame=None))
        prev = q
    return out


def tip_motions(motions, units: str, reference: Frame | None = None) -> list[Motion]:
    """``motions`` (interpreted, with frames) as tool tips in the part's frame and
    ``units`` (see the module docstring): new Motions with ``frame`` None and
    ``tool_offset`` zero. Motions without a frame are taken as tips already.
    ``reference``: the frame the part is set up in (default: the ``reference`` the
    interpreter gave ``motions``, else G54 at zero)."""
    ref = reference or getattr(motions, "reference", None) or Frame()
    part_scale = length_scale(units, "mm")
    out: list[Motion] = []
    maps: dict[Frame, _Map] = {}
    for m in motions:
        f = m.frame
        if f is None:
            out.append(m)
            continue
        mp = maps.get(f)
        if mp is None:
            mp = maps[f] = _Map(f, ref, part_scale)
        if mp.identity and m.tool_offset == _ZERO:
            out.append(replace(m, frame=None))
            continue
        feed = m.feed * mp.k if m.feed_mode != "inverse_time" else m.feed
        if m.kind == "arc" and m.plane != "XY" and not mp.quarter:
            out.extend(_arc_chords(m, mp, part_scale))
            continue
        kw = dict(start=mp.point(m.start), end=mp.point(m.end), feed=feed,
                  tool_offset=_ZERO, frame=None)
        if m.kind == "arc":
            plane, sign = _plane_after(m.plane, mp.c, mp.s)
            kw.update(center=mp.point(m.center), plane=plane, rotation=m.rotation * sign)
        elif m.kind == "cubic" and m.controls is not None:
            kw["controls"] = (mp.xy(m.controls[0]), mp.xy(m.controls[1]))
        elif m.kind == "nurbs" and m.controls is not None:
            n = m.controls
            kw["controls"] = Nurbs(n.order, tuple((*mp.xy(p), p[2]) for p in n.points))
        out.append(replace(m, **kw))
    return out
