"""The exact check's "is this point in the material?" against the solid it was meshed
from: a plate with a round through hole (OpenCASCADE's box minus cylinder). The rays
that matter run down the hole's wall: they graze the rim edges of the top and bottom
faces, whose triangles differ (long slivers to different corners), and a point
just beside the wall, below or above the plate, is in no material whatever the
rounding."""

from __future__ import annotations

import math

import numpy as np
import pytest

from millpath.geometry.index import BoxIndex
from millpath.geometry.inside import in_material
from millpath.part.brep.mesh import reference_mesh
from millpath.simulate.exact import orient_outward

CX, CY, R = 85.447, -36.295, 1.755          # the hole (mm)
BOX = (0.0, -82.2, -17.3, 143.4, 0.0, 0.0)   # the plate


def _solid():
    from OCP.BRepAlgoAPI import BRepAlgoAPI_Cut
    from OCP.BRepPrimAPI import BRepPrimAPI_MakeBox, BRepPrimAPI_MakeCylinder
    from OCP.gp import gp_Ax2, gp_Dir, gp_Pnt
    x0, y0, z0, x1, y1, z1 = BOX
    box = BRepPrimAPI_MakeBox(gp_Pnt(x0, y0, z0), x1 - x0, y1 - y0, z1 - z0).Shape()
    cyl = BRepPrimAPI_MakeCylinder(gp_Ax2(gp_Pnt(CX, CY, z0 - 1), gp_Dir(0, 0, 1)), R,
                                   z1 - z0 + 2).Shape()
    return BRepAlgoAPI_Cut(box, cyl).Shape()


@pytest.fixture(scope="module")
def plate():
    solid = _solid()
    v, t, _ = reference_mesh(solid, 0.00025)
    tri = np.ascontiguousarray(orient_outward(v[t]))
    ix = BoxIndex.build(tri.min(axis=1), tri.max(axis=1)).arrays()
    return solid, tri, ix


def _inside(p, tri, ix) -> bool:
    return bool(in_material(np.asarray(p, float), tri, ix[2], ix[3], ix[8], ix[9], ix[10],
                            ix[11], ix[12]))


def _rim_edges(tri):
    """The hole's polygon seen from above: the XY edges of the wall's facets."""
    c = np.array([CX, CY])
    wall = np.ptp(tri[:, :, 2], axis=1) > 1e-6
    edges = set()
    for T in tri[wall]:
        for a, b in ((0, 1), (1, 2), (2, 0)):
            pa, pb = T[a, :2], T[b, :2]
            if np.linalg.norm(pa - pb) > 1e-9:
                edges.add(tuple(np.round(np.concatenate([pa, pb]), 12)))
    out = []
    for e in edges:
        pa, pb = np.array(e[:2]), np.array(e[2:])
        if abs(np.linalg.norm(pa - c) - R) < 1e-6 and abs(np.linalg.norm(pb - c) - R) < 1e-6:
            out.append((pa, pb))
    return out


def test_rays_down_the_wall_beside_the_plate_find_no_material(plate):
    """Points beside each facet of the hole's wall, a few nanometres into the hole or
    into the plate's side of it, under and over the plate: outside, every one."""
    _, tri, ix = plate
    edges = _rim_edges(tri)
    assert len(edges) > 100
    c = np.array([CX, CY])
    wrong = []
    for pa, pb in edges:
        mid_dir = (pa + pb) / 2 - c
        n = mid_dir / np.linalg.norm(mid_dir)
        for f in (0.1, 0.37, 0.5, 0.83):
            q = pa + f * (pb - pa)
            for off in (-4e-8, -1.5e-8, -5e-9, 0.0, 5e-9, 1.5e-8, 4e-8):
                for z in (BOX[2] - 0.1275, BOX[5] + 0.3):
                    p = (q[0] + off * n[0], q[1] + off * n[1], z)
                    if _inside(p, tri, ix):
                        wrong.append(p)
    assert not wrong, f"{len(wrong)} points outside the plate found in it, e.g. {wrong[0]}"


def _prism(top_fan: bool):
    """A prism between z = -17.3 and 0 over the quadrilateral A B C D (A B the edge a
    hole's wall stands on, C far from it, D near), its top split along A C and its
    bottom along B D (or the other way round): the top's triangle on A B is 40 mm
    high, the bottom's 0.1 mm, as OpenCASCADE splits a plate's faces."""
    o = np.array([85.447, -38.05])
    a, b, c, d = (o + q for q in np.array([[0, 0], [0.04, 0], [50, -40], [-0.01, -0.1]]))

    def at(p, z):
        return [p[0], p[1], z]
    up = [(a, b, c), (a, c, d)]
    down = [(a, b, d), (b, c, d)]
    if not top_fan:
        up, down = down, up
    tri = [[at(p, 0.0) for p in t] for t in up]
    tri += [[at(p, -17.3) for p in t[::-1]] for t in down]
    for p, q in ((a, b), (b, c), (c, d), (d, a)):        # the walls, edge-on from above
        tri += [[at(p, -17.3), at(q, -17.3), at(q, 0.0)], [at(p, -17.3), at(q, 0.0), at(p, 0.0)]]
    tri = np.ascontiguousarray(orient_outward(np.array(tri, float)))
    return tri, BoxIndex.build(tri.min(axis=1), tri.max(axis=1)).arrays(), a, b


@pytest.mark.parametrize("top_fan", [True, False])
def test_a_ray_grazing_faces_split_unlike_top_and_bottom(top_fan):
    """Beside the wall on A B, a few nanometres off the prism, under and over it: no
    material (the rounding of the 40 mm triangle's edge and of the 0.1 mm one's differ
    by more than that); inside the prism near the wall: material."""
    tri, ix, a, b = _prism(top_fan)
    m = (a + b) / 2
    for off in (5e-9, 1e-8, 2e-8, 3e-8, 4e-8, 0.0):
        for z in (-17.4275, 0.3):
            assert not _inside((m[0], m[1] + off, z), tri, ix), (off, z)
    for off in (-1e-4, -0.02):      # (nearer the wall than the rays are moved: either)
        assert _inside((m[0], m[1] + off, -8.65), tri, ix), off


def test_points_beside_the_wall_inside_the_plate(plate):
    """Within the plate's thickness, points a hundredth into the plate beside the hole
    and into the hole: as OpenCASCADE's classifier finds them in the solid."""
    from OCP.BRepClass3d import BRepClass3d_SolidClassifier
    from OCP.gp import gp_Pnt
    from OCP.TopAbs import TopAbs_IN
    solid, tri, ix = plate
    for ang in np.linspace(0, 2 * math.pi, 37)[:-1]:
        for dr in (0.01, -0.01):
            for z in (-17.29, -8.65, -0.01):
                p = (CX + (R + dr) * math.cos(ang), CY + (R + dr) * math.sin(ang), z)
                truth = BRepClass3d_SolidClassifier(solid, gp_Pnt(*p), 1e-7).State() == TopAbs_IN
                assert _inside(p, tri, ix) is truth, (p, truth)
                assert truth is (dr > 0)
