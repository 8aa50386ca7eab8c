"""The tool path preview a machinist reads at a glance (issue 23): equal scale on the
three axes over the stock box, at most five ticks an axis, units on every axis."""

from __future__ import annotations

import numpy as np

from millpath.model import Operation, Stock, Toolpath
from millpath.report.preview import preview_figure, render_preview


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


def _drawn(fig) -> list[tuple[str, np.ndarray]]:
    """(line style, (n, 3) vertices) of every tool path line of the preview (the
    stock's wire frame, colour 0.35, left out)."""
    out = []
    for line in fig.axes[0].lines:
        if line.get_color() == "0.35":
            continue
        xs, ys, zs = line.get_data_3d()
        out.append((line.get_linestyle(), np.column_stack([xs, ys, zs])))
    return out


def test_straight_moves_are_drawn_through_their_end_points_and_arcs_on_their_circle():
    """What the picture draws, against the moves themselves: a run of lines is drawn
    through exactly its end points (a straight segment is straight in the picture),
    a rapid dashed, and a helical arc by points on its circle no further apart than
    the sampling step (the tool path's extent / 400)."""
    tp = Toolpath("mm")
    tp.begin(Operation("pocket", "test", tool=1))
    tp.rapid(0.0, 0.0, 5.0)
    tp.rapid(10.0, 0.0, 5.0)
    tp.line(10.0, 0.0, -1.0, 300.0)
    tp.line(30.0, 0.0, -1.0, 600.0)
    tp.line(30.0, 20.0, -2.0, 600.0)
    tp.arc((10.0, 20.0, -3.0), (20.0, 20.0, -3.0), False, 600.0)   # half circle, r = 10
    fig = preview_figure(tp, "lines and an arc")
    drawn = _drawn(fig)
    assert [ls for ls, _ in drawn] == ["--", "-"]
    assert np.array_equal(drawn[0][1], [[0, 0, 5], [10, 0, 5]])
    feed = drawn[1][1]
    assert np.array_equal(feed[:4], [[10, 0, 5], [10, 0, -1], [30, 0, -1], [30, 20, -2]])
    arc = feed[3:]
    r = np.hypot(arc[:, 0] - 20.0, arc[:, 1] - 20.0)
    assert np.allclose(r, 10.0, atol=1e-9)
    assert np.allclose(arc[[0, -1]], [[30, 20, -2], [10, 20, -3]], atol=1e-12)
    z_span = 5.0 - -3.0
    step = max(30.0, 20.0, z_span) / 400.0
    chords = np.linalg.norm(np.diff(arc, axis=0), axis=1)
    assert chords.max() <= step + 1e-9 and len(arc) >= np.pi * 10.0 / step
    assert np.all(np.diff(arc[:, 2]) <= 0)             # the helix descends steadily
