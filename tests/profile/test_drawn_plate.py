"""profile on a drawn plate: every contour cut on its air side, proven against the part.

Truth: the plate the test draws with ezdxf (tests/support/plates.py: lines, arcs,
circles and an ellipse, measured analytically), not the reader's polygons. Checked: the
design's walls against the drawn contours (within 1/20 of the tolerance, on the air
side), the interpreted program's tool centre against them (a tool radius away on the air
side, within the proof's allowance; each wall reached at the bottom), and the figures of
report.json (within the operation's tolerance and the fit tolerance)."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

from millpath.errors import MillpathError
from millpath.interpret import interpret
from millpath.io.schema import validate
from millpath.job.jobfile import load_job
from millpath.model import Machine, Stock, Tool
from millpath.pipeline import plan_job, run_job
from millpath.plan.base import PlanContext
from millpath.plan.profile import operation as profile
from millpath.plan.twod.contours import classify
from support import plates

TOL = 0.01                 # the operation's default tolerance, mm
FIT = 0.005                # the job's fit tolerance, mm
R = 2.0                    # tool radius, mm
EPS = 1e-6

JOB = """units = "mm"
name = "plate"
fit = "{fit}"
fit_tolerance = {fit_tol}
[stock]
box = [-10, -10, -10, 130, 90, 0]
[[tools]]
number = 1
type = "flat"
diameter = 4.0
flute_length = 15.0
stickout = 25.0
[[operations]]
type = "profile"
tool = 1
dxf = "plate.dxf"
depth = {depth}
stepdown = 5.0
feed = 800.0
spindle = 12000
{extra}
"""


def _job(tmp_path: Path, depth=10.0, fit="arcs", extra="") -> Path:
    plates.write(plates.plate(), tmp_path / "plate.dxf")
    p = tmp_path / "job.toml"
    p.write_text(JOB.format(depth=depth, fit=fit, fit_tol=FIT, extra=extra))
    return p


def _samples(motions, step=0.2):
    """Points (n, 3) along the interpreted feed motions (lines and XY arcs)."""
    out = []
    for m in motions:
        if m.kind not in ("feed", "arc"):
            continue
        a, b = np.asarray(m.start), np.asarray(m.end)
        if m.kind == "feed":
            n = max(1, int(math.ceil(np.linalg.norm(b - a) / step)))
            out.append(a + np.linspace(0, 1, n + 1)[:, None] * (b - a))
            continue
        assert m.plane == "XY"
        c = np.asarray(m.center)
        r = math.hypot(*(a - c)[:2])
        t0 = math.atan2(*(a - c)[1::-1])
        t1 = math.atan2(*(b - c)[1::-1])
        turn = 1 if m.rotation > 0 else -1
        sw = (t1 - t0) % (2 * math.pi) if turn > 0 else -((t0 - t1) % (2 * math.pi))
        if abs(sw) < 1e-12:
            sw = turn * 2 * math.pi
        sw += turn * 2 * math.pi * (abs(m.rotation) - 1)
        n = max(8, int(math.ceil(abs(sw) * r / step)))
        t = t0 + sw * np.linspace(0, 1, n + 1)
        z = a[2] + (b[2] - a[2]) * np.linspace(0, 1, n + 1)
        out.append(np.column_stack([c[0] + r * np.cos(t), c[1] + r * np.sin(t), z]))
    return np.vstack(out)


def test_plate_profiled_outside_with_every_hole_and_slot_inside(tmp_path):
    job = _job(tmp_path)
    res = run_job(job, tmp_path / "out", pictures=False)
    rep = res.report
    assert rep["safety"]["status"] == "ok"
    assert (tmp_path / "out" / "program.ngc").is_file()
    contours = plates.plate()
    # every contour chosen, each on its air side, recognised by kind
    cut = rep["plans"][0]["profile"]["contours"]
    assert len(cut) == len(contours) == 12
    assert sorted(c["side"] for c in cut) == ["inside"] * 11 + ["outside"]
    kinds = sorted(c["kind"] for c in cut)
    assert kinds == ["circle"] * 7 + ["other"] * 2 + ["slot"] * 3
    # the proof ran against this operation's design and found it within the tolerances
    ver = rep["verification"]
    assert ver["reference"] == "operations[0] design"
    assert ver["max_gouge"] is not None and ver["max_gouge"] <= TOL + FIT
    assert ver["max_left"] is not None and ver["max_left"] <= TOL + FIT

    # the program's tool centre, below the top: a radius away from every drawn contour,
    # on its air side (outside the outline, inside a hole)
    j = load_job(job)
    prog = (tmp_path / "out" / "program.ngc").read_text()
    p = _samples(interpret(prog, j.tools, machine_units="mm"))
    p = p[p[:, 2] < -1e-6]
    sd = np.column_stack([plates.signed_distance(c, p[:, :2]) for c in contours])
    allowed = TOL + FIT
    outside = sd[:, 0] >= R - allowed
    in_hole = (-sd[:, 1:] >= R - allowed).any(axis=1)
    assert np.all(outside | in_hole), p[~(outside | in_hole)][:5]
    # every wall reached all round at the bottom: each point of a drawn contour has a
    # tool centre a radius away (within 0.05 mm: chords of the samples, the fit)
    bottom = p[np.abs(p[:, 2] + 10.0) < 1e-6]
    assert len(bottom)
    from scipy.spatial import cKDTree
    tree = cKDTree(bottom[:, :2])
    for k, c in enumerate(contours):
        pts = np.vstack([plates._piece_points(q, 0.5) for q in c.pieces])
        d, _ = tree.query(pts)
        assert d.max() <= R + 0.1, (c.name, d.max())

    # the design's walls follow the drawn contours within 1/20 of the tolerance, on
    # their air side
    design = plan_job(j)[1][0].design
    tri = design.mesh(j.stock.box)
    n = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    wall = tri[np.abs(n[:, 2]) <= 1e-9 * np.linalg.norm(n, axis=1)]
    w = np.concatenate([wall.reshape(-1, 3)] + [(wall[:, i] + wall[:, (i + 1) % 3]) / 2
                                                for i in range(3)])[:, :2]
    sdw = np.column_stack([plates.signed_distance(c, w) for c in contours])
    near = np.argmin(np.abs(sdw), axis=1)
    d = sdw[np.arange(len(w)), near]
    air = np.where(near == 0, d, -d)            # outside the outline, inside the holes
    assert air.min() >= -EPS and air.max() <= TOL / 20 + EPS, (air.min(), air.max())
    assert set(near) == set(range(len(contours)))          # a wall on every contour


def test_profile_deeper_than_the_stock_is_refused_naming_the_key(tmp_path):
    job = _job(tmp_path, depth=12.0)
    with pytest.raises(MillpathError, match=r"operations\[0\]\.depth: 12 below z 0 reaches "
                                            r"z -12, 2 below the stock bottom"):
        run_job(job, tmp_path / "out", pictures=False)
    assert not (tmp_path / "out" / "program.ngc").exists()
    # a cut through by less than the break-through is planned
    plan_job(load_job(_job(tmp_path, depth=10.5)))


def _plan(tmp_path, **keys):
    plates.write(plates.plate(), tmp_path / "plate.dxf")
    ctx = PlanContext("mm", Stock(-10, -10, -10, 130, 90, 0), Machine(),
                      {1: Tool(1, "flat", 4.0), 2: Tool(2, "flat", 8.0)}, tmp_path)
    base = {"tool": 1, "dxf": str(tmp_path / "plate.dxf"), "depth": 10.0, "stepdown": 10.0,
            "feed": 800.0}
    return profile.plan(ctx, validate({**base, **keys}, profile.PARAMS, "op", None))


def _names(res):
    return sorted((c["kind"], round(c["width"], 1)) for c in res.report["profile"]["contours"])


def test_contours_chosen_by_role_kind_size_and_layer(tmp_path):
    assert _names(_plan(tmp_path, contours="outer")) == [("other", 80.0)]
    assert _names(_plan(tmp_path, contours="inner", kinds=["circle"], min_size=8.0)) == [
        ("circle", 10.0), ("circle", 10.0), ("circle", 19.0)]
    assert _names(_plan(tmp_path, kinds=["slot"], max_size=9.0)) == [("slot", 8.0)] * 3
    assert _names(_plan(tmp_path, contour_layer="holes")) == (
        [("circle", 6.6)] * 4 + [("circle", 10.0)] * 2)
    # chosen by layer, a hole keeps its side: the part is every contour read
    res = _plan(tmp_path, contour_layer="BORE")
    assert [c["side"] for c in res.report["profile"]["contours"]] == ["inside"]
    with pytest.raises(MillpathError, match="no contour of the drawing is chosen"):
        _plan(tmp_path, kinds=["slot"], min_size=9.0)


def test_kinds_of_the_drawn_contours():
    import shapely
    for c in plates.plate():
        poly = plates.polygon(c, 0.05)
        kind, width, _ = classify(shapely.geometry.polygon.orient(poly, 1.0), TOL)
        assert kind == {"circle": "circle", "slot": "slot"}.get(c.kind, "other"), c.name
        if c.kind in ("circle", "slot"):
            assert width == pytest.approx(c.width, abs=TOL)


def test_tool_too_wide_for_a_hole_names_it(tmp_path):
    with pytest.raises(MillpathError, match=r"tool 2 \(diameter 8\) does not fit inside the "
                                            r"contour entity \w+ \(a circle 6\.6 wide round "
                                            r"\(10\.000, 10\.000\)\)"):
        _plan(tmp_path, tool=2)
    # chosen by size, the wide holes are cut
    _plan(tmp_path, tool=2, contours="inner", min_size=10.0)


def test_side_inside_cuts_an_opening_and_its_islands(tmp_path):
    """side = "inside": the outline is an opening's wall, the holes islands in it."""
    res = _plan(tmp_path, side="inside", contours="all", kinds=["circle"], min_size=10.0)
    assert [c["side"] for c in res.report["profile"]["contours"]] == ["outside"] * 3
    # the design is the opening's: material outside the outline and inside the islands
    h = res.design.height(np.array([-5.0, 60.0, 30.0]), np.array([40.0, 40.0, 40.0]))
    assert h[0] == 0.0 and h[1] == 0.0          # stock outside, the bore an island
    ring = plates.signed_distance(plates.plate()[7], np.array([[60.0 + 9.5 + 1.0, 40.0]]))
    assert ring[0] == pytest.approx(1.0, abs=1e-3)
    assert res.design.height(np.array([60.0 + 9.5 + 1.0]), np.array([40.0]))[0] == -np.inf


