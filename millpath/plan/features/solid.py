"""A ``features`` operation on a STEP solid (no AP224 features in the file): read the
body, recognise its features (:mod:`millpath.part.brep.recognise`), and provide the
solid itself, tessellated, as the design for verification.

Job keys used here: ``body`` (number or name, needed when the file has several solids),
``setup`` (the file's axis that points up, default '+Z'), ``stock_step`` (a STEP solid
whose bounding box is the stock, e.g. the raw piece). The stock is the job's, else
``stock_step``'s box, else the part's bounding box; the part must lie inside it.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from millpath.errors import PlanningError
from millpath.model import Stock
from millpath.model.units import length_scale
from millpath.part.step.ap224 import Part
from millpath.part.step.shapes import ShapeSet


@dataclass
class SolidPart:
    part: Part                       # the feature model (features with their faces)
    shapes: ShapeSet                 # file units
    stock_box: tuple                 # file units
    box: tuple                       # the part's bounds, file units
    solid: Any = field(repr=False)   # OpenCASCADE shape, mm
    info: dict = field(default_factory=dict)


def _mm(units: str) -> float:
    return length_scale(units, "mm")


def bounds_mm(shape) -> tuple:
    from OCP.Bnd import Bnd_Box
    from OCP.BRepBndLib import BRepBndLib
    b = Bnd_Box()
    BRepBndLib.AddOptimal_s(shape, b, False, False)
    b.SetGap(0.0)
    lo, hi = b.CornerMin(), b.CornerMax()
    return (lo.X(), lo.Y(), lo.Z(), hi.X(), hi.Y(), hi.Z())


def load_solid(path: Path, *, body=None, setup: str = "+Z", stock_step: Path | None = None,
               job_stock: Stock | None = None, job_units: str = "mm") -> SolidPart:
    """Read and recognise the solid of ``path`` (see the module docstring)."""
    from millpath.part.brep.reader import choose_body, read_solids
    from millpath.part.brep.recognise import recognise

    bf = read_solids(path, setup)
    b = choose_body(bf, body)
    part_box = bounds_mm(b.shape)
    if job_stock is not None:
        sb = tuple(v * _mm(job_units) for v in job_stock.box)
        what = "the job's stock"
    elif stock_step is not None:
        raw = read_solids(stock_step, setup)
        sb = bounds_mm(choose_body(raw, None).shape)
        what = f"the stock solid {Path(stock_step).name}"
    else:
        sb = part_box
        what = ""
    if what:
        slack = 1e-3
        if any(part_box[i] < sb[i] - slack for i in range(3)) or \
                any(part_box[i] > sb[i] + slack for i in range(3, 6)):
            f = _mm(job_units)
            pb = ", ".join(f"{v / f:.6g}" for v in part_box)
            ss = ", ".join(f"{v / f:.6g}" for v in sb)
            raise PlanningError(f"{b.entity}: the part [{pb}] is bigger than {what} [{ss}]",
                                path)
    k = 1.0 / bf.units.length_mm
    rec = recognise(b.shape, sb, k)
    part = Part(file=str(path), schema=bf.schema, product=bf.product, units=bf.units,
                stock=None, material=bf.material, features=rec.features)
    info = {"body": b.index, "name": b.name, "entity": b.entity, "faces": rec.faces,
            "setup": setup, "bodies": len(bf.bodies)}
    return SolidPart(part, rec.shapes, tuple(v * k for v in sb), rec.box, b.shape, info)


class SolidDesign:
    """The solid, tessellated within a chord tolerance, as the design: ``vertices``
    (n, 3) and ``triangles`` (m, 3) (job units, outward winding), and ``height(x, y)``:
    the highest point of the solid above (x, y), ``-inf`` off it. :meth:`mesh` gives
    the triangles the exact verification measures against, meshed anew within its
    accuracy."""

    #: the reference mesh's deflection, a fraction of the verification's accuracy (how
    #: far its facets really stand from the faces is measured: ``chord_error``)
    REFERENCE_FRACTION = 0.25

    def __init__(self, solid, chord_tolerance: float, units: str = "mm"):
        from millpath.part.brep.mesh import solid_mesh
        from millpath.part.surface.mesh import Mesh
        from millpath.plan.surface.dropcutter import MeshHeight, build_index
        f = _mm(units)
        self.solid = solid
        self.units = units
        v, t = solid_mesh(solid, chord_tolerance * f)
        self.vertices = v / f
        self.triangles = t
        self.chord_error: float | None = None      # of the last :meth:`mesh`, job units
        self._height = MeshHeight(build_index(Mesh(self.vertices[self.triangles], "solid")))
        self._reference: dict[float, tuple[np.ndarray, float]] = {}

    def height(self, x, y) -> np.ndarray:
        return self._height.height(x, y)

    def mesh(self, accuracy: float | None = None) -> np.ndarray:
        """Triangles (n, 3, 3) of the solid (job units, outward winding) meshed with a
        deflection of ``REFERENCE_FRACTION * accuracy`` (job units); without
        ``accuracy`` the design's own triangles. Sets ``chord_error`` (measured)."""
        if accuracy is None:
            return self.vertices[self.triangles]
        if accuracy not in self._reference:
            from millpath.part.brep.mesh import reference_mesh
            f = _mm(self.units)
            v, t, err = reference_mesh(self.solid, self.REFERENCE_FRACTION * accuracy * f)
            self._reference[accuracy] = (v[t] / f, err / f)
        tri, self.chord_error = self._reference[accuracy]
        return tri
