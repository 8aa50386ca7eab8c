"""Entry moves under cutter radius compensation (the EMC/LinuxCNC manual, seeds/003
"Tool compensation": a straight move turning G41 on, then an arc lead-in tangent to the
contour; the mirrored arc and a G40 straight move to leave). LinuxCNC's rs274 is the
reference: it must accept every such program, and millpath's interpreter must move
exactly as rs274 does."""

from __future__ import annotations

import math
import re
from pathlib import Path

import numpy as np
import pytest
import shapely

import millpath
from millpath.errors import JobError
from millpath.interpret import interpret
from millpath.job.jobfile import load_job
from millpath.plan.base import PlanContext
from millpath.plan.diecavity import operation as op
from millpath.post.writer import post

EXAMPLES = Path(millpath.__file__).parent / "examples"


def _plan(name: str, **override):
    job = load_job(EXAMPLES / name / "job.toml")
    ctx = PlanContext(job.units, job.stock, job.machine, job.tools, job.base_dir, job.path)
    params = dict(job.operations[0][1])
    params.update(override)
    return job, op.plan(ctx, params)


@pytest.fixture(scope="module", params=["die-published", "die-blanking"])
def arc_job(request):
    job, res = _plan(request.param, compensation="control", entry="arc")
    return request.param, job, res, post(res.toolpath, job.tools)


def _motion_blocks(program: str) -> list[tuple[int, str]]:
    """(line number, text) of the program's blocks that move or switch compensation."""
    out = []
    for i, line in enumerate(program.splitlines(), start=1):
        s = re.sub(r"\(.*?\)", "", line).strip()
        if re.search(r"G4[01]|[XYZ]-?\d", s):
            out.append((i, s))
    return out


def test_each_g41_is_followed_by_a_straight_move_and_the_tangent_arc(arc_job):
    name, job, res, program = arc_job
    blocks = _motion_blocks(program)
    g41 = [k for k, (_, s) in enumerate(blocks) if "G41" in s]
    g40 = [k for k, (_, s) in enumerate(blocks) if re.search(r"G40(?!\d)", s)][1:]   # not the header's
    assert len(g41) == len(res.report["curve"]["layers"]) == len(g40)
    for k in g41:
        nxt = [s for _, s in blocks[k + 1:k + 3]]
        assert not re.search(r"G[23](?!\d)", nxt[0])          # the straight G41 move
        assert re.search(r"G3(?!\d)", nxt[1])                 # then the arc onto the contour
    for k in g40:
        assert re.search(r"G3(?!\d)", blocks[k - 1][1])      # the mirrored arc, then G40
    assert res.report["curve"]["entry"]["method"] == "arc"


def test_rs274_accepts_and_millpath_interprets_like_rs274(arc_job, rs274):
    from support.rs274 import run_rs274
    name, job, res, program = arc_job
    r = run_rs274(program, job.tools)
    assert r.ok, (r.error, r.error_line)
    ours = interpret(program, job.tools, machine_units=job.units)
    assert [m.kind for m in ours] == [m.kind for m in r.motions]
    # rs274 prints 4 decimals: 0.00005 of rounding on its side, plus our 0.0001 grid
    for a, b in zip(ours, r.motions):
        assert np.abs(np.subtract(a.end, b.end)).max() <= 1.5e-4, (a, b)
        if a.center is not None:
            assert np.abs(np.subtract(a.center[:2], b.center[:2])).max() <= 1.5e-4, (a, b)


def _ccw_points(m, n=32) -> np.ndarray:
    c = np.asarray(m.center[:2])
    a0 = math.atan2(m.start[1] - c[1], m.start[0] - c[0])
    a1 = math.atan2(m.end[1] - c[1], m.end[0] - c[0])
    if a1 <= a0:
        a1 += 2 * math.pi
    rad = math.hypot(m.start[0] - c[0], m.start[1] - c[1])
    th = np.linspace(a0, a1, n)
    return np.column_stack([c[0] + rad * np.cos(th), c[1] + rad * np.sin(th)])


def test_lead_in_and_lead_out_keep_the_tool_off_the_wall(arc_job, rs274):
    """The tool centre on the entry and exit moves (as rs274 moves it) stays at least
    a radius inside the true curve."""
    from support.rs274 import run_rs274
    name, job, res, program = arc_job
    r = run_rs274(program, job.tools)
    lines = program.splitlines()
    g41 = {i + 1 for i, s in enumerate(lines) if "G41" in s}
    g40 = {i + 1 for i, s in enumerate(lines) if re.match(r"^(N\d+ )?G40(?!\d)", s.strip())
           and i > 10}
    radius = job.tools[1].radius
    outline = res.design.outline
    pts = []
    for k, m in enumerate(r.motions):
        lead_in = any(m.line in (g + 1, g + 2) for g in g41)
        lead_out = any(m.line in (g - 1, g, g + 1) for g in g40)   # rs274 flushes the arc at G40
        if not (lead_in or lead_out) or m.kind not in ("feed", "arc"):
            continue
        if m.kind == "arc":
            pts.append(_ccw_points(m))
        else:
            pts.append(np.linspace(m.start[:2], m.end[:2], 16))
    assert len(pts) >= 4 * len(g41)
    P = np.concatenate(pts)
    d = shapely.distance(outline.boundary, shapely.points(P))
    assert shapely.contains_xy(outline, P[:, 0], P[:, 1]).all()
    assert d.min() >= radius - 1e-3


def test_arc_entry_needs_control_compensation():
    with pytest.raises(JobError, match="entry"):
        _plan("die-blanking", compensation="cam", entry="arc")
