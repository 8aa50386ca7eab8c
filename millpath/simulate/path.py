"""Motion for the simulator: Toolpath moves as interpreted motion, and motion as chords.

Everything here works on :class:`millpath.model.motion.Motion` records (kinds
``traverse``, ``feed``, ``arc``, ``cubic``, ``dwell``), whose coordinates are the tool
tip in program units. A :class:`~millpath.model.Toolpath` is first expanded to motion
the way LinuxCNC executes it (canned drilling cycles become traverses, feeds and
dwells); then every motion is cut into straight chords whose distance from the true
curve is at most a chord tolerance (a length in program units).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from millpath.model.motion import Motion
from millpath.model.toolpath import PLANE_AXES, Move, Toolpath
from millpath.post.lower import cycle_moves

Vec3 = tuple[float, float, float]


# --- Toolpath -> motion ---------------------------------------------------------------

_MOTION_OF = {"rapid": "traverse", "line": "feed", "dwell": "dwell"}


def _drill_motions(m: Move, pos: Vec3, tool: int, line: int, units: str) -> list[Motion]:
    """One canned-cycle move from ``pos`` as LinuxCNC runs it (the moves of
    :func:`millpath.post.lower.cycle_moves`, the run of cycles starting at ``pos``)."""
    out: list[Motion] = []
    cur = tuple(pos)
    for mv in cycle_moves(pos, m, pos[2], units):
        if mv.kind == "dwell":
            out.append(Motion("dwell", line, cur, cur, dwell=mv.dwell, tool=tool))
        elif any(a != b for a, b in zip(cur, mv.end)):
            out.append(Motion(_MOTION_OF[mv.kind], line, cur, mv.end, feed=mv.feed,
                              tool=tool))
            cur = mv.end
    return out


def toolpath_motions(tp: Toolpath) -> tuple[list[Motion], list[int]]:
    """Motion of a Toolpath and, for each motion, the index of the move it came from.

    Each motion's ``line`` is its move index (0-based) and ``tool`` the operation's
    tool. The tool starts at the first move's end point (at the R plane for a drill).
    ``comp`` moves cannot be expanded without the interpreter: ValueError.
    """
    motions: list[Motion] = []
    src: list[int] = []
    if not tp.moves:
        return motions, src
    first = tp.moves[0]
    pos: Vec3 = (first.end[0], first.end[1],
                 max(first.end[2], first.r_plane) if first.kind == "drill" else first.end[2])
    op_tool = [op.tool for op in tp.ops]
    append_m = motions.append
    append_s = src.append
    for i, m in enumerate(tp.moves):
        tool = op_tool[m.op]
        k = m.kind
        if k == "line":                                   # fast paths: most moves
            append_m(Motion("feed", i, pos, m.end, m.feed, (0.0, 0.0, 0.0), tool))
            append_s(i)
            pos = m.end
            continue
        if k == "rapid":
            append_m(Motion("traverse", i, pos, m.end, 0.0, (0.0, 0.0, 0.0), tool))
            append_s(i)
            pos = m.end
            continue
        if k == "comp":
            raise ValueError(
                f"move {i} is a cutter compensation change ({m.comp}); a Toolpath with "
                "compensation cannot be simulated directly: post it and simulate the "
                "interpreted motion (millpath.interpret.interpret + simulate_motions)")
        if k == "drill":
            # G98 returns to the Z the move starts at: for a series of holes posted as
            # one cycle that is max(Z before the series, R), the same for every hole
            ms = _drill_motions(m, pos, tool, i, tp.units)
        elif k == "arc":
            assert m.center is not None
            a1, a2, an = PLANE_AXES[m.plane]
            c = list(m.center)
            c[an] = pos[an]
            rot = -m.turns if m.clockwise else m.turns
            ms = [Motion("arc", i, pos, m.end, feed=m.feed, tool=tool, plane=m.plane,
                         center=tuple(c), rotation=rot)]
        elif k == "cubic":
            ms = [Motion("cubic", i, pos, m.end, feed=m.feed, tool=tool,
                         controls=(m.c1, m.c2))]
        elif k == "dwell":
            ms = [Motion("dwell", i, pos, pos, dwell=m.dwell, tool=tool)]
        else:
            raise ValueError(f"move {i}: unknown move kind {k!r}")
        for mo in ms:
            append_m(mo)
            append_s(i)
        if ms:
            pos = ms[-1].end
    return motions, src


# --- geometry of one motion -----------------------------------------------------------

def arc_params(mo: Motion) -> tuple[float, float, float, float]:
    """(radius, start angle, signed sweep, normal travel) of an arc motion.

    The sweep is counter-clockwise positive about the plane's normal and includes the
    extra full turns of ``|rotation| > 1``; equal start and end make a full circle.
    """
    a1, a2, an = PLANE_AXES[mo.plane]
    c = mo.center
    assert c is not None
    s1, s2 = mo.start[a1] - c[a1], mo.start[a2] - c[a2]
    e1, e2 = mo.end[a1] - c[a1], mo.end[a2] - c[a2]
    r = math.hypot(s1, s2)
    t0 = math.atan2(s2, s1)
    d = math.atan2(e2, e1) - t0
    turns = max(1, abs(mo.rotation))
    if mo.rotation < 0:
        if d >= -1e-12:
            d -= 2 * math.pi
        d -= 2 * math.pi * (turns - 1)
    else:
        if d <= 1e-12:
            d += 2 * math.pi
        d += 2 * math.pi * (turns - 1)
    return r, t0, d, mo.end[an] - mo.start[an]


def _arc_chords(r: float, sweep: float, chord_tol: float) -> int:
    """Chords (at least 2) of an arc of radius ``r`` turning ``sweep`` rad, each within
    ``chord_tol`` of it."""
    step = math.pi / 2 if r <= chord_tol else 2.0 * math.acos(max(-1.0, 1.0 - chord_tol / r))
    return max(2, int(math.ceil(abs(sweep) / max(step, 1e-9))))


def motion_points(mo: Motion, chord_tol: float) -> np.ndarray:
    """Points (n, 3) from start to end whose chords stay within ``chord_tol`` of the
    motion (lines: the two end points)."""
    return _points(mo, chord_tol, False)[0]


def _arc_points(mo: Motion, chord_tol: float, cover: bool):
    """An arc's chord points (vertices on the arc; ``cover``: the inner ones moved out
    by half the sagitta) and each chord's deviation bound (see :func:`cover_points`)."""
    s = np.asarray(mo.start, float)
    e = np.asarray(mo.end, float)
    r, t0, sweep, dn = arc_params(mo)
    a1, a2, an = PLANE_AXES[mo.plane]
    n = _arc_chords(r, sweep, chord_tol)
    t = np.linspace(0.0, 1.0, n + 1)
    c = mo.center
    assert c is not None
    th = abs(sweep) / n                         # each chord's angle
    sag = r * (1.0 - math.cos(th / 2.0))        # an inscribed chord's sagitta
    rad = np.full(n + 1, r + (sag / 2.0 if cover else 0.0))
    rad[0] = rad[-1] = r                        # the motion's own ends
    out = np.empty((n + 1, 3))
    out[:, a1] = c[a1] + rad * np.cos(t0 + sweep * t)
    out[:, a2] = c[a2] + rad * np.sin(t0 + sweep * t)
    out[:, an] = s[an] + dn * t
    out[0] = s
    out[-1] = e
    if not cover:
        return out, None
    # every arc point lies on the ray from the centre through a point of its chord, at
    # |r - rho| from it, rho between the chord's nearest approach to the centre and its
    # farther end (in plane); along the normal the chord's point is off by the normal
    # travel times the gap between the chord's and the arc's parameters on that ray
    A = np.stack([out[:-1, a1] - c[a1], out[:-1, a2] - c[a2]], axis=1)
    B = np.stack([out[1:, a1] - c[a1], out[1:, a2] - c[a2]], axis=1)
    ra, rb = np.hypot(A[:, 0], A[:, 1]), np.hypot(B[:, 0], B[:, 1])
    d = B - A
    ll = np.maximum((d * d).sum(axis=1), 1e-300)
    f = np.clip(-(A * d).sum(axis=1) / ll, 0.0, 1.0)     # the foot of the centre
    near = np.hypot(A[:, 0] + f * d[:, 0], A[:, 1] + f * d[:, 1])
    inplane = np.maximum(np.maximum(ra, rb) - r, r - near)
    along = abs(dn) / n * (th * th / 16.0 + np.abs(ra - rb) / (2.0 * max(r, 1e-300)))
    # (and the coordinates' rounding)
    return out, np.maximum(inplane, 0.0) + along + 1e-12 * max(r, 1.0)


