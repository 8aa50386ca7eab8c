"""The exact gouge figure is never under the truth, and at most the accuracy over it,
where the check cuts the motion into chords or measures a sharp rim between a chord's
ends; ``max_gouge_at`` is the contact point on the design.

Truths are analytic: a plane wall (exact as two triangles) that an arc's tool goes a
known depth past at the arc's apex (in the middle of a chord, or at a chord's end);
a flat end mill's rim a known depth under a plane patch narrower than its move, or
under a sphere (a fine mesh with its vertices on the sphere: its facets lie inside the
sphere by at most their sagitta), in the middle of a straight move; a ball or bull
cutter touching a plane made of two large triangles. Program units mm, accuracy
0.001 mm.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from millpath.model import Stock, Tool
from millpath.model.motion import Motion
from millpath.simulate.exact import Reference, orient_outward, verify_exact
from millpath.simulate.path import PLANE_AXES, _arc_chords, arc_params, cover_points

ACC = 0.001
TOOLS = {"flat": Tool(1, "flat", 6.0, flute_length=20, stickout=30),
         "ball": Tool(1, "ball", 6.0, flute_length=20, stickout=30),
         "bull": Tool(1, "bull", 6.0, corner_radius=1.0, flute_length=20, stickout=30)}


def _box(lo, hi) -> np.ndarray:
    """A closed box, outward normals."""
    v = np.array([[x, y, z] for x in (lo[0], hi[0]) for y in (lo[1], hi[1])
                  for z in (lo[2], hi[2])], float)
    quads = [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)]
    tri = [[v[a], v[b], v[c]] for a, b, c, d in quads] + [[v[a], v[c], v[d]]
                                                          for a, b, c, d in quads]
    return orient_outward(np.array(tri))


# --- arcs: chords inside the arc must not hide a gouge ---------------------------------

def _arc(plane: str, r: float, half: float, rotation: int, apex_at_vertex: bool):
    """An arc of radius r about the origin in ``plane``, ``2 half`` rad symmetric about
    the first axis's direction (its apex), its chords' count odd (apex in the middle of
    a chord) or even (apex at a chord's end)."""
    while (_arc_chords(r, 2 * half, ACC / 4) % 2 == 0) != apex_at_vertex:
        half += 0.0007
    a1, a2, an = PLANE_AXES[plane]
    s, e = np.zeros(3), np.zeros(3)
    s[a1], s[a2] = r * math.cos(half), -r * math.sin(half)
    e[a1], e[a2] = r * math.cos(half), r * math.sin(half)
    if rotation < 0:
        s, e = e, s
    return Motion("arc", 3, tuple(s), tuple(e), 500, tool=1, plane=plane,
                  center=(0.0, 0.0, 0.0), rotation=rotation)


@pytest.mark.parametrize("kind", ["flat", "ball"])
@pytest.mark.parametrize("rotation", [1, -1])
@pytest.mark.parametrize("apex_at_vertex", [False, True])
@pytest.mark.parametrize("depth", [0.0102, 0.0006])
def test_xy_arc_past_a_wall(kind, rotation, apex_at_vertex, depth):
    """G3 / G2 in XY, tip at z = -5 beside a wall x = r + R - depth (material beyond):
    the cutter's side goes ``depth`` past the wall at the apex."""
    r, R = 10.0, TOOLS[kind].radius
    mo = _arc("XY", r, 0.3, rotation, apex_at_vertex)
    mo = Motion("arc", 3, mo.start[:2] + (-5.0,), mo.end[:2] + (-5.0,), 500, tool=1,
                plane="XY", center=(0.0, 0.0, -5.0), rotation=rotation)
    xw = r + R - depth
    res = verify_exact([mo], {1: TOOLS[kind]}, Stock(-30, -30, -10, 30, 30, 0),
                       [Reference(_box((xw, -20, -10), (xw + 10, 20, 0)), "wall")],
                       accuracy=ACC)
    assert depth <= res.max_gouge <= depth + ACC / 4
    assert res.gouge_at["x"] == pytest.approx(xw, abs=1e-9)
    assert abs(res.gouge_at["y"]) < 0.2
    assert res.gouging_moves == (1 if depth > ACC else 0)


@pytest.mark.parametrize("plane", ["XZ", "YZ"])
@pytest.mark.parametrize("apex_at_vertex", [False, True])
def test_vertical_arc_into_a_floor(plane, apex_at_vertex):
    """A ball's arc in XZ / YZ about the origin, through its lowest point (0, 0, -r)
    0.0102 under a floor (material below z = -r + 0.0102): its bottom goes 0.0102 into
    it there."""
    r, depth, half = 10.0, 0.0102, 0.3
    while (_arc_chords(r, 2 * half, ACC / 4) % 2 == 0) != apex_at_vertex:
        half += 0.0007
    other = 0 if plane == "XZ" else 1
    s, e = np.zeros(3), np.zeros(3)
    s[other], e[other] = -r * math.sin(half), r * math.sin(half)
    s[2] = e[2] = -r * math.cos(half)
    mo = None
    for rot in (1, -1):                  # the short way, through the bottom
        mo = Motion("arc", 3, tuple(s), tuple(e), 500, tool=1, plane=plane,
                    center=(0.0, 0.0, 0.0), rotation=rot)
        if abs(arc_params(mo)[2]) < math.pi:
            break
    pts, _ = cover_points(mo, ACC / 4)
    assert pts[:, 2].min() < -r + 1e-3
    zf = -r + depth
    res = verify_exact([mo], {1: TOOLS["ball"]}, Stock(-30, -30, -30, 30, 30, 30),
                       [Reference(_box((-20, -20, -30), (20, 20, zf)), "floor")],
                       accuracy=ACC)
    assert depth <= res.max_gouge <= depth + ACC / 4
    assert res.gouge_at["z"] == pytest.approx(zf, abs=1e-9)
    assert abs(res.gouge_at["x"]) < 0.2 and abs(res.gouge_at["y"]) < 0.2


def test_arc_touching_a_boss_reads_no_gouge():
    """A flat end mill going round a cylinder boss (its facets' corners on the
    cylinder) with its side on the cylinder: no gouge (the chords cross the arc, and
    their bound stays under accuracy / 2)."""
    r, R, n = 10.0, 3.0, 720
    a = np.linspace(0, 2 * math.pi, n + 1)
    rb = r - R
    xy = np.stack([rb * np.cos(a), rb * np.sin(a)], axis=1)
    tri = []
    for i in range(n):
        p, q = xy[i], xy[i + 1]
        lo_p, lo_q, hi_p, hi_q = (*p, -10.0), (*q, -10.0), (*p, 0.0), (*q, 0.0)
        tri += [[lo_p, lo_q, hi_q], [lo_p, hi_q, hi_p], [(0, 0, 0.0), hi_p, hi_q],
                [(0, 0, -10.0), lo_q, lo_p]]
    tri = orient_outward(np.array(tri, float))
    start = (r, 0.0, -5.0)
    mo = [Motion("arc", 3, start, start, 500, tool=1, center=(0.0, 0.0, -5.0), rotation=1)]
    res = verify_exact(mo, {1: TOOLS["flat"]}, Stock(-30, -30, -10, 30, 30, 0),
                       [Reference(tri, "boss")], accuracy=ACC)
    assert res.max_gouge == 0.0 and res.gouging_moves == 0


@pytest.mark.parametrize("tol", [0.001, 0.00025])
def test_cover_points_bound_each_chord(tol):
    """Every point of an arc (helix) lies within its chord's bound of the chord, and the
    bound is at most 0.8 of an inscribed chord's sagitta."""
    for plane, rot, dz in (("XY", 1, 0.0), ("XY", -2, 3.0), ("XZ", 1, 1.0), ("YZ", -1, 0.5)):
        a1, a2, an = PLANE_AXES[plane]
        s, e = np.zeros(3), np.zeros(3)
        s[a1], e[a2], e[an] = 7.0, 7.0, dz
        mo = Motion("arc", 1, tuple(s), tuple(e), 100, tool=1, plane=plane,
                    center=(0.0, 0.0, 0.0), rotation=rot)
        pts, dev = cover_points(mo, tol)
        r, t0, sweep, dn = arc_params(mo)
        n = len(pts) - 1
        sag = r * (1 - math.cos(abs(sweep) / n / 2))
        assert np.all(dev <= 0.8 * sag + abs(dn) / n * 0.1)
        for i in range(n):
            ph = t0 + sweep * np.linspace(i / n, (i + 1) / n, 501)
            P = np.zeros((len(ph), 3))
            P[:, a1], P[:, a2] = r * np.cos(ph), r * np.sin(ph)
            P[:, an] = (ph - t0) / sweep * dn
            A, B = pts[i], pts[i + 1]
            u = np.clip((P - A) @ (B - A) / ((B - A) @ (B - A)), 0.0, 1.0)
            assert np.linalg.norm(P - (A + u[:, None] * (B - A)), axis=1).max() <= dev[i]


# --- a flat end mill's rim between a chord's ends ---------------------------------------

@pytest.mark.parametrize("alpha", [30.0, 45.0, 80.0])
@pytest.mark.parametrize("depth", [0.1, 0.013])
def test_rim_under_a_narrow_slope_mid_move(alpha, depth):
    """A slope (normal (0, -sin a, cos a)) only 2 mm long in X under a flat end mill
    moving 10 mm along X: the rim point uphill of the axis is ``depth`` under the
    plane along its normal while over the patch, outside the design at the move's
    ends."""
    a = math.radians(alpha)
    n = np.array([0.0, -math.sin(a), math.cos(a)])
    t = np.array([0.0, math.cos(a), math.sin(a)])      # up the slope
    ex = np.array([1.0, 0.0, 0.0])
    c = [-ex - 4 * t, ex - 4 * t, ex + 4 * t, -ex + 4 * t]
    tri = np.array([[c[0], c[1], c[2]], [c[0], c[2], c[3]]], float)
    # the rim's lowest point along -n is the one uphill (+Y) of the axis
    R = TOOLS["flat"].radius
    tip = -depth * n - R * np.array([0.0, 1.0, 0.0])
    mo = [Motion("feed", 4, tuple(tip - 5 * ex), tuple(tip + 5 * ex), 500, tool=1)]
    res = verify_exact(mo, {1: TOOLS["flat"]}, Stock(-10, -10, -10, 10, 10, 10),
                       [Reference(tri, "slope")], accuracy=ACC)
    assert depth <= res.max_gouge + 1e-9 <= depth + ACC
    X = np.array([res.gouge_at[k] for k in "xyz"])
    assert abs(X[0]) <= 1.0 + 1e-9 and abs(float(X @ n)) < 1e-9
    assert abs(float(X @ t)) < 1e-6                      # under the rim point


def _sphere(rs: float, step_deg: float) -> np.ndarray:
    """A closed sphere of radius rs about the origin, latitude-longitude facets of
    ``step_deg`` with their corners on the sphere (a convex polyhedron)."""
    nt, nphi = int(round(180 / step_deg)), int(round(360 / step_deg))
    th = np.linspace(0.0, math.pi, nt + 1)
    ph = np.linspace(0.0, 2 * math.pi, nphi + 1)
    T, P = np.meshgrid(th, ph, indexing="ij")
    V = rs * np.stack([np.sin(T) * np.cos(P), np.sin(T) * np.sin(P), np.cos(T)], axis=-1)
    a, b, c, d = V[:-1, :-1], V[1:, :-1], V[1:, 1:], V[:-1, 1:]
    tri = np.concatenate([np.stack([a, b, c], 2).reshape(-1, 3, 3),
                          np.stack([a, c, d], 2).reshape(-1, 3, 3)])
    keep = np.linalg.norm(np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0]), axis=1) > 0
    return orient_outward(np.ascontiguousarray(tri[keep]))


