"""The planners' economies change no result they promise: zigzag station steps
remembered per station give the pass lines computed afresh at every station, and the
waterline's secant-and-halving search leaves each level point on the low side within
its bracket width of the level (checked with the drop-cutter along the dome's radius,
the direction the surface rises)."""

from __future__ import annotations

import numpy as np

from millpath.part.surface.mesh import function_mesh
from millpath.plan.surface import zigzag as zz
from millpath.geometry.cutter import Cutter
from millpath.plan.surface.dropcutter import build_index, drop
from millpath.plan.surface.sampler import Sampler
from millpath.plan.surface.waterline import WaterlineSettings, waterline


def bumps(x, y):
    """Two bumps and a hollow: curvature across the passes changes along them."""
    return (3.0 * np.exp(-((x - 4) ** 2 + (y - 3) ** 2) / 18.0)
            + 2.0 * np.exp(-((x + 5) ** 2 + (y + 2) ** 2) / 10.0)
            - 1.5 * np.exp(-((x - 1) ** 2 + (y + 6) ** 2) / 8.0))


def dome(x, y, R=7.0):
    return np.sqrt(np.maximum(R * R - x * x - y * y, 0.0))


def test_station_memo_gives_the_pass_lines_computed_afresh(monkeypatch):
    mesh = function_mesh(bumps, (-12.0, 12.0), (-12.0, 12.0), 61, 61, "bumps")
    sampler = Sampler(build_index(mesh), Cutter(2.0, 2.0))
    s = zz.ZigzagSettings(0.01, 0.02, (-10.0, -10.0, 10.0, 10.0))
    u, lines, steps = zz.pass_lines(sampler, None, s)

    def forget(self, u, W):             # every station computed again, every time
        return np.full(len(u), np.nan), np.zeros(len(u), bool)

    monkeypatch.setattr(zz.StepMemo, "lookup", forget)
    monkeypatch.setattr(zz.StepMemo, "store", lambda self, *a: None)
    u2, lines2, steps2 = zz.pass_lines(sampler, None, s)
    assert len(lines) > 10 and len(lines) == len(lines2)
    assert np.array_equal(u, u2)
    # equal to the drop-cutter's last bits (its warm start depends on query order)
    assert max(float(np.max(np.abs(a - b))) for a, b in zip(lines, lines2)) < 1e-9
    assert np.allclose(steps, steps2, rtol=0.0, atol=1e-9)


def test_waterline_level_points_lie_within_the_bracket_width_of_the_level():
    mesh = function_mesh(dome, (-9.0, 9.0), (-9.0, 9.0), 73, 73, "dome")
    index = build_index(mesh)
    cutter = Cutter(2.0, 2.0)
    tol = 0.005
    res = waterline(Sampler(index, cutter),
                    WaterlineSettings(tol, 0.02, (-11.0, -11.0, 11.0, 11.0), min_slope=30.0))
    width = min(1e-3 * cutter.radius, 0.1 * tol)          # the search's promise
    P = np.concatenate([p.points for p in res.passes])
    assert len(P) > 500
    z = drop(index, cutter, P[:, :2]).z
    assert np.all(z <= P[:, 2] + 1e-12)                   # the low side of the level
    r = np.hypot(P[:, 0], P[:, 1])
    uphill = -P[:, :2] / r[:, None]                       # towards the dome's top
    # within the bracket width (along the raster's gradient, a few degrees off the
    # radius: 5 % more) the tip rises above the level
    ahead = drop(index, cutter, P[:, :2] + 1.05 * width * uphill).z
    assert np.all(ahead > P[:, 2])
