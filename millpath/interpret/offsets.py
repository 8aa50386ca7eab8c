"""Work coordinate systems, G10 (L1 L10 L11 L2 L20), G28.1/G30.1 and G52/G92 offsets, as
LinuxCNC 2.9 keeps them in its numbered parameters (5161-5186, 5201-5389).

An executor on the interpreter's Machine, whose state it reads and sets (the work system
``origin_index``, ``origin``, ``rotation``, ``axis_offset``, the parameters, the current
point): positions are program coordinates in program units; parameters hold machine
units (``user_to_prog`` / ``prog_to_user`` convert).
Work system XY rotation (``G10 L2 R``) is in degrees, counter-clockwise.
"""

from __future__ import annotations

import math

from millpath.interpret.errors import GCodeError
from millpath.gcode.lexer import Block


def rotate(x: float, y: float, degrees: float) -> tuple[float, float]:
    """Rotate (x, y) counter-clockwise by ``degrees`` (LinuxCNC's Interp::rotate)."""
    if degrees == 0.0:
        return x, y
    t = math.radians(degrees)
    c, s = math.cos(t), math.sin(t)
    return x * c - y * s, x * s + y * c


class Offsets:
    """The work-system and offset executor (G10, G28.1/G30.1, G52/G92, G54-G59.3) on
    machine ``m``."""

    def __init__(self, machine) -> None:
        self.m = machine

    def work_offset_params(self, index: int) -> list[float]:
        base = 5201 + 20 * index
        return [self.m.user_to_prog(self.m.params[base + k]) for k in range(3)]

    def current_in_system(self, system: int, with_tlo: bool = False) -> list[float]:
        """The current point expressed in work system ``system`` (LinuxCNC's
        find_current_in_system: through machine coordinates, rotations included);
        ``with_tlo``: as if the tool length offset were not applied."""
        p = self.m.params
        x = self.m.cur[0] + self.m.axis_offset[0]
        y = self.m.cur[1] + self.m.axis_offset[1]
        z = self.m.cur[2] + self.m.axis_offset[2]
        x, y = rotate(x, y, self.m.rotation)
        o = self.work_offset_params(system)
        x += self.m.origin[0] - o[0]
        y += self.m.origin[1] - o[1]
        z += self.m.origin[2] - o[2]
        if with_tlo:
            x += self.m.tlo[0]
            y += self.m.tlo[1]
            z += self.m.tlo[2]
        x, y = rotate(x, y, -p[5210 + system * 20])
        if p[5210]:
            x -= self.m.user_to_prog(p[5211])
            y -= self.m.user_to_prog(p[5212])
            z -= self.m.user_to_prog(p[5213])
        return [x, y, z]

    def coordinate_system(self, code: int) -> None:
        if self.m.comp.side:
            raise GCodeError("Cannot change coordinate systems with cutter radius "
                             "compensation on")
        index = {540: 1, 550: 2, 560: 3, 570: 4, 580: 5, 590: 6, 591: 7, 592: 8, 593: 9}[code]
        if index == self.m.origin_index:
            return
        self.m.cur = self.current_in_system(index)
        self.m.origin = self.work_offset_params(index)
        self.m.rotation = self.m.params[5210 + index * 20]
        self.m.origin_index = index
        self.m.params[5220] = float(index)
        self.m.sync_out()

    # --- modal group 0 ----------------------------------------------------------------
    def modal_0(self, code: int, blk: Block) -> None:
        w = blk.words
        if code == 100:
            lv = int(w.get("l", -1))
            if lv in (2, 20):
                self.g10_l2(w, lv)
            elif lv in (1, 10, 11):
                self.g10_l1(w, lv)
            else:
                raise GCodeError(f"G10 L{lv} is not supported by this interpreter")
        elif code in (280, 300):
            self.m.home(code, blk)
        elif code in (281, 301):
            if self.m.comp.side:
                raise GCodeError("Cannot set reference point with cutter compensation in "
                                 "effect")
            base = 5161 if code == 281 else 5181
            c, ao = self.m.cur, self.m.axis_offset
            mx, my = rotate(c[0] + ao[0], c[1] + ao[1], self.m.rotation)
            machine = [mx, my, c[2] + ao[2]]
            for k in range(3):
                self.m.params[base + k] = self.m.prog_to_user(
                    machine[k] + self.m.tlo[k] + self.m.origin[k])
        else:
            self.axis_offsets(code, w)

    def g10_l2(self, w: dict, lv: int) -> None:
        if "i" in w or "j" in w:
            raise GCodeError("I J words not allowed with G10 L2")
        p = int(w.get("p", 0) + 0.0001)
        if p == 0:
            p = self.m.origin_index
        if self.m.comp.side and p == self.m.origin_index:
            raise GCodeError("Cannot change the active coordinate system with cutter radius "
                             "compensation on")
        params = self.m.params
        base = 5201 + 20 * p
        cx, cy, cz = self.current_in_system(p)
        if "r" in w:
            if lv == 20:
                raise GCodeError("R not allowed in G10 L20")
            r = w["r"]
            params[base + 9] = r
        else:
            r = params[base + 9]
        old = self.work_offset_params(p)
        active = p == self.m.origin_index
        if lv == 20:
            ox, oy = rotate(cx, cy, r)
            x, y = rotate(w.get("x", cx), w.get("y", cy), r)
            x = ox + old[0] - x
            y = oy + old[1] - y
            params[base] = self.m.prog_to_user(x)
            params[base + 1] = self.m.prog_to_user(y)
            if active:
                self.m.cur[0], self.m.cur[1] = rotate(self.m.cur[0], self.m.cur[1], self.m.rotation)
                self.m.rotation = 0.0
        else:
            x = w.get("x", old[0])
            y = w.get("y", old[1])
            if "x" in w:
                params[base] = self.m.prog_to_user(x)
            if "y" in w:
                params[base + 1] = self.m.prog_to_user(y)
        if "z" in w:
            z = w["z"]
            if lv == 20:
                z = cz + old[2] - z
            params[base + 2] = self.m.prog_to_user(z)
        else:
            z = old[2]
        if active:
            c = self.m.cur
            c[0], c[1] = rotate(c[0], c[1], self.m.rotation)
            c[0] += self.m.origin[0] - x
            c[1] += self.m.origin[1] - y
            c[2] += self.m.origin[2] - z
            self.m.origin = [x, y, z]
            c[0], c[1] = rotate(c[0], c[1], -r)
            self.m.rotation = r
            self.m.sync_out()

    def g10_l1(self, w: dict, lv: int = 1) -> None:
        """Tool table rows: L1 sets offsets directly, L10 (L11) so that the current point
        becomes the given value in the active system (in G59.3), LinuxCNC's
        convert_setup_tool."""
        p = w.get("p", 0.0)
        t = int(p + 0.5)
        if t != 0 and t not in self.m.tools:
            raise GCodeError(f"Requested tool {t} not found in the tool table")
        if not any(a in w for a in "xyzabcuvwrqij"):
            raise GCodeError("G10 L1 without offsets has no effect")
        d, x, y, z = self.m.tools.get(t, (0.0, 0.0, 0.0, 0.0))
        if lv == 1:
            if "x" in w:
                x = self.m.prog_to_user(w["x"])
            if "y" in w:
                y = self.m.prog_to_user(w["y"])
            if "z" in w:
                z = self.m.prog_to_user(w["z"])
        else:
            dest = 9 if lv == 11 else self.m.origin_index
            rot = self.m.params[5210 + dest * 20]
            tx, ty, tz = self.current_in_system(dest, with_tlo=True)
            if lv == 11 and self.m.params[5210]:
                tx += self.m.user_to_prog(self.m.params[5211])
                ty += self.m.user_to_prog(self.m.params[5212])
                tz += self.m.user_to_prog(self.m.params[5213])
            if "x" in w and "y" in w:
                ox, oy = rotate(tx - w["x"], ty - w["y"], rot)
                x, y = self.m.prog_to_user(ox), self.m.prog_to_user(oy)
            elif "x" in w or "y" in w:
                kx, ky = rotate(self.m.user_to_prog(x), self.m.user_to_prog(y), -rot)
                if "x" in w:
                    kx = 0.0
                    ax, ay = tx - w["x"], 0.0
                else:
                    ky = 0.0
                    ax, ay = 0.0, ty - w["y"]
                kx, ky = rotate(kx, ky, rot)
                ax, ay = rotate(ax, ay, rot)
                x, y = self.m.prog_to_user(ax + kx), self.m.prog_to_user(ay + ky)
            if "z" in w:
                z = self.m.prog_to_user(tz - w["z"])
        if "r" in w:
            d = self.m.prog_to_user(w["r"]) * 2.0
        self.m.tools = dict(self.m.tools)
        self.m.tools[t] = (d, x, y, z)

    def axis_offsets(self, code: int, w: dict) -> None:
        if self.m.comp.side:
            raise GCodeError("Cannot change axis offsets with cutter radius comp")
        p = self.m.params
        if code in (520, 920):
            p[5210] = 1.0
            for k, a in enumerate("xyz"):
                if a not in w:
                    continue
                if code == 520:
                    self.m.cur[k] += self.m.axis_offset[k] - w[a]
                    self.m.axis_offset[k] = w[a]
                else:
                    self.m.axis_offset[k] = self.m.cur[k] + self.m.axis_offset[k] - w[a]
                    self.m.cur[k] = w[a]
            for k in range(3):
                p[5211 + k] = self.m.prog_to_user(self.m.axis_offset[k])
        elif code in (921, 922):
            for k in range(3):
                self.m.cur[k] += self.m.axis_offset[k]
                self.m.axis_offset[k] = 0.0
            if code == 921:
                for k in range(3):
                    p[5211 + k] = 0.0
                p[5210] = 0.0
        elif code == 923:
            for k in range(3):
                new = self.m.user_to_prog(p[5211 + k])
                self.m.cur[k] = self.m.cur[k] + self.m.axis_offset[k] - new
                self.m.axis_offset[k] = new
            p[5210] = 1.0
        self.m.sync_out()
