"""Checks that a stretch of a polyline can be written as one line or one circular arc.

All functions work on ``P``, an ``(n, 3)`` float array of tool-tip points in job units
(mm or inch) that already lie on the post-processor's grid (``q`` = 1e-4 mm or 1e-5 in),
and test the stretch ``P[i] .. P[j]`` (vertices ``i`` to ``j`` and the segments between
them) against an absolute tolerance ``tol`` (job units). A check returns True only when
the replacement is within ``tol`` of every original vertex and segment *and* every point
of the replacement is within ``tol`` of the original polyline (both directions).

Arcs lie in a plane given by the axis indices ``(a1, a2, an)`` of
:data:`millpath.model.toolpath.PLANE_AXES` (XY = (0, 1, 2), XZ = (2, 0, 1),
YZ = (1, 2, 0)); the normal coordinate may change linearly with the swept angle (a
helix, for example an XY arc with linear Z). Arc centres are chosen on the grid so that
the start and end radii, as LinuxCNC computes them from the written numbers, agree to
well within its limit (``|r1 - r2| <= 0.028 mm`` or ``0.1 %`` of the radius).
"""

from __future__ import annotations

import math

from numba import njit

#: LinuxCNC's CENTER_ARC_RADIUS_TOLERANCE in mm (2 * 0.01 * sqrt 2) and its relative
#: SPIRAL_RELATIVE_TOLERANCE; inch programs use a tenth of the mm value in inches.
LINUXCNC_ARC_ABS_MM = 0.02 * math.sqrt(2.0)
LINUXCNC_ARC_ABS_INCH = 0.002 * math.sqrt(2.0)
LINUXCNC_ARC_REL = 0.001
#: the fraction of LinuxCNC's radius limit a fitted arc may use.
ARC_RADIUS_MARGIN = 0.1


@njit(cache=True)
def line_ok(P, i, j, tol):
    """True if the segment ``P[i] -> P[j]`` replaces vertices ``i..j`` within ``tol``.

    Every vertex must lie within ``tol`` of the chord and their projections on it must
    advance monotonically (so the chord also stays within ``tol`` of the polyline).
    """
    dx = P[j, 0] - P[i, 0]
    dy = P[j, 1] - P[i, 1]
    dz = P[j, 2] - P[i, 2]
    L2 = dx * dx + dy * dy + dz * dz
    if L2 <= 0.0:
        return False
    L = math.sqrt(L2)
    ux, uy, uz = dx / L, dy / L, dz / L
    prev = 0.0
    tol2 = tol * tol
    for k in range(i + 1, j):
        qx = P[k, 0] - P[i, 0]
        qy = P[k, 1] - P[i, 1]
        qz = P[k, 2] - P[i, 2]
        s = qx * ux + qy * uy + qz * uz
        if s < prev - 1e-12 or s > L + 1e-12:
            return False
        prev = s
        d2 = qx * qx + qy * qy + qz * qz - s * s
        if d2 > tol2:
            return False
    return True


@njit(cache=True)
def _grid_centre(ax, ay, bx, by, cx, cy, q, lim):
    """Grid point near (cx, cy) whose start and end radii agree as written.

    Candidates are the 5 x 5 grid points around (cx, cy) with ``|r1 - r2| <= lim``.
    A post-processor that re-projects the centre on the chord bisector and rounds it
    again (as millpath.post.writer does) moves it by ``shift + 0.71 q`` at most, which
    moves the arc by twice that; when ``shift`` is below a quarter step the rounding
    returns the same point and nothing moves. The candidate with the smallest distance
    to (cx, cy) plus that possible movement wins. Returns (cx, cy, r1, r2, slack, ok)
    where ``slack`` is the possible movement of the written arc.
    """
    gx = round(cx / q) * q
    gy = round(cy / q) * q
    chord = math.hypot(bx - ax, by - ay)
    best = 1e300
    ok = False
    rx, ry, rr1, rr2, rslack = gx, gy, 0.0, 0.0, 0.0
    for di in range(-2, 3):
        for dj in range(-2, 3):
            x = gx + di * q
            y = gy + dj * q
            r1 = math.hypot(ax - x, ay - y)
            r2 = math.hypot(bx - x, by - y)
            dr = abs(r1 - r2)
            if dr > lim:
                continue
            shift = dr * (r1 + r2) / (2.0 * chord)
            slack = 0.0 if shift <= 0.25 * q else 2.0 * (shift + 0.71 * q)
            score = math.hypot(x - cx, y - cy) + slack + dr
            if score < best:
                best = score
                ok = True
                rx, ry, rr1, rr2, rslack = x, y, r1, r2, slack
    return rx, ry, rr1, rr2, rslack, ok


