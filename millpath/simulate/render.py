"""Pictures of a simulation (PNG through matplotlib's Agg backend).

- :func:`render_stock`: the simulated stock seen from above, hill-shaded (light from the
  north-west) and coloured by height, with a height scale bar.
- :func:`render_deviation`: deviation from the design per cell (see
  :func:`millpath.simulate.simulator.deviation`): gouges in red, material left in blue,
  within-design white; each side scaled to its own maximum, with a scale bar.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from millpath.simulate.designgrid import DesignGrid, grid_of
from millpath.simulate.zmap import ZMap


def _figure(zmap: ZMap):
    """A figure on an Agg canvas (no pyplot: cheaper to import, no global state), one
    axes, and the largest image (columns, rows) in pixels the axes can show."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure
    ny, nx = zmap.heights.shape
    w = nx * zmap.dx
    h = ny * zmap.dy
    aspect = h / w if w > 0 else 1.0
    fw = 8.0
    fh = min(12.0, max(3.5, fw * aspect * 0.85 + 1.2))
    dpi = 120
    fig = Figure(figsize=(fw, fh), dpi=dpi)
    FigureCanvasAgg(fig)
    # margins about those tight_layout gave (the colorbar takes its room from the axes)
    fig.subplots_adjust(left=0.08, right=0.97, bottom=0.1, top=0.93)
    ax = fig.add_subplot()
    return fig, ax, (int(fw * dpi), int(fh * dpi))


def _step(a: np.ndarray, shown: tuple[int, int]) -> int:
    """Stride that brings ``a`` (rows, columns) within ``shown`` (columns, rows) pixels:
    the image is drawn at about the size it is shown, not resampled down by Agg."""
    ny, nx = a.shape
    return max(1, int(np.ceil(nx / shown[0])), int(np.ceil(ny / shown[1])))


def _decimate(a: np.ndarray, shown: tuple[int, int]) -> tuple[np.ndarray, int]:
    step = _step(a, shown)
    return a[::step, ::step], step


def render_stock(zmap: ZMap, path: str | Path, *, title: str = "", units: str = "") -> Path:
    """Write a shaded top view of ``zmap`` to ``path`` (PNG); returns the path."""
    from matplotlib import cm, colormaps
    from matplotlib.colors import LightSource, Normalize
    fig, ax, shown = _figure(zmap)
    h, step = _decimate(zmap.heights, shown)
    lo, hi = float(zmap.heights.min()), float(zmap.ztop)
    if hi - lo <= 1e-12:
        lo = float(zmap.zmin) if zmap.zmin < hi else hi - 1.0
    norm = Normalize(vmin=lo, vmax=hi)
    cmap = colormaps["viridis"]
    ls = LightSource(azdeg=315, altdeg=40)
    rgb = ls.shade(h, cmap=cmap, norm=norm, blend_mode="soft",
                   vert_exag=1.0, dx=zmap.dx * step, dy=zmap.dy * step)
    ax.imshow(rgb, origin="lower", extent=zmap.extent(), interpolation="nearest")
    sm = cm.ScalarMappable(norm=norm, cmap=cmap)
    cb = fig.colorbar(sm, ax=ax, shrink=0.85)
    cb.set_label(f"stock top Z{f' ({units})' if units else ''}")
    return _save_plan_view(fig, ax, path, title or "simulated stock")


def _save_plan_view(fig, ax, path, title: str) -> Path:
    """Label the plan view ``ax`` (X, Y, equal scale, ``title``), write ``fig`` to
    ``path``."""
    ax.set_xlabel("X")
    ax.set_ylabel("Y")
    ax.set_title(title)
    ax.set_aspect("equal")
    p = Path(path)
    # cropped to what is drawn (labels never clipped), 0.15 in around it: the box is
    # measured once without rasterising, so the figure is drawn once (savefig's
    # bbox_inches="tight" would draw it twice, and tight_layout a third time)
    box = fig.get_tightbbox(fig.canvas.get_renderer()).padded(0.15)
    fig.savefig(p, bbox_inches=box)
    return p


def _design_outline(ax, zmap: ZMap, grid: DesignGrid, max_px: int = 600) -> None:
    """Thin grey contours of the design's height (its values at the cell centres of
    ``grid``, every ``step``-th), so deviations can be placed."""
    ny, nx = zmap.heights.shape
    step = max(1, int(np.ceil(max(nx, ny) / max_px)))
    xs, ys = zmap.xs()[::step], zmap.ys()[::step]
    X, Y = np.meshgrid(xs, ys)
    z = grid.centre[::step, ::step]
    z = np.where(np.isfinite(z), z, zmap.zmin)
    z = np.clip(z, zmap.zmin, zmap.ztop)
    lo, hi = float(z.min()), float(z.max())
    if hi - lo <= 1e-9 * max(1.0, abs(hi)) or len(xs) < 2 or len(ys) < 2:
        return
    levels = np.linspace(lo, hi, 9)[1:-1] if hi - lo > 0 else []
    levels = np.unique(np.concatenate([levels, [lo + 1e-6 * (hi - lo)]]))
    ax.contour(X, Y, z, levels=levels, colors="0.45", linewidths=0.5, alpha=0.8)


