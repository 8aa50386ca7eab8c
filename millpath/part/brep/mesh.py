"""The solid's triangles: OpenCASCADE's mesh within a chord tolerance (mm in, mm out).

:func:`solid_mesh` returns ``(vertices (n, 3), triangles (m, 3) int)``, triangles
wound so their normals point out of the material; every face is meshed, so the mesh
is the closed surface of the solid within ``chord_tolerance`` of it.
:func:`reference_mesh` meshes a copy of the solid for verification and measures how far
its facets stand from the true faces (:func:`chord_error`).
"""

from __future__ import annotations

import numpy as np

from millpath.errors import GeometryError

#: barycentric points where a triangle's distance from its face is measured: the
#: vertices' edge midpoints, the centroid and the points halfway to it (where a facet
#: spanning a curved face stands farthest from it)
_BARY = np.array([[.5, .5, 0], [0, .5, .5], [.5, 0, .5], [1 / 3, 1 / 3, 1 / 3],
                  [2 / 3, 1 / 6, 1 / 6], [1 / 6, 2 / 3, 1 / 6], [1 / 6, 1 / 6, 2 / 3]])


def meshed_faces(shape, chord_tolerance: float, angular_deflection: float, file, entity):
    """(face, nodes (n, 3), triangles (m, 3) int) of each face of ``shape`` meshed
    within ``chord_tolerance`` (outward winding)."""
    from OCP.BRep import BRep_Tool
    from OCP.BRepMesh import BRepMesh_IncrementalMesh
    from OCP.TopAbs import TopAbs_FACE, TopAbs_REVERSED
    from OCP.TopExp import TopExp_Explorer
    from OCP.TopLoc import TopLoc_Location
    from millpath.part.brep.faces import as_face

    BRepMesh_IncrementalMesh(shape, chord_tolerance, False, angular_deflection, True)
    ex = TopExp_Explorer(shape, TopAbs_FACE)
    k = 0
    while ex.More():
        face = as_face(ex.Current())
        ex.Next()
        k += 1
        loc = TopLoc_Location()
        tri = BRep_Tool.Triangulation_s(face, loc)
        if tri is None or tri.NbTriangles() == 0:
            raise GeometryError(f"OpenCASCADE could not mesh face {k}", file, entity=entity)
        trsf = loc.Transformation()
        nodes = np.empty((tri.NbNodes(), 3))
        for i in range(tri.NbNodes()):
            p = tri.Node(i + 1).Transformed(trsf)
            nodes[i] = (p.X(), p.Y(), p.Z())
        idx = np.array([tri.Triangle(i + 1).Get() for i in range(tri.NbTriangles())]) - 1
        if face.Orientation() == TopAbs_REVERSED:
            idx = idx[:, ::-1]
        yield face, nodes, idx


def face_triangles(shape, chord_tolerance: float, angular_deflection: float,
                   file=None, entity: str | None = None):
    """Mesh ``shape`` (OpenCASCADE lengths) within ``chord_tolerance`` and
    ``angular_deflection`` (radians) and yield each face's ``(nodes (n, 3), triangles
    (m, 3) int)``, triangles wound so their normals point out of the material. A face
    OpenCASCADE cannot mesh raises :class:`GeometryError` naming ``file``/``entity``."""
    for _, nodes, idx in meshed_faces(shape, chord_tolerance, angular_deflection, file,
                                       entity):
        yield nodes, idx


def solid_mesh(solid, chord_tolerance: float, name: str = "solid") -> tuple[np.ndarray, np.ndarray]:
    """The closed triangle mesh ``(vertices, triangles)`` of ``solid`` within
    ``chord_tolerance`` (mm)."""
    if not chord_tolerance > 0:
        raise GeometryError("chord tolerance must be positive", entity=name)
    return _joined(face_triangles(solid, chord_tolerance, 0.2, entity=name), name)


def _joined(faces, name: str) -> tuple[np.ndarray, np.ndarray]:
    """One ``(vertices, triangles)`` mesh of the faces' ``(nodes, triangles)``."""
    verts, tris = [], []
    base = 0
    for nodes, idx in faces:
        verts.append(nodes)
        tris.append(idx + base)
        base += len(nodes)
    if not verts:
        raise GeometryError("the solid has no faces", entity=name)
    return np.concatenate(verts), np.concatenate(tris)


