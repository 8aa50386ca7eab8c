"""Stepped solids with vertical walls as triangle meshes (generated test parts).

A stepped solid is given by flat top faces: ``(polygon, z)`` pairs (shapely polygons in
XY, job units) that tile its footprint without overlapping. Each face is triangulated
(constrained Delaunay, the polygon's own vertices only); along every edge of a face a
vertical wall goes down from the face to whatever lies just outside the edge (a lower
face, or ``base_z`` outside the footprint), and the footprint gets a bottom at
``base_z``. Walls are built from the higher side only, on the faces' own vertices, so
neighbouring faces and walls share their edges.
"""

from __future__ import annotations

import math

import numpy as np

from millpath.part.surface.mesh import Mesh


def _rings(poly) -> list[np.ndarray]:
    return [np.asarray(poly.exterior.coords)[:-1]] + [np.asarray(r.coords)[:-1]
                                                       for r in poly.interiors]


def stepped_solid(faces: list[tuple[object, float]], base_z: float,
                  name: str = "stepped solid") -> Mesh:
    """Mesh of the stepped solid whose top faces are ``faces`` (see module docstring)."""
    import shapely
    from shapely.geometry import Point
    polys = []
    for geom, z in faces:
        parts = getattr(geom, "geoms", [geom])
        polys.extend((p, float(z)) for p in parts if not p.is_empty)
    footprint = shapely.union_all([p for p, _ in polys])
    tree = shapely.STRtree([p for p, _ in polys])
    tris: list[np.ndarray] = []
    for poly, z in polys:
        t = shapely.constrained_delaunay_triangles(poly)
        for g in t.geoms:
            c = np.asarray(g.exterior.coords)[:3]
            tris.append(np.column_stack([c, np.full(3, z)])[None])
    span = max(footprint.bounds[2] - footprint.bounds[0], footprint.bounds[3] - footprint.bounds[1])
    eps = 1e-6 * span
    for poly, z in polys:
        for ring in _rings(poly):
            a = ring
            b = np.roll(ring, -1, axis=0)
            d = b - a
            L = np.hypot(d[:, 0], d[:, 1])
            nrm = np.column_stack([d[:, 1], -d[:, 0]]) / np.maximum(L, 1e-300)[:, None]
            mid = 0.5 * (a + b)
            for k in range(len(a)):
                if L[k] <= 0:
                    continue
                # the side of the edge away from this face
                p = mid[k] + eps * nrm[k]
                if poly.contains(Point(p)):
                    p = mid[k] - eps * nrm[k]
                below = base_z
                for i in tree.query(Point(p), predicate="intersects"):
                    below = polys[i][1]
                if below >= z:
                    continue
                A, B = a[k], b[k]
                q = np.array([[A[0], A[1], z], [B[0], B[1], z], [B[0], B[1], below],
                              [A[0], A[1], below]])
                tris.append(q[[0, 1, 2]][None])
                tris.append(q[[0, 2, 3]][None])
    for g in shapely.constrained_delaunay_triangles(footprint).geoms:
        c = np.asarray(g.exterior.coords)[:3]
        tris.append(np.column_stack([c, np.full(3, base_z)])[None])
    return Mesh(np.concatenate(tris), name)


def box_and_wheel(size: float = 200.0, height: float = 50.0, segments: int = 512) -> Mesh:
    """A ``size`` x ``size`` x ``height`` block (top at Z 0, centred on the origin) with a
    square pocket 40 mm deep and 10 mm walls, and in it a wheel 25 mm tall (rim 140 mm
    across, 10 mm wide; hub 30 mm; six spokes 8 mm wide), all walls vertical.
    Dimensions in mm for ``size = 200``, scaled with ``size``; circles have
    ``segments`` sides."""
    import shapely
    from shapely.geometry import Point, box
    s = size / 200.0
    qs = max(1, segments // 4)
    outer = box(-size / 2, -size / 2, size / 2, size / 2)
    pocket = box(-90 * s, -90 * s, 90 * s, 90 * s)
    rim = Point(0, 0).buffer(70 * s, quad_segs=qs).difference(
        Point(0, 0).buffer(60 * s, quad_segs=qs))
    hub = Point(0, 0).buffer(15 * s, quad_segs=qs)
    spokes = []
    for k in range(6):
        a = math.pi * k / 3
        r = box(0, -4 * s, 65 * s, 4 * s)
        spokes.append(shapely.affinity.rotate(r, a, origin=(0, 0), use_radians=True))
    wheel = shapely.union_all([rim, hub] + spokes).simplify(1e-9 * size)
    floor = pocket.difference(wheel)
    frame = outer.difference(pocket)
    return stepped_solid([(frame, 0.0), (floor, -40 * s), (wheel, -15 * s)], -height,
                         "box and wheel")
