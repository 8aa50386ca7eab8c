"""Generated G-code programs for the interpreter benchmarks and differential tests.

``free_order(n)``: what hand-written code and other CAM posts write: words in free order
and mixed case, spacing varied, modal moves without a G word, R and I/J arcs, line
numbers and comments, a few canned-cycle runs (G81/G83 with modal X Y lines).
``comp_heavy(n)``: almost all under G41/G42 (tool 1), about 45 % of moves arcs (I/J
and R), closed pockets of random shape entered and left with straight moves.
Both are valid for LinuxCNC's rs274 (tool table ``TOOL_TABLE``, inches) and
deterministic for a seed. Coordinates are mm.
"""

from __future__ import annotations

import math
import random

TOOL_TABLE = "T1 P1 D0.25 Z1.5 ;quarter inch mill\nT2 P2 D0.125 Z1.2 ;eighth inch drill\n"


def _case(rng: random.Random, letter: str) -> str:
    return letter if rng.random() < 0.7 else letter.lower()


def _words(rng: random.Random, words: list[tuple[str, str]]) -> str:
    """Words joined in random order, case and spacing."""
    words = list(words)
    rng.shuffle(words)
    sep = rng.choice((" ", " ", "", "  ", "\t"))
    out = []
    for letter, value in words:
        gap = " " if rng.random() < 0.1 else ""
        out.append(_case(rng, letter) + gap + value)
    return sep.join(out)


def free_order(n_lines: int, seed: int = 11) -> str:
    """A program of about ``n_lines`` lines; see the module docstring."""
    rng = random.Random(seed)
    out = ["%", "(free order benchmark)", "g21 G17 g90 G94 G40 G49 G80", "t1 M6", "g43 h1",
           "s12000 m3", "F900", "G0 X0 Y0 Z5", "G1 Z-1"]
    x = y = 0.0
    mode = 1
    num = 10
    while len(out) < n_lines - 3:
        r = rng.random()
        if r < 0.01:
            # a short run of drilling cycles, modal X Y lines after the first
            cyc = rng.choice(("G81", "G83"))
            words = [("G", cyc[1:]), ("X", f"{x:.3f}"), ("Y", f"{y:.3f}"), ("Z", "-3"),
                     ("R", "1")]
            if cyc == "G83":
                words.append(("Q", "0.8"))
            out.append("G0 Z2")
            out.append("G98 " + _words(rng, words))
            for _ in range(rng.randint(3, 8)):
                x += rng.uniform(-5, 5)
                y += rng.uniform(-5, 5)
                out.append(_words(rng, [("X", f"{x:.3f}"), ("Y", f"{y:.3f}")]))
            out.append("G80")
            out.append("G1 Z-1")
            mode = 1
            continue
        words: list[tuple[str, str]] = []
        if r < 0.35:
            # arc of random radius and sweep from the current point, I/J or R
            rad = rng.uniform(1, 30)
            a0 = rng.uniform(0, 2 * math.pi)
            sweep = rng.uniform(0.2, 2.8)
            ccw = rng.random() < 0.5
            cx, cy = x - rad * math.cos(a0), y - rad * math.sin(a0)
            a1 = a0 + (sweep if ccw else -sweep)
            ex, ey = round(cx + rad * math.cos(a1), 4), round(cy + rad * math.sin(a1), 4)
            code = 3 if ccw else 2
            if code != mode or rng.random() < 0.6:
                words.append(("G", rng.choice((f"{code}", f"0{code}"))))
            words += [("X", f"{ex:.4f}"), ("Y", f"{ey:.4f}")]
            if rng.random() < 0.5:
                words += [("I", f"{cx - x:.4f}"), ("J", f"{cy - y:.4f}")]
            else:
                # R form: the short arc (sweep < pi) with this radius, recomputed so
                # that both interpreters agree within the arc's tolerance
                chord = math.hypot(ex - x, ey - y)
                rr = max(rad, chord / 2 + 1e-3) if sweep < math.pi else rad
                words.append(("R", f"{rr:.4f}"))
            x, y = ex, ey
            mode = code
        else:
            x = round(x + rng.uniform(-10, 10), 3)
            y = round(y + rng.uniform(-10, 10), 3)
            if mode != 1 or rng.random() < 0.4:
                words.append(("G", rng.choice(("1", "01"))))
                mode = 1
            words += [("X", f"{x:.3f}"), ("Y", f"{y:.3f}")]
            if rng.random() < 0.2:
                words.append(("Z", f"{rng.uniform(-1.5, -0.5):.3f}"))
        if rng.random() < 0.05:
            words.append(("F", f"{rng.randint(300, 1500)}"))
        line = _words(rng, words)
        if rng.random() < 0.15:
            line = f"N{num} " + line
            num += 10
        if rng.random() < 0.05:
            line += rng.choice((" (move)", " ;note", "(cut)"))
        out.append(line)
    out += ["G0 Z5", "M2", "%"]
    return "\n".join(out) + "\n"


