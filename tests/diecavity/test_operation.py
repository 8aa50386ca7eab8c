"""The die-cavity operation: the bundled examples, CAM vs control compensation,
LinuxCNC acceptance and simulated removal."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import shapely
from shapely.geometry import Polygon

import millpath
from millpath.errors import GeometryError, JobError
from millpath.job.jobfile import load_job
from millpath.plan.base import PlanContext
from millpath.plan.diecavity import operation as op
from millpath.report.document import plan_sections

EXAMPLES = Path(millpath.__file__).parent / "examples"


def _plan(name: str, **override):
    job = load_job(EXAMPLES / name / "job.toml")
    ctx = PlanContext(job.units, job.stock, job.machine, job.tools, job.base_dir, job.path)
    params = dict(job.operations[0][1])
    params.update(override)
    return job, op.plan(ctx, params)


@pytest.fixture(scope="module")
def published():
    return {c: _plan("die-published", compensation=c) for c in ("cam", "control")}


@pytest.fixture(scope="module")
def blanking():
    return {c: _plan("die-blanking", compensation=c) for c in ("cam", "control")}


def _finish_xy(motions, z):
    """(kind, end xy, centre xy) of the feed and arc motions at height z."""
    out = []
    for m in motions:
        if m.kind in ("feed", "arc") and abs(m.start[2] - z) < 1e-6 and abs(m.end[2] - z) < 1e-6:
            out.append((m.kind, np.array(m.end[:2]),
                        None if m.center is None else np.array(m.center[:2])))
    return out


def test_params_keys_are_the_issue_keys():
    assert set(op.PARAMS) == {"tool", "points", "points_file", "close", "tolerance", "depth",
                              "stepdown", "allowance", "stepover", "compensation", "entry", "feed",
                              "plunge_feed", "spindle", "safe_z", "breakthrough"}


def test_published_example_reports_the_curve_and_eight_layers(published):
    job, res = published["cam"]
    rep = res.report["curve"]
    assert [s["kind"] for s in rep["segments"]] == ["given", "blend", "given"]
    assert rep["tolerance"] == 0.00004
    assert all(s["max_deviation"] <= 0.00004 for s in rep["segments"])
    assert rep["chords"] < rep["uniform_chords"]
    assert len(rep["layers"]) == 8 and rep["layers"][-1] == pytest.approx(30.0)
    assert not rep["through"]
    # the sharp tip at (60, 340) (scaled published (1, 15)) is out of the tool's reach
    assert rep["unreachable_corners"]
    tip = min(rep["unreachable_corners"],
              key=lambda c: np.hypot(c["at"][0] - 60, c["at"][1] - 340))
    assert np.hypot(tip["at"][0] - 60, tip["at"][1] - 340) < 20
    res.toolpath.check_finite()
    # a sensible size: the finishing lap is one line per programmed point
    assert len(res.toolpath) < 60_000


def test_design_is_stock_top_outside_and_floor_inside(published, blanking):
    _, res = published["cam"]
    h = res.design.height(np.array([200.0, 5.0]), np.array([250.0, 5.0]))
    assert h.tolist() == [30.0, 50.0]
    _, res = blanking["cam"]
    h = res.design.height(np.array([80.0, 1.0]), np.array([60.0, 1.0]))
    assert h[0] == -np.inf and h[1] == 12.0
    assert res.report["curve"]["through"]
    assert res.report["curve"]["layers"][-1] == pytest.approx(-1.0)     # breakthrough 1


def test_blanking_example_reports_corners_tighter_than_the_tool(blanking):
    _, res = blanking["cam"]
    rep = res.report["curve"]
    assert sum(len(s["points"]) for s in rep["segments"] if s["kind"] == "given") >= 20
    corners = [c["at"] for c in rep["unreachable_corners"]]
    for sharp in ([110, 20], [100, 112], [20, 20]):
        assert min(np.hypot(c[0] - sharp[0], c[1] - sharp[1]) for c in corners) < 5
    assert any(0 < t["min_radius"] < 5.0 for t in rep["tight_curvature"])
    for j in rep["junctions"]:
        if "blend" in j["kinds"]:
            assert j["position_gap"] <= 1e-9 and j["derivative_gap"] <= 1e-9


@pytest.mark.parametrize("example", ["published", "blanking"])
def test_control_compensation_interprets_like_the_cam_offset(example, published, blanking):
    from millpath.interpret import interpret
    from millpath.post.writer import post
    pair = published if example == "published" else blanking
    job = pair["cam"][0]
    motions = {}
    for c in ("cam", "control"):
        prog = post(pair[c][1].toolpath, job.tools, title=c)
        assert ("G41 D1" in prog) == (c == "control")
        motions[c] = interpret(prog, job.tools, machine_units=job.units)
    z = pair["cam"][1].report["curve"]["layers"][0]
    a, b = _finish_xy(motions["cam"], z), _finish_xy(motions["control"], z)
    assert len(a) == len(b) > 100
    assert [k for k, _, _ in a] == [k for k, _, _ in b]
    worst = max(float(np.abs(p - q).max()) for (_, p, _), (_, q, _) in zip(a, b))
    assert worst <= 1e-4
    for (k, _, c1), (_, _, c2) in zip(a, b):
        if k == "arc":
            assert np.abs(c1 - c2).max() <= 1e-4


@pytest.mark.parametrize("comp", ["cam", "control"])
def test_programs_are_accepted_by_rs274(rs274, blanking, comp):
    from millpath.post.writer import post
    from support.rs274 import run_rs274
    job, res = blanking[comp]
    r = run_rs274(post(res.toolpath, job.tools), job.tools)
    assert r.ok, (r.error, r.error_line)
    assert len(r.motions) > 1000


def test_rs274_compensates_the_control_variant_like_the_cam_offset(rs274, published):
    from millpath.post.writer import post
    from support.rs274 import run_rs274
    job = published["cam"][0]
    got = {}
    for c in ("cam", "control"):
        tp = published[c][1].toolpath
        r = run_rs274(post(tp, job.tools), job.tools)
        assert r.ok, (r.error, r.error_line)
        got[c] = _finish_xy(r.motions, published[c][1].report["curve"]["layers"][0])
    a, b = got["cam"], got["control"]
    assert len(a) == len(b) > 1000
    # rs274 prints 4 decimals: each side carries up to 0.00005 of rounding
    assert max(float(np.abs(p - q).max()) for (_, p, _), (_, q, _) in zip(a, b)) <= 1.5e-4


@pytest.mark.parametrize("example,res_xy", [("blanking", 0.25), ("published", 1.0)])
def test_simulated_wall_follows_the_curve_without_gouge(example, res_xy, blanking, published):
    from millpath.part.curve.blend import build_curve
    from millpath.part.curve.points import points_from_params
    from millpath.simulate import simulate_toolpath
    job, res = (blanking if example == "blanking" else published)["cam"]
    params = job.operations[0][1]
    tol = params["tolerance"]
    sim = simulate_toolpath(res.toolpath, job.tools, job.stock, resolution=res_xy,
                            design=res.design, machine=job.machine)
    assert sim.rapids_through_material == 0
    zm = sim.zmap
    X, Y = np.meshgrid(zm.xs(), zm.ys())
    curve = build_curve(points_from_params(params["points"], params["points_file"]))
    true = Polygon(curve.sample(2000))
    if not true.is_valid:            # the published tip crosses itself in a tiny loop
        true = max(shapely.make_valid(true).geoms, key=lambda g: g.area)
    shapely.prepare(true)
    inside = shapely.contains_xy(true, X, Y)
    cut = zm.heights < job.stock.zmax - 1e-6
    floor = res.report["curve"]["layers"][-1]
    through = zm.heights <= max(floor, job.stock.zmin) + 1e-6
    # never inside the wall: no cut cell centre further outside the true curve than
    # the tolerance; the published tolerance (0.00004 mm) is below the program's
    # number grid (0.0001 mm): there the chords within the tolerance, each point moved
    # by the grid's rounding
    bound = tol if example == "blanking" else tol + 0.0001
    bad = cut & ~inside
    if bad.any():
        d = shapely.distance(true.exterior, shapely.points(X[bad], Y[bad]))
        assert d.max() <= bound + 1e-6
    # the wall is within T + resolution of the curve wherever the tool can reach
    r = job.tools[1].radius
    reach = true.buffer(-r).buffer(r, quad_segs=64).buffer(-(tol + res_xy))
    shapely.prepare(reach)
    must = shapely.contains_xy(reach, X, Y)
    assert must.sum() > 1000
    assert np.all(through[must])


def _job_text(extra: str, tool_type: str = "flat") -> str:
    return f"""units = "mm"
