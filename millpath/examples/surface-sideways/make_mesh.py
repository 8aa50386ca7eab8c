"""Generate cavity-sideways.stl: a mould cavity block exported lying on its side.

The block is 60 x 40 x 20 mm; its cavity (a rounded-rectangle bowl 44 x 28 mm across,
10 mm deep, ``z = -10 cos^2(pi q / 2)`` with ``q`` the superellipse distance
``((x/22)^4 + (y/14)^4)^(1/4)``, slopes up to about 48 degrees) is cut into the
60 x 40 face. It is a closed solid (a 0.5 mm top grid, four side walls, a bottom on
the walls' vertices). Like a mould half exported from a CAD assembly (OpenCAMLib's
``ktoolcav.stl``), the file holds it turned so the cavity opens towards -Y: the
block's own (x, y, z) is written as (x, -z, y), which the job's
``rotate = [-90, 0, 0]`` turns back. Run ``python make_mesh.py`` to rebuild the file
(binary STL, about 20,400 triangles; on a 1 mm grid the ball could not reach into the
facets' concave creases and left more than the scallop there).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from millpath.part.surface.mesh import Mesh, grid_triangles, write_stl

LX, LY, LZ = 60.0, 40.0, 20.0          # block, mm; top at z = 0, centred on the origin
A, B, DEPTH = 22.0, 14.0, 10.0         # cavity half-lengths and depth, mm
STEP = 0.5                             # grid, mm


def cavity(x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """Top surface height (mm) of the block with the cavity opening upwards."""
    q = ((np.abs(x) / A) ** 4 + (np.abs(y) / B) ** 4) ** 0.25
    return np.where(q < 1.0, -DEPTH * np.cos(0.5 * np.pi * np.minimum(q, 1.0)) ** 2, 0.0)


def block() -> Mesh:
    """The closed block, cavity up (outward normals)."""
    x = np.linspace(-LX / 2, LX / 2, int(round(LX / STEP)) + 1)
    y = np.linspace(-LY / 2, LY / 2, int(round(LY / STEP)) + 1)
    X, Y = np.meshgrid(x, y)
    top = grid_triangles(x, y, cavity(X, Y))
    # the bottom: the boundary ring's own vertices, triangulated (shared wall edges)
    import shapely
    ring = np.concatenate([np.column_stack([x, np.full_like(x, y[0])]),
                           np.column_stack([np.full_like(y, x[-1]), y])[1:],
                           np.column_stack([x[::-1], np.full_like(x, y[-1])])[1:],
                           np.column_stack([np.full_like(y, x[0]), y[::-1]])[1:-1]])
    tris = shapely.constrained_delaunay_triangles(shapely.Polygon(ring))
    bottom = np.array([[[*c, -LZ] for c in np.asarray(g.exterior.coords)[:3]]
                       for g in tris.geoms])
    n = np.cross(bottom[:, 1] - bottom[:, 0], bottom[:, 2] - bottom[:, 0])[:, 2]
    bottom[n > 0] = bottom[n > 0][:, ::-1]                              # facing down
    walls = []
    for xs, ys in ((x, np.full_like(x, y[0])), (np.full_like(y, x[-1]), y),
                   (x[::-1], np.full_like(x, y[-1])), (np.full_like(y, x[0]), y[::-1])):
        a = np.column_stack([xs[:-1], ys[:-1]])
        b = np.column_stack([xs[1:], ys[1:]])
        za, zb = cavity(a[:, 0], a[:, 1]), cavity(b[:, 0], b[:, 1])
        A3 = np.column_stack([a, za])
        B3 = np.column_stack([b, zb])
        a0 = np.column_stack([a, np.full(len(a), -LZ)])
        b0 = np.column_stack([b, np.full(len(b), -LZ)])
        walls.append(np.stack([A3, a0, b0], axis=1))
        walls.append(np.stack([A3, b0, B3], axis=1))
    return Mesh(np.concatenate([top, bottom, *walls]), "cavity block")


def sideways(m: Mesh) -> Mesh:
    """The block turned so that the cavity opens towards -Y: (x, y, z) -> (x, -z, y)."""
    t = m.triangles
    return Mesh(np.stack([t[..., 0], -t[..., 2], t[..., 1]], axis=-1), "cavity sideways")


if __name__ == "__main__":
    mesh = sideways(block())
    out = Path(__file__).with_name("cavity-sideways.stl")
    write_stl(mesh, out)
    print(f"{out}: {len(mesh)} triangles")
