"""Shared helpers for the grid-pocket tests (fixture ``gp``): small jobs, planning, a
brute-force gouge check and plan-view analysis of a simulated Z-map."""

from __future__ import annotations

from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest
import shapely

from millpath.geometry.cutter import Cutter
from millpath.job.jobfile import load_job
from millpath.model.toolpath import sample_move
from millpath.plan.base import PlanContext
from millpath.plan.gridpocket import operation
from millpath.plan.gridpocket.cells import inward_offset

HEADER = """units = "inch"
[stock]
box = [-0.2, -0.2, -1.0, 3.2, 2.2, 0.0]
[[tools]]
number = 1
type = "{tool}"
diameter = 0.25
flute_length = 1.0
stickout = 1.5
"""


def write_job(tmp_path: Path, op: str, tool: str = "flat") -> Path:
    p = tmp_path / "job.toml"
    if "spindle" not in op:
        op += "spindle = 5000\n"
    p.write_text(HEADER.format(tool=tool) + "[[operations]]\ntype = \"grid-pocket\"\n" + op)
    return p


def plan_file(path: Path):
    job = load_job(path)
    ctx = PlanContext(units=job.units, stock=job.stock, machine=job.machine, tools=job.tools,
                      base_dir=job.base_dir, job_file=job.path)
    return job, operation.plan(ctx, job.operations[0][1])


def path_points(tp, step: float = 0.005) -> np.ndarray:
    """Points along every feed move (lines, arcs, cubics), about ``step`` apart."""
    pts, pos = [], None
    for m in tp.moves:
        if pos is not None and m.kind in ("line", "arc", "cubic"):
            pts.append(sample_move(pos, m, step))
        pos = m.end
    return np.concatenate(pts)


def brute_force_gouge(P: np.ndarray, tool, surface) -> float:
    """Deepest the tool (tip at P) reaches below the bottom surface anywhere under its
    footprint, by dense polar sampling of the footprint (the tool centre stays a radius
    inside the walls, so the footprint is inside the pocket)."""
    R = tool.radius
    rr, th = np.meshgrid(np.linspace(0, R, 13), np.linspace(0, 2 * np.pi, 49)[:-1])
    ox, oy = (rr * np.cos(th)).ravel(), (rr * np.sin(th)).ravel()
    prof = Cutter.of(tool).height(np.hypot(ox, oy))
    worst = -np.inf
    for k in range(0, len(P), 2000):
        Q = P[k:k + 2000]
        need = (surface.height(Q[:, :1] + ox, Q[:, 1:2] + oy) - prof).max(axis=1)
        worst = max(worst, float((need - Q[:, 2]).max()))
    return worst


def plan_view(zmap, design, polygon, tool):
    """(largest material above the design inside the reachable area, deepest cut
    outside the walls) of a simulated Z-map. The reachable area is where the tool's
    flat bottom can reach inside the walls (the offset outline grown back by the flat
    radius R - corner radius; for a ball, the tool centre positions), less 1.5 Z-map
    cells; the walls are checked 1.5 cells outside the outline."""
    tool_radius = tool.radius
    X, Y = np.meshgrid(zmap.xs(), zmap.ys())
    cell = max(zmap.dx, zmap.dy)
    reach = inward_offset(polygon, tool_radius).buffer(
        tool_radius - tool.corner_radius - 1.5 * cell)
    inner = shapely.contains_xy(reach, X, Y)
    left = float(np.max((zmap.heights - design.height(X, Y))[inner], initial=0.0))
    outside = ~shapely.contains_xy(polygon.buffer(1.5 * cell), X, Y)
    wall_cut = float(np.max((zmap.ztop - zmap.heights)[outside], initial=0.0))
    return left, wall_cut


@pytest.fixture(scope="session")
def gp() -> SimpleNamespace:
    """The helpers of this module, for tests (importlib mode cannot import them)."""
    return SimpleNamespace(write_job=write_job, plan_file=plan_file, path_points=path_points,
                           brute_force_gouge=brute_force_gouge, plan_view=plan_view)
