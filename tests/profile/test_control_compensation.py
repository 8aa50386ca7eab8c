"""Profiles with control compensation (G41/G42): the programmed contour is the one the
tool can follow (concave corners and narrow notches rounded to the tool radius plus
the wear margin), so the control accepts it."""

from pathlib import Path

import numpy as np
import pytest
import tomllib
from shapely.geometry import LineString, Point, Polygon

from millpath.errors import MillpathError
from millpath.interpret import interpret
from millpath.job.jobfile import load_job
from millpath.pipeline import fit_job, plan_job, post_job, run_job
from millpath.plan.profile.operation import FILLET_SEGS, followable, on_grain, reachable
from support.rs274 import run_rs274

JOBS = Path(__file__).parent / "jobs"


def _polygon(name):
    with open(JOBS / name, "rb") as fh:
        return Polygon(tomllib.load(fh)["operations"][0]["polygon"])


def test_star_with_a_notch_narrower_than_the_tool_runs_written_and_proven(tmp_path, rs274):
    job = JOBS / "control_star_notch.toml"
    res = run_job(job, tmp_path / "out", pictures=False)
    rep = res.report
    assert rep["safety"]["status"] == "ok"
    program = (tmp_path / "out" / "program.ngc").read_text()
    assert "G42" in program and "G40" in program
    v = rep["verification"]
    assert v["max_gouge"] <= 0.015          # the operation's tolerance (default 0.01) + proof
    r = run_rs274(program, load_job(job).tools)
    assert r.ok, r.error


def test_rounded_outline_inside_is_accepted_by_rs274_and_interpreted(rs274):
    """Planned, fitted and posted (the full proof of this job takes a minute and a half:
    bench/generated_jobs.py runs it)."""
    job = load_job(JOBS / "control_rounded_notch.toml")
    tp, _, stock = plan_job(job)
    text = post_job(job, fit_job(job, tp), stock).text
    assert "G41" in text
    r = run_rs274(text, job.tools)
    assert r.ok, r.error
    motions = interpret(text, job.tools, machine_units=job.units)
    # every feed of the tool centre keeps the tool out of the part (within tolerance)
    Q = _polygon("control_rounded_notch.toml")
    R = job.tools[14].radius
    worst = min(Q.exterior.distance(LineString([m.start[:2], m.end[:2]]))
                for m in motions if m.kind == "feed" and m.start[2] < 0 and m.end[2] < 0
                and m.start[:2] != m.end[:2] and Q.contains(Point(m.end[:2])))
    assert worst >= R - 0.0427


@pytest.mark.parametrize("name, outside, r", [("control_star_notch.toml", True, 6.1),
                                               ("control_rounded_notch.toml", False, 5.1)])
def test_followable_contour_is_the_opening_by_the_rounding_radius(name, outside, r):
    P = _polygon(name)
    eps = 1e-3
    f = followable(P, r, outside, eps)
    # the rounded corners' chords: GEOS splits a corner in equal parts of at most 1.5
    # quarter circles over the segments asked for
    sag = max(eps, r * (1 - np.cos(0.75 * np.pi / 2 / FILLET_SEGS[0])))
    # shapely's own opening (on the air side) by r, finer
    if outside:
        ref = Polygon(P.buffer(r, quad_segs=256).exterior).buffer(-r, quad_segs=256)
        assert P.difference(f).area < P.length * eps        # the part stays inside
    else:
        ref = P.buffer(-r, quad_segs=256).buffer(r, quad_segs=256)
        assert f.difference(P).area < P.length * eps        # the opening stays inside
    assert f.symmetric_difference(ref).area < 2 * f.length * sag       # chords within sag
    assert f.hausdorff_distance(ref) < 25 * eps + sag       # vertex to vertex (discrete)
    # a tool of the radius of the chords' inscribed circle rolls along the whole
    # contour: its centre path offset back gives the contour again (no corner tighter
    # than r on the air side but the chords')
    rr = r * np.cos(0.75 * np.pi / 2 / FILLET_SEGS[0])
    centre = f.buffer(rr if outside else -rr, quad_segs=256)
    again = centre.buffer(-rr if outside else rr, quad_segs=256)
    assert again.hausdorff_distance(f) < 25 * eps + sag


def test_reachable_drops_a_notch_the_tool_cannot_enter():
    # a square followed counter-clockwise with the tool on the left (inside) and a notch
    # 1 wide, 3 deep in its bottom edge: a tool of radius 2 cannot enter it
    ring = np.array([[0, 0], [4.5, 0], [4.5, -3], [5.5, -3], [5.5, 0], [10, 0], [10, 10],
                     [0, 10]], float)
    out = reachable(ring, 2.0, +1)
    assert len(out) < len(ring)
    # what is left never leaves the square's side of the notch (material left, not cut)
    assert all(q[1] >= -3 for q in out)
    assert reachable(out, 2.0, +1).shape == out.shape


