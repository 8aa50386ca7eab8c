"""Plan-view regions of a solid as shapely polygons (mm): a face's projection, the
solid's section at a height, the material above a height.

Edges are cut into chords within ``sagitta`` of the curve (circles by angle, other
curves by OpenCASCADE's deflection sampler); edge ends are the B-rep vertices, so edges
meeting at a vertex meet exactly in the plane. A closed set of edges becomes a region
by even-odd nesting of the loops it encloses (holes in a face, islands in a section).
"""

from __future__ import annotations

import math

import numpy as np
import shapely
from shapely.geometry import LineString, Polygon
from shapely.ops import polygonize

from millpath.part.brep.faces import angle_step

SAGITTA = 0.002          # mm, chord error of edges in regions


def edge_points(edge, sagitta: float = SAGITTA) -> np.ndarray:
    """Points (n, 3) along ``edge`` from its first vertex to its last."""
    from OCP.BRep import BRep_Tool
    from OCP.BRepAdaptor import BRepAdaptor_Curve
    from OCP.GCPnts import GCPnts_QuasiUniformDeflection
    from OCP.GeomAbs import GeomAbs_Circle, GeomAbs_Line
    from OCP.TopExp import TopExp

    c = BRepAdaptor_Curve(edge)
    t0, t1 = c.FirstParameter(), c.LastParameter()
    kind = c.GetType()
    if kind == GeomAbs_Line:
        ts = [t0, t1]
    elif kind == GeomAbs_Circle:
        n = max(2, int(math.ceil(abs(t1 - t0) / angle_step(c.Circle().Radius(), sagitta))))
        ts = list(np.linspace(t0, t1, n + 1))
    else:
        d = GCPnts_QuasiUniformDeflection(c, sagitta, t0, t1)
        ts = [d.Parameter(k) for k in range(1, d.NbPoints() + 1)] if d.IsDone() else [t0, t1]
    pts = np.array([[p.X(), p.Y(), p.Z()] for p in (c.Value(t) for t in ts)])
    v0, v1 = TopExp.FirstVertex_s(edge), TopExp.LastVertex_s(edge)
    if not v0.IsNull():
        p = BRep_Tool.Pnt_s(v0)
        pts[0] = (p.X(), p.Y(), p.Z())
    if not v1.IsNull():
        p = BRep_Tool.Pnt_s(v1)
        pts[-1] = (p.X(), p.Y(), p.Z())
    return pts


def _edges(shape) -> list:
    from OCP.TopAbs import TopAbs_EDGE
    from OCP.TopExp import TopExp_Explorer
    from millpath.part.brep.faces import as_edge
    out = []
    ex = TopExp_Explorer(shape, TopAbs_EDGE)
    while ex.More():
        out.append(as_edge(ex.Current()))
        ex.Next()
    return out


def loops_region(lines: list[LineString]):
    """The region enclosed by closed loops of ``lines``, by even-odd nesting: a face of
    the loops' arrangement is material when an odd number of loops encloses it."""
    lines = [ln for ln in lines if ln.length > 1e-9]
    if not lines:
        return Polygon()
    merged = shapely.node(shapely.set_precision(shapely.MultiLineString(lines), 1e-7))
    faces = list(polygonize(list(getattr(merged, "geoms", [merged]))))
    if len(faces) <= 1:
        return faces[0] if faces else Polygon()
    shells = [Polygon(f.exterior) for f in faces]
    pts = [f.representative_point() for f in faces]
    tree = shapely.STRtree(shells)
    inside, _ = tree.query(pts, predicate="within")
    depth = np.bincount(inside, minlength=len(faces))
    out = shapely.union_all([f for f, d in zip(faces, depth) if d % 2 == 1])
    return shapely.make_valid(out) if not out.is_valid else out


def edges_region(shape, sagitta: float = SAGITTA):
    """Plan-view region bounded by the edges of ``shape`` (a face or a section)."""
    from OCP.BRep import BRep_Tool
    lines = []
    for e in _edges(shape):
        if BRep_Tool.Degenerated_s(e):
            continue
        p = edge_points(e, sagitta)
        if len(p) >= 2:
            lines.append(LineString(p[:, :2]))
    return loops_region(lines)


def section(solid, z: float, sagitta: float = SAGITTA):
    """The solid's material in the plane ``Z = z`` as a plan-view region."""
    from OCP.BRepAlgoAPI import BRepAlgoAPI_Section
    from OCP.gp import gp_Dir, gp_Pln, gp_Pnt
    s = BRepAlgoAPI_Section(solid, gp_Pln(gp_Pnt(0.0, 0.0, z), gp_Dir(0.0, 0.0, 1.0)), False)
    s.Approximation(False)
    s.SetRunParallel(True)
    s.Build()
    if not s.IsDone():
        return Polygon()
    return edges_region(s.Shape(), sagitta)


class Shadows:
    """Material above a height, seen from above: the union of the solid's sections just
    above each level of ``levels`` at or over the height (a 2.5D part's walls are
    vertical between levels, so its sections change only there) and, for parts that
    are not 2.5D, at the ``critical`` heights where faces begin or end: just above
    and just below each, and halfway between two (material between two such heights
    shows in those sections: a face crossing the slab spans it whole)."""

    def __init__(self, solid, levels: list[float], eps: float = 1e-3,
                 critical: list[float] | None = None):
        self.solid = solid
        self.levels = sorted(set(levels))
        self.eps = eps
        self.samples = _samples(critical or [], eps)
        self._sections: dict[float, object] = {}
        self._shadow: dict[float, object] = {}

    def section_above(self, z: float):
        return self.section_at(z + self.eps)

    def section_at(self, z: float):
        if z not in self._sections:
            self._sections[z] = section(self.solid, z)
        return self._sections[z]

    def above(self, z: float, rect: tuple[float, float, float, float] | None = None):
        """Material of the solid higher than ``z`` (plus its sections' chords' error),
        within ``rect`` (xmin, ymin, xmax, ymax) when given (much faster on large parts:
        each section is clipped to the rectangle before the union)."""
        key = (round(z, 9), rect)
        if key not in self._shadow:
            parts = [self.section_above(z)] + [self.section_above(L) for L in self.levels
                                               if L > z + 1e-9]
            parts += [self.section_at(h) for h in self.samples if h > z + self.eps]
            if rect is not None:
                parts = [shapely.clip_by_rect(p, *rect) for p in parts]
            parts = [p for p in parts if not p.is_empty]
            g = shapely.union_all(parts) if len(parts) > 1 else \
                (parts[0] if parts else Polygon())
            self._shadow[key] = g.buffer(SAGITTA, quad_segs=4) if not g.is_empty else g
        return self._shadow[key]


def _samples(critical: list[float], eps: float) -> list[float]:
    """Heights between the ``critical`` ones: just above and below each, and halfway."""
    c = sorted(set(round(v, 6) for v in critical))
    out: set[float] = set()
    for a, b in zip(c, c[1:]):
        if b - a > 4 * eps:
            out.update((a + eps, (a + b) / 2.0, b - eps))
    return sorted(out)
