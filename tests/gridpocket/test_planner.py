"""The grid-pocket operation: job keys and errors, layers, phase order, wall pass,
tool-shape Z against the thesis's surface Z, design and report."""

from __future__ import annotations

import math

import numpy as np
import pytest
import shapely

from millpath.errors import GeometryError, JobError, MillpathError, PlanningError
from millpath.plan.gridpocket import operation
from millpath.plan.gridpocket.planner import layer_floors

L_POCKET = 'polygon = [[0, 0], [3, 0], [3, 1], [1.2, 1], [1.2, 2], [0, 2]]\n'
STEEP = 'bottom = { bezier = [[-0.2, -0.5, -0.2], [-0.3, -0.6, -0.3], [-0.2, -0.5, -0.2]] }\n'


def test_params_are_exactly_the_keys_of_the_issue():
    assert set(operation.PARAMS) == {
        "tool", "polygon", "bottom", "grid", "depths", "stepdown", "motion", "tolerance",
        "zigzag", "feed", "finish_feed", "plunge_feed", "spindle", "safe_z", "z_mode",
        "force_grid",
        "navigation", "grid_centre", "bezier_parameters",        # issue 17
        "rest", "rest_allowance"}                                     # issue 21


def test_force_grid_accepts_cells_larger_than_d_over_sqrt2(tmp_path, gp):
    op = L_POCKET + STEEP + "feed = 10\ngrid = [0.2, 0.1]\n"
    with pytest.raises(PlanningError, match="D/sqrt"):
        gp.plan_file(gp.write_job(tmp_path, "tool = 1\n" + op))
    _, res = gp.plan_file(gp.write_job(tmp_path, "tool = 1\n" + op + "force_grid = true\n"))
    assert res.report["pocket"]["grid"]["dx"] == 0.2
    assert res.report["pocket"]["grid"]["cells_inside"] > 0


def test_registry_finds_the_operation():
    from millpath.plan.registry import strategy
    assert strategy("grid-pocket") is operation


@pytest.mark.parametrize("op,where,exc", [
    (L_POCKET + STEEP + "feed = 10\nspeed = 3\n", "operations[0].speed: unknown key", JobError),
    ('polygon = [[0, 0], [2, 2], [2, 0], [0, 2]]\n' + STEEP + "feed = 10\n",
     "operations[0].polygon: the outline intersects itself", JobError),
    (L_POCKET + 'bottom = { bezier = [[0, nan], [0, 0]] }\nfeed = 10\n',
     "operations[0].bottom: bezier", JobError),
    (L_POCKET + 'bottom = { bezier = [[0, 0], [0, 0]], points = "a.csv" }\nfeed = 10\n',
     "operations[0].bottom: give exactly one", JobError),
    (L_POCKET + STEEP + "feed = 10\nmotion = \"spline\"\n", "operations[0].motion", JobError),
    (L_POCKET + STEEP + "feed = 10\nspindle = 0\n", "operations[0].spindle", JobError),
    (L_POCKET + STEEP + "feed = 10\ndepths = [-0.1, -0.1]\n", "operations[0].depths", JobError),
])
def test_bad_keys_name_the_job_file_and_key(tmp_path, gp, op, where, exc):
    p = gp.write_job(tmp_path, "tool = 1\n" + op)
    with pytest.raises(exc) as e:
        gp.plan_file(p)
    assert str(e.value).startswith(str(p)) and where in str(e.value)