def test_a_chord_made_short_by_the_posts_rounding_is_reachable_by_the_control(
        tmp_path, rs274):
    """A generated job: rounded to the post's decimals, a 0.014 mm chord where a rounded
    corner meets a wall turns enough that the control cannot reach its corner; the
    planner checks the contour as written, and drops that corner."""
    job = JOBS / "control_u_short_chord.toml"
    res = run_job(job, tmp_path / "out", pictures=False)
    assert res.report["safety"]["status"] == "ok"
    program = (tmp_path / "out" / "program.ngc").read_text()
    assert "G41" in program or "G42" in program
    r = run_rs274(program, load_job(job).tools)
    assert r.ok, r.error


def _fillet_square(rho: float, turns: list[float], side: float = 20.0) -> np.ndarray:
    """A square ``side`` wide followed counter-clockwise, each corner rounded by chords
    of a circle of radius ``rho`` turning by ``turns`` in turn (a quarter turn each)."""
    pts = []
    for k in range(4):
        a0 = k * np.pi / 2
        c = np.array([[side - rho, rho], [side - rho, side - rho], [rho, side - rho],
                      [rho, rho]])[k]
        a, j = a0 - np.pi / 2, 0
        pts.append(c + rho * np.array([np.cos(a), np.sin(a)]))
        while a < a0 - 1e-9:
            a = min(a + turns[j % len(turns)], a0)
            j += 1
            pts.append(c + rho * np.array([np.cos(a), np.sin(a)]))
    return np.array(pts)


def _compensated(ring: np.ndarray) -> str:
    """G41 D1 around ``ring`` (counter-clockwise: the tool inside), entered from
    inside at the middle of its longest segment."""
    k = int(np.argmax(np.hypot(*(np.roll(ring, -1, axis=0) - ring).T)))
    ring = np.roll(ring, -k, axis=0)
    m = (ring[0] + ring[1]) / 2
    t = (ring[1] - ring[0]) / np.hypot(*(ring[1] - ring[0]))
    a = m + 5 * np.array([-t[1], t[0]])
    lines = ["G21 G90 G17 G40", "T1 M6", "G43 H1", f"G0 X{a[0]:.4f} Y{a[1]:.4f} Z5",
             "G1 Z-1 F300", "G41 D1", f"G1 X{m[0]:.4f} Y{m[1]:.4f}"]
    for q in list(ring[1:]) + [ring[0], m]:
        lines.append(f"G1 X{q[0]:.4f} Y{q[1]:.4f}")
    lines += ["G40", f"G1 X{a[0]:.4f} Y{a[1]:.4f}", "G0 Z5", "M2"]
    return "\n".join(lines) + "\n"


@pytest.mark.parametrize("d", [3.0, 3.1])
def test_rounded_corners_are_reachable_by_the_control_as_written(rs274, d):
    """LinuxCNC takes a turn towards the tool under 0.05 rad as a tangent join (the next
    move starts where the last offset ended, r sin(turn) along it) and a larger one as
    a corner (r tan(turn / 2) back along each move). Corners rounded to 1.6 mm by
    chords turning 0.047 and 0.0505 rad in turn, written to 4 decimals, leave a tool of
    1.5 mm radius (turn x 0.1 mm) less room than the rounding takes: rs274 refuses
    them. The followable contour's corners (chords of FILLET_SEGS a quarter circle),
    checked as written, are accepted with nothing dropped, for the tool's radius and
    one of up to half the wear margin more; and stay on the tool's side of the drawn
    square (material left, never cut)."""
    from millpath.model import Tool
    tools = {1: Tool(1, "flat", d, flute_length=10, stickout=30)}
    fine = on_grain(_fillet_square(1.6, [0.047, 0.0505]), 1e-4)
    raw = run_rs274(_compensated(fine), tools)
    assert not raw.ok and "concave corner cannot be reached" in raw.error
    square = Polygon([(0, 0), (20, 0), (20, 20), (0, 20)])
    ring = on_grain(np.asarray(followable(square, 1.6, False, 1e-4).exterior.coords)[:-1], 1e-4)
    out = reachable(ring, 1.55, +1)
    assert len(out) == len(ring)
    r = run_rs274(_compensated(out), tools)
    assert r.ok, r.error
    assert Polygon(out).difference(square).area < 1e-9