def _points(mo: Motion, chord_tol: float, cover: bool):
    """(points, per-chord deviation bound or None) of a motion, see :func:`cover_points`."""
    s = np.asarray(mo.start, float)
    e = np.asarray(mo.end, float)
    if mo.kind == "arc":
        return _arc_points(mo, chord_tol, cover)
    if mo.kind == "cubic" and mo.controls is not None:
        p0, p3 = s[:2], e[:2]
        p1, p2 = np.asarray(mo.controls[0], float), np.asarray(mo.controls[1], float)
        # flatness bound: |B''| <= 6 max|second differences|; chord error <= |B''| / (8 n^2)
        m2 = 6.0 * max(np.linalg.norm(p0 - 2 * p1 + p2), np.linalg.norm(p1 - 2 * p2 + p3))
        n = max(1, int(math.ceil(math.sqrt(m2 / (8.0 * chord_tol)))))
        t = np.linspace(0.0, 1.0, n + 1)[:, None]
        xy = ((1 - t) ** 3 * p0 + 3 * (1 - t) ** 2 * t * p1 + 3 * (1 - t) * t ** 2 * p2
              + t ** 3 * p3)
        out = np.empty((n + 1, 3))
        out[:, :2] = xy
        out[:, 2] = s[2] + (e[2] - s[2]) * t[:, 0]
        out[0] = s
        out[-1] = e
        # each point of the curve within m2 / (8 n^2) of the chord's point at the same
        # parameter (Z is linear in it on both)
        return out, (np.full(n, m2 / (8.0 * n * n)) if cover else None)
    if mo.kind == "nurbs" and mo.controls is not None:
        xy = mo.controls.sample(chord_tol)
        out = np.empty((len(xy), 3))
        out[:, :2] = xy
        out[:, 2] = s[2]
        out[0] = s
        out[-1] = e
        # (an estimate: the sampling measures the curve at each chord's middle)
        return out, (np.full(len(out) - 1, chord_tol) if cover else None)
    return np.vstack([s, e]), (np.zeros(1) if cover else None)


