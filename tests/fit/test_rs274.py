"""LinuxCNC's rs274 accepts fitted programs and moves within tolerance of the original."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings, strategies as st

from millpath.fit import fit_program, fit_toolpath
from millpath.model import Tool
from millpath.model.toolpath import Move, Operation, Toolpath

pytestmark = pytest.mark.rs274

TOOLS = {1: Tool(1, diameter=6.0)}


def motion_moves(motions):
    """rs274 motions as (start, [Move]) for sampling (traverses and feeds as lines)."""
    out = []
    for m in motions:
        if m.kind in ("feed", "traverse"):
            out.append(Move("line", m.end))
        elif m.kind == "arc":
            out.append(Move("arc", m.end, center=m.center, plane=m.plane,
                            clockwise=m.rotation < 0, turns=abs(m.rotation)))
        elif m.kind in ("nurbs", "cubic"):
            out.append(None)
    return out


def feed_path(motions):
    """Start and moves of the feed motion after the first plunge (rs274 motions)."""
    feeds = [m for m in motions if m.kind != "traverse"]
    return feeds[0].start, motion_moves(feeds)


def toolpath_from(P, units="mm"):
    tp = Toolpath(units=units)
    tp.begin(Operation("contour", "c", 1, spindle=10000))
    tp.rapid(P[0][0], P[0][1], 5.0)
    tp.line(*P[0], 200.0)
    for p in P[1:]:
        tp.line(*p, 800.0)
    tp.rapid(P[-1][0], P[-1][1], 5.0)
    return tp


def shapes(rng):
    t = np.linspace(0, 2 * math.pi, 721)
    yield "circle", np.column_stack([12 * np.cos(t), 12 * np.sin(t), np.full_like(t, -1.0)])
    yield "helix", np.column_stack([4 * np.cos(3 * t), 4 * np.sin(3 * t), -t / 3])
    x = np.linspace(-10, 10, 401)
    yield "profile", np.column_stack([x, np.full_like(x, 2.0), 3 * np.cos(x / 4)])
    yield "yz", np.column_stack([np.full_like(x, 1.0), x, 2 * np.sin(x / 3)])
    yield "noisy", np.column_stack([x, 5 * np.sin(x / 5) + rng.uniform(-0.002, 0.002, len(x)),
                                    np.full_like(x, -2.0)])


def test_rs274_runs_fitted_toolpaths_within_tolerance(rs274, fitkit):
    from millpath.post.writer import post
    from support.rs274 import run_rs274
    rng = np.random.default_rng(3)
    tol = 0.005
    for name, P in shapes(rng):
        tp = toolpath_from([tuple(p) for p in P])
        fitted = fit_toolpath(tp, tol, "arcs", min_radius=3.0)
        assert fitted.counts()["arc"] > 0, name
        r0 = run_rs274(post(tp, TOOLS), TOOLS)
        r1 = run_rs274(post(fitted, TOOLS), TOOLS)
        assert r0.ok and r1.ok, (name, r1.error, r1.error_block)
        s0, m0 = feed_path(r0.motions)
        s1, m1 = feed_path(r1.motions)
        assert np.allclose(s0, s1)
        h = fitkit.hausdorff(s0, m0, m1, tol / 4)
        assert h <= tol, (name, h)
        assert len(m1) * 4 < len(m0), name


def test_rs274_accepts_cubic_programs(rs274):
    from millpath.post.writer import post
    from support.rs274 import run_rs274
    t = np.linspace(0, 6 * math.pi, 900)
    P = np.column_stack([t * 2, 3 * np.sin(t) * np.exp(-t / 10), np.full_like(t, -1.0)])
    fitted = fit_toolpath(toolpath_from([tuple(p) for p in P]), 0.005, "arcs+cubics")
    r = run_rs274(post(fitted, TOOLS), TOOLS)
    assert r.ok, (r.error, r.error_block)
    ends = [m.end for m in r.motions if m.kind != "traverse"]
    assert np.allclose(ends[-1], np.round(P[-1], 4), atol=1e-4)


@settings(max_examples=16, deadline=None, derandomize=True,
          suppress_health_check=[HealthCheck.too_slow, HealthCheck.function_scoped_fixture])
@given(seed=st.integers(0, 2**32 - 1), tol=st.floats(0.002, 0.05),
       plane=st.sampled_from(["XY", "XZ", "YZ", "helix"]),
       mode=st.sampled_from(["arcs", "arcs+cubics"]))
def test_rs274_accepts_every_fitted_program(rs274, fitkit, seed, tol, plane, mode):
    from support.rs274 import run_rs274
    rng = np.random.default_rng(seed)
    n = 300
    t = np.cumsum(rng.uniform(0.02, 0.3, n))
    w = sum(rng.uniform(0.2, 4) * np.sin(t / rng.uniform(0.5, 10) + rng.uniform(0, 6))
            for _ in range(2))
    w = w + rng.uniform(-1, 1, n) * rng.uniform(0, 2) * tol
    if plane == "XY":
        P = np.column_stack([t, w, np.full(n, -1.0)])
    elif plane == "XZ":
        P = np.column_stack([t, np.full(n, 1.0), w])
    elif plane == "YZ":
        P = np.column_stack([np.full(n, 1.0), t, w])
    else:
        r = rng.uniform(0.5, 20)
        P = np.column_stack([r * np.cos(t / r), r * np.sin(t / r), -t * rng.uniform(0, 0.2)])
    lines = ["G21 G90 G17 G94", "G0 X{:.4f} Y{:.4f} Z5".format(*P[0, :2]),
             "G1 Z{:.4f} F200".format(P[0, 2]), "F800"]
    lines += ["G1 X{:.4f} Y{:.4f} Z{:.4f}".format(*p) for p in P[1:]]
    lines += ["G0 Z5", "M2"]
    src = "\n".join(lines) + "\n"
    out = fit_program(src, tol, mode)
    r0 = run_rs274(src)
    r1 = run_rs274(out)
    assert r0.ok and r1.ok, (r1.error, r1.error_block)
    if mode == "arcs":          # rs274 reports G5 without its control points
        s0, m0 = feed_path(r0.motions)
        s1, m1 = feed_path(r1.motions)
        assert fitkit.hausdorff(s0, m0, m1, tol / 4) <= tol * 1.002


def test_rs274_accepts_fit_program_cubics_in_a_row(rs274):
    from support.rs274 import run_rs274
    t = np.linspace(0.5, 6 * math.pi, 1200)
    lines = ["G21 G90 G18 G94", "G0 X0 Y0 Z5", "G1 Z-1 F200", "F900"]
    lines += [f"G1 X{a * math.cos(a):.4f} Y{0.5 * a * math.sin(a):.4f}" for a in t]
    lines += ["X0 Y0", "G0 Z5", "M2"]
    src = "\n".join(lines) + "\n"
    out = fit_program(src, 0.005, "arcs+cubics")
    g5 = [l for l in out.splitlines() if l.startswith(("G5", "G17 G5"))]
    assert len(g5) >= 3
    ol = out.splitlines()
    assert "G18" in ol[ol.index(g5[-1]):ol.index("G0 Z5")]     # the plane comes back
    r = run_rs274(out)
    assert r.ok, (r.error, r.error_block)
    assert sum(m.kind == "nurbs" for m in r.motions) == len(g5)
