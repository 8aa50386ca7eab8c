"""The surface keys shared by the surface operations (``surface-finish``,
``surface-rough``) and loading the surface they name, in the job's units."""

from __future__ import annotations

from pathlib import Path

from millpath.io.schema import Param
from millpath.part.surface.load import load_surface
from millpath.part.surface.mesh import Mesh
from millpath.plan.base import PlanContext

SURFACE_PARAMS = {
    "surface": Param("any", doc="STL/STEP/grid file, Bezier net or grid table, or "
                     "{ file = ..., rotate, scale, units, translate | place = \"stock-top\" }"),
    "divisions": Param("int", 160, positive=True, doc="Bezier tessellation per direction"),
    "chord_tolerance": Param("float", None, positive=True,
                             doc="STEP meshing tolerance (default 0.01 mm / 0.0004 in)"),
}


#: the last surfaces loaded (a job's operations and their preflight share them)
_LOADED: dict[str, Mesh] = {}


def load_op_surface(ctx: PlanContext, params: dict) -> Mesh:
    """The operation's ``surface`` as a mesh (see :mod:`millpath.part.surface.load`);
    the same surface with the same placement is read once (the last four are kept,
    files by their modification time)."""
    tol = params["chord_tolerance"] or (0.0004 if ctx.units == "inch" else 0.01)
    stock_box = ctx.stock.box if ctx.stock is not None else None
    key = repr((params["surface"], params["divisions"], str(ctx.base_dir), tol, ctx.units,
                stock_box, _mtimes(params["surface"], ctx.base_dir)))
    if key not in _LOADED:
        mesh = load_surface(params["surface"], params["divisions"], ctx.base_dir,
                            ctx.job_file, chord_tolerance=tol, units=ctx.units,
                            stock_box=stock_box)
        while len(_LOADED) >= 4:
            _LOADED.pop(next(iter(_LOADED)))
        _LOADED[key] = mesh
    return _LOADED[key]


def _mtimes(surface, base_dir) -> tuple:
    """Modification times of the files ``surface`` names (strings, or ``file``/``grid``
    of a table); 0 where there is none."""
    names = [surface] if isinstance(surface, str) else (
        [v for k, v in surface.items() if k in ("file", "grid") and isinstance(v, str)]
        if isinstance(surface, dict) else [])
    out = []
    for n in names:
        p = Path(n) if Path(n).is_absolute() else Path(base_dir or ".") / n
        try:
            out.append(p.stat().st_mtime_ns)
        except OSError:
            out.append(0)
    return tuple(out)
