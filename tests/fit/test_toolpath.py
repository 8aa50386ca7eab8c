"""fit_toolpath: which moves are rewritten, and what is left alone."""

from __future__ import annotations

import math

import numpy as np
import pytest

from millpath.fit import fit_toolpath
from millpath.model.toolpath import Operation, Toolpath


def arc_points(r=10.0, n=90, z=-1.0, start=0.0, sweep=math.pi):
    t = np.linspace(start, start + sweep, n + 1)
    return [(r * math.cos(a), r * math.sin(a), z) for a in t]


def lines(tp, pts, feed=400.0):
    for p in pts:
        tp.line(*p, feed)


def test_rapids_drills_and_existing_arcs_are_kept():
    tp = Toolpath()
    tp.begin(Operation("a", "a", 1))
    tp.rapid(10, 0, 5)
    tp.drill(10, 0, -5, 1, 100)
    tp.rapid(10, 0, 1)
    tp.arc((0, 10, 1), (0, 0, 1), False, 200)
    tp.rapid(0, 10, 5)
    out = fit_toolpath(tp, 0.01)
    assert out.moves == tp.moves
    assert out.ops == tp.ops and out is not tp


def test_only_lines_under_no_compensation_are_fitted():
    tp = Toolpath()
    tp.begin(Operation("a", "a", 1))
    tp.rapid(10, 0, -1)
    lines(tp, arc_points()[1:])                           # fitted
    tp.compensation("left", 1)
    lines(tp, arc_points(sweep=-math.pi)[1:])             # under G41: kept
    tp.compensation("off")
    lines(tp, arc_points(start=math.pi, sweep=-math.pi)[1:])  # first after G40 kept
    out = fit_toolpath(tp, 0.005)
    kinds = [m.kind for m in out.moves]
    i41 = kinds.index("comp")
    i40 = len(kinds) - 1 - kinds[::-1].index("comp")
    assert "arc" in kinds[:i41]
    assert kinds[i41 + 1:i40] == ["line"] * 90
    assert out.moves[i41 + 1:i40] == tp.moves[92:182]
    assert kinds[i40 + 1] == "line" and out.moves[i40 + 1] == tp.moves[183]
    assert "arc" in kinds[i40 + 2:]


def test_feed_change_and_operation_change_split_runs():
    tp = Toolpath()
    tp.begin(Operation("a", "a", 1))
    tp.rapid(10, 0, -1)
    pts = arc_points(n=180, sweep=2 * math.pi)
    lines(tp, pts[1:91], feed=400)
    lines(tp, pts[91:], feed=200)
    tp.begin(Operation("b", "b", 2))
    lines(tp, arc_points(r=5, n=90)[1:])                  # new tool: start unknown
    out = fit_toolpath(tp, 0.005)
    feeds = [(m.kind, m.feed, m.op) for m in out.moves]
    # the feed change is at vertex 90 (180 degrees): some move ends exactly there
    ends = [m.end for m in out.moves]
    assert any(np.allclose(e, pts[90], atol=1e-4) for e in ends)
    assert all(f in (0.0, 400.0, 200.0) for _, f, _ in feeds)
    first_b = next(i for i, m in enumerate(out.moves) if m.op == 1)
    assert out.moves[first_b] == tp.moves[next(i for i, m in enumerate(tp.moves) if m.op == 1)]
    assert out.moves[first_b].kind == "line"
    assert any(m.kind == "arc" and m.op == 1 for m in out.moves)
    for i in range(1, len(out.moves)):
        if out.moves[i].kind == "arc":
            assert out.moves[i].op == out.moves[i - 1].op


def test_a_toolpath_that_starts_with_lines_keeps_the_first_one():
    tp = Toolpath()
    tp.begin(Operation("a", "a", 1))
    lines(tp, arc_points())
    out = fit_toolpath(tp, 0.005)
    assert out.moves[0] == tp.moves[0] and out.counts()["arc"] >= 1


def test_mode_none_returns_a_copy_and_bad_arguments_raise():
    tp = Toolpath()
    tp.begin(Operation("a", "a", 1))
    tp.rapid(10, 0, -1)
    lines(tp, arc_points()[1:])
    assert fit_toolpath(tp, 0.005, "none").moves == tp.moves
    with pytest.raises(ValueError, match="mode"):
        fit_toolpath(tp, 0.005, "splines")
    for bad in (0.0, -1.0, float("nan"), float("inf")):
        with pytest.raises(ValueError, match="tolerance"):
            fit_toolpath(tp, bad)
    with pytest.raises(ValueError, match="too small"):
        fit_toolpath(tp, 0.00005)


def test_empty_toolpath_and_duplicate_points():
    assert fit_toolpath(Toolpath(), 0.01).moves == []
    tp = Toolpath()
    tp.begin(Operation("a", "a", 1))
    tp.rapid(0, 0, 0)
    for p in [(1, 0, 0), (1, 0, 0), (2, 0, 0), (2.00001, 0, 0), (3, 0, 0)]:
        tp.line(*p, 100)
    out = fit_toolpath(tp, 0.01)
    assert [m.kind for m in out.moves] == ["rapid", "line"]
    assert out.moves[-1].end == (3.0, 0.0, 0.0)
