"""2D drawings for pocket and profile operations.

- :func:`read_dxf`: DXF entities (LINE, ARC, CIRCLE, LWPOLYLINE with bulges, POLYLINE,
  SPLINE, ELLIPSE, INSERTs exploded) flattened within a chordal tolerance, converted to
  the job's units, joined into closed loops (:mod:`.chains`).
- :func:`regions_from_loops` / :func:`region_from_polygon`: loops nested into regions
  (outer boundary with islands), checked for self-intersections and crossings.
- :func:`shift_region`: a region's contours moved sideways (mitred), to put flattened
  curves wholly on one side of the drawn ones.

Coordinates are the part frame's X and Y in job units. Loops are counter-clockwise.
"""

from millpath.part.drawing.chains import Loop, Piece, join_pieces
from millpath.part.drawing.dxf import read_dxf
from millpath.part.drawing.region import (Region, region_from_polygon, regions_from_loops,
                                          shift_region)

__all__ = ["Loop", "Piece", "Region", "join_pieces", "read_dxf", "region_from_polygon",
           "regions_from_loops", "shift_region"]
