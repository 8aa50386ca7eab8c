"""Generate cavity.stl: a flat top (z = 0) over 50 x 40 mm with a deep narrow cavity.

The cavity is a stadium (slot) 30 x 20 mm at the top, centred at (25, 20), 18 mm deep,
with 80-degree walls and a 4 mm fillet between wall and floor, so its smallest concave
radius is about 4 mm. Run ``python make_surface.py`` to rebuild the file (binary STL,
0.4 mm grid, about 25,000 triangles).
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from millpath.part.surface.mesh import function_mesh, write_stl

DEPTH, WALL, FILLET = 18.0, math.radians(80.0), 4.0
HALF_LEN, HALF_WIDTH = 15.0, 10.0


def depth_profile(d: np.ndarray) -> np.ndarray:
    """Z at distance ``d`` inside the top edge (mm; ``d <= 0`` is the top plane)."""
    t = math.tan(WALL)
    # the fillet circle is tangent to the floor z = -DEPTH and to the wall z = -t d,
    # its centre on the air side of both
    k = math.hypot(t, 1.0)
    cz = -DEPTH + FILLET                                   # fillet centre height
    cd = (FILLET * k - cz) / t                             # at FILLET from the wall
    d_wall_end = cd - FILLET * t / k                       # tangent point on the wall
    z = np.where(d <= 0.0, 0.0, -t * d)
    in_fillet = (d > d_wall_end) & (d < cd)
    z = np.where(in_fillet, cz - np.sqrt(np.maximum(FILLET ** 2 - (d - cd) ** 2, 0.0)), z)
    return np.where(d >= cd, -DEPTH, z)


def cavity(x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """The surface height (mm) over the 50 x 40 mm plate."""
    px = np.clip(x - 25.0, -(HALF_LEN - HALF_WIDTH), HALF_LEN - HALF_WIDTH)
    dist_axis = np.hypot(x - 25.0 - px, y - 20.0)
    return depth_profile(HALF_WIDTH - dist_axis)


if __name__ == "__main__":
    mesh = function_mesh(cavity, (0.0, 50.0), (0.0, 40.0), 126, 101, "cavity")
    out = Path(__file__).with_name("cavity.stl")
    write_stl(mesh, out)
    print(f"{out}: {len(mesh)} triangles")
