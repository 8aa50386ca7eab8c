"""Generated differential tests against rs274: random closed contours with cutter
compensation, random arcs in all planes, random canned cycles.

Each run uses a new base seed (printed; set MILLPATH_SEED to replay) unless
MILLPATH_SEED is given; every program's own seed is in the failure message.
"""

from __future__ import annotations

import math
import os
import random

import pytest

from support.difftest import differential
from millpath.io.tooltable import ToolEntry

N_CONTOURS = 160
N_ARCS = 80
N_CYCLES = 80
BASE_SEED = int(os.environ.get("MILLPATH_SEED", random.SystemRandom().randrange(10**6)))
print(f"test_generated: MILLPATH_SEED={BASE_SEED}")


def f4(v: float) -> str:
    s = f"{v:.4f}"
    return "0" if s in ("-0.0000", "0.0000") else s


def random_tools(rng: random.Random, scale: float) -> list[ToolEntry]:
    """Tool table (inches) with random diameters relative to the part scale."""
    return [ToolEntry(n, n, round(rng.uniform(0.02, 0.35) * scale / 25.4 * 2, 4),
                      {"Z": round(rng.uniform(0.5, 3.0), 4)}) for n in range(1, 6)]


def contour_program(seed: int) -> tuple[str, list[ToolEntry]]:
    """A random star-shaped closed contour of lines and arcs, cut with G41/G42 (D from
    the table) or G41.1/G42.1 (diameter in the block), in G17 or G18, G1 or G0 moves."""
    rng = random.Random(seed)
    metric = rng.random() < 0.7
    scale = 25.0 if metric else 1.0
    plane = "G18" if rng.random() < 0.2 else "G17"
    # plane letters: first, second, normal; center letters for first and second
    a, b, nrm, ca, cb = ("Z", "X", "Y", "K", "I") if plane == "G18" else ("X", "Y", "Z", "I", "J")
    n = rng.randint(3, 8)
    angles = sorted(rng.uniform(0, 2 * math.pi) for _ in range(n))
    pts = [(rng.uniform(0.4, 1.0) * scale * math.cos(t),
            rng.uniform(0.4, 1.0) * scale * math.sin(t)) for t in angles]
    if rng.random() < 0.5:
        pts.reverse()
    start = rng.randrange(n)
    pts = pts[start:] + pts[:start]
    tools = random_tools(rng, scale)
    d = rng.randint(1, 5)
    if rng.random() < 0.25:
        dia = rng.uniform(0.04, 0.7) * scale
        comp = f"{rng.choice(['G41.1', 'G42.1'])} D{f4(dia)}"
    else:
        comp = f"{rng.choice(['G41', 'G42'])} D{d}"
    ang = rng.uniform(0, 2 * math.pi)
    entry = (1.6 * scale * math.cos(ang), 1.6 * scale * math.sin(ang))
    lines = ["G21" if metric else "G20", f"F{rng.choice([100, 250, 600]) if metric else 10}",
             f"T{d} M6 G43", f"G0 {a}{f4(entry[0])} {b}{f4(entry[1])} {nrm}{f4(0.2 * scale)}",
             plane, comp, f"G1 {a}{f4(pts[0][0])} {b}{f4(pts[0][1])}",
             f"G1 {nrm}{f4(-0.1 * scale)}"]
    ring = pts[1:] + [pts[0]]
    cur = pts[0]
    for p in ring:
        if rng.random() < 0.45:
            # arc with a random bulge: center on the chord's perpendicular bisector
            mx, my = (cur[0] + p[0]) / 2, (cur[1] + p[1]) / 2
            dx, dy = p[0] - cur[0], p[1] - cur[1]
            chord = math.hypot(dx, dy)
            if chord < 1e-3 * scale:
                continue
            off = rng.uniform(-1.5, 1.5) * chord
            cx, cy = mx - dy / chord * off, my + dx / chord * off
            code = rng.choice(["G2", "G3"])
            if rng.random() < 0.5:
                r = math.hypot(cx - cur[0], cy - cur[1])
                cw_center = (dx * (cy - cur[1]) - dy * (cx - cur[0])) < 0
                big = (code == "G2") == cw_center
                lines.append(f"{code} {a}{f4(p[0])} {b}{f4(p[1])} R{f4(-r if big else r)}")
            else:
                lines.append(f"{code} {a}{f4(p[0])} {b}{f4(p[1])} {ca}{f4(cx - cur[0])} "
                             f"{cb}{f4(cy - cur[1])}")
        else:
            g = "G0" if rng.random() < 0.1 else "G1"
            lines.append(f"{g} {a}{f4(p[0])} {b}{f4(p[1])}")
        if rng.random() < 0.1:
            lines.append(f"G1 {nrm}{f4(-0.15 * scale)}")
        if rng.random() < 0.05:
            lines.append(f"G4 P{f4(rng.uniform(0, 1))}")
        cur = p
    ex = 1.6 * scale * math.cos(ang + 0.5)
    ey = 1.6 * scale * math.sin(ang + 0.5)
    lines += [f"G40 G1 {a}{f4(ex)} {b}{f4(ey)}", f"G0 {nrm}{f4(0.2 * scale)}", "G17", "M2"]
    return "\n".join(lines) + "\n", tools


