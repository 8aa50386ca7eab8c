"""Grid-free verification against triangle-mesh references: gouge and material left.

A :class:`Reference` is a design as triangles (walls included) and the operations it
applies to. :func:`verify_exact` checks every chord of the motion (see
:mod:`millpath.simulate.gouge`) against the references of its operation and measures
the material left along the normal at points of each reference
(:mod:`millpath.simulate.leftover`). ``accuracy`` (program units) bounds the gouge
figure; the material left is exact (to ``accuracy``) at sample points ``spacing``
apart. Designs that are only height fields are meshed by
:func:`millpath.geometry.heightmesh.height_field_mesh` (walls placed exactly on a 50 * ``accuracy`` grid).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from millpath.geometry.heightmesh import height_field_mesh
from millpath.geometry.index import BoxIndex
from millpath.model.motion import Motion
from millpath.model.stock import Stock
from millpath.model.tool import Tool
from millpath.simulate.gouge import ToolShapes, gouge_chords, locate
from millpath.simulate.leftover import material_left, sample_triangles
from millpath.simulate.path import motion_segments


@dataclass
class Reference:
    """A design as triangles (n, 3, 3) and where it comes from; ``ops`` lists the
    operations checked against it (None: all)."""

    triangles: np.ndarray
    name: str
    ops: list[int] | None = None


def orient_outward(tri: np.ndarray) -> np.ndarray:
    """Wind triangles so their normals point out of the material: a closed solid by
    the sign of its volume, an open surface (a height field) upward."""
    tri = np.ascontiguousarray(np.asarray(tri, float).reshape(-1, 3, 3))
    if not len(tri):
        return tri
    n = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    vol = float(np.einsum("ij,ij->i", tri[:, 0], n).sum()) / 6.0
    lo, hi = tri.reshape(-1, 3).min(axis=0), tri.reshape(-1, 3).max(axis=0)
    box = float(np.prod(np.maximum(hi - lo, 1e-12)))
    # an open surface's "volume" depends on the origin; a closed one does not
    shift = tri + np.array([1.0, 1.0, 1.0]) * float(np.max(hi - lo) + 1.0)
    vol2 = float(np.einsum("ij,ij->i", shift[:, 0], n).sum()) / 6.0
    closed = abs(vol - vol2) <= 1e-6 * box and abs(vol) > 1e-9 * box
    if closed:
        return tri if vol > 0 else np.ascontiguousarray(tri[:, ::-1])
    flip = n[:, 2] < 0
    out = tri.copy()
    out[flip] = tri[flip][:, ::-1]
    return out


def design_triangles(design, stock: Stock, accuracy: float, size: float) -> np.ndarray:
    """Triangles of a design: its ``mesh()`` when it has one, else a height-field mesh
    over the stock box with cells of ``size`` refined to ``50 accuracy`` where walls
    or curvature need it (walls cut exactly at the cell edges, flat to ``accuracy / 2``)."""
    if hasattr(design, "mesh"):
        import inspect
        takes_box = "box" in inspect.signature(design.mesh).parameters
        return orient_outward(design.mesh(stock.box) if takes_box else design.mesh())
    x0, y0, z0, x1, y1, z1 = stock.box
    tri = height_field_mesh(design, (x0, y0, x1, y1), size=size, min_size=accuracy * 50,
                            flat_tol=accuracy / 2, floor=z0 - max(1.0, 0.1 * (z1 - z0)))
    return orient_outward(tri)


@dataclass
class ExactResult:
    """What the grid-free check found (program units). ``*_at`` are dicts with x, y, z
    (the design point), line, operation (or None)."""

    max_gouge: float
    max_left: float
    gouging_moves: int
    gouge_at: dict | None
    left_at: dict | None
    motion_gouge: np.ndarray            # per motion, 0 where none
    op_gouge: dict[int, float] = field(default_factory=dict)
    op_gouging: dict[int, int] = field(default_factory=dict)
    op_left: dict[int, float] = field(default_factory=dict)
    references: list[str] = field(default_factory=list)
    accuracy: float = 0.001
    spacing: float = 0.0
    chords: int = 0


def verify_exact(motions: list[Motion], tools: dict[int, Tool], stock: Stock,
                 references: list[Reference], *, motion_op: np.ndarray | None = None,
                 accuracy: float = 0.001, spacing: float | None = None) -> ExactResult:
    """Gouge and material left of ``motions`` against ``references`` (see the module
    doc). ``motion_op`` gives each motion's operation (default all 0). Material left is
    measured up to twice the largest tool diameter (more is reported as that). ``spacing`` is
    the distance between material-left sample points (default a quarter of the
    smallest tool radius)."""
    nm = len(motions)
    mop = np.zeros(nm, np.int64) if motion_op is None else np.asarray(motion_op, np.int64)
    segs = motion_segments(motions, accuracy / 4.0)
    keep = segs.tool != 0
    S, E, smo, stool = segs.start[keep], segs.end[keep], segs.motion[keep], segs.tool[keep]
    numbers = sorted({int(t) for t in np.unique(stool)})
    missing = [t for t in numbers if t not in tools]
    if missing:
        raise ValueError(f"tool {missing[0]} is not defined: give its shape")
    lut = np.zeros(max(numbers, default=0) + 1, np.int64)
    for s, t in enumerate(numbers):
        lut[t] = s
    slot = lut[stool] if len(stool) else np.zeros(0, np.int64)
    shapes = ToolShapes.of([tools[t] for t in numbers])
    if spacing is None:
        rmin = min((tools[t].radius for t in numbers), default=1.0)
        spacing = max(rmin / 4.0, accuracy * 10)
    cop = mop[smo] if len(smo) else np.zeros(0, np.int64)
    motion_g = np.zeros(nm)
    best_g, g_at = 0.0, None
    best_l, l_at = 0.0, None
    op_left: dict[int, float] = {}
    for ref in references:
        tri = np.ascontiguousarray(ref.triangles, float)
        if not len(tri):
            continue
        idx = BoxIndex.build(tri.min(axis=1), tri.max(axis=1))
        sel = np.ones(len(S), bool) if ref.ops is None else np.isin(cop, ref.ops)
        cs = np.flatnonzero(sel)
        res = gouge_chords(S[cs], E[cs], slot[cs], shapes, tri, idx, accuracy)
        g = np.maximum(res.gouge, 0.0)
        if len(cs):
            np.maximum.at(motion_g, smo[cs], g)
            c = int(np.argmax(g))
            if g[c] > best_g:
                best_g = float(g[c])
                _, X = locate(S[cs], E[cs], slot[cs], shapes, tri, res, c, accuracy)
                mo = motions[int(smo[cs[c]])]
                g_at = {"x": float(X[0]), "y": float(X[1]), "z": float(X[2]),
                        "line": int(mo.line), "operation": int(cop[cs[c]])}
        # material left on this reference, by all cutting chords
        pts, nrm, own = sample_triangles(tri, spacing)
        pts, nrm, own = _thin(pts, nrm, own, spacing)
        # material left is measured up to twice the largest tool diameter: beyond
        # that it is uncut stock, reported as that much
        reach = float(min(max(stock.size), 2.0 * max(tools[t].diameter for t in numbers)))
        left, who = material_left(pts, nrm, own, stock.box, tri, idx, S, E, slot, shapes,
                                  accuracy, reach, float(spacing) * 4.0)
        if len(left):
            q = int(np.argmax(left))
            lq = float(left[q]) if left[q] >= accuracy / 2 else 0.0
            for o in (ref.ops if ref.ops is not None else sorted(set(mop.tolist())) or [0]):
                op_left[o] = max(op_left.get(o, 0.0), lq)
            if lq > best_l:
                best_l = lq
                c = int(who[q])
                l_at = {"x": float(pts[q, 0]), "y": float(pts[q, 1]), "z": float(pts[q, 2]),
                        "line": int(motions[int(smo[c])].line) if c >= 0 else None,
                        "operation": int(cop[c]) if c >= 0 else None}
    gouging = motion_g > accuracy
    op_g: dict[int, float] = {}
    op_n: dict[int, int] = {}
    for o in sorted(set(mop.tolist())):
        m = mop == o
        op_g[o] = float(motion_g[m].max(initial=0.0))
        op_n[o] = int(gouging[m].sum())
    return ExactResult(best_g, best_l, int(gouging.sum()), g_at, l_at, motion_g, op_g, op_n,
                       op_left, [r.name for r in references], accuracy, float(spacing),
                       int(len(S)))


def _thin(pts, nrm, own, cell: float):
    """One sample per (cell-sized voxel, normal direction): tiny triangles (walls of a
    height-field mesh) would otherwise give far more points than ``spacing`` asks."""
    if not len(pts) or cell <= 0:
        return pts, nrm, own
    key = np.concatenate([np.floor(pts / cell).astype(np.int64),
                          np.round(nrm * 4).astype(np.int64)], axis=1)
    _, first = np.unique(key, axis=0, return_index=True)
    first.sort()
    return pts[first], nrm[first], own[first]