@njit(cache=True)
def arc_fit(P, i, j, a1, a2, an, tol, q, abs_lim, rmin, rmax, corner, out):
    """Fit one arc through ``P[i]`` and ``P[j]`` in plane (a1, a2, an) and check it.

    ``q`` is the output grid step, ``abs_lim`` LinuxCNC's absolute start/end radius limit
    (job units), ``rmin``/``rmax`` the accepted radius range, ``corner`` the turning
    angle (radians) above which an original vertex counts as a corner whose turning
    direction the arc must keep. On success returns True and writes
    ``out = [c1, c2, clockwise (1.0/0.0), radius, sweep]`` (centre in plane coordinates).
    """
    if j - i < 2:
        return False
    ax, ay = P[i, a1], P[i, a2]
    bx, by = P[j, a1], P[j, a2]
    dx, dy = bx - ax, by - ay
    L = math.hypot(dx, dy)
    if L < 20.0 * q:
        return False
    mx, my = 0.5 * (ax + bx), 0.5 * (ay + by)
    nx, ny = -dy / L, dx / L
    h2 = 0.25 * L * L
    num = 0.0
    den = 0.0
    # least squares over the inner vertices and the segment midpoints, so that the
    # arc runs between a coarse polyline's vertices and its chords
    for k in range(i + 1, j + 1):
        for half in range(2):
            if half == 0:
                qx = 0.5 * (P[k, a1] + P[k - 1, a1]) - mx
                qy = 0.5 * (P[k, a2] + P[k - 1, a2]) - my
            elif k < j:
                qx = P[k, a1] - mx
                qy = P[k, a2] - my
            else:
                break
            w = nx * qx + ny * qy
            num += w * (qx * qx + qy * qy - h2)
            den += w * w
    if den <= 1e-30:
        return False
    t = num / (2.0 * den)
    cx, cy = mx + t * nx, my + t * ny
    r0 = math.hypot(ax - cx, ay - cy)
    if r0 < rmin or r0 > rmax:
        return False
    lim = ARC_RADIUS_MARGIN * min(abs_lim, LINUXCNC_ARC_REL * r0)
    cx, cy, r1, r2, slack, ok = _grid_centre(ax, ay, bx, by, cx, cy, q, lim)
    if not ok:
        return False
    r = 0.5 * (r1 + r2)
    if r - slack <= rmin or r > rmax:
        return False
    tl = tol - 0.5 * abs(r1 - r2) - slack      # the written arc spirals from r1 to r2
    if tl <= 0.0:
        return False
    tl2 = tl * tl
    # angular progress of the vertices about the centre: one direction, short steps
    sweep = 0.0
    sgn = 0.0
    px, py = ax - cx, ay - cy
    for k in range(i + 1, j + 1):
        vx, vy = P[k, a1] - cx, P[k, a2] - cy
        cr = px * vy - py * vx
        dt = math.atan2(cr, px * vx + py * vy)
        if dt == 0.0 or abs(dt) > 0.5 * math.pi:
            return False
        if sgn == 0.0:
            sgn = 1.0 if dt > 0 else -1.0
        elif dt * sgn < 0:
            return False
        sweep += dt
        px, py = vx, vy
    if abs(sweep) > 1.9 * math.pi:
        return False
    # the turning direction at corners of the original must match the arc's
    for k in range(i + 1, j):
        ux, uy = P[k, a1] - P[k - 1, a1], P[k, a2] - P[k - 1, a2]
        wx, wy = P[k + 1, a1] - P[k, a1], P[k + 1, a2] - P[k, a2]
        tau = math.atan2(ux * wy - uy * wx, ux * wx + uy * wy)
        if tau * sgn < 0 and abs(tau) > corner:
            return False
    # distances: vertices, segment midpoints and the segments' inward bulge
    n0 = P[i, an]
    dn = P[j, an] - n0
    theta = 0.0
    px, py = ax - cx, ay - cy
    pr = math.hypot(px, py)
    pen = 0.0                           # normal error at the previous vertex
    for k in range(i + 1, j + 1):
        vx, vy = P[k, a1] - cx, P[k, a2] - cy
        vr = math.hypot(vx, vy)
        dt = math.atan2(px * vy - py * vx, px * vx + py * vy)
        # vertex
        er = vr - r
        en = P[k, an] - (n0 + dn * (theta + dt) / sweep)
        if er * er + en * en > tl2:
            return False
        # segment midpoint (normal error) and the radial extremes of the segment
        hx, hy = 0.5 * (px + vx), 0.5 * (py + vy)
        hdt = math.atan2(px * hy - py * hx, px * hx + py * hy)
        hn = 0.5 * (P[k - 1, an] + P[k, an]) - (n0 + dn * (theta + hdt) / sweep)
        sx, sy = vx - px, vy - py
        s2 = sx * sx + sy * sy
        dmin = min(pr, vr)
        if s2 > 0.0:
            u = -(px * sx + py * sy) / s2
            if 0.0 < u < 1.0:
                dmin = math.hypot(px + u * sx, py + u * sy)
        er_seg = max(max(abs(pr - r), abs(vr - r)), r - dmin)
        en_seg = max(max(abs(pen), abs(en)), abs(hn))
        if er_seg * er_seg + en_seg * en_seg > tl2:
            return False
        theta += dt
        px, py, pr, pen = vx, vy, vr, en
    out[0] = cx
    out[1] = cy
    out[2] = 1.0 if sweep < 0 else 0.0
    out[3] = r
    out[4] = sweep
    return True


@njit(cache=True)
def plane_possible(P, i, n, a1, a2, an, tol):
    """Cheap pre-test: can an arc in this plane start at vertex ``i``? The first two
    segments must move in the plane and their normal coordinate change linearly."""
    if i + 2 >= n:
        return False
    d1 = math.hypot(P[i + 1, a1] - P[i, a1], P[i + 1, a2] - P[i, a2])
    d2 = math.hypot(P[i + 2, a1] - P[i + 1, a1], P[i + 2, a2] - P[i + 1, a2])
    if d1 <= 0.0 or d2 <= 0.0:
        return False
    n1 = P[i + 1, an] - P[i, an]
    n2 = P[i + 2, an] - P[i + 1, an]
    # normal slope per in-plane length must agree (a helix has a constant slope)
    return abs(n1 / d1 - n2 / d2) * min(d1, d2) <= 2.0 * tol