def test_planning_errors_name_the_job_file(tmp_path, gp):
    cases = [
        ('polygon = [[0, 0], [0.2, 0], [0.2, 2], [0, 2]]\n' + STEEP + "feed = 10\n",
         PlanningError, "too big"),
        (L_POCKET + STEEP + "feed = 10\ngrid = [0.2, 0.1]\n", PlanningError, "D/sqrt(2)"),
        (L_POCKET + STEEP + "feed = 10\nsafe_z = -0.1\n", JobError, "safe_z"),
        (L_POCKET + 'bottom = { points = "missing.csv" }\nfeed = 10\n', GeometryError,
         "missing.csv"),
        (L_POCKET + STEEP + "feed = 10\ndepths = [-0.1]\nstepdown = 0.1\n", JobError, "either"),
        (L_POCKET + 'bottom = { bezier = [[0, 0], [0, 0]], box = [0, 0, 2, 2] }\nfeed = 10\n',
         GeometryError, "does not reach the pocket outline at (2.0625, 0)"),
    ]
    for op, exc, text in cases:
        p = gp.write_job(tmp_path, "tool = 1\n" + op)
        with pytest.raises(exc) as e:
            gp.plan_file(p)
        assert isinstance(e.value, MillpathError) and text in str(e.value)
        assert e.value.file is not None


def test_layer_floors_from_step_and_depths():
    assert layer_floors(0.0, -1.2, None, 0.2, None)[:-1] == pytest.approx(
        [-0.2, -0.4, -0.6, -0.8, -1.0])
    assert layer_floors(0.0, -1.2, None, 0.2, None)[-1] == -math.inf
    assert layer_floors(0.0, -0.5, [-0.1, -0.35, -0.6], None, None) == [-0.1, -0.35, -math.inf]
    assert layer_floors(0.0, -0.5, None, None, None) == [-math.inf]
    with pytest.raises(JobError, match="depths"):
        layer_floors(0.0, -0.5, [0.1], None, None)


def _ops(res):
    return [(m, res.toolpath.ops[m.op].info["phase"]) for m in res.toolpath.moves]


def test_layers_and_phase_order(tmp_path, gp):
    p = gp.write_job(tmp_path, "tool = 1\n" + L_POCKET + STEEP + "feed = 10\nfinish_feed = 7\n"
                  "plunge_feed = 3\nstepdown = 0.12\ngrid = [0.125, 0.125]\n")
    job, res = gp.plan_file(p)
    phases = [op.info["phase"] for op in res.toolpath.ops]
    assert phases == ["rough", "rough", "rough", "finish", "wall", "zigzag_x", "zigzag_y"]
    layers = res.report["pocket"]["layers"]
    # the bottom lies between -0.4 and -0.2: floors -0.12, -0.24, -0.36, then the finish
    assert -0.4 <= res.report["pocket"]["bottom_min_tip_z"] < -0.36
    assert [l["floor"] for l in layers[:3]] == pytest.approx([-0.12, -0.24, -0.36])
    assert layers[3]["floor"] is None and layers[3]["finish"]
    # a rough layer never goes below its floor; the finish and clean-up use finish_feed
    for k, floor in ((0, -0.12), (1, -0.24), (2, -0.36)):
        zs = [m.end[2] for m in res.toolpath.moves if m.op == k and m.kind != "rapid"]
        assert min(zs) >= floor - 1e-9
    for m, ph in _ops(res):
        if m.kind in ("line", "arc") and ph in ("finish", "zigzag_x") and m.feed != 3:
            assert m.feed == 7
    # a roughing layer skips the cells whose bottom is above its floor; the finish
    # layer visits them all
    assert layers[2]["cells"] < layers[1]["cells"] <= layers[0]["cells"] <= layers[3]["cells"]
    assert layers[3]["cells"] == res.report["pocket"]["grid"]["cells_inside"]


def test_wall_pass_starts_at_the_outline_corner_nearest_the_finish_end(tmp_path, gp):
    p = gp.write_job(tmp_path, "tool = 1\n" + L_POCKET + STEEP + "feed = 10\nzigzag = false\n")
    job, res = gp.plan_file(p)
    moves = res.toolpath.moves
    finish_end = [m.end for m in moves if res.toolpath.ops[m.op].info["phase"] == "finish"][-1]
    wall = [m for m in moves if res.toolpath.ops[m.op].info["phase"] == "wall"
            and m.kind != "rapid"]
    from millpath.plan.gridpocket.cells import inward_offset, pocket_polygon
    ring = np.asarray(inward_offset(pocket_polygon(
        [[0, 0], [3, 0], [3, 1], [1.2, 1], [1.2, 2], [0, 2]]), 0.125).exterior.coords)
    start = wall[0].end
    d = np.hypot(ring[:, 0] - finish_end[0], ring[:, 1] - finish_end[1])
    assert np.allclose(start[:2], ring[np.argmin(d)], atol=1e-5)
    assert np.allclose(wall[-1].end[:2], start[:2], atol=1e-5)   # all the way round


