"""The toolpath: an ordered list of moves of the tool tip.

Coordinates are the tool tip (the controlled point before tool length offset) in the
job's units (mm or inch), in the part frame. Feeds are units per minute. Arcs follow
the canonical convention of LinuxCNC: ``clockwise`` seen from the positive normal of
the plane (XY: +Z, XZ: +Y, YZ: +X); ``turns`` is the P word, the number of times the
arc passes its end point (1 for an ordinary arc). Cubics are cubic Bezier curves in the
XY plane at constant Z (G5): start point (the previous end), control points ``c1`` and
``c2`` (x, y), end point.

Every move refers to the operation that produced it by index into ``Toolpath.ops``;
the operation carries the tool number, spindle speed and coolant.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Iterator, Literal

import numpy as np

Vec3 = tuple[float, float, float]
MoveKind = Literal["rapid", "line", "arc", "cubic", "drill", "comp", "dwell"]
Plane = Literal["XY", "XZ", "YZ"]

#: indices (first, second, normal) of each plane's axes in (x, y, z), as in RS274NGC:
#: XY: first X, second Y; XZ (G18): first Z, second X; YZ (G19): first Y, second Z.
PLANE_AXES: dict[str, tuple[int, int, int]] = {"XY": (0, 1, 2), "XZ": (2, 0, 1), "YZ": (1, 2, 0)}
#: the planes in the order of their codes (0 XY / G17, 1 XZ / G18, 2 YZ / G19)
PLANES: tuple[Plane, ...] = ("XY", "XZ", "YZ")


#: move kinds made by :meth:`Toolpath.rapid` and :meth:`Toolpath.line`: only ``end``,
#: ``feed`` and ``op`` set
_PLAIN = frozenset(("rapid", "line"))


@dataclass(slots=True)
class Move:
    """One move. Which fields matter depends on ``kind``:

    - ``rapid``: ``end``.
    - ``line``: ``end``, ``feed``.
    - ``arc``: ``end``, ``feed``, ``center`` (3D; its normal-axis component is ignored),
      ``plane``, ``clockwise``, ``turns``. Travel along the normal (helix) goes from the
      start's to the end's normal coordinate.
    - ``cubic``: ``end``, ``feed``, ``c1``, ``c2`` (XY control points); Z stays constant.
    - ``drill``: a canned cycle at ``end`` (x, y, z of the hole bottom): ``cycle`` is
      ``"G81"``, ``"G82"``, ``"G83"``, ``"G73"``, ``"G85"`` or ``"G89"``, ``r_plane`` the Z
      of the R plane, ``peck`` the Q increment, ``dwell`` the P seconds, ``feed``. The
      tool returns to the R plane (G99) or to the Z it started at (G98, ``retract_initial``).
    - ``dwell``: ``dwell`` seconds where the tool stands (``end`` is that point).
    - ``comp``: cutter radius compensation state change, ``comp`` in
      ``"left"`` (G41), ``"right"`` (G42) or ``"off"`` (G40); ``comp_d`` is the D word
      (tool number whose table diameter is used). Takes effect on the next motion.
    """

    kind: MoveKind
    end: Vec3
    feed: float = 0.0
    op: int = 0
    center: Vec3 | None = None
    plane: Plane = "XY"
    clockwise: bool = False
    turns: int = 1
    c1: tuple[float, float] | None = None
    c2: tuple[float, float] | None = None
    cycle: str = ""
    r_plane: float = 0.0
    peck: float = 0.0
    dwell: float = 0.0
    retract_initial: bool = False
    comp: str = ""
    comp_d: int = 0


@dataclass
class Operation:
    """What produced a run of moves: strategy type, a human name, tool and spindle.

    ``tolerance`` (job units) is how far below the design the operation may cut: the
    strategy's own tolerance key (chord / fit tolerance); the safety gate refuses a
    program whose simulated gouge under this operation exceeds it. None: no promise
    (any gouge beyond the job's fit tolerance is refused).
    """

    type: str
    name: str
    tool: int
    spindle: float = 0.0          # rpm, clockwise (M3); negative for M4
    coolant: str = "flood"        # "flood" (M8), "mist" (M7) or "off"
    info: dict = field(default_factory=dict)
    tolerance: float | None = None


@dataclass
class Toolpath:
    """An ordered list of moves in one unit system, with the operations behind them."""

    units: str = "mm"
    moves: list[Move] = field(default_factory=list)
    ops: list[Operation] = field(default_factory=list)

    # --- building -------------------------------------------------------------------
    def begin(self, op: Operation) -> int:
        """Start a new operation; later moves refer to it. Returns its index."""
        self.ops.append(op)
        return len(self.ops) - 1

    @property
    def _op(self) -> int:
        if not self.ops:
            raise ValueError("Toolpath.begin(Operation) must be called before adding moves")
        return len(self.ops) - 1

    def rapid(self, x: float, y: float, z: float) -> None:
        self.moves.append(Move("rapid", (float(x), float(y), float(z)), 0.0, self._op))

    def line(self, x: float, y: float, z: float, feed: float) -> None:
        self.moves.append(Move("line", (float(x), float(y), float(z)), float(feed), self._op))

    def lines(self, points, feed: float) -> None:
        """Feed lines to each of ``points`` ((n, 3) tip positions) in turn."""
        op = self._op
        feed = float(feed)
        self.moves.extend(Move("line", (x, y, z), feed, op)
                          for x, y, z in np.asarray(points, dtype=float).reshape(-1, 3).tolist())

    def arc(self, end: Vec3, center: Vec3, clockwise: bool, feed: float,
            plane: Plane = "XY", turns: int = 1) -> None:
        self.moves.append(Move("arc", tuple(map(float, end)), float(feed), self._op,
                               center=tuple(map(float, center)), plane=plane,
                               clockwise=bool(clockwise), turns=int(turns)))

    def cubic(self, c1: tuple[float, float], c2: tuple[float, float], end: Vec3,
              feed: float) -> None:
        self.moves.append(Move("cubic", tuple(map(float, end)), float(feed), self._op,
                               c1=(float(c1[0]), float(c1[1])), c2=(float(c2[0]), float(c2[1]))))

    def drill(self, x: float, y: float, z_bottom: float, r_plane: float, feed: float,
              cycle: str = "G81", peck: float = 0.0, dwell: float = 0.0,
              retract_initial: bool = False) -> None:
        self.moves.append(Move("drill", (float(x), float(y), float(z_bottom)), float(feed),
                               self._op, cycle=cycle, r_plane=float(r_plane),
                               peck=float(peck), dwell=float(dwell),
                               retract_initial=retract_initial))

    def compensation(self, side: str, d: int = 0) -> None:
        """Cutter radius compensation: side ``left`` (G41), ``right`` (G42), ``off`` (G40)."""
        if side not in ("left", "right", "off"):
            raise ValueError(f"compensation side must be left, right or off, not {side!r}")
        end = self.moves[-1].end if self.moves else (0.0, 0.0, 0.0)
        self.moves.append(Move("comp", end, 0.0, self._op, comp=side, comp_d=int(d)))

    def extend(self, other: "Toolpath") -> None:
        """Append another toolpath's operations and moves (same units)."""
        if other.units != self.units:
            raise ValueError(f"cannot join a {other.units} toolpath to a {self.units} one")
        base = len(self.ops)
        self.ops.extend(other.ops)
        append = self.moves.append
        for m in other.moves:
            if m.kind in _PLAIN and m.center is None:      # the other fields are defaults
                append(Move(m.kind, m.end, m.feed, m.op + base))
            else:
                append(Move(m.kind, m.end, m.feed, m.op + base, m.center, m.plane,
                            m.clockwise, m.turns, m.c1, m.c2, m.cycle, m.r_plane,
                            m.peck, m.dwell, m.retract_initial, m.comp, m.comp_d))

    # --- queries --------------------------------------------------------------------
    def __len__(self) -> int:
        return len(self.moves)

    def __iter__(self) -> Iterator[Move]:
        return iter(self.moves)

    def counts(self) -> dict[str, int]:
        """Number of moves of each kind that makes motion."""
        c = {"rapid": 0, "line": 0, "arc": 0, "cubic": 0, "drill": 0}
        for m in self.moves:
            if m.kind in c:
                c[m.kind] += 1
        return c

    def ends(self) -> np.ndarray:
        """(n, 3) array of move end points (all kinds)."""
        if not self.moves:
            return np.zeros((0, 3))
        return np.array([m.end for m in self.moves], dtype=float)

    def tool_of(self, move: Move) -> int:
        return self.ops[move.op].tool

    def check_finite(self) -> None:
        """Raise ValueError naming the first move with a NaN or infinite coordinate."""
        isfinite = math.isfinite
        for i, m in enumerate(self.moves):
            e = m.end
            # a sum of finite values is finite (unless it overflows: then look closer)
            if (isfinite(e[0] + e[1] + e[2] + m.feed) and m.center is None and m.c1 is None
                    and m.c2 is None):
                continue
            vals = list(m.end) + list(m.center or ()) + list(m.c1 or ()) + list(m.c2 or ())
            if not all(isfinite(v) for v in vals) or not isfinite(m.feed):
                raise ValueError(f"move {i} ({m.kind}, operation "
                                 f"{self.ops[m.op].name!r}) has a non-finite coordinate")


def arc_geometry(start: Vec3, m: Move) -> tuple[float, float, float, float]:
    """Return (radius, start angle, signed sweep in radians, normal travel) of an arc move.

    Angles are measured in the plane's (first, second) axes; the sweep is positive
    counter-clockwise and includes the extra full turns (``turns - 1``).
    """
    a1, a2, an = PLANE_AXES[m.plane]
    c = m.center
    assert c is not None
    s1, s2 = start[a1] - c[a1], start[a2] - c[a2]
    e1, e2 = m.end[a1] - c[a1], m.end[a2] - c[a2]
    r = math.hypot(s1, s2)
    t0 = math.atan2(s2, s1)
    t1 = math.atan2(e2, e1)
    if m.clockwise:
        sweep = t1 - t0
        if sweep >= -1e-12:
            sweep -= 2 * math.pi
        sweep -= 2 * math.pi * (m.turns - 1)
    else:
        sweep = t1 - t0
        if sweep <= 1e-12:
            sweep += 2 * math.pi
        sweep += 2 * math.pi * (m.turns - 1)
    return r, t0, sweep, m.end[an] - start[an]


def sample_move(start: Vec3, m: Move, step: float) -> np.ndarray:
    """Points along a motion move from ``start`` (inclusive) to its end, about ``step`` apart.

    Works for rapid, line, arc (any plane, helical) and cubic moves; returns (n, 3).
    """
    s = np.asarray(start, float)
    e = np.asarray(m.end, float)
    if m.kind in ("rapid", "line"):
        n = max(1, int(math.ceil(np.linalg.norm(e - s) / step)))
        t = np.linspace(0.0, 1.0, n + 1)[:, None]
        return s + (e - s) * t
    if m.kind == "arc":
        r, t0, sweep, dn = arc_geometry(start, m)
        a1, a2, an = PLANE_AXES[m.plane]
        length = math.hypot(abs(sweep) * r, dn)
        n = max(2, int(math.ceil(length / step)))
        t = np.linspace(0.0, 1.0, n + 1)
        out = np.empty((n + 1, 3))
        c = m.center
        assert c is not None
        out[:, a1] = c[a1] + r * np.cos(t0 + sweep * t)
        out[:, a2] = c[a2] + r * np.sin(t0 + sweep * t)
        out[:, an] = s[an] + dn * t
        out[-1] = e
        return out
    if m.kind == "cubic":
        assert m.c1 is not None and m.c2 is not None
        p0 = s[:2]
        p1, p2, p3 = np.asarray(m.c1), np.asarray(m.c2), e[:2]
        approx = (np.linalg.norm(p1 - p0) + np.linalg.norm(p2 - p1) + np.linalg.norm(p3 - p2))
        n = max(2, int(math.ceil(approx / step)))
        t = np.linspace(0.0, 1.0, n + 1)[:, None]
        xy = ((1 - t) ** 3 * p0 + 3 * (1 - t) ** 2 * t * p1 + 3 * (1 - t) * t ** 2 * p2
              + t ** 3 * p3)
        z = np.full((n + 1, 1), s[2])
        out = np.hstack([xy, z])
        out[-1] = e
        return out
    raise ValueError(f"cannot sample a {m.kind} move")
