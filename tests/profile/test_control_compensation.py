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
from millpath.plan.profile.operation import followable, reachable
from millpath.verify.rs274 import run_rs274

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
    text, _ = post_job(job, fit_job(job, tp), stock)
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
    # shapely's own opening (on the air side) by r, finer
    if outside:
        ref = Polygon(P.buffer(r, quad_segs=256).exterior).buffer(-r, quad_segs=256)
        assert P.difference(f).area < P.length * eps        # the part stays inside
    else:
        ref = P.buffer(-r, quad_segs=256).buffer(r, quad_segs=256)
        assert f.difference(P).area < P.length * eps        # the opening stays inside
    assert f.symmetric_difference(ref).area < 2 * f.length * eps       # chords within eps
    assert f.hausdorff_distance(ref) < 25 * eps       # vertex to vertex (discrete)
    # the tool of radius r rolls along the whole contour: its centre path offset back
    # by r gives the contour again (no corner tighter than r on the air side)
    centre = f.buffer(r if outside else -r, quad_segs=256)
    again = centre.buffer(-r if outside else r, quad_segs=256)
    assert again.hausdorff_distance(f) < 25 * eps


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


@pytest.mark.xfail(strict=True, raises=MillpathError, reason=(
    "planner defect, open: the rounded corners' chords (about 0.06 mm, turning 0.014 rad) "
    "leave the control 0.0007 mm of slack where the post's rounding to 4 decimals can turn "
    "a chord enough to take 0.005 mm; here a 0.014 mm chord at (46.75, 56.68) is refused "
    "('Straight feed in concave corner cannot be reached')"))
def test_a_chord_made_short_by_the_posts_rounding_is_reachable_by_the_control(
        tmp_path, rs274):
    """A generated job: rounded to the post's decimals, a 0.014 mm chord where a rounded
    corner meets a wall turns enough that the control cannot reach its corner."""
    job = JOBS / "control_u_short_chord.toml"
    res = run_job(job, tmp_path / "out", pictures=False)
    assert res.report["safety"]["status"] == "ok"
    program = (tmp_path / "out" / "program.ngc").read_text()
    assert "G41" in program or "G42" in program
    r = run_rs274(program, load_job(job).tools)
    assert r.ok, r.error