def arc_program(seed: int) -> tuple[str, list[ToolEntry]]:
    """Random arcs (I/J/K, R, P turns, helices, absolute centers) in G17/G18/G19."""
    rng = random.Random(seed)
    metric = rng.random() < 0.5
    s = 20.0 if metric else 1.0
    lines = ["G21" if metric else "G20", "F100" if metric else "F5"]
    pos = [0.0, 0.0, 0.0]
    lines.append("G0 X0 Y0 Z0")
    for _ in range(rng.randint(3, 10)):
        plane = rng.choice(["G17", "G18", "G19"])
        a1, a2, an = {"G17": (0, 1, 2), "G18": (2, 0, 1), "G19": (1, 2, 0)}[plane]
        letters = {0: "X", 1: "Y", 2: "Z"}
        cen = {0: "I", 1: "J", 2: "K"}
        r = rng.uniform(0.1, 1.0) * s
        t0 = rng.uniform(0, 2 * math.pi)
        c1 = pos[a1] - r * math.cos(t0)
        c2 = pos[a2] - r * math.sin(t0)
        t1 = t0 + rng.uniform(-2 * math.pi, 2 * math.pi)
        end = list(pos)
        end[a1] = c1 + r * math.cos(t1)
        end[a2] = c2 + r * math.sin(t1)
        if rng.random() < 0.4:
            end[an] = pos[an] + rng.uniform(-0.5, 0.5) * s
        code = rng.choice(["G2", "G3"])
        words = [plane, code] + [f"{letters[k]}{f4(end[k])}" for k in (a1, a2, an)]
        form = rng.random()
        if form < 0.5:
            words += [f"{cen[a1]}{f4(c1 - pos[a1])}", f"{cen[a2]}{f4(c2 - pos[a2])}"]
            if rng.random() < 0.3:
                words.append(f"P{rng.randint(1, 3)}")
        elif form < 0.7:
            words = ["G90.1"] + words + [f"{cen[a1]}{f4(c1)}", f"{cen[a2]}{f4(c2)}", "G91.1"]
            words = words[:-1] + ["\nG91.1"]
        else:
            words.append(f"R{f4(rng.choice([-1, 1]) * r)}")
        lines.append(" ".join(words))
        pos = [float(f4(v)) for v in end]
        if rng.random() < 0.3:
            pos = [rng.uniform(-1, 1) * s for _ in range(3)]
            lines.append(f"G0 X{f4(pos[0])} Y{f4(pos[1])} Z{f4(pos[2])}")
            pos = [float(f4(v)) for v in pos]
    lines.append("M2")
    return "\n".join(lines) + "\n", []


def cycle_program(seed: int) -> tuple[str, list[ToolEntry]]:
    """Random canned cycles G81 G82 G83 G73 G85 G89 with G98/G99, G90/G91, L, planes."""
    rng = random.Random(seed)
    metric = rng.random() < 0.6
    s = 10.0 if metric else 0.5
    plane = rng.choice(["G17", "G17", "G18", "G19"])
    lines = ["G21" if metric else "G20", "F200" if metric else "F8", plane,
             f"G0 X0 Y0 Z{f4(rng.uniform(0.5, 2) * s)}"]
    normal = {"G17": "Z", "G18": "Y", "G19": "X"}[plane]
    inplane = [a for a in "XYZ" if a != normal]
    for _ in range(rng.randint(2, 6)):
        code = rng.choice(["G81", "G82", "G83", "G73", "G85", "G89"])
        words = [rng.choice(["G98", "G99", ""]), rng.choice(["G90", "G90", "G91"]), code]
        inc = "G91" in words
        for a in inplane:
            if rng.random() < 0.8:
                words.append(f"{a}{f4(rng.uniform(-1, 1) * s)}")
        if inc:
            words.append(f"R{f4(rng.uniform(-1, 0.5) * s)}")
            words.append(f"{normal}{f4(-rng.uniform(0.1, 1.5) * s)}")
        else:
            r = rng.uniform(-0.2, 1.2) * s
            words.append(f"R{f4(r)}")
            words.append(f"{normal}{f4(r - rng.uniform(0.05, 1.5) * s)}")
        if code in ("G83", "G73"):
            words.append(f"Q{f4(rng.uniform(0.1, 0.6) * s)}")
        if code in ("G82", "G89"):
            words.append(f"P{f4(rng.uniform(0, 1))}")
        if rng.random() < 0.3:
            words.append(f"L{rng.randint(1, 4)}")
        lines.append(" ".join(w for w in words if w))
        if rng.random() < 0.4:
            lines.append(" ".join(f"{a}{f4(rng.uniform(-1, 1) * s)}" for a in inplane))
        if rng.random() < 0.3:
            lines.append(f"G80 G90 G0 {normal}{f4(rng.uniform(0, 2) * s)}")
    lines += ["G80", "M2"]
    return "\n".join(lines) + "\n", []


GENERATORS = ([("contour", contour_program, i) for i in range(N_CONTOURS)]
              + [("arcs", arc_program, i) for i in range(N_ARCS)]
              + [("cycles", cycle_program, i) for i in range(N_CYCLES)])


@pytest.mark.parametrize("kind,gen,i", GENERATORS, ids=[f"{k}{i}" for k, _, i in GENERATORS])
def test_generated_program_same_as_rs274(rs274, kind, gen, i):
    seed = BASE_SEED * 1000 + i
    text, tools = gen(seed)
    c = differential(text, tools or None, machine_units="inch")
    assert c.same, (f"{kind} program, seed {seed} (MILLPATH_SEED={BASE_SEED}):\n{text}\n{c}")


def test_generators_exercise_both_outcomes():
    """Most contours run cleanly; some hit LinuxCNC's compensation errors."""
    from millpath.interpret import run
    ok = err = 0
    for i in range(60):
        text, tools = contour_program(BASE_SEED * 1000 + i)
        r = run(text, tools)
        if r.error is None:
            ok += 1
        else:
            err += 1
    assert ok >= 20
