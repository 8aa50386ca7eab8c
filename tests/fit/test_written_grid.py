"""The fitter works on the points as the post writes them, so a fitted arc's centre is
the one LinuxCNC takes (start + I J as written).

An arc that starts where a planner left the tool on a half step of the grid (27.00625 mm
with 4 decimals) is the hard case: a start rounded one step away from the written one
turns the written chord, and on a short chord of a large radius the post's centre (on
that chord's bisector) moves by many grid steps.

Truth: Python's decimal formatting (the post's text), LinuxCNC's rs274 reading the
posted program, and the circle the points were taken from."""

from __future__ import annotations

import math

import numpy as np
import pytest

from millpath.fit import fit_toolpath
from millpath.model import Tool
from millpath.model.toolpath import Operation, Toolpath
from millpath.model.units import as_written, default
from millpath.post.writer import post_with_lines
from support.rs274 import run_rs274
from millpath.verify.roundtrip import compare_toolpath

TOOLS = {1: Tool(1, diameter=6.0)}
FIT_TOL = 0.005                                 # mm
START = (27.00625, 63.75625)                    # half steps of the 4-decimal grid (mm)


@pytest.mark.parametrize("decimals", [4, 5])
def test_as_written_is_the_posts_text(decimals):
    rng = np.random.default_rng(7)
    q = 10.0 ** -decimals
    k = rng.integers(-10**8, 10**8, 4000)
    values = np.concatenate([
        (k + 0.5) * q,                          # half steps, as a planner's links land
        (k + 0.5) * q + rng.uniform(-1e-12, 1e-12, len(k)),
        rng.uniform(-500.0, 500.0, 4000),
        [0.0, -0.0, -0.4 * q, 27.00625, 63.75625, 35.63125, 12.38125]])
    want = np.array([float(format(v, f".{decimals}f")) for v in values])
    got = as_written(values, decimals)
    assert np.array_equal(got, want)
    assert not np.any(np.signbit(got[got == 0.0]))
    assert as_written(np.array([[27.00625, 63.75625]]), 4).tolist() == [[27.0063, 63.7563]]


def _half_step_arc(radius: float) -> tuple[Toolpath, tuple[float, float]]:
    """A line to START, then 12 points on a circle of ``radius`` (mm) through START,
    0.7 mm of chord counter-clockwise; returns the toolpath and the circle's centre."""
    cx, cy = START[0] + radius, START[1]
    tp = Toolpath(units="mm")
    tp.begin(Operation("test", "test", 1, spindle=10000))
    tp.rapid(START[0] - 5.0, START[1], 5.0)
    tp.line(START[0] - 5.0, START[1], -1.0, 300.0)
    tp.line(START[0], START[1], -1.0, 800.0)
    for t in np.linspace(0.0, 0.7 / radius, 12)[1:]:
        tp.line(cx - radius * math.cos(t), cy - radius * math.sin(t), -1.0, 800.0)
    tp.rapid(tp.moves[-1].end[0], tp.moves[-1].end[1], 5.0)
    return tp, (cx, cy)


@pytest.mark.rs274
@pytest.mark.parametrize("radius", [3.3, 9.0])
def test_arc_from_a_half_step_start_is_written_with_its_planned_centre(rs274, radius):
    tp, (cx, cy) = _half_step_arc(radius)
    fitted = fit_toolpath(tp, FIT_TOL)
    arcs = [i for i, m in enumerate(fitted.moves) if m.kind == "arc"]
    assert len(arcs) == 1
    program, lines = post_with_lines(fitted, TOOLS)
    res = run_rs274(program, TOOLS)
    assert res.ok, res.error
    plan = fitted.moves[arcs[0]]
    got = [m for m in res.motions if m.line == lines[arcs[0]]]
    assert [m.kind for m in got] == ["arc"]
    arc = got[0]
    # LinuxCNC's centre is the planned one (rs274 prints 4 decimals: exact on the grid)
    tol = default("roundtrip", "mm")
    assert math.dist(arc.center[:2], plan.center[:2]) <= tol
    assert compare_toolpath(fitted, lines, res.motions, tol) == []
    # and the arc LinuxCNC moves stays within the fit tolerance of the true circle
    a0 = math.atan2(arc.start[1] - arc.center[1], arc.start[0] - arc.center[0])
    a1 = math.atan2(arc.end[1] - arc.center[1], arc.end[0] - arc.center[0])
    r0 = math.dist(arc.start[:2], arc.center[:2])
    r1 = math.dist(arc.end[:2], arc.center[:2])
    sweep = (a1 - a0) % (2 * math.pi)
    for u in np.linspace(0.0, 1.0, 101):
        r, a = r0 + (r1 - r0) * u, a0 + sweep * u
        x, y = arc.center[0] + r * math.cos(a), arc.center[1] + r * math.sin(a)
        assert abs(math.hypot(x - cx, y - cy) - radius) <= FIT_TOL
