"""A surface to machine, from whatever describes it, as a triangle mesh (job units).

``spec`` (the ``surface`` key of a surface operation, or the ``millpath drop`` argument) is:

- an ``.stl`` file, binary or ASCII, read as it is;
- a Bezier net as a table ``{ heights = [[z, ...], ...], box = [xmin, ymin, xmax, ymax] }``
  (``heights[i][j]``: ``i`` along X, ``j`` along Y) or ``{ control = [[[x, y, z], ...], ...] }``,
  or a ``.toml`` file holding such a table; tessellated into ``divisions`` x ``divisions``
  parameter cells, two triangles each;
- a measured grid of ``x, y, z`` points (:mod:`millpath.part.surface.grid`): a ``.csv``,
  ``.xyz`` or ``.txt`` file (linear interpolation), or a table
  ``{ grid = "points.csv", method = "linear" | "cubic" }``. Each grid cell is split into
  ``k`` x ``k`` sub-cells, ``k = ceil(divisions / cells along the longer side)`` (at least
  1), so the mesh passes through every sample and has at least ``divisions`` cells along
  the longer side. Linear: the sub-cell corners lie on the bilinear quadrilateral through
  the cell's four samples. Cubic: they lie on the interpolating spline;
- a ``.step`` / ``.stp`` file (every face of every shape in it), meshed by OpenCASCADE
  with chord tolerance ``chord_tolerance`` (largest distance between a face and its
  triangles). Needs the optional extra ``millpath[step-brep]`` (``cadquery-ocp``).
  OpenCASCADE converts the file's length unit to millimetres; with ``units="inch"`` the
  mesh is scaled to inches (``chord_tolerance`` is then in inches too).

- a table ``{ file = "part.stl", rotate = [rx, ry, rz], scale = s, units = "inch",
  translate = [x, y, z] }`` or ``place = "stock-top"`` instead of ``translate``: any of
  the above moved into the job's frame (:mod:`millpath.part.surface.placement`); grid
  and Bezier tables take the same keys.

Relative file names are resolved from ``base_dir``. Errors are :class:`JobError` or
:class:`GeometryError` naming ``file`` (the job file) or the surface file, and the line
where known.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from millpath.errors import GeometryError, JobError, MillpathError
from millpath.io.schema import parse_toml
from millpath.io.text import MAX_COORDINATE
from millpath.model.units import length_scale
from millpath.part.surface.mesh import Mesh, read_stl
from millpath.part.surface.placement import place_mesh, split_placement

GRID_SUFFIXES = (".csv", ".xyz", ".txt")
STEP_SUFFIXES = (".step", ".stp")
STEP_EXTRA = "STEP surfaces need the optional extra: pip install 'millpath[step-brep]'"


def load_surface(spec, divisions: int, base_dir: Path, file=None, *,
                 chord_tolerance: float = 0.01, units: str = "mm",
                 stock_box=None) -> Mesh:
    """The surface described by ``spec`` as a :class:`Mesh` (see the module docstring).

    ``divisions``: Bezier cells per direction, least grid cells along a measured grid's
    longer side. ``chord_tolerance``: STEP meshing tolerance (job units). A table may
    also place the model (``rotate``, ``scale``, ``units``, ``translate``, ``place``,
    :mod:`millpath.part.surface.placement`; ``stock_box`` for ``place``).
    """
    where = "surface"
    if isinstance(spec, dict):
        placement, spec = split_placement(spec, file)
        if "file" in spec:
            unknown = sorted(set(spec) - {"file"})
            if unknown:
                raise JobError(f"surface.{unknown[0]}: unknown key (a file table has file, "
                               "rotate, scale, units, translate, place)", file)
            name = spec["file"]
            if not isinstance(name, str):
                raise JobError("surface.file: expected a file name", file)
            if placement.units and Path(name).suffix.lower() in STEP_SUFFIXES:
                raise JobError("surface.units: a STEP file states its own units", file)
            mesh = _load_file(name, divisions, base_dir, file, chord_tolerance, units)
        elif "grid" in spec:
            mesh = _grid_table(spec, divisions, base_dir, file)
        else:
            try:
                mesh = _bezier_mesh(spec, divisions, where, file)
            except (ValueError, TypeError) as e:
                raise JobError(f"{where}: {e}", file) from None
        return place_mesh(mesh, placement, units, stock_box, file)
    if not isinstance(spec, str):
        raise JobError(f"{where}: expected a file name, a Bezier net table or a grid table",
                       file)
    return _load_file(spec, divisions, base_dir, file, chord_tolerance, units)


def _load_file(spec: str, divisions: int, base_dir: Path, file, chord_tolerance: float,
               units: str) -> Mesh:
    where = "surface"
    path = _resolve(spec, base_dir)
    suffix = path.suffix.lower()
    known = (".stl", ".toml") + GRID_SUFFIXES + STEP_SUFFIXES
    if suffix not in known:
        raise JobError(f"{where}: unknown surface file type {suffix or spec!r} "
                       f"(use {', '.join(known)})", file)
    if not path.is_file():
        raise JobError(f"{where}: no such file {spec!r}", file)
    if suffix == ".stl":
        return read_stl(path)
    if suffix == ".toml":
        try:
            text = path.read_text(encoding="utf-8")
        except UnicodeDecodeError:
            raise JobError("not a UTF-8 text file", path) from None
        data = parse_toml(text, path)
        try:
            return _bezier_mesh(data, divisions, where, path)
        except (ValueError, TypeError) as e:
            raise JobError(str(e), path) from None
    if suffix in GRID_SUFFIXES:
        return grid_mesh(path, "linear", divisions)
    return read_step(path, chord_tolerance, units)


def _resolve(name: str, base_dir: Path) -> Path:
    path = Path(name)
    return path if path.is_absolute() else Path(base_dir) / path


def _bezier_mesh(table: dict, divisions: int, where: str, file) -> Mesh:
    """Mesh of a Bezier net table; every problem is an error naming ``file``."""
    from millpath.part.surface.bezier import BezierPatch

    def numbers(key: str) -> np.ndarray:
        try:
            a = np.array(table[key], dtype=float)
        except (ValueError, TypeError, OverflowError):
            raise JobError(f"{where}.{key}: expected a (nested) list of numbers", file) from None
        if not np.all(np.isfinite(a)) or (a.size and np.abs(a).max() > MAX_COORDINATE):
            raise JobError(f"{where}.{key}: numbers must be finite and at most "
                           f"{MAX_COORDINATE:g} in size", file)
        return a

    try:
        if "heights" in table:
            if "box" not in table:
                raise JobError(f"{where}.box: a heights net needs box = [xmin, ymin, xmax, "
                               "ymax]", file)
            box = numbers("box")
            if box.shape != (4,):
                raise JobError(f"{where}.box: expected [xmin, ymin, xmax, ymax]", file)
            patch = BezierPatch.from_heights(numbers("heights"), tuple(box))
        elif "control" in table:
            patch = BezierPatch(numbers("control"))
        else:
            raise JobError(f"{where}: a Bezier net needs heights (with box) or control; "
                           "a measured grid needs grid", file)
        return Mesh(patch.to_mesh(divisions, divisions), "bezier")
    except GeometryError as e:
        raise GeometryError(f"{where}: {e.message}", file) from None
    except (ValueError, TypeError) as e:
        raise JobError(f"{where}: {e}", file) from None


def _grid_table(table: dict, divisions: int, base_dir: Path, file) -> Mesh:
    unknown = sorted(set(table) - {"grid", "method"})
    if unknown:
        raise JobError(f"surface.{unknown[0]}: unknown key (a grid table has grid, method)",
                       file)
    name, method = table["grid"], table.get("method", "linear")
    if not isinstance(name, str):
        raise JobError("surface.grid: expected a file name", file)
    if method not in ("linear", "cubic"):
        raise JobError(f"surface.method: linear or cubic expected, not {method!r}", file)
    path = _resolve(name, base_dir)
    if not path.is_file():
        raise JobError(f"surface.grid: no such file {name!r}", file)
    return grid_mesh(path, method, divisions)


def grid_mesh(path: Path, method: str, divisions: int) -> Mesh:
    """Mesh of the measured grid in ``path`` (see the module docstring for the density)."""
    from millpath.part.surface.bezier import point_grid_triangles
    from millpath.part.surface.grid import MeasuredGrid
    g = MeasuredGrid.from_csv(path, method=method)
    nx, ny = g.xs.size, g.ys.size
    k = max(1, math.ceil(divisions / (max(nx, ny) - 1)))
    t = np.linspace(0.0, 1.0, k + 1)[:-1]
    # parameters (cell index + fraction) of the sub-cell corners along each direction
    pu = np.concatenate([np.arange(nx - 1)[:, None] + t[None, :], [[nx - 1]]], axis=None)
    pv = np.concatenate([np.arange(ny - 1)[:, None] + t[None, :], [[ny - 1]]], axis=None)
    if method == "cubic":
        gx = np.interp(pu, np.arange(nx), g.xs)
        gy = np.interp(pv, np.arange(ny), g.ys)
        X, Y = np.meshgrid(gx, gy, indexing="ij")
        P = np.stack([X, Y, g.height(X, Y)], axis=-1)
    else:
        # bilinear blend of the four real samples of each cell: exact at the samples,
        # also on a near-regular grid
        i = np.minimum(np.floor(pu).astype(int), nx - 2)
        j = np.minimum(np.floor(pv).astype(int), ny - 2)
        s = (pu - i)[:, None, None]
        r = (pv - j)[None, :, None]
        S = np.stack([g.X, g.Y, g.Z], axis=-1)              # (nx, ny, 3)
        I, J = np.meshgrid(i, j, indexing="ij")
        P = ((1 - s) * (1 - r) * S[I, J] + s * (1 - r) * S[I + 1, J]
             + (1 - s) * r * S[I, J + 1] + s * r * S[I + 1, J + 1])
    try:
        return Mesh(point_grid_triangles(P), path.name)
    except GeometryError as e:
        raise GeometryError(e.message, path) from None


def read_step(path: Path, chord_tolerance: float = 0.01, units: str = "mm") -> Mesh:
    """Mesh every face in the STEP file ``path`` within ``chord_tolerance`` (``units``)."""
    if not (chord_tolerance > 0 and math.isfinite(chord_tolerance)):
        raise JobError(f"chord_tolerance: must be positive, got {chord_tolerance!r}", path)
    if units not in ("mm", "inch"):
        raise JobError(f"units: mm or inch expected, not {units!r}", path)
    try:
        import OCP  # noqa: F401
    except ImportError:
        raise JobError(STEP_EXTRA, path) from None
    from millpath.part.brep.mesh import face_triangles
    from millpath.part.brep.reader import transfer_step
    from millpath.part.step.p21 import read as read_p21
    try:
        read_p21(path).check_tree()       # what OpenCASCADE would follow without a guard
    except MillpathError as e:
        raise GeometryError(f"cannot read STEP: {e.message}", path, e.line,
                            e.entity) from None
    scale = length_scale("mm", units)
    shape, log = transfer_step(path)      # a native crash is an error naming the file
    if shape is None:
        detail = next((ln.strip(" *") for ln in log if "ERR" in ln or "Fail" in ln), "")
        raise GeometryError("cannot read STEP" + (f": {detail}" if detail else
                                                  " (no shape in the file)"), path)
    tris = [nodes[idx] for nodes, idx in
            face_triangles(shape, chord_tolerance / scale, 0.5, file=path)]
    if not tris:
        raise GeometryError("the STEP file has no faces", path)
    return Mesh(np.concatenate(tris) * scale, path.name)