def comp_heavy(n_lines: int, seed: int = 13) -> str:
    """About ``n_lines`` lines, almost all under G41/G42 with ~45 % arcs."""
    rng = random.Random(seed)
    out = ["G21 G17 G90 G94 G40 G49 G80", "T1 M6", "G43 H1", "S12000 M3", "F800",
           "G0 X0 Y0 Z5", "G1 Z-1"]
    while len(out) < n_lines - 2:
        # a closed pocket: a convex-ish polygon walked by lines and outward bulging arcs
        cx, cy = rng.uniform(-300, 300), rng.uniform(-300, 300)
        base = rng.uniform(40, 90)
        k = rng.randint(40, int(2 * math.pi * base * 0.85 / 3.0))      # chords >= 3 mm
        pts = []
        for i in range(k):
            t = 2 * math.pi * i / k
            rad = base * (1 + 0.05 * math.sin(3 * t + rng.uniform(-0.2, 0.2)))
            pts.append((round(cx + rad * math.cos(t), 4), round(cy + rad * math.sin(t), 4)))
        # the tool runs outside the pocket: G42 walking CCW, G41 walking CW, so that
        # every corner is convex for the tool (no "concave corner" arcs to refuse)
        side = rng.choice(("G41", "G42"))
        turn = 1.0 if side == "G42" else -1.0
        if turn < 0:
            pts.reverse()
        sx, sy = pts[0]
        out.append(f"G0 X{cx:.3f} Y{cy:.3f}")
        out.append(f"{side} D1")
        out.append(f"G1 X{sx:.4f} Y{sy:.4f}")
        px, py = sx, sy
        for qx, qy in pts[1:] + [pts[0]]:
            if rng.random() < 0.45:
                # arc through the chord, bulging away from the pocket centre
                mx, my = (px + qx) / 2, (py + qy) / 2
                chord = math.hypot(qx - px, qy - py)
                rr = max(chord * rng.uniform(0.8, 3.0), 6.0)
                h = math.sqrt(max(rr * rr - chord * chord / 4, 0.0))
                # normal of the chord towards the inside of the walk
                nx, ny = -turn * (qy - py) / chord, turn * (qx - px) / chord
                ccx, ccy = mx + h * nx, my + h * ny
                g = "G3" if turn > 0 else "G2"
                if rng.random() < 0.7:
                    out.append(f"{g} X{qx:.4f} Y{qy:.4f} I{ccx - px:.4f} J{ccy - py:.4f}")
                else:
                    out.append(f"{g} X{qx:.4f} Y{qy:.4f} R{rr:.4f}")
            else:
                out.append(f"G1 X{qx:.4f} Y{qy:.4f}")
            px, py = qx, qy
        out.append(f"G40 G1 X{cx:.3f} Y{cy:.3f}")
    out += ["G0 Z5", "M2"]
    return "\n".join(out) + "\n"