def render_deviation(zmap: ZMap, design, path: str | Path, *, title: str = "",
                     units: str = "", tolerance: float = 0.0,
                     gouge_at=None, left_at=None, gouge: float | None = None,
                     left: float | None = None, grid: DesignGrid | None = None) -> Path:
    """Write the deviation of ``zmap`` from ``design`` to ``path`` (PNG).

    Red: the tool went below the design (gouge); blue: material left above it; white:
    within ``tolerance`` (job units; pass the proof's accuracy: a deviation below it is
    no figure, and a scale stretched to rounding noise would paint it red). Grey lines: contours of the design's height;
    circles mark the largest gouge and the most material left: where the exact check
    found them when ``gouge_at`` / ``left_at`` ((x, y), with the figures ``gouge`` /
    ``left``) are given (walls included), else the Z-map's extreme cells. ``grid``: the
    design already sampled on ``zmap`` (``SimResult.design_grid``), used when it is that
    of ``design``. Returns the path."""
    from matplotlib.colors import LinearSegmentedColormap, Normalize, TwoSlopeNorm
    from millpath.simulate.simulator import deviation
    fig, ax, shown = _figure(zmap)
    grid = grid_of(zmap, design, grid)
    dev = deviation(zmap, grid)
    if tolerance > 0:
        dev = np.where(np.abs(dev) <= tolerance, 0.0, dev)
    gmax = max(float(-dev.min()), 0.0) + 0.0        # + 0.0: no "-0" in titles
    lmax = max(float(dev.max()), 0.0) + 0.0
    red = ["#b2001d", "#f26b5b", "#ffffff"]
    blue = ["#ffffff", "#6baed6", "#08306b"]
    if gmax > 0 and lmax > 0:
        norm = TwoSlopeNorm(vmin=-gmax, vcenter=0.0, vmax=lmax)
        cmap = LinearSegmentedColormap.from_list("dev", red + blue[1:])
        ticks = [-gmax, -gmax / 2, 0.0, lmax / 2, lmax]
    elif gmax > 0:
        norm = Normalize(vmin=-gmax, vmax=0.0)
        cmap = LinearSegmentedColormap.from_list("dev", red)
        ticks = [-gmax, -gmax / 2, 0.0]
    else:
        top = lmax if lmax > 0 else 1.0
        norm = Normalize(vmin=0.0, vmax=top)
        cmap = LinearSegmentedColormap.from_list("dev", blue)
        ticks = [0.0, top / 2, top]
    # keep the extremes visible when decimating: take the block extremes
    step = _step(dev, shown)
    d = dev
    if step > 1:
        ny, nx = dev.shape
        pad = np.pad(dev, ((0, (-ny) % step), (0, (-nx) % step)))
        blk = pad.reshape(pad.shape[0] // step, step, pad.shape[1] // step, step)
        mx, mn = blk.max(axis=(1, 3)), blk.min(axis=(1, 3))
        d = np.where(-mn > mx, mn, mx)
    im = ax.imshow(d, origin="lower", extent=zmap.extent(), cmap=cmap, norm=norm,
                   interpolation="nearest")
    _design_outline(ax, zmap, grid)
    ny, nx = dev.shape
    xs, ys = zmap.xs(), zmap.ys()
    marks = []
    if gouge_at is not None:
        marks.append((gouge_at[0], gouge_at[1], "#b2001d", f"max gouge {gouge or 0:.3g}"))
    elif gmax > 0:
        j, i = np.unravel_index(int(np.argmin(dev)), dev.shape)
        marks.append((xs[i], ys[j], "#b2001d", f"max gouge {gmax:.3g}"))
    if left_at is not None:
        marks.append((left_at[0], left_at[1], "#08306b", f"max left {left or 0:.3g}"))
    elif lmax > 0:
        j, i = np.unravel_index(int(np.argmax(dev)), dev.shape)
        marks.append((xs[i], ys[j], "#08306b", f"max left {lmax:.3g}"))
    for x, y, colour, label in marks:
        ax.plot([x], [y], marker="o", markersize=14, markerfacecolor="none",
                markeredgecolor=colour, markeredgewidth=1.8, linestyle="none", label=label,
                clip_on=False, zorder=5)
    if marks:
        ax.legend(loc="upper right", fontsize=8, framealpha=0.85)
    cb = fig.colorbar(im, ax=ax, shrink=0.85)
    u = f" ({units})" if units else ""
    within = f", white: within ±{tolerance:.3g}" if tolerance > 0 else ""
    cb.set_label(f"deviation{u}\nred: gouge (below design), blue: material left{within}")
    cb.set_ticks(ticks)
    cb.set_ticklabels([f"{t:.3g}" for t in ticks])
    if not title and (gouge is not None or left is not None):
        # the figures of the exact check; the colours stay the Z-map cells' deviation
        title = (f"exact: max gouge {gouge or 0.0:.4g}, max left {left or 0.0:.4g}{u}\n"
                 f"colours: deviation of the stock model's cells")
    return _save_plan_view(fig, ax, path, title or f"deviation from design: max gouge "
                                              f"{gmax:.4g}, max left {lmax:.4g}{u}")
