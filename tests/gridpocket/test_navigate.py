"""Window-frame navigation, the reversed main path and the zigzag clean-up runs."""

from __future__ import annotations

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from millpath.plan.gridpocket.navigate import (adjacent, joined_edges, main_path, navigate,
                                               zigzag_runs)


def test_full_rectangle_spirals_inward_counter_clockwise_without_jumps():
    mask = np.ones((5, 4), bool)
    order = navigate(mask)
    # bottom row left to right, right column up, top row right to left, left column down
    assert order[:5] == [(i, 0) for i in range(5)]
    assert order[5:8] == [(4, 1), (4, 2), (4, 3)]
    assert order[8:12] == [(3, 3), (2, 3), (1, 3), (0, 3)]
    assert order[12:14] == [(0, 2), (0, 1)]
    # then the next ring starts with +X (the priority after -Y when -Y is blocked)
    assert order[14] == (1, 1)
    assert all(adjacent(a, b) for a, b in zip(order[:-1], order[1:]))


def test_navigation_starts_at_the_leftmost_cell_of_the_lowest_row():
    mask = np.zeros((6, 5), bool)
    mask[2:5, 1:4] = True
    mask[1, 2] = True
    assert navigate(mask)[0] == (2, 1)


def test_direction_priority_follows_the_previous_move():
    # after a +Y move the tool keeps going +Y even though -X is also free
    mask = np.ones((3, 3), bool)
    order = navigate(mask)
    assert order[:5] == [(0, 0), (1, 0), (2, 0), (2, 1), (2, 2)]


def test_boxed_in_jumps_to_the_nearest_unvisited_cell():
    # a U shape: the spiral gets boxed in at the end of one arm
    mask = np.ones((5, 4), bool)
    mask[2, 1:] = False
    order = navigate(mask)
    jumps = [(a, b) for a, b in zip(order[:-1], order[1:]) if not adjacent(a, b)]
    assert jumps, "a U shape cannot be covered without a jump"
    visited = set()
    for a, b in zip(order[:-1], order[1:]):
        visited.add(a)
        if not adjacent(a, b):
            left = [c for c in zip(*np.nonzero(mask)) if c not in visited]
            d = [np.hypot(c[0] - a[0], c[1] - a[1]) for c in left]
            assert np.hypot(b[0] - a[0], b[1] - a[1]) == min(d)


def test_main_path_is_the_navigation_reversed_and_ends_at_the_wall():
    mask = np.ones((7, 5), bool)
    nav = navigate(mask)
    path = main_path(mask)
    assert path == nav[::-1]
    assert path[-1] == (0, 0)                      # the start cell, on the wall
    assert 1 <= path[0][0] <= 5 and 1 <= path[0][1] <= 3   # starts inside, near the middle


def test_dx_dy_scale_the_jump_distance():
    mask = np.zeros((9, 9), bool)
    mask[0, 0] = True
    mask[3, 0] = True      # 3 cells away in X
    mask[0, 2] = True      # 2 cells away in Y
    assert navigate(mask, dx=1.0, dy=1.0)[1] == (0, 2)
    assert navigate(mask, dx=0.5, dy=1.0)[1] == (3, 0)


@settings(max_examples=60, deadline=None)
@given(st.integers(2, 9), st.integers(2, 9), st.integers(0, 10_000))
def test_navigation_visits_every_inside_cell_once(nx, ny, seed):
    rng = np.random.default_rng(seed)
    mask = rng.random((nx, ny)) < 0.7
    order = navigate(mask)
    assert len(order) == int(mask.sum())
    assert len(set(order)) == len(order)
    assert all(mask[c] for c in order)


@settings(max_examples=40, deadline=None)
@given(st.integers(2, 9), st.integers(2, 9), st.integers(0, 10_000))
def test_zigzag_runs_join_exactly_the_pairs_the_main_path_missed(nx, ny, seed):
    rng = np.random.default_rng(seed)
    mask = rng.random((nx, ny)) < 0.75
    path = main_path(mask)
    joined = joined_edges(path)
    for axis in (0, 1):
        runs = zigzag_runs(mask, joined, axis)
        got = set()
        for run in runs:
            assert len(run) >= 2
            for a, b in zip(run[:-1], run[1:]):
                assert adjacent(a, b) and a[1 - axis] == b[1 - axis]   # straight along axis
                got.add((min(a, b), max(a, b)))
        want = set()
        for i in range(nx):
            for j in range(ny):
                b = (i + 1, j) if axis == 0 else (i, j + 1)
                if b[0] < nx and b[1] < ny and mask[i, j] and mask[b]:
                    e = ((i, j), b)
                    if e not in joined:
                        want.add(e)
        assert got == want


def test_zigzag_rows_alternate_direction():
    mask = np.ones((4, 3), bool)
    runs = zigzag_runs(mask, set(), 0)
    assert runs[0] == [(0, 0), (1, 0), (2, 0), (3, 0)]
    assert runs[1] == [(3, 1), (2, 1), (1, 1), (0, 1)]
    assert runs[2] == [(0, 2), (1, 2), (2, 2), (3, 2)]