def cover_points(mo: Motion, chord_tol: float) -> tuple[np.ndarray, np.ndarray]:
    """Points (n + 1, 3) of a motion for the exact check and, per chord, a bound
    (program units) on how far a point of the motion between the chord's ends lies
    from the chord: the tool swept along the motion lies within that of the tool swept
    along the chords, so a depth measured against a chord plus its bound is never
    under the motion's. Arcs: inner points moved out from the centre by half the
    sagitta ``s`` of chords within ``chord_tol`` of the arc (the chords then cross it:
    bounds about ``s / 2``, ``3 s / 4`` for the first and last); cubics: chords within
    ``chord_tol / 2`` (bound: the curve's second derivative's, exact); NURBS: within
    ``chord_tol / 2`` at each chord's middle (bound: that, an estimate); lines: 0."""
    if mo.kind == "arc":
        return _arc_points(mo, chord_tol, True)
    if is_curve(mo):
        return _points(mo, chord_tol / 2.0, True)
    return _points(mo, chord_tol, True)


def chord_count(mo: Motion, chord_tol: float) -> int:
    """How many chords :func:`motion_points` makes of ``mo`` (1 for a straight motion);
    cubics and NURBS: at most that many, from their control points' spread."""
    if mo.kind == "arc":
        r, _, sweep, _ = arc_params(mo)
        return _arc_chords(r, sweep, chord_tol)
    if is_curve(mo):
        c = np.asarray(mo.controls if mo.kind == "cubic" else mo.controls.points, float)
        span = float(np.ptp(np.vstack([np.asarray(mo.start, float)[:2], c[:, :2]]), axis=0).max())
        return max(1, int(math.ceil(math.sqrt(3.0 * span / max(chord_tol, 1e-12)))))
    return 1