[stock]
box = [0.0, 0.0, 0.0, 170.0, 140.0, 12.0]
[[tools]]
number = 1
type = "{tool_type}"
diameter = 10.0
[[operations]]
type = "die-cavity"
tool = 1
tolerance = 0.01
depth = 5.0
stepdown = 2.5
feed = 500.0
{extra}
"""


def _plan_file(path):
    job = load_job(path)
    ctx = PlanContext(job.units, job.stock, job.machine, job.tools, job.base_dir, job.path)
    return op.plan(ctx, job.operations[0][1])


def test_bad_points_file_line_is_named_in_the_error(tmp_path):
    src = (EXAMPLES / "die-blanking" / "outline.csv").read_text().splitlines()
    src[7] = "50,18,3"
    (tmp_path / "pts.csv").write_text("\n".join(src) + "\n")
    (tmp_path / "job.toml").write_text(_job_text('points_file = "pts.csv"'))
    with pytest.raises(GeometryError) as e:
        _plan_file(tmp_path / "job.toml")
    assert str(e.value).startswith(f"{tmp_path / 'pts.csv'}:8: ")


def test_points_and_points_file_together_and_ball_tools_are_job_errors(tmp_path):
    pts = "points = [[0.0,0.0],[10.0,0.0],[20.0,0.0],[30.0,0.0]]"
    (tmp_path / "job.toml").write_text(_job_text(pts + '\npoints_file = "x.csv"'))
    with pytest.raises(JobError, match="exactly one of points and points_file"):
        _plan_file(tmp_path / "job.toml")
    (tmp_path / "job.toml").write_text(_job_text(pts, tool_type="ball"))
    with pytest.raises(JobError, match="flat end mill"):
        _plan_file(tmp_path / "job.toml")


def test_unreachable_corners_say_how_much_is_left(blanking):
    _, res = blanking["cam"]
    corners = res.report["curve"]["unreachable_corners"]
    # a square-ish corner leaves about r (sqrt 2 - 1) = 2.07 for r = 5, never more
    assert all(0 <= c["max_uncut"] < 5.0 for c in corners)
    assert max(c["max_uncut"] for c in corners) > 0.5


def test_inch_job_control_and_cam_interpret_alike(rs274):
    from millpath.interpret import interpret
    from millpath.io.schema import validate
    from millpath.model import Machine, Stock, Tool
    from millpath.post.writer import post
    from support.rs274 import run_rs274
    from millpath.part.curve.points import read_points_csv
    pts = read_points_csv(EXAMPLES / "die-blanking" / "outline.csv") / 25.4
    tools = {3: Tool(3, "flat", 0.375)}
    ctx = PlanContext("inch", Stock(0, 0, 0, 170 / 25.4, 140 / 25.4, 0.5),
                      Machine.default_for("inch"), tools, Path("."))
    got = {}
    for comp in ("cam", "control"):
        params = validate({"tool": 3, "points": pts.tolist(), "tolerance": 0.0001,
                           "depth": 0.25, "stepdown": 0.125, "allowance": 0.01, "feed": 20.0,
                           "compensation": comp}, op.PARAMS, "op", None)
        res = op.plan(ctx, params)
        prog = post(res.toolpath, tools)
        r = run_rs274(prog, tools, table_units="inch")
        assert r.ok, (r.error, r.error_line)
        got[comp] = [m for m in interpret(prog, tools, machine_units="inch")
                     if m.kind in ("feed", "arc")]
    a, b = got["cam"], got["control"]
    assert len(a) == len(b) > 500
    # the post writes 5 decimals in inch: the CAM side carries up to 0.000005
    assert max(float(np.abs(np.subtract(x.end, y.end)).max()) for x, y in zip(a, b)) <= 1e-5


def test_millpath_run_writes_the_curve_analysis(tmp_path, rs274):
    import json
    from millpath.pipeline import run_job
    import shutil
    src = tmp_path / "job"
    shutil.copytree(EXAMPLES / "die-blanking", src)
    job = src / "job.toml"
    job.write_text(job.read_text().replace("[simulation]\n", "[simulation]\nexact = true\n"))
    run_job(job, tmp_path / "out")
    rep = json.loads((tmp_path / "out" / "report.json").read_text())
    assert rep["verification"]["reference"] == "operations[0] design"
    (curve,) = plan_sections(rep, "curve")
    assert {"segments", "chords", "uniform_chords", "unreachable_corners"} <= set(curve)
    assert all({"chords", "steps", "deviations", "uniform_chords"} <= set(s)
               for s in curve["segments"])
    # the exact check measures the finishing pass against the true wall: within
    # the job's tolerance (0.001 mm), which the Z-map's cells could not see
    assert rep["verification"]["max_gouge"] <= 0.001
    assert rep["verification"]["rapids_through_material"] == 0
    assert "G41 D1" in (tmp_path / "out" / "program.ngc").read_text()


def _square_job(tmp_path, corners, diameter=10.0):
    pts = []
    for a, b in zip(corners, corners[1:] + corners[:1]):
        a, b = np.array(a, float), np.array(b, float)
        pts += [(a + (b - a) * f).tolist() for f in (0, 1 / 3, 2 / 3, 1)]
    text = _job_text(f"points = {pts}").replace("diameter = 10.0", f"diameter = {diameter}")
    (tmp_path / "job.toml").write_text(text)
    return tmp_path / "job.toml"


def test_a_neck_narrower_than_the_tool_is_a_planning_error(tmp_path):
    from millpath.errors import PlanningError
    neck = [(0, 0), (40, 0), (40, 17), (60, 17), (60, 0), (100, 0), (100, 40), (60, 40),
            (60, 23), (40, 23), (40, 40), (0, 40)]
    with pytest.raises(PlanningError, match="2 separate parts"):
        _plan_file(_square_job(tmp_path, neck))
    # a 5 mm tool passes the 6 mm neck
    res = _plan_file(_square_job(tmp_path, neck, diameter=5.0))
    corners = res.report["curve"]["unreachable_corners"]
    assert len(corners) == 8           # the 8 inside corners; 4 outside ones are rounded
    assert all(c["max_uncut"] == pytest.approx(2.5 * (2 ** 0.5 - 1), abs=0.01) for c in corners)


def test_an_outline_crossing_itself_is_a_geometry_error(tmp_path):
    bowtie = [(0, 0), (40, 40), (40, 0), (0, 40)]
    with pytest.raises(GeometryError, match="crosses itself"):
        _plan_file(_square_job(tmp_path, bowtie))


#: a generated outline whose blend from the first segment to the second loops back
#: over itself: a tongue 1.3 mm long stands in the cavity where the tool passes
TONGUE = [[41.276, 36.771], [30.159, 51.289], [28.473, 69.985], [39.104, 85.189],
          [44.831, 89.902], [54.95, 95.327], [66.652, 96.375], [77.505, 91.969],
          [93.032, 74.643], [95.844, 55.883], [86.015, 39.856], [70.726, 29.067]]


def test_a_loop_the_tool_reaches_is_a_geometry_error_one_it_cannot_is_dropped(tmp_path):
    """A loop of the outline the tool would pass (the blend's tongue: the planner once
    cut through it and the proof refused a 0.098 gouge) is refused before planning,
    naming where; at the published cavity's tip the two segments cross in a loop
    0.5 mm long that the 10 mm tool cannot come near: dropped, the job planned."""
    text = _job_text(f"points = {TONGUE}").replace("diameter = 10.0", "diameter = 8.0")
    (tmp_path / "job.toml").write_text(text)
    with pytest.raises(GeometryError, match=r"crosses itself \(a loop round \(4[45]\.\d+, 8[89]\."):
        _plan_file(tmp_path / "job.toml")
    res = _plan_file(EXAMPLES / "die-published" / "job.toml")
    assert res.report["curve"]["self_intersecting"]


def test_sharp_cornered_cavity_control_matches_cam_with_arcs_and_trims(tmp_path, rs274):
    """Square corners: the contour is trimmed at inside corners and rounded with arcs
    round the outside ones, by the control and by the CAM offset alike."""
    from millpath.interpret import interpret
    from millpath.post.writer import post
    from support.rs274 import run_rs274
    neck = [(0, 0), (40, 0), (40, 17), (60, 17), (60, 0), (100, 0), (100, 40), (60, 40),
            (60, 23), (40, 23), (40, 40), (0, 40)]
    path = _square_job(tmp_path, neck, diameter=5.0)
    job = load_job(path)
    ctx = PlanContext(job.units, job.stock, job.machine, job.tools, job.base_dir, job.path)
    moves = {}
    for comp in ("cam", "control"):
        params = dict(job.operations[0][1], compensation=comp)
        res = op.plan(ctx, params)
        prog = post(res.toolpath, job.tools)
        r = run_rs274(prog, job.tools)
        assert r.ok, (r.error, r.error_line)
        z = res.report["curve"]["layers"][0]
        moves[comp] = _finish_xy(interpret(prog, job.tools, machine_units="mm"), z)
        if comp == "cam":
            assert sum(m.kind == "arc" for m in res.toolpath.moves) >= 4 * 2   # per layer
    a, b = moves["cam"], moves["control"]
    assert [k for k, _, _ in a] == [k for k, _, _ in b]
    assert sum(k == "arc" for k, _, _ in a) == 4
    assert max(float(np.abs(p - q).max()) for (_, p, _), (_, q, _) in zip(a, b)) <= 1e-4
