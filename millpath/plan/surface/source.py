"""The surface keys shared by the surface operations (``surface-finish``,
``surface-rough``) and loading the surface they name, in the job's units."""

from __future__ import annotations

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


def load_op_surface(ctx: PlanContext, params: dict) -> Mesh:
    """The operation's ``surface`` as a mesh (see :mod:`millpath.part.surface.load`)."""
    tol = params["chord_tolerance"] or (0.0004 if ctx.units == "inch" else 0.01)
    return load_surface(params["surface"], params["divisions"], ctx.base_dir, ctx.job_file,
                        chord_tolerance=tol, units=ctx.units,
                        stock_box=ctx.stock.box if ctx.stock is not None else None)
