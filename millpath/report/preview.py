"""Tool path preview: a 3D picture, rapids dashed grey, feeds one colour per operation.

matplotlib is imported only by the functions that draw (object API on an Agg canvas,
no pyplot), so that importing this module costs nothing."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from millpath.model import Toolpath
from millpath.model.toolpath import sample_move


def path_runs(tp: Toolpath, step: float):
    """Yield (op index, is_rapid, (n,3) points) runs of consecutive moves. Straight
    moves (rapid, line) are given by their end points, as they are drawn (a straight
    segment stays straight in the picture's projection); arcs and cubics are sampled
    about ``step`` apart."""
    moves = [m for m in tp.moves if m.kind not in ("comp", "dwell")]
    if len(moves) < 2:
        return
    ends = np.array([m.end for m in moves], dtype=float)
    pos = ends[0]
    chunks: list[np.ndarray] = []
    key = None
    i, n = 1, len(moves)
    while i < n:
        m = moves[i]
        if m.kind in ("rapid", "line"):            # a stretch of them: their end points
            j = i + 1
            while j < n and moves[j].kind == m.kind and moves[j].op == m.op:
                j += 1
            pts = ends[i:j]
            k = (m.op, m.kind == "rapid")
            i = j
        else:
            if m.kind == "drill":
                top = (m.end[0], m.end[1], m.r_plane)
                pts = np.array([(m.end[0], m.end[1], pos[2]), top, m.end, top], dtype=float)
            else:
                pts = sample_move(pos, m, step)[1:]
            k = (m.op, False)
            i += 1
        if k != key:
            if chunks:
                yield key[0], key[1], np.concatenate(chunks)
            chunks = [pos[None, :]]
            key = k
        chunks.append(pts)
        pos = pts[-1]
    if chunks and key is not None:
        yield key[0], key[1], np.concatenate(chunks)


def render_preview(tp: Toolpath, path: str | Path, title: str = "", stock=None) -> None:
    """Write :func:`preview_figure` as a PNG to ``path``."""
    fig = preview_figure(tp, title, stock)
    fig.savefig(path)


def preview_figure(tp: Toolpath, title: str = "", stock=None):
    """A matplotlib figure of the tool path (tip positions).

    Axes are equal (a round bar stays round), spanning the tool path and the stock box
    (``stock``: a :class:`millpath.model.Stock`, drawn as a wire frame) with at most five
    ticks an axis, labelled with the units."""
    from matplotlib import colormaps
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure
    from matplotlib.lines import Line2D
    from matplotlib.ticker import MaxNLocator
    from mpl_toolkits.mplot3d.art3d import Line3DCollection

    from millpath.fit.collinear import kept_points
    ends = tp.ends()
    extent = ends if len(ends) else np.zeros((1, 3))
    if stock is not None:
        b = np.array(stock.box, float)
        extent = np.vstack([extent, b[:3], b[3:]])
    span = float(np.ptp(extent, axis=0).max()) or 1.0
    step = max(span / 400.0, 1e-6)
    fig = Figure(figsize=(8, 6.5), dpi=110)         # on an Agg canvas, without pyplot
    FigureCanvasAgg(fig)
    ax = fig.add_subplot(111, projection="3d")
    ax.set_autoscale_on(False)      # the limits are set below, from ``extent``
    colours = colormaps["tab10"]
    # one collection of every run in program order (later runs drawn over earlier
    # ones), drawn before the stock's wire frame: as many lines would be, in one artist
    ax.computed_zorder = False
    runs, colour, width, style = [], [], [], []
    seen_ops: set[int] = set()
    # points within a fifth of a pixel of the line through their neighbours add
    # nothing to the picture but drawing time (the figure is ~600 px across ``span``)
    thin = span / 3000.0
    for op, rapid, pts in path_runs(tp, step):
        if len(pts) > 2:
            pts = pts[kept_points(pts, thin)]
        runs.append(pts)
        colour.append("0.6" if rapid else colours(op % 10))
        width.append(0.5 if rapid else 0.6)
        style.append("--" if rapid else "-")
        if not rapid:
            seen_ops.add(op)
    if runs:
        ax.add_collection3d(Line3DCollection(runs, colors=colour, linewidths=width,
                                             linestyles=style, zorder=Line2D.zorder))
    handles = [Line2D([], [], color="0.6", ls="--", label="rapid")]
    for op in sorted(seen_ops):
        o = tp.ops[op]
        handles.append(Line2D([], [], color=colours(op % 10), label=f"{o.name} (T{o.tool})"))
    ax.legend(handles=handles, loc="upper left", fontsize=7)
    ax.set_xlabel(f"X [{tp.units}]")
    ax.set_ylabel(f"Y [{tp.units}]")
    ax.set_zlabel(f"Z [{tp.units}]")
    if stock is not None and stock.cylinder is not None:       # a bar: end circles
        cx, cy, r = stock.cylinder
        a = np.linspace(0.0, 2.0 * np.pi, 97)
        for z in (stock.zmin, stock.zmax):
            ax.plot(cx + r * np.cos(a), cy + r * np.sin(a), np.full_like(a, z),
                    color="0.35", lw=0.6)
        for t in a[:-1:24]:
            ax.plot([cx + r * np.cos(t)] * 2, [cy + r * np.sin(t)] * 2,
                    [stock.zmin, stock.zmax], color="0.35", lw=0.6)
        handles.append(Line2D([], [], color="0.35", label="stock"))
        ax.legend(handles=handles, loc="upper left", fontsize=7)
    elif stock is not None:
        x0, y0, z0, x1, y1, z1 = stock.box
        for (xa, ya), (xb, yb) in (((x0, y0), (x1, y0)), ((x1, y0), (x1, y1)),
                                   ((x1, y1), (x0, y1)), ((x0, y1), (x0, y0))):
            for z in (z0, z1):
                ax.plot([xa, xb], [ya, yb], [z, z], color="0.35", lw=0.6)
            ax.plot([xa, xa], [ya, ya], [z0, z1], color="0.35", lw=0.6)
        handles.append(Line2D([], [], color="0.35", label="stock"))
        ax.legend(handles=handles, loc="upper left", fontsize=7)
    lo, hi = extent.min(axis=0), extent.max(axis=0)
    mid, half = (lo + hi) / 2.0, np.maximum((hi - lo) / 2.0, 0.02 * span)
    for setter, m, h in zip((ax.set_xlim, ax.set_ylim, ax.set_zlim), mid, half):
        setter(m - h, m + h)
    ax.set_box_aspect(tuple(2.0 * half))                 # equal scale on X, Y and Z
    for axis, h in zip((ax.xaxis, ax.yaxis, ax.zaxis), half):
        # fewer ticks on a short axis, so that their labels do not overprint
        axis.set_major_locator(MaxNLocator(max(2, min(5, int(10 * h / span) + 1))))
    ax.tick_params(labelsize=7)
    ax.view_init(elev=30, azim=-60)
    ax.set_title(title or "tool path", fontsize=10)
    fig.tight_layout()
    fig.set_layout_engine(None)     # laid out once: no second layout pass when saved
    return fig