POCKET = """units = "mm"
name = "counterbores"
fit = "none"
[stock]
box = [-10, -10, -10, 130, 90, 0]
[[tools]]
number = 1
type = "flat"
diameter = 6.0
flute_length = 15.0
stickout = 25.0
[[operations]]
type = "pocket"
tool = 1
dxf = "plate.dxf"
{keys}
depth = 3.0
stepdown = 3.0
feed = 800.0
"""


def test_pocket_clears_inside_the_chosen_contours(tmp_path):
    """Counterbores in the bore and the 10 mm holes (circles 10 wide or more): each
    cleared inside its drawn circle, walls on the air side, proven against them."""
    plates.write(plates.plate(), tmp_path / "plate.dxf")
    job = tmp_path / "job.toml"
    job.write_text(POCKET.format(keys='kinds = ["circle"]\nmin_size = 10.0'))
    res = run_job(job, tmp_path / "out", pictures=False)
    assert res.report["safety"]["status"] == "ok"
    ver = res.report["verification"]
    assert ver["max_gouge"] <= TOL
    circles = [c for c in plates.plate() if c.kind == "circle" and c.width >= 10]
    assert len(circles) == 3
    j = load_job(job)
    design = plan_job(j)[1][0].design
    tri = design.mesh(j.stock.box)
    n = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    wall = tri[np.abs(n[:, 2]) <= 1e-9 * np.linalg.norm(n, axis=1)]
    w = wall.reshape(-1, 3)[:, :2]
    sd = np.column_stack([plates.signed_distance(c, w) for c in circles])
    near = np.argmin(np.abs(sd), axis=1)
    d = -sd[np.arange(len(w)), near]                 # inside each circle: the air
    assert d.min() >= -EPS and d.max() <= TOL / 20 + EPS, (d.min(), d.max())
    assert set(near) == {0, 1, 2}
    # the tool stays inside the circles, a radius in
    p = _samples(interpret(res.program, j.tools, machine_units="mm"))
    p = p[p[:, 2] < -1e-6]
    sdp = np.column_stack([plates.signed_distance(c, p[:, :2]) for c in circles])
    assert (-sdp >= 3.0 - TOL).any(axis=1).all()