def surface_distance(face, pts: np.ndarray) -> np.ndarray:
    """Distance (mm) from each point ``pts`` (n, 3) to the surface that carries ``face``:
    exact for planes, cylinders, cones, spheres and tori, by projection
    (``GeomAPI_ProjectPointOnSurf``) for free-form faces."""
    from OCP.BRepAdaptor import BRepAdaptor_Surface
    from OCP.GeomAbs import (GeomAbs_Cone, GeomAbs_Cylinder, GeomAbs_Plane, GeomAbs_Sphere,
                             GeomAbs_Torus)
    a = BRepAdaptor_Surface(face, True)
    t = a.GetType()

    def v(p):
        return np.array([p.X(), p.Y(), p.Z()])

    def frame(g):
        c = v(g.Location())
        ax = v(g.Position().Direction())
        w = pts - c
        h = w @ ax
        rho = np.linalg.norm(w - h[:, None] * ax, axis=1)
        return w, h, rho

    if t == GeomAbs_Plane:
        g = a.Plane()
        return np.abs((pts - v(g.Location())) @ v(g.Position().Direction()))
    if t == GeomAbs_Cylinder:
        g = a.Cylinder()
        return np.abs(frame(g)[2] - g.Radius())
    if t == GeomAbs_Cone:
        # (rho, h) half-plane: the generator rho = R0 + h tan(a), from the apex up
        g = a.Cone()
        _, h, rho = frame(g)
        ang = g.SemiAngle()
        d = np.array([np.sin(ang), np.cos(ang)])          # generator direction (rho, h)
        apex = np.array([0.0, -g.RefRadius() / np.tan(ang)])
        q = np.stack([rho, h], axis=1) - apex
        s = np.maximum(q @ d, 0.0)
        return np.linalg.norm(q - s[:, None] * d, axis=1)
    if t == GeomAbs_Sphere:
        g = a.Sphere()
        return np.abs(np.linalg.norm(pts - v(g.Location()), axis=1) - g.Radius())
    if t == GeomAbs_Torus:
        g = a.Torus()
        _, h, rho = frame(g)
        return np.abs(np.hypot(rho - g.MajorRadius(), h) - g.MinorRadius())
    from OCP.BRep import BRep_Tool
    from OCP.BRepTools import BRepTools
    from OCP.GeomAPI import GeomAPI_ProjectPointOnSurf
    from OCP.gp import gp_Pnt
    from OCP.TopLoc import TopLoc_Location
    loc = TopLoc_Location()
    surf = BRep_Tool.Surface_s(face, loc)
    trsf = loc.Transformation().Inverted()          # points into the surface's frame
    u0, u1, v0, v1 = BRepTools.UVBounds_s(face)
    pr = GeomAPI_ProjectPointOnSurf()
    pr.Init(surf, u0, u1, v0, v1)
    out = np.empty(len(pts))
    for i, p in enumerate(pts):
        pr.Perform(gp_Pnt(*map(float, p)).Transformed(trsf))
        out[i] = pr.LowerDistance() if pr.NbPoints() else np.inf
    return out


#: free-form faces (distance by projection, about half a millisecond a point) are
#: measured on at most this many of their triangles, evenly spread
FREE_FORM_SAMPLE = 250


def chord_error(face, nodes: np.ndarray, idx: np.ndarray) -> float:
    """Largest distance (mm) between the triangles ``nodes[idx]`` of ``face`` and the
    face's surface, measured at seven points of each triangle (edge midpoints,
    centroid, halfway between centroid and vertices); on a free-form face at those of
    ``FREE_FORM_SAMPLE`` triangles only (an estimate)."""
    from OCP.BRepAdaptor import BRepAdaptor_Surface
    from OCP.GeomAbs import (GeomAbs_Cone, GeomAbs_Cylinder, GeomAbs_Plane, GeomAbs_Sphere,
                             GeomAbs_Torus)
    if not len(idx):
        return 0.0
    analytic = BRepAdaptor_Surface(face, True).GetType() in (
        GeomAbs_Plane, GeomAbs_Cylinder, GeomAbs_Cone, GeomAbs_Sphere, GeomAbs_Torus)
    if not analytic and len(idx) > FREE_FORM_SAMPLE:
        idx = idx[np.linspace(0, len(idx) - 1, FREE_FORM_SAMPLE).astype(np.int64)]
    pts = np.einsum("kj,mjc->mkc", _BARY, nodes[idx]).reshape(-1, 3)
    return float(surface_distance(face, pts).max())


def reference_mesh(solid, bound: float, name: str = "solid") -> tuple[np.ndarray, np.ndarray, float]:
    """``(vertices, triangles, error)``: a copy of ``solid`` meshed with ``bound`` (mm)
    as OpenCASCADE's deflection, and ``error`` (mm), the largest distance between a
    facet and its face as :func:`chord_error` measures it. OpenCASCADE's deflection is
    a target: ``error`` can exceed ``bound`` a little (tori: by about 15 %), which is
    why it is measured and returned."""
    from OCP.BRepBuilderAPI import BRepBuilderAPI_Copy
    if not bound > 0:
        raise GeometryError("chord tolerance must be positive", entity=name)
    shape = BRepBuilderAPI_Copy(solid, True, False).Shape()     # the caller's mesh kept
    errors = [0.0]

    def measured():
        for face, nodes, idx in meshed_faces(shape, bound, 0.2, None, name):
            errors.append(chord_error(face, nodes, idx))
            yield nodes, idx

    verts, tris = _joined(measured(), name)
    return verts, tris, max(errors)
