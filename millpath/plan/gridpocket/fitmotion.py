"""Turn a chain of tool-tip points into lines, circular arcs or cubic curves.

Modes (job units, tolerance an absolute length):

- ``line``: a line to every point (points exactly on one straight line are merged).
- ``arc``: points in a principal plane (XZ: constant Y, YZ: constant X, XY: constant
  Z) are fitted by circular arcs with the three-point method: the circle through the
  first, middle and last point of a span is accepted when every point's distance
  error ``|r - d|`` is within the tolerance; otherwise the span shrinks by one point
  and the test repeats. Spans whose points lie within the tolerance of their chord
  become lines (this covers very large radii).
- ``bezier``: spans of four or more points in a principal plane are fitted by a cubic
  Bezier curve with fixed end points whose inner control points are solved so that
  the curve passes through the second and the second-to-last points at parameters
  u1 and u2: ``"chord"`` (default) takes them from the chord lengths of the points,
  ``"uniform"`` is the thesis's u1 = 1/(n-1), u2 = 1 - u1 for n points (Choi 1999,
  seeds/000 §4.3, Fig. 18); every point must lie within the tolerance of the curve.
  Cubics in the XY plane (constant Z: wall laps and main-path runs on a flat floor)
  are written as cubic moves (G5); LinuxCNC's G5 is XY-only, so cubics in XZ or YZ
  are approximated by arcs (half the tolerance each). :meth:`Fitter.bezier_report`
  counts both kinds and compares the two parameterisations on the accepted spans.

Arcs are ``clockwise`` as seen from the plane's positive normal, as RS274NGC.

Gouge protection: a chain may carry check points (tip positions the path must not go
below, with their distance along the chain). A candidate line, arc or cubic in a
vertical plane is rejected when it passes more than half the tolerance below a check
point inside its span (the other half: the sampling between check points and the
post's rounding); XY candidates must stay within the tolerance of the point polyline
(so they never cut corners), or, on the wall pass, inside the offset outline grown by
the tolerance (so they follow the true round corners but never swing into a wall).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from millpath.model.toolpath import PLANE_AXES


@dataclass
class Seg:
    """One fitted piece from the previous end to ``end``."""

    kind: str                       # "line" | "arc" | "cubic"
    end: np.ndarray                 # (3,)
    center: np.ndarray | None = None
    plane: str = "XY"
    clockwise: bool = False
    c1: tuple[float, float] | None = None
    c2: tuple[float, float] | None = None


@dataclass
class Chain:
    """Points the tool feeds through, in order (the first is where it already is)."""

    pts: np.ndarray                 # (n, 3)
    pos: np.ndarray                 # (n,) XY distance along the chain
    checks: np.ndarray | None = None    # (k, 3) required tip positions
    check_pos: np.ndarray | None = None
    region: object = None           # shapely area an XY curve may use (wall pass), else
                                    # XY curves must stay within tol of the polyline


# --- small geometry ------------------------------------------------------------------
def _circle(p1, p2, p3):
    """Centre and radius of the circle through three 2D points, or None if collinear."""
    ax, ay = p2[0] - p1[0], p2[1] - p1[1]
    bx, by = p3[0] - p1[0], p3[1] - p1[1]
    d = 2.0 * (ax * by - ay * bx)
    scale = max(ax * ax + ay * ay, bx * bx + by * by)
    if abs(d) <= 1e-12 * scale or scale == 0:
        return None
    a2, b2 = ax * ax + ay * ay, bx * bx + by * by
    ux = (by * a2 - ay * b2) / d
    uy = (ax * b2 - bx * a2) / d
    c = np.array([p1[0] + ux, p1[1] + uy])
    return c, math.hypot(ux, uy)


def _dist_to_polyline(P: np.ndarray, poly: np.ndarray) -> np.ndarray:
    """Distance from each point ``P`` (m, d) to the polyline ``poly`` (k, d)."""
    a = poly[:-1][None]
    b = poly[1:][None]
    ab = b - a
    L2 = (ab ** 2).sum(-1)
    L2 = np.where(L2 == 0, 1.0, L2)
    t = np.clip(((P[:, None] - a) * ab).sum(-1) / L2, 0.0, 1.0)
    proj = a + t[..., None] * ab
    return np.sqrt(((P[:, None] - proj) ** 2).sum(-1)).min(axis=1)


def _cubic_points(p0, c1, c2, p3, n: int) -> np.ndarray:
    t = np.linspace(0.0, 1.0, n)[:, None]
    return ((1 - t) ** 3 * p0 + 3 * (1 - t) ** 2 * t * c1 + 3 * (1 - t) * t ** 2 * c2
            + t ** 3 * p3)


def fit_cubic(Q: np.ndarray, parameters: str = "chord"):
    """Control points (c1, c2) of the cubic through Q[0], Q[1], Q[-2], Q[-1] (Q is
    (k, d), k >= 4) passing Q[1] at u1 and Q[-2] at u2: chord-length parameters, or
    ``"uniform"``: u1 = 1/(k-1), u2 = 1 - u1 (the thesis's); None if singular."""
    seg = np.linalg.norm(np.diff(Q, axis=0), axis=1)
    total = seg.sum()
    if total <= 0:
        return None
    if parameters == "uniform":
        t1 = 1.0 / (len(Q) - 1)
        t2 = 1.0 - t1
    else:
        t = np.concatenate([[0.0], np.cumsum(seg)]) / total
        t1, t2 = t[1], t[-2]

    def basis(s):
        return np.array([(1 - s) ** 3, 3 * (1 - s) ** 2 * s, 3 * (1 - s) * s ** 2, s ** 3])

    b1, b2 = basis(t1), basis(t2)
    A = np.array([[b1[1], b1[2]], [b2[1], b2[2]]])
    if abs(np.linalg.det(A)) < 1e-12:
        return None
    rhs = np.stack([Q[1] - b1[0] * Q[0] - b1[3] * Q[-1], Q[-2] - b2[0] * Q[0] - b2[3] * Q[-1]])
    C = np.linalg.solve(A, rhs)
    return C[0], C[1]


# --- the fitter ----------------------------------------------------------------------
class Fitter:
    """Fit chains in one ``mode`` with ``tol`` (job units); ``max_radius`` turns arcs of
    larger radius into lines."""

    def __init__(self, mode: str, tol: float, max_radius: float, decimals: int = 12,
                 parameters: str = "chord"):
        if mode not in ("line", "arc", "bezier"):
            raise ValueError(f"motion must be line, arc or bezier, not {mode!r}")
        if parameters not in ("chord", "uniform"):
            raise ValueError(f"bezier parameters must be chord or uniform, not {parameters!r}")
        self.parameters = parameters
        # Bezier statistics: cubics written as G5, cubics turned into arcs and lines,
        # and the largest point-to-curve deviation of the accepted spans under each
        # parameterisation (the other one refitted on the same span)
        self.cubics_g5 = 0
        self.cubics_as_arcs = 0
        self.arcs_from_cubics = 0
        self.lines_from_cubics = 0
        self.deviation = {"chord": 0.0, "uniform": 0.0}
        self.mode = mode
        self.tol = tol
        self.max_radius = max_radius
        self.decimals = decimals    # points are written with this many decimals
        self.max_span = 40          # longest span (segments) tried as one arc or cubic

    def fit(self, chain: Chain) -> list[Seg]:
        P = chain.pts
        if len(P) < 2:
            return []
        out: list[Seg] = []
        for a, b, plane in self._planar_groups(P):
            out.extend(self._fit_group(chain, a, b, plane))
        return out

    # planar sub-chains: consecutive segments sharing a principal plane
    def _planar_groups(self, P: np.ndarray):
        d = np.diff(P, axis=0)
        scale = max(1.0, float(np.abs(P).max()))
        eps = 1e-9 * scale
        flags = [set() for _ in range(len(d))]
        for k, (ddx, ddy, ddz) in enumerate(d):
            if abs(ddy) <= eps:
                flags[k].add("XZ")
            if abs(ddx) <= eps:
                flags[k].add("YZ")
            if abs(ddz) <= eps:
                flags[k].add("XY")
        k = 0
        while k < len(d):
            common = set(flags[k])
            e = k + 1
            while e < len(d) and common & flags[e]:
                common &= flags[e]
                e += 1
            plane = None
            for cand in ("XZ", "YZ", "XY"):
                if cand in common:
                    plane = cand
                    break
            yield k, e, plane          # points k..e
            k = e

    def _fit_group(self, chain: Chain, a: int, b: int, plane: str | None) -> list[Seg]:
        P = chain.pts
        out: list[Seg] = []
        line_tol = self.tol if self.mode != "line" else 1e-9 * max(1.0, float(np.abs(P).max()))
        i = a
        while i < b:
            done = False
            for e in range(b, i, -1):
                if e - i >= 2 and self._line_ok(chain, i, e, line_tol, plane):
                    out.append(Seg("line", P[e].copy()))
                    done = True
                elif e - i == 1:
                    out.append(Seg("line", P[e].copy()))
                    done = True
                elif e - i > self.max_span:
                    continue        # curves are tried on at most max_span segments
                elif plane is not None and self.mode == "arc":
                    seg = self._arc(chain, i, e, plane, self.tol, self.tol / 2.0)
                    if seg is not None:
                        out.append(seg)
                        done = True
                elif plane is not None and self.mode == "bezier" and e - i >= 3:
                    segs = self._cubic(chain, i, e, plane)
                    if segs is not None:
                        out.extend(segs)
                        done = True
                if done:
                    i = e
                    break
        return out

    # --- tests ------------------------------------------------------------------------
    def _checks_in(self, chain: Chain, i: int, e: int):
        if chain.checks is None:
            return None
        lo, hi = chain.pos[i], chain.pos[e]
        k0 = np.searchsorted(chain.check_pos, lo - 1e-12, side="left")
        k1 = np.searchsorted(chain.check_pos, hi + 1e-12, side="right")
        return chain.checks[k0:k1]

    def _z_ok(self, chain: Chain, i: int, e: int, curve: np.ndarray, budget: float) -> bool:
        """Curve samples (m, 3) along a straight XY span not below the check points."""
        K = self._checks_in(chain, i, e)
        if K is None or len(K) == 0:
            return True
        p0 = chain.pts[i, :2]
        u = chain.pts[e, :2] - p0
        L = np.hypot(u[0], u[1])
        if L == 0:
            return True
        u = u / L
        sc = (curve[:, :2] - p0) @ u
        order = np.argsort(sc)
        sk = (K[:, :2] - p0) @ u
        zc = np.interp(sk, sc[order], curve[order, 2])
        return bool(np.all(zc >= K[:, 2] - budget))

    def _xy_ok(self, chain: Chain, S: np.ndarray, Q: np.ndarray, tol: float) -> bool:
        """An XY curve (samples S) may replace the polyline Q: inside the chain's region
        (wall pass), else within tol of the polyline everywhere."""
        if chain.region is not None:
            import shapely
            return bool(shapely.covers(chain.region, shapely.points(S)).all())
        return bool(_dist_to_polyline(S, Q).max() <= tol)

    def _line_ok(self, chain: Chain, i: int, e: int, tol: float, plane) -> bool:
        Q = chain.pts[i:e + 1]
        if _dist_to_polyline(Q[1:-1], Q[[0, -1]]).max() > tol:
            return False
        return self._z_ok(chain, i, e, Q[[0, -1]], min(tol, self.tol / 2.0)) if plane != "XY" else True

    def _arc(self, chain: Chain, i: int, e: int, plane: str, tol: float,
             budget: float, pts: np.ndarray | None = None) -> Seg | None:
        """The three-point arc of points i..e in ``plane``, or None if it fails."""
        P = chain.pts if pts is None else pts
        a1, a2, an = PLANE_AXES[plane]
        Q = P[i:e + 1][:, [a1, a2]]
        m = (i + e) // 2 - i
        circ = _circle(Q[0], Q[m], Q[-1])
        if circ is None:
            return None
        c, r = circ
        if r > self.max_radius:
            return None
        d = np.hypot(Q[:, 0] - c[0], Q[:, 1] - c[1])
        if np.abs(d - r).max() > tol:
            return None
        ang = np.unwrap(np.arctan2(Q[:, 1] - c[1], Q[:, 0] - c[0]))
        steps = np.diff(ang)
        if not (np.all(steps > 0) or np.all(steps < 0)):
            return None
        sweep = ang[-1] - ang[0]
        if abs(sweep) >= 0.95 * math.pi:
            return None
        if pts is None:
            # the real arc between the points: not below check points, not out of the walls
            # samples close enough that chords stay within tol / 8 of the arc
            n = int(np.clip(abs(sweep) * r / math.sqrt(r * tol) + 2, 4 * (e - i), 4000))
            th = np.linspace(ang[0], ang[-1], max(8, n))
            S = np.empty((len(th), 3))
            S[:, a1] = c[0] + r * np.cos(th)
            S[:, a2] = c[1] + r * np.sin(th)
            S[:, an] = P[i, an]
            if plane == "XY":
                if not self._xy_ok(chain, S[:, :2], P[i:e + 1, :2], tol):
                    return None
            elif not self._z_ok(chain, i, e, S, budget):
                return None
        # the centre on the bisector of the chord, as a control recomputes it from the
        # written end points
        chord = Q[-1] - Q[0]
        clen = math.hypot(chord[0], chord[1])
        if clen > 0:
            mid = (Q[0] + Q[-1]) / 2.0
            nrm = np.array([-chord[1], chord[0]]) / clen
            c = mid + ((c - mid) @ nrm) * nrm
        center = P[i].copy()
        center[a1], center[a2] = c
        return Seg("arc", P[e].copy(), center=center, plane=plane, clockwise=bool(sweep < 0))

    def _cubic(self, chain: Chain, i: int, e: int, plane: str) -> list[Seg] | None:
        P = chain.pts
        a1, a2, an = PLANE_AXES[plane]
        Q = P[i:e + 1][:, [a1, a2]]
        cc = fit_cubic(Q, self.parameters)
        if cc is None:
            return None
        c1, c2 = cc
        tol = self.tol if plane == "XY" else self.tol / 2.0
        S2 = _cubic_points(Q[0], c1, c2, Q[-1], 64 + 8 * (e - i))
        dev = float(_dist_to_polyline(Q, S2).max())
        if dev > tol:
            return None
        S = np.empty((len(S2), 3))
        S[:, a1], S[:, a2] = S2[:, 0], S2[:, 1]
        S[:, an] = P[i, an]
        if plane == "XY":
            if not self._xy_ok(chain, S2, Q, tol):
                return None
            self._note_cubic(Q, dev)
            self.cubics_g5 += 1
            return [Seg("cubic", P[e].copy(), c1=(float(c1[0]), float(c1[1])),
                        c2=(float(c2[0]), float(c2[1])))]
        if not self._z_ok(chain, i, e, S, tol):
            return None
        # approximate the vertical cubic by arcs within the other half of the tolerance
        S2 = _cubic_points(Q[0], c1, c2, Q[-1], 3 * (e - i) + 4)
        S = np.empty((len(S2), 3))
        S[:, a1], S[:, a2] = S2[:, 0], S2[:, 1]
        S[:, an] = P[i, an]
        S = np.round(S, self.decimals)
        S[0], S[-1] = P[i], P[e]
        sub = Chain(S, np.zeros(len(S)))
        out: list[Seg] = []
        k = 0
        n = len(S) - 1
        while k < n:
            for f in range(n, k, -1):
                if f - k == 1:
                    out.append(Seg("line", S[f].copy()))
                    break
                Qs = S[k:f + 1]
                if _dist_to_polyline(Qs[1:-1], Qs[[0, -1]]).max() <= tol:
                    out.append(Seg("line", S[f].copy()))
                    break
                seg = self._arc(sub, k, f, plane, tol, tol, pts=S)
                if seg is not None:
                    out.append(seg)
                    break
            k = f
        self._note_cubic(Q, dev)
        self.cubics_as_arcs += 1
        self.arcs_from_cubics += sum(s.kind == "arc" for s in out)
        self.lines_from_cubics += sum(s.kind == "line" for s in out)
        return out

    def _note_cubic(self, Q: np.ndarray, dev: float) -> None:
        """Record an accepted cubic's deviation and the other parameterisation's."""
        self.deviation[self.parameters] = max(self.deviation[self.parameters], dev)
        other = "uniform" if self.parameters == "chord" else "chord"
        cc = fit_cubic(Q, other)
        if cc is not None:
            S2 = _cubic_points(Q[0], cc[0], cc[1], Q[-1], 64 + 8 * len(Q))
            d = float(_dist_to_polyline(Q, S2).max())
            self.deviation[other] = max(self.deviation[other], d)

    def bezier_report(self) -> dict:
        """Cubics written as G5 (XY) and as arcs (XZ/YZ), and the largest deviation of
        the accepted spans' points from their cubic under both parameterisations."""
        return {"parameters": self.parameters, "cubics_written_as_g5": self.cubics_g5,
                "cubics_written_as_arcs": self.cubics_as_arcs,
                "arcs_from_cubics": self.arcs_from_cubics,
                "lines_from_cubics": self.lines_from_cubics,
                "max_deviation": {k: round(v, 9) for k, v in self.deviation.items()}}
