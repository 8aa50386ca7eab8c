"""Triangle meshes: STL reading (binary and ASCII) and generated test surfaces.

A :class:`Mesh` is an ``(n, 3, 3)`` float64 array of triangles (triangle, corner, xyz)
in the job's units (mm or inch), part frame, Z up. Orientation of the triangles is not
used: drop-cutter queries treat every triangle as seen from above.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Callable

import numpy as np

from millpath.errors import GeometryError
from millpath.io.text import MAX_COORDINATE


@dataclass
class Mesh:
    """Triangles ``(n, 3, 3)`` (job units). ``name`` is used in messages."""

    triangles: np.ndarray
    name: str = "mesh"

    def __post_init__(self) -> None:
        t = np.ascontiguousarray(self.triangles, dtype=np.float64)
        if t.ndim != 3 or t.shape[1:] != (3, 3):
            raise GeometryError(f"triangles must have shape (n, 3, 3), got {t.shape}",
                                entity=self.name)
        if len(t) == 0:
            raise GeometryError("the mesh has no triangles", entity=self.name)
        if not np.all(np.isfinite(t)):
            bad = int(np.argmax(~np.all(np.isfinite(t), axis=(1, 2))))
            raise GeometryError(f"triangle {bad} has a non-finite coordinate",
                                entity=self.name)
        self.triangles = t

    def __len__(self) -> int:
        return len(self.triangles)

    @property
    def bounds(self) -> tuple[np.ndarray, np.ndarray]:
        """(min xyz, max xyz) of all vertices."""
        p = self.triangles.reshape(-1, 3)
        return p.min(axis=0), p.max(axis=0)

    def normals(self) -> np.ndarray:
        """Unit normals ``(n, 3)`` oriented upward (nz >= 0); zero for degenerate triangles."""
        t = self.triangles
        n = np.cross(t[:, 1] - t[:, 0], t[:, 2] - t[:, 0])
        n[n[:, 2] < 0] *= -1.0
        ln = np.linalg.norm(n, axis=1)
        ok = ln > 0
        n[ok] /= ln[ok, None]
        return n


def read_stl(path: str | Path) -> Mesh:
    """Read a binary or ASCII STL file (job units are the file's numbers as they are)."""
    p = Path(path)
    if not p.is_file():
        raise GeometryError("no such STL file", p)
    try:
        from stl import mesh as stl_mesh
        with np.errstate(all="ignore"):          # normals of absurd facets overflow
            m = stl_mesh.Mesh.from_file(str(p))
    except Exception as e:  # numpy-stl raises assorted errors on malformed files
        raise GeometryError(f"cannot read STL: {e}", p) from None
    tris = np.asarray(m.vectors, dtype=np.float64).reshape(-1, 3, 3)
    if len(tris) == 0:
        raise GeometryError("the STL file has no triangles", p)
    if not np.all(np.isfinite(tris)):
        bad = int(np.argmax(~np.all(np.isfinite(tris), axis=(1, 2))))
        raise GeometryError(f"facet {bad} has a non-finite coordinate", p)
    if np.abs(tris).max() > MAX_COORDINATE:
        bad = int(np.argmax(np.abs(tris).max(axis=(1, 2)) > MAX_COORDINATE))
        raise GeometryError(f"facet {bad} has a coordinate larger than {MAX_COORDINATE:g}", p)
    area2 = np.linalg.norm(np.cross(tris[:, 1] - tris[:, 0], tris[:, 2] - tris[:, 0]), axis=1)
    if not np.any(area2 > 1e-12 * max(1.0, float(np.abs(tris).max())) ** 2):
        raise GeometryError(f"none of the {len(tris)} facets has an area (all degenerate)", p)
    return Mesh(tris, p.name)


def write_stl(mesh: Mesh, path: str | Path, ascii: bool = False) -> None:
    """Write a mesh as STL (binary by default)."""
    from stl import Mode
    from stl import mesh as stl_mesh
    m = stl_mesh.Mesh(np.zeros(len(mesh), dtype=stl_mesh.Mesh.dtype))
    m.vectors[:] = mesh.triangles
    m.update_normals()
    m.save(str(path), mode=Mode.ASCII if ascii else Mode.BINARY)


def grid_triangles(x: np.ndarray, y: np.ndarray, z: np.ndarray) -> np.ndarray:
    """Triangulate a height grid ``z[j, i]`` over ``x[i]``, ``y[j]``: two triangles per cell.

    Returns ``(2 (nx-1) (ny-1), 3, 3)``. The diagonal alternates between cells so the
    mesh has no preferred direction.
    """
    x = np.asarray(x, float)
    y = np.asarray(y, float)
    z = np.asarray(z, float)
    X, Y = np.meshgrid(x, y)
    P = np.stack([X, Y, z], axis=-1)          # (ny, nx, 3)
    a, b = P[:-1, :-1], P[:-1, 1:]
    c, d = P[1:, 1:], P[1:, :-1]
    flip = ((np.arange(len(y) - 1)[:, None] + np.arange(len(x) - 1)[None, :]) % 2) == 1
    f = flip[..., None]
    t1 = np.stack([a, b, np.where(f, d, c)], axis=2)
    t2 = np.stack([np.where(f, b, a), c, d], axis=2)
    return np.concatenate([t1.reshape(-1, 3, 3), t2.reshape(-1, 3, 3)])


def function_mesh(f: Callable[[np.ndarray, np.ndarray], np.ndarray],
                  xlim: tuple[float, float], ylim: tuple[float, float],
                  nx: int, ny: int, name: str = "function") -> Mesh:
    """Mesh of the graph ``z = f(x, y)`` on an ``nx`` by ``ny`` vertex grid."""
    x = np.linspace(xlim[0], xlim[1], nx)
    y = np.linspace(ylim[0], ylim[1], ny)
    X, Y = np.meshgrid(x, y)
    return Mesh(grid_triangles(x, y, f(X, Y)), name)


def mould_surface(x: np.ndarray, y: np.ndarray, size: float = 100.0) -> np.ndarray:
    """A sculptured test surface over ``[0, size]^2`` (mm): a bump, a valley and a ridge.

    Smallest concave radius of curvature is about 13 mm at ``size = 100``; heights
    stay within [0, 25].
    """
    s = size / 100.0
    u, v = x / s, y / s
    z = (12.0 + 8.0 * np.exp(-((u - 35) ** 2 + (v - 60) ** 2) / 400.0)
         - 6.0 * np.exp(-((u - 70) ** 2 + (v - 35) ** 2) / 300.0)
         + 3.0 * np.sin(u / 16.0) * np.cos(v / 21.0))
    return z * s


def random_mesh(n: int, seed: int = 0, size: float = 50.0, zrange: float = 10.0) -> Mesh:
    """A bumpy, irregular test mesh: a jittered grid of about ``n`` triangles."""
    rng = np.random.default_rng(seed)
    k = max(2, int(np.sqrt(n / 2.0)) + 1)
    x = np.linspace(0.0, size, k)
    y = np.linspace(0.0, size, k)
    X, Y = np.meshgrid(x, y)
    h = size / (k - 1)
    X = X + rng.uniform(-0.3, 0.3, X.shape) * h
    Y = Y + rng.uniform(-0.3, 0.3, Y.shape) * h
    Z = (zrange * 0.5 * np.sin(X / size * 7.0) * np.cos(Y / size * 5.0)
         + rng.uniform(0.0, zrange * 0.2, X.shape))
    P = np.stack([X, Y, Z], axis=-1)
    a, b, c, d = P[:-1, :-1], P[:-1, 1:], P[1:, 1:], P[1:, :-1]
    t = np.concatenate([np.stack([a, b, c], 2).reshape(-1, 3, 3),
                        np.stack([a, c, d], 2).reshape(-1, 3, 3)])
    return Mesh(t, f"random{seed}")