@pytest.mark.parametrize("depth", [0.1, 0.013])
@pytest.mark.parametrize("lat", [30.0, 45.0, 60.0])
def test_rim_over_a_sphere_mid_move(depth, lat):
    """A flat end mill moving 8 mm along X with its rim nearest the centre of a sphere
    (radius 10) at the move's middle, ``depth`` inside it at polar angle ``lat``: the
    rim's lowest point is ``depth`` deep along the sphere's normal; the moves' ends are
    clear of it."""
    rs, R, step = 10.0, TOOLS["flat"].radius, 1.0
    tri = _sphere(rs, step)
    a = math.radians(lat)
    n = np.array([0.0, math.sin(a), math.cos(a)])
    tip = n * (rs - depth) + np.array([0.0, R, 0.0])
    mo = [Motion("feed", 4, tuple(tip + [-4, 0, 0]), tuple(tip + [4, 0, 0]), 500, tool=1)]
    res = verify_exact(mo, {1: TOOLS["flat"]}, Stock(-20, -20, -20, 20, 20, 20),
                       [Reference(tri, "sphere")], accuracy=ACC)
    # the facets lie inside the sphere by at most rs (1 - cos(half a facet's diagonal))
    sag = rs * (1 - math.cos(math.radians(step) / math.sqrt(2)))
    assert depth - sag <= res.max_gouge <= depth + ACC
    X = np.array([res.gouge_at[k] for k in "xyz"])
    assert np.linalg.norm(X - rs * n) < 0.02