def motion_blocks(motions: list[Motion], chord_tol: float, max_motions: int,
                  max_chords: int) -> list[tuple[int, int]]:
    """Ranges [a, b) of ``motions`` holding at most ``max_motions`` motions and, unless a
    single motion has more, about ``max_chords`` chords at ``chord_tol``: the blocks a
    long program is cut into (and checked) one after another, so that memory stays
    bounded however finely its arcs are chorded."""
    out: list[tuple[int, int]] = []
    a, n_ch = 0, 0
    for k, mo in enumerate(motions):
        c = chord_count(mo, chord_tol) if is_curve(mo) else 1
        if k > a and (k - a >= max_motions or n_ch + c > max_chords):
            out.append((a, k))
            a, n_ch = k, 0
        n_ch += c
    if a < len(motions):
        out.append((a, len(motions)))
    return out


def is_curve(mo: Motion) -> bool:
    """Whether ``mo`` is cut into chords (arcs; cubics and NURBS with their control
    points; rs274's NURBS output without them is known only by its end points)."""
    k = mo.kind
    return k == "arc" or ((k == "cubic" or k == "nurbs") and mo.controls is not None)


@dataclass
class Segments:
    """Straight chords of a motion list, in order.

    ``start``/``end`` (n, 3) tool tip positions, ``motion`` (n,) index of the source
    motion, ``rapid`` (n,) bool, ``tool`` (n,) tool number; ``dev`` (n,) each chord's
    deviation bound when made with ``cover`` (see :func:`cover_points`), else None.
    """

    start: np.ndarray
    end: np.ndarray
    motion: np.ndarray
    rapid: np.ndarray
    tool: np.ndarray
    dev: np.ndarray | None = None

    def __len__(self) -> int:
        return len(self.motion)


def motion_segments(motions: list[Motion], chord_tol: float, cover: bool = False) -> Segments:
    """Cut motion into chords within ``chord_tol`` (program units) of the true path;
    ``cover``: as :func:`cover_points` cuts them, with each chord's deviation bound."""
    starts: list = []
    ends: list = []
    idx: list = []
    rap: list = []
    tools: list = []
    big_s: list[np.ndarray] = []
    big_e: list[np.ndarray] = []
    big_i: list[np.ndarray] = []
    big_d: list[np.ndarray] = []

    def flush() -> None:
        big_s.append(np.asarray(starts, float).reshape(-1, 3))
        big_e.append(np.asarray(ends, float).reshape(-1, 3))
        big_i.append(np.array([idx, rap, tools], dtype=np.int64).reshape(3, -1))
        big_d.append(np.zeros(len(idx)))

    for k, mo in enumerate(motions):
        kind = mo.kind
        if kind == "dwell":
            continue
        if not is_curve(mo):
            # traverse, feed, and motion known only by its end points (rs274's NURBS
            # output of G5): a straight chord
            starts.append(mo.start)
            ends.append(mo.end)
            idx.append(k)
            rap.append(kind == "traverse")
            tools.append(mo.tool)
        else:
            pts, dev = cover_points(mo, chord_tol) if cover else (motion_points(mo, chord_tol),
                                                                  None)
            if starts:      # flush the pending straight moves to keep order
                flush()
                starts, ends, idx, rap, tools = [], [], [], [], []
            n = len(pts) - 1
            big_s.append(pts[:-1])
            big_e.append(pts[1:])
            big_i.append(np.array([[k] * n, [0] * n, [mo.tool] * n], dtype=np.int64))
            big_d.append(dev if dev is not None else np.zeros(n))
    if starts:
        flush()
    if not big_s:
        z = np.zeros((0, 3))
        e = np.zeros(0, np.int64)
        return Segments(z, z.copy(), e, e.astype(bool), e.copy(),
                        np.zeros(0) if cover else None)
    S = np.ascontiguousarray(np.vstack(big_s))
    E = np.ascontiguousarray(np.vstack(big_e))
    I = np.hstack(big_i)
    return Segments(S, E, np.ascontiguousarray(I[0]), I[1].astype(bool),
                    np.ascontiguousarray(I[2]),
                    np.ascontiguousarray(np.concatenate(big_d)) if cover else None)
