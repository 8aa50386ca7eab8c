"""Four-point curve segments: a cubic through four points at u = 0, 1/3, 2/3, 1.

Each segment interpolates P1..P4 (job units, 2D) with the Lagrange basis on the nodes
u = 0, 1/3, 2/3, 1:

    L1(u) = -4.5 u^3 +  9.0 u^2 - 5.5 u + 1
    L2(u) = 13.5 u^3 - 22.5 u^2 + 9.0 u
    L3(u) = -13.5 u^3 + 18.0 u^2 - 4.5 u
    L4(u) =  4.5 u^3 -  4.5 u^2 + 1.0 u

(L_k is 1 at its own node and 0 at the three others), so P(u) = sum L_k(u) P_k and

    L1'(u) = -13.5 u^2 + 18 u - 5.5        L2'(u) =  40.5 u^2 - 45 u + 9
    L3'(u) = -40.5 u^2 + 36 u - 4.5        L4'(u) =  13.5 u^2 -  9 u + 1

At the ends: P'(0) = -5.5 P1 + 9 P2 - 4.5 P3 + P4 and P'(1) = -P1 + 4.5 P2 - 9 P3 + 5.5 P4.

Misprint (Mohamed 2006, seeds/001, eq. (5)): the paper prints G2'(u) = 41.5 u^2 - 45 u
+ 9 and G3'(u) = -41.5 u^2 + 36 u - 4.5; the derivative of L2 and L3 has 40.5 (as
above, derived from BASIS). The printed form does not reproduce a straight line's
constant tangent; tests/diecavity/test_misprints.py shows it failing and 40.5 agreeing
with finite differences and with that line.
Derivatives are with respect to u (job units per unit of u).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

#: rows: coefficients of (u^3, u^2, u, 1) for L1..L4
BASIS = np.array([[-4.5, 9.0, -5.5, 1.0],
                  [13.5, -22.5, 9.0, 0.0],
                  [-13.5, 18.0, -4.5, 0.0],
                  [4.5, -4.5, 1.0, 0.0]])
#: rows: coefficients of (u^2, u, 1) for L1'..L4'
DBASIS = BASIS[:, :3] * np.array([3.0, 2.0, 1.0])
#: rows: coefficients of (u, 1) for L1''..L4''
DDBASIS = DBASIS[:, :2] * np.array([2.0, 1.0])


def basis(u: np.ndarray | float) -> np.ndarray:
    """Lagrange basis values, shape (..., 4), at parameters ``u``."""
    u = np.asarray(u, float)[..., None]
    return ((BASIS[:, 0] * u + BASIS[:, 1]) * u + BASIS[:, 2]) * u + BASIS[:, 3]


def dbasis(u: np.ndarray | float) -> np.ndarray:
    """Derivatives of the basis with respect to u, shape (..., 4)."""
    u = np.asarray(u, float)[..., None]
    return (DBASIS[:, 0] * u + DBASIS[:, 1]) * u + DBASIS[:, 2]


def ddbasis(u: np.ndarray | float) -> np.ndarray:
    """Second derivatives of the basis, shape (..., 4)."""
    u = np.asarray(u, float)[..., None]
    return DDBASIS[:, 0] * u + DDBASIS[:, 1]


@dataclass
class FourPointSegment:
    """One cubic segment through ``points`` (4, 2) at u = 0, 1/3, 2/3, 1.

    ``kind`` is ``"given"`` (four points from the job) or ``"blend"`` (computed to join
    two given segments with C1 continuity); ``source`` is the index of the first given
    point (or -1 for a blend).
    """

    points: np.ndarray
    kind: str = "given"
    source: int = -1

    def __post_init__(self) -> None:
        self.points = np.asarray(self.points, float).reshape(4, 2)

    @property
    def start(self) -> np.ndarray:
        return self.points[0]

    @property
    def end(self) -> np.ndarray:
        return self.points[3]

    def poly(self) -> np.ndarray:
        """Power-basis coefficients (4, 2): rows u^3, u^2, u, 1 of P(u)."""
        return BASIS.T @ self.points

    def at(self, u: np.ndarray | float) -> np.ndarray:
        """Points P(u), shape (..., 2)."""
        return basis(u) @ self.points

    def d1(self, u: np.ndarray | float) -> np.ndarray:
        """First derivative dP/du, shape (..., 2)."""
        return dbasis(u) @ self.points

    def d2(self, u: np.ndarray | float) -> np.ndarray:
        """Second derivative d2P/du2, shape (..., 2)."""
        return ddbasis(u) @ self.points

    def curvature(self, u: np.ndarray | float) -> np.ndarray:
        """Signed curvature (1/length; positive turning counter-clockwise)."""
        d1, d2 = self.d1(u), self.d2(u)
        cross = d1[..., 0] * d2[..., 1] - d1[..., 1] * d2[..., 0]
        speed = np.hypot(d1[..., 0], d1[..., 1])
        with np.errstate(divide="ignore", invalid="ignore"):
            return cross / speed ** 3

    def bezier(self) -> np.ndarray:
        """The same cubic as Bezier control points (4, 2)."""
        p = self.points
        c1 = (-5 * p[0] + 18 * p[1] - 9 * p[2] + 2 * p[3]) / 6.0
        c2 = (2 * p[0] - 9 * p[1] + 18 * p[2] - 5 * p[3]) / 6.0
        return np.array([p[0], c1, c2, p[3]])

    def reversed(self) -> "FourPointSegment":
        return FourPointSegment(self.points[::-1].copy(), self.kind, self.source)


@dataclass
class Curve:
    """A chain of four-point segments; closed when the last ends where the first starts."""

    segments: list[FourPointSegment]

    @property
    def closed(self) -> bool:
        return float(np.hypot(*(self.segments[-1].end - self.segments[0].start))) < 1e-12

    def sample(self, per_segment: int = 200) -> np.ndarray:
        """Points along the whole curve, ``per_segment`` steps per segment, (n, 2).

        The end of each segment is not repeated as the start of the next."""
        u = np.linspace(0.0, 1.0, per_segment + 1)[:-1]
        pts = [s.at(u) for s in self.segments]
        pts.append(self.segments[-1].end[None, :])
        return np.vstack(pts)

    def signed_area(self, per_segment: int = 400) -> float:
        """Shoelace area of the sampled curve: positive when counter-clockwise."""
        p = self.sample(per_segment)
        x, y = p[:, 0], p[:, 1]
        return 0.5 * float(np.sum(x[:-1] * y[1:] - x[1:] * y[:-1]))

    def reversed(self) -> "Curve":
        return Curve([s.reversed() for s in reversed(self.segments)])

    def transformed(self, scale: float = 1.0, offset=(0.0, 0.0)) -> "Curve":
        off = np.asarray(offset, float)
        return Curve([FourPointSegment(s.points * scale + off, s.kind, s.source)
                      for s in self.segments])

    def junctions(self) -> list[dict]:
        """Continuity at each junction (segment i end -> segment i+1 start; the closing
        junction last when closed): position gap, derivative difference (per unit u),
        and the turn of the tangent in degrees."""
        out = []
        n = len(self.segments)
        last = n if self.closed else n - 1
        for i in range(last):
            a, b = self.segments[i], self.segments[(i + 1) % n]
            da, db = a.d1(1.0), b.d1(0.0)
            ang = float(np.degrees(np.arctan2(da[0] * db[1] - da[1] * db[0], da @ db)))
            out.append({"after": i, "before": (i + 1) % n,
                        "point": [float(a.end[0]), float(a.end[1])],
                        "position_gap": float(np.hypot(*(a.end - b.start))),
                        "derivative_gap": float(np.hypot(*(da - db))),
                        "tangent_turn_deg": ang,
                        "kinds": [a.kind, b.kind]})
        return out
