"""Waterline and steep/shallow finishing: contours on their level and on the CL surface,
planned jobs simulated (no gouge, no rapid through material, scallops on the walls,
coverage), programs accepted by our interpreter."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from millpath.errors import JobError
from millpath.interpret import interpret
from millpath.job.jobfile import load_job
from millpath.part.surface.mesh import function_mesh, write_stl
from millpath.plan.base import PlanContext
from millpath.plan.surface import operation
from millpath.geometry.cutter import Cutter
from millpath.plan.surface.dropcutter import build_index, drop
from millpath.plan.surface.sampler import Sampler
from millpath.plan.surface.waterline import WaterlineSettings, waterline
from millpath.post.writer import post_with_lines
from millpath.simulate import simulate_toolpath
from millpath.verify.roundtrip import compare_toolpath

WALL = 80.0            # degrees
DEPTH = 6.0
RIM = 1.0              # rim rounding radius
FILLET = 2.5           # floor fillet radius, larger than the 2 mm ball
TOL = 0.005
SCALLOP = 0.02
RES = 0.05             # simulation resolution


def profile(d):
    """Cavity section: Z and the part (0 plate, 1 rim, 2 wall, 3 fillet, 4 floor) at
    signed distance ``d`` from the rim (negative inside): a RIM-radius rounding, a
    WALL-degree wall, a FILLET-radius floor fillet, the floor DEPTH down."""
    a = math.radians(WALL)
    t = math.tan(a)
    e2 = -RIM * math.sin(a)                               # rim rounding meets the wall
    z2 = -RIM + RIM * math.cos(a)
    c = z2 - t * e2                                       # wall: z = t d + c
    zc = -DEPTH + FILLET
    dc = (zc - c - FILLET * math.sqrt(1 + t * t)) / t     # fillet centre
    dt = dc + FILLET * math.sin(a)                        # fillet meets the wall
    rim = -RIM + np.sqrt(np.maximum(RIM ** 2 - d * d, 0.0))
    fil = zc - np.sqrt(np.maximum(FILLET ** 2 - (d - dc) ** 2, 0.0))
    part = np.select([d >= 0, d >= e2, d >= dt, d > dc], [0, 1, 2, 3], 4)
    z = np.choose(part, [np.zeros_like(d), rim, t * d + c, fil, np.full_like(d, -DEPTH)])
    return z, part


def stadium(x, y, a=4.0, w=5.0):
    """A plate at z = 0 with a stadium cavity (straight part 2a along X, half-width w at
    the top), see :func:`profile`."""
    return profile(np.hypot(x - np.clip(x, -a, a), y) - w)[0]


def hemisphere(x, y, R=7.0):
    return np.sqrt(np.maximum(R * R - x * x - y * y, 0.0))


JOB = """units = "mm"
[stock]
box = [{x0}, {y0}, {z0}, {x1}, {y1}, {z1}]
[[tools]]
number = 1
type = "ball"
diameter = 4.0
flute_length = {flute}
stickout = {stickout}
holder = [[20.0, 30.0]]
[[operations]]
type = "surface-finish"
surface = "s.stl"
tool = 1
tolerance = {tol}
scallop = {scallop}
compare = false
{extra}
"""


def plan_job(tmp: Path, mesh, extra: str, stickout: float = 30.0):
    tmp.mkdir(parents=True, exist_ok=True)
    write_stl(mesh, tmp / "s.stl")
    lo, hi = mesh.bounds
    (tmp / "job.toml").write_text(JOB.format(x0=lo[0], y0=lo[1], z0=lo[2] - 1, x1=hi[0],
                                             y1=hi[1], z1=hi[2] + 0.5, stickout=stickout,
                                             flute=min(12.0, stickout - 1.0),
                                             tol=TOL, scallop=SCALLOP, extra=extra))
    job = load_job(tmp / "job.toml")
    ctx = PlanContext(units=job.units, stock=job.stock, machine=job.machine, tools=job.tools,
                      base_dir=job.base_dir, job_file=job.path)
    res = operation.plan(ctx, job.operations[0][1])
    return job, res


def simulate(job, res):
    sim = simulate_toolpath(res.toolpath, job.tools, job.stock, resolution=RES,
                            design=res.design, machine=job.machine)
    zm = sim.zmap
    X, Y = np.meshgrid(zm.xs(), zm.ys())
    des = res.design.height(X, Y)
    gy, gx = np.gradient(np.where(np.isfinite(des), des, 0.0), RES)
    slope = np.degrees(np.arctan(np.hypot(gx, gy)))
    return sim, X, Y, zm.heights - des, slope


@pytest.fixture(scope="module")
def stadium_mesh():
    return function_mesh(stadium, (-10.0, 10.0), (-8.0, 8.0), 101, 81, "stadium")


@pytest.fixture(scope="module")
def waterline_job(stadium_mesh, tmp_path_factory):
    job, res = plan_job(tmp_path_factory.mktemp("wl"), stadium_mesh, 'strategy = "waterline"')
    return job, res, *simulate(job, res)


@pytest.fixture(scope="module")
def steep_shallow_job(stadium_mesh, tmp_path_factory):
    job, res = plan_job(tmp_path_factory.mktemp("ss"), stadium_mesh,
                        'strategy = "steep-shallow"\nsteep_angle = 50.0')
    return job, res, *simulate(job, res)


@pytest.fixture(scope="module")
def zigzag_job(stadium_mesh, tmp_path_factory):
    job, res = plan_job(tmp_path_factory.mktemp("zz"), stadium_mesh, 'strategy = "zigzag"')
    return job, res, *simulate(job, res)


def _wall_cells(X, Y, a=4.0, w=5.0):
    """Cells on the straight WALL-degree part of the wall, 0.2 mm clear of its ends."""
    d = np.hypot(X - np.clip(X, -a, a), Y) - w
    return (profile(d - 0.2)[1] == 2) & (profile(d + 0.2)[1] == 2)


def test_contour_points_are_on_their_level_and_on_the_cl_surface():
    mesh = function_mesh(hemisphere, (-9.0, 9.0), (-9.0, 9.0), 73, 73, "dome")
    index = build_index(mesh)
    cutter = Cutter(2.0, 2.0)
    sampler = Sampler(index, cutter)
    s = WaterlineSettings(TOL, SCALLOP, (-11.0, -11.0, 11.0, 11.0), min_slope=30.0)
    res = waterline(sampler, s)
    assert len(res.levels) > 10 and res.passes
    levels = np.array(res.levels)
    assert np.all(np.diff(levels) < 0)                      # top down
    for p in res.passes:
        P = p.points
        assert np.ptp(P[:, 2]) == 0.0 and np.min(np.abs(levels - P[0, 2])) == 0.0
        z = drop(index, cutter, P[:, :2]).z
        assert np.all(z <= P[:, 2] + 1e-9)                  # never below the drop-cutter Z
        # on the CL surface: the gap is the bisection width on the slope
        assert np.all(P[:, 2] - z <= TOL)
        mid = 0.5 * (P[1:, :2] + P[:-1, :2])
        assert np.all(drop(index, cutter, mid).z <= P[0, 2] + TOL + 1e-9)
    # climb: the dome (rising side) on the right, i.e. clockwise loops seen from +Z
    for p in res.passes:
        P = p.points
        if np.all(P[0] == P[-1]):
            area = 0.5 * np.sum(P[:-1, 0] * P[1:, 1] - P[1:, 0] * P[:-1, 1])
            assert area < 0
    assert res.max_chord_ratio <= 1.0 + 1e-6


def test_waterline_job_no_gouge_no_rapid_through_material_scallop_held(waterline_job):
    job, res, sim, X, Y, left, slope = waterline_job
    sec = res.report["surface_finish"][0]
    wl = sec["waterline"]
    assert sec["strategy"] == "waterline" and wl["levels"] > 10
    assert sim.max_gouge <= TOL + 0.001
    assert sim.rapids_through_material == 0 and sim.holder_contacts == 0
    assert sec["links"]["retract"] == 0                      # levels joined on the surface
    wall = _wall_cells(X, Y)
    assert wall.sum() > 1000
    normal = left[wall] * np.cos(np.radians(slope[wall]))     # scallop along the normal
    assert 0.3 * SCALLOP < normal.max() <= SCALLOP
    # the level step on the wall follows from the flat side step for the target scallop
    assert wl["level_step_max"] <= 2.0 + 1e-9


def test_waterline_program_is_accepted_by_our_interpreter(waterline_job):
    job, res, *_ = waterline_job
    program, lines = post_with_lines(res.toolpath, job.tools, title="waterline")
    motions = interpret(program, job.tools, machine_units="mm")
    assert compare_toolpath(res.toolpath, lines, motions, 2e-4) == []


def test_steep_shallow_finishes_the_whole_surface(steep_shallow_job, waterline_job,
                                                  zigzag_job):
    job, res, sim, X, Y, left, slope = steep_shallow_job
    sec = res.report["surface_finish"][0]
    assert sec["steep_shallow"]["zigzag_pieces"] > 0 and sec["waterline"]["contours"] > 0
    assert sim.max_gouge <= TOL + 0.001
    assert sim.rapids_through_material == 0 and sim.holder_contacts == 0
    inner = (np.abs(X) < 9.0) & (np.abs(Y) < 7.0)            # off the plate's open edges
    cos = np.cos(np.radians(slope))
    normal = left * cos
    wall = _wall_cells(X, Y)
    assert normal[wall].max() <= SCALLOP
    # elsewhere the scallop is held too, except in the tessellation's concave grooves
    # (where the rim's circle crosses the mesh cells) that no ball position reaches:
    # zigzag alone leaves as much material there
    zz_normal = zigzag_job[5] * cos
    over = inner & (normal > SCALLOP)
    print(f"steep-shallow: {over.sum()} of {inner.sum()} cells over the scallop, "
          f"max {normal[inner].max():.4f} (zigzag alone {zz_normal[inner].max():.4f})")
    assert over.sum() <= 0.005 * inner.sum()
    assert np.all(normal[over] <= zz_normal[over] + 0.25 * SCALLOP)
    # waterline alone leaves the plate uncut (0.5 mm of stock on it)
    wl_left = waterline_job[5]
    assert wl_left[inner].max() >= 0.49 and left[inner].max() < 0.49
    program, lines = post_with_lines(res.toolpath, job.tools, title="steep-shallow")
    motions = interpret(program, job.tools, machine_units="mm")
    assert compare_toolpath(res.toolpath, lines, motions, 2e-4) == []


def test_holder_contact_splits_contours_and_is_reported(stadium_mesh, tmp_path):
    # 5 mm out of a 20 mm holder: below tip Z -4 the holder would reach the plate
    job, res = plan_job(tmp_path, stadium_mesh, 'strategy = "waterline"', stickout=5.0)
    sec = res.report["surface_finish"][0]
    assert sec["waterline"]["points_not_cut"]["holder"] > 0
    assert sec["holder"]["lifted_points"] > 0
    zs = [m.end[2] for m in res.toolpath.moves if m.kind == "line"]
    assert min(zs) >= -4.0 - 1e-6
    sim = simulate_toolpath(res.toolpath, job.tools, job.stock, resolution=0.1,
                            design=res.design, machine=job.machine)
    assert sim.holder_contacts == 0 and sim.rapids_through_material == 0


@pytest.mark.parametrize("strategy", ["zigzag", "waterline", "steep-shallow"])
def test_a_flat_end_mill_is_refused_naming_the_tool_key(stadium_mesh, tmp_path, strategy):
    """Passes are spaced by a ball's or bull corner's scallop: a flat end mill is refused
    before planning, naming ``tool``."""
    write_stl(stadium_mesh, tmp_path / "s.stl")
    lo, hi = stadium_mesh.bounds
    text = JOB.format(x0=lo[0], y0=lo[1], z0=lo[2] - 1, x1=hi[0], y1=hi[1], z1=hi[2] + 0.5,
                      stickout=30.0, flute=12.0, tol=TOL, scallop=SCALLOP,
                      extra=f'strategy = "{strategy}"')
    (tmp_path / "job.toml").write_text(text.replace('type = "ball"', 'type = "flat"', 1))
    job = load_job(tmp_path / "job.toml")
    ctx = PlanContext(units=job.units, stock=job.stock, machine=job.machine, tools=job.tools,
                      base_dir=job.base_dir, job_file=job.path)
    for step in (operation.preflight, operation.plan):
        with pytest.raises(JobError, match=r"job.toml: tool: T1 is a flat end mill"):
            step(ctx, job.operations[0][1])


def test_steep_angle_must_be_an_angle(stadium_mesh, tmp_path):
    with pytest.raises(JobError, match="steep_angle"):
        plan_job(tmp_path, stadium_mesh, 'strategy = "steep-shallow"\nsteep_angle = 95.0')



def test_vertical_walls_get_the_flat_level_step_and_hold_the_scallop(shared_dir):
    """PyCAM's text box (letters 2.95 mm tall with vertical walls, acute inner corners,
    on a floor at -5 mm), waterline with a 2 mm ball. Analytic truth: on a vertical
    wall two levels ``dz`` apart leave a scallop ``r - sqrt(r^2 - (dz/2)^2)`` (the two
    ball circles meet halfway), so the scallop is held while ``dz`` is at most the flat
    step ``2 sqrt(2 r h - h^2)``; the raster's jump at a wall (an inner corner too) is
    no concave crease, so the levels there are not a quarter of that."""
    from millpath.part.surface.mesh import read_stl
    mesh = read_stl(shared_dir / "meshes" / "pycam-textbox.stl")
    r, h = 1.0, 0.05
    sampler = Sampler(build_index(mesh), Cutter(r, r))
    s = WaterlineSettings(0.01, h, (-1.0, -1.0, 131.0, 51.0), material_tolerance=0.005,
                          min_slope=45.0)
    res = waterline(sampler, s)
    z = np.array(res.levels)
    wall = (z < -2.05 - r - 0.05) & (z > -4.95)         # tip beside the letters' walls
    dz = -np.diff(z)[wall[1:] & wall[:-1]]
    assert len(dz) >= 4
    assert np.all(r - np.sqrt(r * r - (dz / 2) ** 2) <= h)
    flat = 2.0 * math.sqrt(2.0 * r * h - h * h)
    assert dz.min() >= 0.5 * flat                       # not the crease's quarter step


def test_a_level_segment_is_checked_along_its_length():
    """A 10 mm level segment whose middle is clear but whose first quarter lies under a
    ridge of the drop-cutter surface (0.46 above the level there, analytic): the
    segment is removed, its clear neighbours kept."""
    from types import SimpleNamespace

    from millpath.plan.surface.waterline import _gouge_split
    z = -2.0

    def zc(xy):
        x = np.asarray(xy, float)[:, 0]
        return z - 1.0 + 2.0 * np.exp(-((x - 2.5) ** 2) / 0.25)

    lv = SimpleNamespace(zc=zc, tol_g=0.005,
                         sampler=SimpleNamespace(cutter=SimpleNamespace(radius=6.0)))
    P = np.array([[-4.0, 0.0], [-2.0, 0.0], [0.0, 0.0], [10.0, 0.0], [12.0, 0.0],
                  [14.0, 0.0]])
    assert zc(0.5 * (P[2:3] + P[3:4]))[0] < z               # the middle is clear
    pieces = _gouge_split(lv, P, z, False, {"unbracketed": 0})
    assert [p[:, 0].tolist() for p in pieces] == [[-4.0, -2.0], [12.0, 14.0]]
