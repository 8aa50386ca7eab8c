"""The solid's triangles: OpenCASCADE's mesh within a chord tolerance (mm in, mm out).

:func:`solid_mesh` returns ``(vertices (n, 3), triangles (m, 3) int)``, triangles
wound so their normals point out of the material; every face is meshed, so the mesh
is the closed surface of the solid within ``chord_tolerance`` of it.
"""

from __future__ import annotations

import numpy as np

from millpath.errors import GeometryError


def face_triangles(shape, chord_tolerance: float, angular_deflection: float,
                   file=None, entity: str | None = None):
    """Mesh ``shape`` (OpenCASCADE lengths) within ``chord_tolerance`` and
    ``angular_deflection`` (radians) and yield each face's ``(nodes (n, 3), triangles
    (m, 3) int)``, triangles wound so their normals point out of the material. A face
    OpenCASCADE cannot mesh raises :class:`GeometryError` naming ``file``/``entity``."""
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
        yield nodes, idx


def solid_mesh(solid, chord_tolerance: float, name: str = "solid") -> tuple[np.ndarray, np.ndarray]:
    """The closed triangle mesh ``(vertices, triangles)`` of ``solid`` within
    ``chord_tolerance`` (mm)."""
    if not chord_tolerance > 0:
        raise GeometryError("chord tolerance must be positive", entity=name)
    verts, tris = [], []
    base = 0
    for nodes, idx in face_triangles(solid, chord_tolerance, 0.2, entity=name):
        verts.append(nodes)
        tris.append(idx + base)
        base += len(nodes)
    if not verts:
        raise GeometryError("the solid has no faces", entity=name)
    return np.concatenate(verts), np.concatenate(tris)