def test_feed_moves_keep_the_tool_inside_the_walls(tmp_path, gp):
    p = gp.write_job(tmp_path, "tool = 1\n" + L_POCKET + STEEP + "feed = 10\nmotion = \"arc\"\n")
    job, res = gp.plan_file(p)
    P = gp.path_points(res.toolpath, 0.01)
    poly = shapely.Polygon([[0, 0], [3, 0], [3, 1], [1.2, 1], [1.2, 2], [0, 2]])
    feed_pts = P[P[:, 2] < 0]
    d = shapely.distance(poly.exterior, shapely.points(feed_pts[:, :2]))
    assert shapely.contains_xy(poly, feed_pts[:, 0], feed_pts[:, 1]).all()
    assert d.min() >= 0.125 - 2e-4 - 1e-6


#: a star whose corners point into the pocket, with cells near D / sqrt(2): a straight
#: step between two neighbouring cell centres (both clear of the walls) can pass
#: within a radius of such a corner
STAR = [[47.673, 73.308], [36.808, 65.606], [27.926, 61.678], [19.398, 49.992],
        [26.709, 44.866], [12.657, 37.573], [42.733, 17.183], [53.361, 29.582],
        [68.633, 30.229], [59.468, 37.878], [65.132, 41.88]]


@pytest.mark.parametrize("navigation", ["wall-first", "straight-first"])
def test_steps_between_neighbouring_cells_keep_clear_of_corners_into_the_pocket(
        tmp_path, gp, navigation):
    s = 0.25 / 12.0                 # the star drawn for a 12 mm tool, for the 0.25 in one
    poly = shapely.Polygon([(x * s, y * s) for x, y in STAR])
    p = gp.write_job(tmp_path, "tool = 1\n"
                     f"polygon = {[[x * s, y * s] for x, y in STAR]}\n"
                     "bottom = { bezier = [[-0.1, -0.1], [-0.1, -0.1]] }\nfeed = 10\nmotion = \"arc\"\nzigzag = true\n"
                     f"navigation = \"{navigation}\"\n"
                     f"grid = [{7.929 * s}, {5.399 * s}]\n")
    job, res = gp.plan_file(p)
    P = gp.path_points(res.toolpath, 0.002)
    feed_pts = P[P[:, 2] < 0]
    d = shapely.distance(poly.exterior, shapely.points(feed_pts[:, :2]))
    assert shapely.contains_xy(poly, feed_pts[:, 0], feed_pts[:, 1]).all()
    # the tool's edge stays off the walls (and their corners) within the tolerance
    assert d.min() >= 0.125 - res.report["pocket"]["tolerance"] - 1e-6


@pytest.mark.parametrize("tool", ["flat", "bull"])
def test_tool_mode_never_gouges_a_steep_bottom_and_surface_mode_does(tmp_path, gp, tool):
    extra = "corner_radius = 0.05\n" if tool == "bull" else ""
    ops = "tool = 1\n" + L_POCKET + STEEP + "feed = 10\ngrid = [0.125, 0.125]\nmotion = \"arc\"\n"
    header_tool = tool
    p = gp.write_job(tmp_path, ops + 'z_mode = "tool"\n', tool=header_tool)
    if extra:
        p.write_text(p.read_text().replace("stickout = 1.5\n", "stickout = 1.5\n" + extra))
    job, res = gp.plan_file(p)
    t = job.tools[1]
    g_tool = gp.brute_force_gouge(gp.path_points(res.toolpath, 0.01), t, res.design.surface)
    assert g_tool <= 2.5e-4        # tolerance 2e-4 plus sampling
    p.write_text(p.read_text().replace('z_mode = "tool"', 'z_mode = "surface"'))
    job, res_s = gp.plan_file(p)
    g_surf = gp.brute_force_gouge(gp.path_points(res_s.toolpath, 0.01), t, res_s.design.surface)
    assert g_surf > 10 * 5e-4
    assert res.report["pocket"]["surface_mode_gouge_at_centres"] > 5e-3


