"""Placing a model in the job's frame: rotate, scale, convert units, translate, place.

A surface table may carry, beside what names the model (``file``, ``grid``, a Bezier
net)::

    rotate = [rx, ry, rz]      # degrees about the origin's X, then Y, then Z axes
    scale = s                  # then a uniform scale (> 0)
    units = "inch"             # the model file's units (default: the job's), then converted
    translate = [x, y, z]      # then a translation (job units)
    place = "stock-top"        # or: the model's top on the stock top, centred in X and Y

``translate`` and ``place`` exclude each other. Rotations follow the right-hand rule
(positive = counter-clockwise looking down the axis towards the origin).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from millpath.errors import JobError
from millpath.model.units import MM_PER_INCH
from millpath.part.surface.mesh import Mesh

KEYS = ("rotate", "scale", "units", "translate", "place")
UNIT_MM = {"mm": 1.0, "inch": MM_PER_INCH}


@dataclass
class Placement:
    """How to put a model into the job's frame (see the module docstring)."""

    rotate: tuple[float, float, float] = (0.0, 0.0, 0.0)
    scale: float = 1.0
    units: str | None = None
    translate: tuple[float, float, float] = (0.0, 0.0, 0.0)
    place: str | None = None

    @property
    def is_identity(self) -> bool:
        return (self.rotate == (0.0, 0.0, 0.0) and self.scale == 1.0 and self.units is None
                and self.translate == (0.0, 0.0, 0.0) and self.place is None)


def _triple(v, key: str, file) -> tuple[float, float, float]:
    if (not isinstance(v, list) or len(v) != 3
            or not all(isinstance(a, (int, float)) and not isinstance(a, bool) for a in v)):
        raise JobError(f"surface.{key}: expected 3 numbers [x, y, z], got {v!r}", file)
    out = tuple(float(a) for a in v)
    if not all(math.isfinite(a) for a in out):
        raise JobError(f"surface.{key}: numbers must be finite", file)
    return out


def split_placement(table: dict, file=None) -> tuple[Placement, dict]:
    """The placement keys of a surface table, validated, and the table without them."""
    rest = {k: v for k, v in table.items() if k not in KEYS}
    p = Placement()
    if "rotate" in table:
        p.rotate = _triple(table["rotate"], "rotate", file)
    if "translate" in table:
        p.translate = _triple(table["translate"], "translate", file)
    if "scale" in table:
        s = table["scale"]
        if isinstance(s, bool) or not isinstance(s, (int, float)) or not (
                math.isfinite(s) and s > 0):
            raise JobError(f"surface.scale: expected a positive number, got {s!r}", file)
        p.scale = float(s)
    if "units" in table:
        if table["units"] not in UNIT_MM:
            raise JobError(f"surface.units: mm or inch expected, not {table['units']!r}",
                           file)
        p.units = table["units"]
    if "place" in table:
        if table["place"] != "stock-top":
            raise JobError(f"surface.place: only \"stock-top\" is known, not "
                           f"{table['place']!r}", file)
        if "translate" in table:
            raise JobError("surface: give translate or place, not both", file)
        p.place = table["place"]
    return p, rest


def rotation(rx: float, ry: float, rz: float) -> np.ndarray:
    """Matrix of the rotation about X by ``rx``, then Y by ``ry``, then Z by ``rz``
    (degrees): ``Rz @ Ry @ Rx``."""
    a, b, c = (math.radians(v) for v in (rx, ry, rz))
    Rx = np.array([[1, 0, 0], [0, math.cos(a), -math.sin(a)], [0, math.sin(a), math.cos(a)]])
    Ry = np.array([[math.cos(b), 0, math.sin(b)], [0, 1, 0], [-math.sin(b), 0, math.cos(b)]])
    Rz = np.array([[math.cos(c), -math.sin(c), 0], [math.sin(c), math.cos(c), 0], [0, 0, 1]])
    return Rz @ Ry @ Rx


def place_mesh(mesh: Mesh, p: Placement, job_units: str, stock_box=None, file=None) -> Mesh:
    """``mesh`` moved into the job's frame by ``p``. ``stock_box`` is the job's
    ``(xmin, ymin, zmin, xmax, ymax, zmax)`` (needed for ``place``)."""
    if p.is_identity:
        return mesh
    t = mesh.triangles.reshape(-1, 3)
    if p.rotate != (0.0, 0.0, 0.0):
        t = t @ rotation(*p.rotate).T
    k = p.scale
    if p.units is not None:
        k *= UNIT_MM[p.units] / UNIT_MM[job_units]
    if k != 1.0:
        t = t * k
    t = t + np.array(p.translate)
    if p.place == "stock-top":
        if stock_box is None:
            raise JobError("surface.place: \"stock-top\" needs the job's [stock] box", file)
        x0, y0, _, x1, y1, z1 = (float(v) for v in stock_box)
        lo, hi = t.min(axis=0), t.max(axis=0)
        t = t + np.array([0.5 * (x0 + x1) - 0.5 * (lo[0] + hi[0]),
                          0.5 * (y0 + y1) - 0.5 * (lo[1] + hi[1]), z1 - hi[2]])
    return Mesh(t.reshape(-1, 3, 3), mesh.name)
