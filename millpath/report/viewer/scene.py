"""What view.html shows, gathered from a program's motion, its tools, the stock and the
simulation, and written as one page.

All lengths are in the program's units (``units``); coordinates are the tool tip in
program coordinates (:class:`millpath.interpret.motion.Motion`). The motion given is
drawn as it is: pass the motion the simulator swept (after
:func:`millpath.simulate.approach.approach_from_above`) so that picture and proof agree.
"""

from __future__ import annotations

import math
import os
from pathlib import Path
from typing import Any

import numpy as np

from millpath.interpret.motion import Motion
from millpath.io.atomic import write_text
from millpath.model.stock import Stock
from millpath.model.tool import Tool
from millpath.report.viewer.motionpack import (ViewOperation, operations_from_program,
                                               operations_from_toolpath, pack_motions)
from millpath.report.viewer.page import b64, render_page
from millpath.report.viewer.stocksurface import display_surface
from millpath.report.viewer.toolshape import tool_shape
from millpath.model.units import default


def default_tolerance(units: str) -> float:
    """Deviation shown as neutral by default: 0.01 mm, or 0.0005 inch."""
    return default("drawing_tolerance", units)


def _le(a: np.ndarray, dtype: str) -> str:
    return b64(np.ascontiguousarray(a, dtype=np.dtype(dtype).newbyteorder("<")))


def scene_data(*, program: str, motions: list[Motion], tools: dict[int, Tool], stock: Stock,
               units: str, operations: list[ViewOperation] | None = None, sim=None,
               design=None, tolerance: float | None = None, title: str = "",
               program_name: str = "program.ngc", toolpath=None,
               move_lines: list[int | None] | None = None) -> dict[str, Any]:
    """The page's data (a JSON-ready dict).

    ``operations``: the operations list (default: those of ``toolpath`` posted with
    ``move_lines`` when given, else read from the program text, see
    :func:`operations_from_program`). ``sim``: a :class:`millpath.simulate.SimResult`
    whose Z-map is drawn as the stock (and whose worst gouge / leftover are marked when
    ``design`` is given). ``tolerance``: deviations within it are drawn neutral
    (default :func:`default_tolerance`)."""
    if not motions:
        raise ValueError("the program has no motion to show")
    ops = operations
    if ops is None and toolpath is not None and move_lines is not None:
        ops = operations_from_toolpath(toolpath, move_lines) or None
    if ops is None:
        ops = operations_from_program(program, motions)
    span = math.dist(stock.box[:3], stock.box[3:])
    packed = pack_motions(motions, ops, chord_tol=max(span / 4000.0, 1e-6))
    used = sorted({int(t) for t in np.unique(packed.tool)} & set(tools))
    surface = None
    if sim is not None:
        ds = display_surface(sim.zmap, design, gouge_at=sim.gouge_at, left_at=sim.left_at,
                             grid=sim.design_grid)
        surface = {
            "nx": len(ds.xs), "ny": len(ds.ys), "step": ds.step,
            "xs": _le(ds.xs, "f4"), "ys": _le(ds.ys, "f4"),
            "heights": _le(ds.heights, "f4"),
            "deviation": None if ds.deviation is None else _le(ds.deviation, "f4"),
            "design": None if ds.design is None else _le(ds.design, "f4"),
            "zmin": ds.zmin, "ztop": ds.ztop,
            "max_gouge": ds.max_gouge, "max_left": ds.max_left,
            "gouge_at": ds.gouge_at, "left_at": ds.left_at,
        }
    exact = None
    ex = getattr(sim, "exact", None) if sim is not None else None
    if ex is not None:
        def at(d):
            return None if not d else [float(d["x"]), float(d["y"]), float(d["z"])]
        # the proof's own figures (report.json's), measured normal to the design
        exact = {"max_gouge": float(ex.max_gouge), "max_left": float(ex.max_left),
                 "gouge_at": at(ex.gouge_at), "left_at": at(ex.left_at),
                 "accuracy": float(ex.accuracy)}
    return {
        "title": title or program_name,
        "program_name": program_name,
        "units": units,
        "stock": [float(v) for v in stock.box],
        # a bar: [cx, cy, radius] of its circle (drawn instead of the box), else None
        "stock_cylinder": None if stock.cylinder is None else [float(v) for v in stock.cylinder],
        "tolerance": float(tolerance if tolerance is not None else default_tolerance(units)),
        "verification": sim.to_json() if sim is not None else None,
        "operations": [{"name": o.name, "tool": o.tool, "first_line": o.first_line}
                       for o in ops],
        "tools": {str(t): tool_shape(tools[t]) for t in used},
        "program": program,
        "path": {
            "chord_tol": packed.chord_tol,
            "points": _le(packed.points, "f4"), "first": _le(packed.first, "i4"),
            "last": _le(packed.last, "i4"), "kind": _le(packed.kind, "u1"),
            "feed": _le(packed.feed, "f4"), "line": _le(packed.line, "i4"),
            "op": _le(packed.op, "u2"), "tool": _le(packed.tool, "u4"),
        },
        "surface": surface,
        "exact": exact,
    }


def write_view(path: str | Path, **kw) -> Path:
    """Write view.html for the scene of :func:`scene_data` (same keyword arguments) to
    ``path`` atomically; returns the path."""
    from millpath import __version__
    data = scene_data(**kw)
    text = render_page(data, title=data["title"], units=data["units"], version=__version__)
    p = Path(path)
    write_text(p, text)
    umask = os.umask(0)
    os.umask(umask)
    os.chmod(p, 0o666 & ~umask)            # a page to share, like the files beside it
    return p