def _polyhedron_rim_truth(tri, P0, P1, R):
    """The deepest point of a flat end mill's rim swept along P0 -> P1 in a convex
    polyhedron: max over the rim of the least distance to the faces' planes (the
    distance from the surface inside a convex solid), by a grid over (position,
    angle) zoomed five times round its best."""
    n = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    n /= np.linalg.norm(n, axis=1)[:, None]
    pd = np.einsum("ij,ij->i", n, tri[:, 0])
    P0, P1 = np.asarray(P0, float), np.asarray(P1, float)

    def depth(u, ph):
        U, PH = np.meshgrid(u, ph, indexing="ij")
        q = (P0 + U[..., None] * (P1 - P0)
             + R * np.stack([np.cos(PH), np.sin(PH), np.zeros_like(PH)], -1))
        q = q.reshape(-1, 3)
        # in blocks of points: all points by all faces at once is gigabytes
        out = np.concatenate([(pd[None, :] - q[a:a + 2000] @ n.T).min(axis=1)
                              for a in range(0, len(q), 2000)])
        return out.reshape(U.shape)

    u, ph = np.linspace(0.0, 1.0, 401), np.linspace(-math.pi, math.pi, 721)
    for _ in range(6):
        F = depth(u, ph)
        i, j = np.unravel_index(np.argmax(F), F.shape)
        best, bu, bp = F[i, j], u[i], ph[j]
        du, dp = 2 * (u[1] - u[0]), 2 * (ph[1] - ph[0])
        u = np.clip(np.linspace(bu - du, bu + du, 41), 0.0, 1.0)
        ph = np.linspace(bp - dp, bp + dp, 41)
    return float(best)