def test_ball_tool_on_a_measured_bottom(tmp_path, gp):
    xs, ys = np.arange(0, 3.01, 0.3), np.arange(0, 2.11, 0.3)
    rows = ["x,y,z"] + [f"{x:.2f},{y:.2f},{-0.3 - 0.1 * math.sin(x) * math.cos(y):.5f}"
                        for y in ys for x in xs]
    (tmp_path / "pts.csv").write_text("\n".join(rows) + "\n")
    p = gp.write_job(tmp_path, "tool = 1\n" + L_POCKET + 'bottom = { points = "pts.csv" }\n'
                  "feed = 10\ngrid = [0.15, 0.15]\n", tool="ball")
    job, res = gp.plan_file(p)
    g = gp.brute_force_gouge(gp.path_points(res.toolpath, 0.01), job.tools[1], res.design.surface)
    assert g <= 1.5e-4


def test_design_is_stock_top_outside_and_bottom_inside(tmp_path, gp):
    p = gp.write_job(tmp_path, "tool = 1\n" + L_POCKET + STEEP + "feed = 10\n")
    job, res = gp.plan_file(p)
    d = res.design
    z = d.height(np.array([0.5, 2.0, 2.0, -0.1]), np.array([0.5, 0.5, 1.5, 0.5]))
    assert z[2] == 0.0 and z[3] == 0.0
    assert z[0] == pytest.approx(d.surface.height(np.array([0.5]), np.array([0.5]))[0])
    assert -0.6 < z[1] < -0.2


def test_report_section(tmp_path, gp):
    p = gp.write_job(tmp_path, "tool = 1\n" + L_POCKET + STEEP + "feed = 10\n")
    job, res = gp.plan_file(p)
    r = res.report["pocket"]
    assert r["grid"]["cells_inside"] > 100 and r["layers"][0]["finish"]
    assert set(r["feed_length"]) == {"finish", "wall", "zigzag_x", "zigzag_y"}
    assert r["path_length"] == pytest.approx(sum(r["feed_length"].values()), rel=0.05)


def test_bezier_mode_writes_g5_on_a_flat_concave_pocket(tmp_path, gp):
    p = gp.write_job(tmp_path, "tool = 1\n" + L_POCKET + 'bottom = { bezier = [[-0.3, -0.3], '
                  '[-0.3, -0.3]] }\nfeed = 10\nmotion = "bezier"\nzigzag = false\n'
                  "depths = [-0.15]\n")
    job, res = gp.plan_file(p)
    assert res.toolpath.counts()["cubic"] >= 1


def test_a_narrow_neck_splits_the_pocket_into_two_regions(tmp_path, gp):
    dumbbell = ('polygon = [[0, 0], [1, 0], [1, 0.4], [1.5, 0.4], [1.5, 0], [2.5, 0], '
                '[2.5, 1], [1.5, 1], [1.5, 0.6], [1, 0.6], [1, 1], [0, 1]]\n')
    p = gp.write_job(tmp_path, "tool = 1\n" + dumbbell + STEEP + "feed = 10\n"
                     "grid = [0.125, 0.125]\nmotion = \"arc\"\n")
    job, res = gp.plan_file(p)
    tp = res.toolpath
    wall = [m for m in tp.moves if tp.ops[m.op].info["phase"] == "wall"]
    # the neck (0.2 wide) is narrower than the tool: two wall laps, joined by a move
    # above the stock top
    feeds = [m for m in wall if m.kind != "rapid"]
    assert min(m.end[0] for m in feeds) < 0.2 and max(m.end[0] for m in feeds) > 2.3
    assert any(m.kind == "rapid" and m.end[2] > 0 for m in wall[1:])
    poly = res.design.polygon
    P = gp.path_points(tp, 0.01)
    cut = P[P[:, 2] < 0]
    d = shapely.distance(poly.exterior, shapely.points(cut[:, :2]))
    assert shapely.contains_xy(poly, cut[:, 0], cut[:, 1]).all() and d.min() >= 0.125 - 2.1e-4
    assert 0.7 < P[P[:, 2] < 0][:, 0].max() and P[P[:, 2] < 0][:, 0].min() < 1.8


