"""millpath's interpreter runs fitted programs (cubics included) within tolerance."""

from __future__ import annotations

import math

import numpy as np

from millpath.fit import fit_program, fit_toolpath
from millpath.model import Tool
from millpath.model.toolpath import Move, Operation, Toolpath

TOOLS = {1: Tool(1, diameter=6.0)}


def moves_of(motions):
    out = []
    for m in motions:
        if m.kind in ("feed", "traverse"):
            out.append(Move("line", m.end))
        elif m.kind == "arc":
            out.append(Move("arc", m.end, center=m.center, plane=m.plane,
                            clockwise=m.rotation < 0, turns=abs(m.rotation)))
        elif m.kind == "cubic":
            out.append(Move("cubic", m.end, c1=m.controls[0], c2=m.controls[1]))
    return out


def feed_part(motions):
    feeds = [m for m in motions if m.kind != "traverse"]
    return feeds[0].start, moves_of(feeds)


def test_interpreted_cubic_and_arc_programs_stay_within_tolerance(fitkit):
    from millpath.interpret import interpret
    from millpath.post.writer import post
    t = np.linspace(0, 6 * math.pi, 1500)
    shapes = {
        "spiral": np.column_stack([t * np.cos(t), 0.5 * t * np.sin(t), np.full_like(t, -1.0)]),
        "ellipse": np.column_stack([30 * np.cos(t / 3), 10 * np.sin(t / 3),
                                    np.full_like(t, -2.0)]),
        "profile": np.column_stack([t, np.full_like(t, 3.0), np.sin(t) * 2]),
    }
    tol = 0.005
    for name, P in shapes.items():
        tp = Toolpath(units="mm")
        tp.begin(Operation("c", "c", 1, spindle=9000))
        tp.rapid(P[0, 0], P[0, 1], 5.0)
        tp.line(*P[0], 200.0)
        for p in P[1:]:
            tp.line(*p, 900.0)
        fitted = fit_toolpath(tp, tol, "arcs+cubics")
        if name != "profile":
            assert fitted.counts()["cubic"] > 0, name
        m0 = interpret(post(tp, TOOLS), TOOLS, machine_units="mm")
        m1 = interpret(post(fitted, TOOLS), TOOLS, machine_units="mm")
        s0, a = feed_part(list(m0))
        s1, b = feed_part(list(m1))
        assert np.allclose(s0, s1)
        assert fitkit.hausdorff(s0, a, b, tol / 4) <= tol * 1.002, name


def test_fit_program_output_interprets_like_the_original(fitkit):
    from millpath.interpret import interpret
    t = np.linspace(0, 2 * math.pi, 800)
    lines = ["G21 G90 G17 G94", "G0 X20 Y0 Z5", "G1 Z-1 F200", "F900"]
    lines += [f"G1 X{20 * math.cos(a):.4f} Y{12 * math.sin(a):.4f}" for a in t[1:]]
    lines += [f"X{20 + 0.05 * k:.4f} Z{-1 - math.sin(k / 40):.4f}" for k in range(1, 300)]
    lines += ["G0 Z5", "M2"]
    src = "\n".join(lines) + "\n"
    out = fit_program(src, 0.005, "arcs+cubics")
    assert "G5 " in out and ("G18 G2" in out or "G18 G3" in out)
    s0, a = feed_part(list(interpret(src, machine_units="mm")))
    s1, b = feed_part(list(interpret(out, machine_units="mm")))
    assert fitkit.hausdorff(s0, a, b, 0.005 / 4) <= 0.005 * 1.002