@pytest.mark.parametrize("step", [10.0, 5.0])
@pytest.mark.parametrize("seed", [1, 2, 3])
def test_rim_over_a_faceted_sphere_mid_move(step, seed):
    """A flat end mill's rim dipping into a coarsely faceted sphere (a convex
    polyhedron) in the middle of a move nearly tangent to it: the truth is where the
    rim crosses a ridge between facets, between their own deepest rim points."""
    rng = np.random.default_rng(seed)
    rs, R = 10.0, TOOLS["flat"].radius
    tri = _sphere(rs, step)
    lat, az = math.radians(rng.uniform(25, 65)), math.radians(rng.uniform(0, 360))
    depth, tilt = rng.uniform(0.005, 0.05), math.radians(rng.uniform(-10, 10))
    n = np.array([math.sin(lat) * math.cos(az), math.sin(lat) * math.sin(az), math.cos(lat)])
    h = np.array([n[0], n[1], 0.0]) / math.hypot(n[0], n[1])
    tip = n * (rs - depth) + R * h
    m = math.cos(tilt) * np.array([-h[1], h[0], 0.0]) + math.sin(tilt) * h
    P0, P1 = tip - 4 * m, tip + 4 * m
    truth = _polyhedron_rim_truth(tri, P0, P1, R)
    assert truth > ACC
    res = verify_exact([Motion("feed", 4, tuple(P0), tuple(P1), 500, tool=1)],
                       {1: TOOLS["flat"]}, Stock(-20, -20, -20, 20, 20, 20),
                       [Reference(tri, "facets")], accuracy=ACC)
    assert truth - 1e-6 <= res.max_gouge <= truth + ACC


# --- where: the contact point, not a triangle's corner ----------------------------------

@pytest.mark.parametrize("kind", ["ball", "bull"])
@pytest.mark.parametrize("alpha", [0.0, 30.0])
def test_gouge_at_is_the_contact_on_a_large_triangle(kind, alpha):
    """A ball / bull cutter 0.02 into a plane made of two 80 mm triangles, moving along Y
    through (5, 0): ``max_gouge_at`` is on the contact line (for a bull on a level
    plane: under its flat bottom), not a corner 45 mm away."""
    a = math.radians(alpha)
    n = np.array([math.sin(a), 0.0, math.cos(a)])
    t = np.array([math.cos(a), 0.0, -math.sin(a)])
    ey = np.array([0.0, 1.0, 0.0])
    c = [-40 * t - 40 * ey, 40 * t - 40 * ey, 40 * t + 40 * ey, -40 * t + 40 * ey]
    tri = np.array([[c[0], c[1], c[2]], [c[0], c[2], c[3]]], float)
    tool = TOOLS[kind]
    rc, a_ = tool.corner_radius, tool.radius - tool.corner_radius
    contact = 5.0 * t
    uphill = np.array([n[0], 0.0, 0.0]) / max(abs(n[0]), 1e-300) if alpha else np.zeros(3)
    tip = contact + n * (rc - 0.02) + a_ * uphill - np.array([0.0, 0.0, rc])
    mo = [Motion("feed", 7, tuple(tip - 8 * ey), tuple(tip + 8 * ey), 500, tool=1)]
    res = verify_exact(mo, {1: tool}, Stock(-50, -50, -50, 50, 50, 50),
                       [Reference(tri, "plane")], accuracy=ACC)
    assert res.max_gouge == pytest.approx(0.02, abs=ACC / 2)
    X = np.array([res.gouge_at[k] for k in "xyz"])
    assert abs(float((X - contact) @ n)) < 1e-9           # on the plane
    off = abs(float((X - contact) @ t))                   # across the contact line
    assert off < (a_ + 1e-3 if alpha == 0.0 else 0.01)
    assert abs(X[1]) <= 8.0 + a_ + 1e-6
