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
