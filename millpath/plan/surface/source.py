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

#: the ``plunge_feed`` key of both surface operations (units/min)
PLUNGE_FEED = Param("float", None, positive=True, unit="feed",
                    doc="feed down into material (default: feed / 3)")


def plunge_feed(params: dict, feed: float) -> float:
    """The ``plunge_feed`` key, by default a third of the cutting ``feed``."""
    return params["plunge_feed"] or feed / 3.0


def _surface_key(ctx: PlanContext, params: dict) -> tuple:
    """Everything the operation's mesh depends on (see :mod:`millpath.part.cache`)."""
    return (params["surface"], params["divisions"], ctx.base_dir, _chord_tolerance(ctx, params),
            ctx.units, ctx.stock.box if ctx.stock is not None else None)


def _chord_tolerance(ctx: PlanContext, params: dict) -> float:
    return params["chord_tolerance"] or default("chord_tolerance", ctx.units)


def load_op_surface(ctx: PlanContext, params: dict) -> Mesh:
    """The operation's ``surface`` as a mesh (see :mod:`millpath.part.surface.load`),
    loaded once per job (``ctx.parts``), with a progress bar while it is read."""
    src = params["surface"]
    name = src if isinstance(src, str) else src.get("file", "surface") \
        if isinstance(src, dict) else "surface"

    def load() -> Mesh:
        with ctx.progress.task(f"reading {name}", total=1) as bar:
            mesh = load_surface(src, params["divisions"], ctx.base_dir, ctx.job_file,
                                chord_tolerance=_chord_tolerance(ctx, params), units=ctx.units,
                                stock_box=ctx.stock.box if ctx.stock is not None else None)
            bar.advance()
        return mesh
    return ctx.parts.get("surface", _surface_key(ctx, params), load)


def op_surface_index(ctx: PlanContext, params: dict) -> MeshIndex:
    """The drop-cutter index (default cell) of the operation's surface, built once per
    job (a progress bar while it is built)."""
    mesh = load_op_surface(ctx, params)

    def build() -> MeshIndex:
        with ctx.progress.task(f"indexing {len(mesh.triangles):,} triangles", total=1) as bar:
            index = build_index(mesh)
            bar.advance()
        return index
    return ctx.parts.get("surface-index", _surface_key(ctx, params), build)