def test_a_millimetre_job_uses_millimetre_defaults(tmp_path, gp):
    p = tmp_path / "job.toml"
    p.write_text("""units = "mm"
[stock]
box = [-5, -5, -30, 85, 55, 0]
[[tools]]
number = 4
type = "ball"
diameter = 6
[[operations]]
type = "grid-pocket"
tool = 4
polygon = [[0, 0], [80, 0], [80, 50], [0, 50]]
bottom = { bezier = [[-8, -12, -8], [-10, -14, -10], [-8, -12, -8]] }
feed = 600
spindle = 8000
stepdown = 5
motion = "arc"
""")
    job, res = gp.plan_file(p)
    r = res.report["pocket"]
    assert r["tolerance"] == 0.005 and r["grid"]["dx"] == 3.0
    assert [l["floor"] for l in r["layers"]][:1] == [-5.0]
    tp = res.toolpath
    assert max(m.end[2] for m in tp.moves) == pytest.approx(5.0)      # safe_z = top + 5 mm
    assert tp.units == "mm" and tp.counts()["arc"] > 0


@pytest.mark.parametrize("mode,kind", [("arc", "arc"), ("bezier", "cubic")])
def test_flat_concave_pocket_wall_corners_as_xy_arcs_or_g5_accepted_by_rs274(
        tmp_path, gp, rs274, mode, kind):
    from millpath.interpret import interpret
    from millpath.post.writer import post_with_lines
    from millpath.verify.roundtrip import compare_toolpath
    from support.rs274 import run_rs274
    p = gp.write_job(tmp_path, "tool = 1\n" + L_POCKET + 'bottom = { bezier = [[-0.3, -0.3], '
                     f'[-0.3, -0.3]] }}\nfeed = 10\nmotion = "{mode}"\nzigzag = false\n'
                     "grid = [0.15, 0.15]\n")
    job, res = gp.plan_file(p)
    tp = res.toolpath
    wall_curves = [m for m in tp.moves if m.kind == kind and m.plane == "XY"
                   and tp.ops[m.op].info["phase"] == "wall"]
    assert wall_curves, f"no XY {kind} on the wall pass"
    program, lines = post_with_lines(tp, job.tools)
    assert ("G5 " in program) == (kind == "cubic")
    assert compare_toolpath(tp, lines, interpret(program, job.tools, machine_units="inch"),
                            2e-5) == []
    r = run_rs274(program, job.tools, table_units="inch")
    assert r.ok, f"rs274: line {r.error_line}: {r.error}"


def test_bezier_rows_run_along_x_from_the_lowest_y_up(tmp_path, gp):
    p = gp.write_job(tmp_path, "tool = 1\n" + L_POCKET +
                     'bottom = { bezier = [[-0.1, -0.1, -0.1], [-0.5, -0.5, -0.5]] }\n'
                     "feed = 10\ngrid = [0.15, 0.15]\nzigzag = false\n")
    job, res = gp.plan_file(p)
    h = res.design.surface.height(np.array([1.0, 1.0, 0.1]), np.array([0.0, 2.0, 1.0]))
    assert h == pytest.approx([-0.1, -0.5, -0.3])
