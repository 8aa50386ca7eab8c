"""The tool path preview a machinist reads at a glance: equal scale on the
three axes over the stock box, at most five ticks an axis, units on every axis."""

from __future__ import annotations

import numpy as np

from millpath.model import Operation, Stock, Toolpath
from millpath.report.preview import path_runs, preview_figure, render_preview


def _bar_toolpath() -> Toolpath:
    tp = Toolpath("mm")
    tp.begin(Operation("contour", "round bar", tool=1))
    tp.rapid(60.0, 50.0, 5.0)
    tp.line(60.0, 50.0, -40.0, 100.0)
    return tp


def test_axes_have_equal_scale_over_the_stock_and_name_the_units(tmp_path):
    stock = Stock.from_box([0, 0, -80, 100, 100, 0])          # a tall round bar's box
    fig = preview_figure(_bar_toolpath(), "bar", stock)
    ax = fig.axes[0]
    lims = np.array([ax.get_xlim(), ax.get_ylim(), ax.get_zlim()])
    spans = lims[:, 1] - lims[:, 0]
    aspect = np.asarray(ax.get_box_aspect())
    assert np.allclose(aspect / aspect[0], spans / spans[0], rtol=1e-6)   # equal scale
    assert lims[0, 0] <= 0 and lims[0, 1] >= 100 and lims[2, 0] <= -80 and lims[2, 1] >= 5
    for axis in (ax.xaxis, ax.yaxis, ax.zaxis):
        assert 2 <= len(axis.get_ticklocs()) <= 7
    assert [ax.get_xlabel(), ax.get_ylabel(), ax.get_zlabel()] == ["X [mm]", "Y [mm]", "Z [mm]"]
    render_preview(_bar_toolpath(), tmp_path / "p.png", "bar", stock)
    assert (tmp_path / "p.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"



def test_straight_moves_are_drawn_through_their_end_points_and_arcs_on_their_circle():
    """What the picture draws, against the moves themselves: a run of lines is drawn
    through exactly its end points (a straight segment is straight in the picture),
    a rapid dashed, and a helical arc by points on its circle no further apart than
    the sampling step (the tool path's extent / 400); the figure holds every run."""
    tp = Toolpath("mm")
    tp.begin(Operation("pocket", "test", tool=1))
    tp.rapid(0.0, 0.0, 5.0)
    tp.rapid(10.0, 0.0, 5.0)
    tp.line(10.0, 0.0, -1.0, 300.0)
    tp.line(30.0, 0.0, -1.0, 600.0)
    tp.line(30.0, 20.0, -2.0, 600.0)
    tp.arc((10.0, 20.0, -3.0), (20.0, 20.0, -3.0), False, 600.0)   # half circle, r = 10
    step = 30.0 / 400.0                                  # extent: 30 x 20 x 8 mm
    runs = list(path_runs(tp, step))
    assert [(op, rapid) for op, rapid, _ in runs] == [(0, True), (0, False)]
    assert np.array_equal(runs[0][2], [[0, 0, 5], [10, 0, 5]])
    feed = runs[1][2]
    assert np.array_equal(feed[:4], [[10, 0, 5], [10, 0, -1], [30, 0, -1], [30, 20, -2]])
    arc = feed[3:]
    r = np.hypot(arc[:, 0] - 20.0, arc[:, 1] - 20.0)
    assert np.allclose(r, 10.0, atol=1e-9)
    assert np.allclose(arc[[0, -1]], [[30, 20, -2], [10, 20, -3]], atol=1e-12)
    chords = np.linalg.norm(np.diff(arc, axis=0), axis=1)
    assert chords.max() <= step + 1e-9 and len(arc) >= np.pi * 10.0 / step
    assert np.all(np.diff(arc[:, 2]) <= 0)             # the helix descends steadily
    fig = preview_figure(tp, "lines and an arc")
    (paths,) = fig.axes[0].collections
    assert len(paths.get_linestyles()) == 2
