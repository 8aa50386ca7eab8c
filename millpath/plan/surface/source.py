"""The surface keys shared by the surface operations (``surface-finish``,
``surface-rough``) and loading the surface they name, in the job's units."""

from __future__ import annotations

from millpath.io.schema import Param
from millpath.part.surface.load import load_surface
from millpath.part.surface.mesh import Mesh
from millpath.plan.base import PlanContext
from millpath.plan.surface.dropcutter import MeshIndex, build_index
from millpath.model.units import default

SURFACE_PARAMS = {
    "surface": Param("any", doc="STL/STEP/grid file, Bezier net or grid table, or "
                     "{ file = ..., rotate, scale, units, translate | place = \"stock-top\" }"),
    "divisions": Param("int", 160, positive=True, doc="Bezier tessellation per direction"),
    "chord_tolerance": Param("float", None, positive=True,
                             doc="STEP meshing tolerance (default 0.01 mm / 0.0004 in)"),
}


def load_op_surface(ctx: PlanContext, params: dict) -> Mesh:
    """The operation's ``surface`` as a mesh (see :mod:`millpath.part.surface.load`)."""
    tol = params["chord_tolerance"] or default("chord_tolerance", ctx.units)
    src = params["surface"]
    name = src if isinstance(src, str) else src.get("file", "surface") \
        if isinstance(src, dict) else "surface"
    with ctx.progress.task(f"reading {name}", total=1) as bar:
        mesh = load_surface(src, params["divisions"], ctx.base_dir, ctx.job_file,
                            chord_tolerance=tol, units=ctx.units,
                            stock_box=ctx.stock.box if ctx.stock is not None else None)
        bar.advance()
    return mesh


def indexed(ctx: PlanContext, mesh: Mesh) -> MeshIndex:
    """The drop-cutter index of ``mesh`` (a progress bar while it is built)."""
    with ctx.progress.task(f"indexing {len(mesh.triangles):,} triangles", total=1) as bar:
        index = build_index(mesh)
        bar.advance()
    return index
