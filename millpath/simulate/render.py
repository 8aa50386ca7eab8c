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

from millpath.simulate.zmap import ZMap


def _figure(zmap: ZMap):
    import matplotlib
    matplotlib.use("Agg", force=False)
    import matplotlib.pyplot as plt
    ny, nx = zmap.heights.shape
    w = nx * zmap.dx
    h = ny * zmap.dy
    aspect = h / w if w > 0 else 1.0
    fw = 8.0
    fh = min(12.0, max(3.5, fw * aspect * 0.85 + 1.2))
    fig, ax = plt.subplots(figsize=(fw, fh), dpi=120)
    return plt, fig, ax


def _decimate(a: np.ndarray, max_px: int = 1600) -> tuple[np.ndarray, int]:
    step = max(1, int(np.ceil(max(a.shape) / max_px)))
    return a[::step, ::step], step


def render_stock(zmap: ZMap, path: str | Path, *, title: str = "", units: str = "") -> Path:
    """Write a shaded top view of ``zmap`` to ``path`` (PNG); returns the path."""
    from matplotlib.colors import LightSource, Normalize
    from matplotlib import cm
    plt, fig, ax = _figure(zmap)
    h, step = _decimate(zmap.heights)
    lo, hi = float(zmap.zmin), float(zmap.ztop)
    if hi - lo <= 0:
        hi = lo + 1.0
    norm = Normalize(vmin=lo, vmax=hi)
    cmap = plt.get_cmap("viridis")
    ls = LightSource(azdeg=315, altdeg=40)
    rgb = ls.shade(h, cmap=cmap, norm=norm, blend_mode="soft",
                   vert_exag=1.0, dx=zmap.dx * step, dy=zmap.dy * step)
    ax.imshow(rgb, origin="lower", extent=zmap.extent(), interpolation="nearest")
    sm = cm.ScalarMappable(norm=norm, cmap=cmap)
    cb = fig.colorbar(sm, ax=ax, shrink=0.85)
    cb.set_label(f"stock top Z{f' ({units})' if units else ''}")
    ax.set_xlabel("X")
    ax.set_ylabel("Y")
    ax.set_title(title or "simulated stock")
    ax.set_aspect("equal")
    fig.tight_layout()
    p = Path(path)
    fig.savefig(p)
    plt.close(fig)
    return p


def render_deviation(zmap: ZMap, design, path: str | Path, *, title: str = "",
                     units: str = "", tolerance: float = 0.0) -> Path:
    """Write the deviation of ``zmap`` from ``design`` to ``path`` (PNG).

    Red: the tool went below the design (gouge); blue: material left above it; white:
    within ``tolerance`` (job units). Returns the path."""
    from matplotlib.colors import LinearSegmentedColormap, TwoSlopeNorm
    from millpath.simulate.simulator import deviation
    plt, fig, ax = _figure(zmap)
    dev = deviation(zmap, design)
    if tolerance > 0:
        dev = np.where(np.abs(dev) <= tolerance, 0.0, dev)
    gmax = float(max(-dev.min(), 0.0))
    lmax = float(max(dev.max(), 0.0))
    tiny = 1e-9
    norm = TwoSlopeNorm(vmin=-max(gmax, tiny), vcenter=0.0, vmax=max(lmax, tiny))
    cmap = LinearSegmentedColormap.from_list(
        "gouge_left", [(0.0, "#b2001d"), (0.35, "#f26b5b"), (0.5, "#ffffff"),
                       (0.65, "#6baed6"), (1.0, "#08306b")])
    d, _ = _decimate(dev)
    # keep the extremes visible when decimating: take the block extremes instead
    if d.shape != dev.shape:
        step = int(np.ceil(max(dev.shape) / 1600))
        ny, nx = dev.shape
        pad = np.pad(dev, ((0, (-ny) % step), (0, (-nx) % step)))
        blk = pad.reshape(pad.shape[0] // step, step, pad.shape[1] // step, step)
        mx, mn = blk.max(axis=(1, 3)), blk.min(axis=(1, 3))
        d = np.where(-mn > mx, mn, mx)
    im = ax.imshow(d, origin="lower", extent=zmap.extent(), cmap=cmap, norm=norm,
                   interpolation="nearest")
    cb = fig.colorbar(im, ax=ax, shrink=0.85)
    u = f" ({units})" if units else ""
    cb.set_label(f"deviation{u}: red = gouge (below design), blue = material left")
    ticks = sorted({-gmax, -gmax / 2, 0.0, lmax / 2, lmax})
    cb.set_ticks([t for t in ticks if abs(t) > 0 or t == 0.0])
    ax.set_xlabel("X")
    ax.set_ylabel("Y")
    ax.set_title(title or f"deviation from design: max gouge {gmax:.4g}, "
                          f"max left {lmax:.4g}{u}")
    ax.set_aspect("equal")
    fig.tight_layout()
    p = Path(path)
    fig.savefig(p)
    plt.close(fig)
    return p
