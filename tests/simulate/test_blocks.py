"""Long programs are simulated in blocks bounded by motions *and* chords (finely chorded
arcs would otherwise make one block of millions of chords): the blocks cover the program
in order, hold no more chords than asked, and give the same stock and the same exact
figures as one block."""

from __future__ import annotations

import math

import numpy as np
import pytest

from millpath.model import Stock, Tool
from millpath.model.motion import Motion
from millpath.simulate import simulate_motions
from millpath.simulate.exact import Reference, verify_exact
from millpath.simulate.path import chord_count, motion_blocks, motion_points


def _program(n_arcs: int = 12) -> list[Motion]:
    """Full circles of radius 3..8 (alternating G2/G3, 1 mm down each) joined by lines."""
    out, z = [], 0.0
    for k in range(n_arcs):
        r = 3.0 + (k % 6)
        s = (r, 0.0, z)
        out.append(Motion("feed", 2 * k + 1, (r, 0.0, z + 1.0), s, feed=500, tool=1))
        out.append(Motion("arc", 2 * k + 2, s, s, feed=500, tool=1, center=(0.0, 0.0, z),
                          rotation=1 if k % 2 else -1))
        z -= 0.25
    return out


@pytest.mark.parametrize("tol", [0.01, 0.001, 0.00025])
def test_chord_count_is_that_of_the_chords_made(tol):
    for mo in _program():
        assert chord_count(mo, tol) == len(motion_points(mo, tol)) - 1


def test_cubic_chord_count_bounds_the_chords_made():
    cub = Motion("cubic", 1, (0.0, 0.0, -1.0), (10.0, 0.0, -1.0), feed=100, tool=1,
                 controls=((0.0, 8.0), (10.0, 8.0)))
    for tol in (0.1, 0.01, 0.001):
        assert chord_count(cub, tol) >= len(motion_points(cub, tol)) - 1


def test_blocks_cover_the_program_and_bound_the_chords():
    prog = _program()
    tol = 0.001
    counts = [chord_count(m, tol) for m in prog]
    blocks = motion_blocks(prog, tol, max_motions=1000, max_chords=max(counts) + 1)
    assert blocks[0][0] == 0 and blocks[-1][1] == len(prog)
    assert all(b0[1] == b1[0] for b0, b1 in zip(blocks, blocks[1:]))
    for a, b in blocks:
        assert sum(counts[a:b]) <= max(counts) + 1
    assert len(blocks) > 4
    assert motion_blocks(prog, tol, 3, 10 ** 9) == [(a, min(a + 3, len(prog)))
                                                     for a in range(0, len(prog), 3)]
    # one motion with more chords than asked is a block of its own
    assert motion_blocks(prog, tol, 1000, 10) == [(k, k + 1) for k in range(len(prog))]


def test_small_blocks_simulate_and_check_as_one(monkeypatch):
    import millpath.simulate.exact as exact
    import millpath.simulate.simulator as simulator
    prog = _program()
    tools = {1: Tool(1, "flat", 2.0)}
    stock = Stock(-10, -10, -4, 10, 10, 0.5)
    # the design: a plate whose top is 1.6 mm down (the last circles gouge it)
    x0, y0, x1, y1, zt = -10.0, -10.0, 10.0, 10.0, -1.6
    plate = np.array([[(x0, y0, zt), (x1, y0, zt), (x1, y1, zt)],
                      [(x0, y0, zt), (x1, y1, zt), (x0, y1, zt)]])
    ref = Reference(plate, "plate")
    one = simulate_motions(prog, tools, stock, resolution=0.1)
    ex1 = verify_exact(prog, tools, stock, [ref])
    monkeypatch.setattr(simulator, "CHORD_BLOCK", 50)
    monkeypatch.setattr(exact, "CHORD_BLOCK", 50)
    many = simulate_motions(prog, tools, stock, resolution=0.1)
    exn = verify_exact(prog, tools, stock, [ref])
    assert np.array_equal(one.zmap.heights, many.zmap.heights)
    # the last circle (z = -2.75) goes 1.15 below the plate's top
    assert ex1.max_gouge == pytest.approx(1.15, abs=0.001)
    assert exn.max_gouge == ex1.max_gouge and exn.gouging_moves == ex1.gouging_moves
    assert exn.max_left == pytest.approx(ex1.max_left, abs=1e-9)
    assert math.isfinite(exn.max_left)
