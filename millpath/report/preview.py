"""Tool path preview: a 3D picture, rapids dashed grey, feeds one colour per operation."""

from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.lines import Line2D  # noqa: E402

from millpath.model import Toolpath  # noqa: E402
from millpath.model.toolpath import sample_move  # noqa: E402


def _polylines(tp: Toolpath, step: float):
    """Yield (op index, is_rapid, (n,3) points) runs of consecutive moves."""
    pos = None
    run: list[np.ndarray] = []
    key = None
    for m in tp.moves:
        if m.kind in ("comp",):
            continue
        if pos is None:
            pos = m.end
            continue
        if m.kind == "drill":
            pts = np.array([pos, (m.end[0], m.end[1], pos[2]), (m.end[0], m.end[1], m.r_plane),
                            m.end, (m.end[0], m.end[1], m.r_plane)])
            k = (m.op, False)
            end = tuple(pts[-1])
        else:
            pts = sample_move(pos, m, step)
            k = (m.op, m.kind == "rapid")
            end = m.end
        if k != key and run:
            yield key[0], key[1], np.vstack(run)
            run = []
        key = k
        run.append(pts if not run else pts[1:])
        pos = end
    if run and key is not None:
        yield key[0], key[1], np.vstack(run)


def render_preview(tp: Toolpath, path: str | Path, title: str = "") -> None:
    """Write a PNG of the tool path (tip positions) to ``path``."""
    ends = tp.ends()
    span = float(np.ptp(ends, axis=0).max()) if len(ends) else 1.0
    step = max(span / 400.0, 1e-6)
    fig = plt.figure(figsize=(8, 6.5), dpi=110)
    ax = fig.add_subplot(111, projection="3d")
    colours = plt.get_cmap("tab10")
    seen_ops: set[int] = set()
    for op, rapid, pts in _polylines(tp, step):
        if rapid:
            ax.plot(pts[:, 0], pts[:, 1], pts[:, 2], color="0.6", lw=0.5, ls="--")
        else:
            ax.plot(pts[:, 0], pts[:, 1], pts[:, 2], color=colours(op % 10), lw=0.6)
            seen_ops.add(op)
    handles = [Line2D([], [], color="0.6", ls="--", label="rapid")]
    for op in sorted(seen_ops):
        o = tp.ops[op]
        handles.append(Line2D([], [], color=colours(op % 10), label=f"{o.name} (T{o.tool})"))
    ax.legend(handles=handles, loc="upper left", fontsize=7)
    ax.set_xlabel(f"X [{tp.units}]")
    ax.set_ylabel(f"Y [{tp.units}]")
    ax.set_zlabel(f"Z [{tp.units}]")
    if len(ends):
        lo, hi = ends.min(axis=0), ends.max(axis=0)
        ax.set_box_aspect((max(hi[0] - lo[0], 1e-9), max(hi[1] - lo[1], 1e-9),
                           max(hi[2] - lo[2], 0.05 * span)))
    ax.set_title(title or "tool path", fontsize=10)
    fig.tight_layout()
    fig.savefig(path)
    plt.close(fig)
