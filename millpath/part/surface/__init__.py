"""Surfaces as height fields: Bezier patches and measured grids (job units)."""

from millpath.part.surface.bezier import BezierPatch, bernstein
from millpath.part.surface.grid import MeasuredGrid

__all__ = ["BezierPatch", "MeasuredGrid", "bernstein"]
