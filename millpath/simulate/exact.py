"""Grid-free verification against triangle-mesh references: gouge and material left.

A :class:`Reference` is a design as triangles (walls included) and the operations it
applies to. :func:`verify_exact` checks every chord of the motion (see
:mod:`millpath.simulate.gouge`) against the references of its operation and measures
the material left along the normal at points of each reference
(:mod:`millpath.simulate.leftover`). ``accuracy`` (program units) bounds the gouge
figure: curves are cut into chords whose bound on the curve's distance is added to
their depths (:func:`millpath.simulate.path.cover_points`), so a figure is not under
the motion's for that; the material left is exact (to ``accuracy``) at sample points
``spacing`` apart. Designs that are only height fields are meshed by
:func:`millpath.geometry.heightmesh.height_field_mesh` (walls placed exactly on a 50 * ``accuracy`` grid).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Iterator

import numpy as np

from millpath.geometry.heightmesh import height_field_mesh
from millpath.geometry.index import BoxIndex
from millpath.model.motion import Motion
from millpath.model.stock import Stock
from millpath.model.tool import Tool
from millpath.progress import QUIET, Progress
from millpath.simulate.gouge import (GougeResult, ToolShapes, faces_of, gouge_chords, locate,
                                     near_chords)
from millpath.simulate.leftover import (SweptChords, first_of_each, medial_cap, ray_caps,
                                        sample_keys, sample_triangles, shorten_rays,
                                        swept_chords)
from millpath.simulate.groups import ChordGroups, chord_groups
from millpath.simulate.leftpeak import peak_rounds, refine_peaks
from millpath.simulate.path import motion_blocks, motion_segments


@dataclass
class Reference:
    """A design as triangles (n, 3, 3) and where it comes from; ``ops`` lists the
    operations checked against it (None: all)."""

    triangles: np.ndarray
    name: str
    ops: list[int] | None = None


def orient_outward(tri: np.ndarray) -> np.ndarray:
    """Wind triangles so their normals point out of the material: a closed solid by
    the sign of its volume, an open surface (a height field) upward."""
    tri = np.ascontiguousarray(np.asarray(tri, float).reshape(-1, 3, 3))
    if not len(tri):
        return tri
    n = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    vol = float(np.einsum("ij,ij->i", tri[:, 0], n).sum()) / 6.0
    lo, hi = tri.reshape(-1, 3).min(axis=0), tri.reshape(-1, 3).max(axis=0)
    box = float(np.prod(np.maximum(hi - lo, 1e-12)))
    # an open surface's "volume" depends on the origin; a closed one does not
    shift = tri + np.array([1.0, 1.0, 1.0]) * float(np.max(hi - lo) + 1.0)
    vol2 = float(np.einsum("ij,ij->i", shift[:, 0], n).sum()) / 6.0
    closed = abs(vol - vol2) <= 1e-6 * box and abs(vol) > 1e-9 * box
    if closed:
        return tri if vol > 0 else np.ascontiguousarray(tri[:, ::-1])
    flip = n[:, 2] < 0
    out = tri.copy()
    out[flip] = tri[flip][:, ::-1]
    return out


def design_triangles(design, stock: Stock, accuracy: float, size: float,
                     merge: bool = False) -> np.ndarray:
    """Triangles of a design: its ``mesh()`` when it has one (given ``accuracy`` when it
    takes it: meshed within a part of it), else a height-field mesh
    over the stock box with cells of ``size`` refined to ``50 accuracy`` where walls
    or curvature need it (walls cut exactly at the cell edges, flat to ``accuracy / 2``;
    corners of walls in cells refined to ``accuracy / 2``).
    Where the design has no part (through openings) the mesh closes a stock height
    under the stock's bottom, below anything a drill reaching through the part cuts.
    ``merge``: flat regions as few large triangles (see
    :func:`millpath.geometry.flatmerge.merge_horizontal`; the same surface)."""
    m = getattr(design, "mesh", None)
    if callable(m):         # (a ``mesh`` attribute that is data may be in another frame)
        import inspect
        takes = inspect.signature(m).parameters
        kw = {"accuracy": accuracy} if "accuracy" in takes else {}   # a B-rep's own mesh
        m = m(stock.box, **kw) if "box" in takes else m(**kw)
        return orient_outward(getattr(m, "triangles", m))      # a Mesh, or (n, 3, 3)
    x0, y0, z0, x1, y1, z1 = stock.box
    # corners of the outline and walls not cut whole at 50 accuracy: cells down to
    # accuracy / 2 (a ramp across one is off the design by under 0.71 accuracy)
    tri = height_field_mesh(design, (x0, y0, x1, y1), size=size, min_size=accuracy * 50,
                            flat_tol=accuracy / 2, floor=z0 - max(1.0, z1 - z0), merge=merge,
                            wall_size=accuracy / 2)
    return orient_outward(tri)


@dataclass
class ExactResult:
    """What the grid-free check found (program units). ``*_at`` are dicts with x, y, z
    (the design point), line, operation (or None)."""

    max_gouge: float
    max_left: float
    gouging_moves: int
    gouge_at: dict | None
    left_at: dict | None
    motion_gouge: np.ndarray            # per motion, 0 where none
    op_gouge: dict[int, float] = field(default_factory=dict)
    op_gouging: dict[int, int] = field(default_factory=dict)
    op_left: dict[int, float] = field(default_factory=dict)
    references: list[str] = field(default_factory=list)
    accuracy: float = 0.001
    spacing: float = 0.0
    chords: int = 0
    reach: float = 0.0                  # material left is measured up to this
    # per design: its operations (None: all), the material left at each sample and the
    # design area each sample stands for (its triangle's area over its samples)
    left_samples: list[tuple[list[int] | None, np.ndarray, np.ndarray]] = field(
        default_factory=list)

    @property
    def left_is_uncut(self) -> bool:
        """The largest material left reaches the measuring cap: stock no cutter came
        near, at least ``reach`` deep (not a measured figure)."""
        return self.reach > 0 and self.max_left >= self.reach * (1 - 1e-9)

    def left_area(self, threshold: float, op: int | None = None) -> float:
        """About how much design surface has more than ``threshold`` left (program
        units squared): the areas the samples over it stand for; ``op``: on the designs
        of that operation only."""
        return float(sum(w[v > threshold].sum() for ops, v, w in self.left_samples
                         if op is None or ops is None or op in ops))


MOTION_BLOCK = 100_000      # motions turned into chords at a time (bounds memory)
CHORD_BLOCK = 1_000_000     # and about this many chords at most (fine arcs)
GROUP_DEV = 10.0            # runs of chords checked first as one within GROUP_DEV * accuracy
LEFT_DEV = 200.0            # and, for the material-left rays, within LEFT_DEV * accuracy


@dataclass
class _Chords:
    """The cutting chords of one block of motions: start, end, motion number (in the
    whole program), tool slot, operation, deviation bound (how far the motion strays
    from the chord, see :func:`millpath.simulate.path.cover_points`)."""

    S: np.ndarray
    E: np.ndarray
    motion: np.ndarray
    slot: np.ndarray
    op: np.ndarray
    dev: np.ndarray


def _chords(motions: list[Motion], first: int, mop: np.ndarray, lut: np.ndarray,
            chord: float) -> _Chords:
    """Chords within ``chord`` of ``motions`` (tool 0 left out), curves cut so that a
    depth plus the chord's bound is never under the curve's; their motion numbers are
    ``first + k``."""
    segs = motion_segments(motions, chord, cover=True)
    keep = segs.tool != 0
    mo = segs.motion[keep] + first
    return _Chords(np.ascontiguousarray(segs.start[keep], float),
                   np.ascontiguousarray(segs.end[keep], float), mo,
                   lut[segs.tool[keep]] if keep.any() else np.zeros(0, np.int64),
                   mop[mo] if len(mo) else np.zeros(0, np.int64),
                   np.ascontiguousarray(segs.dev[keep], float))


def _blocks(motions: list[Motion], mop: np.ndarray, lut: np.ndarray, chord: float,
            block: int):
    """(first motion, chords) of ``motions``, ``block`` motions (and about
    ``CHORD_BLOCK`` chords) at a time, the last
    block first (later operations, usually finishing, leave the least material: rays
    they shorten first are cheaper for all the others)."""
    for a, b in reversed(motion_blocks(motions, chord, block, CHORD_BLOCK)):
        yield a, _chords(motions[a:b], a, mop, lut, chord)


def _chord_blocks(motions: list[Motion], mop: np.ndarray, lut: np.ndarray, chord: float,
                  block: int, accuracy: float, group_len: float, shapes: ToolShapes):
    """(chords, their groups, swept chords last first) of each block of :func:`_blocks`
    that has chords. Groups: runs of connected chords (the fine chords of a curve, a
    raster's short lines) whose chords are checked only where the coarse chord of the
    run, grown by the run's deviation (at most ``GROUP_DEV * accuracy``; for the
    material-left rays ``LEFT_DEV * accuracy``), may gouge or cut a ray
    (:mod:`millpath.simulate.groups`)."""
    for _, ch in _blocks(motions, mop, lut, chord, block):
        if len(ch.S):
            grp = chord_groups(ch.S, ch.E, ch.slot, ch.op, GROUP_DEV * accuracy, group_len)
            rays = chord_groups(ch.S, ch.E, ch.slot, ch.op, LEFT_DEV * accuracy, group_len)
            yield ch, grp, _last_first(ch, rays, shapes)


@dataclass
class _LeftState:
    """Material-left rays of one reference, carried from block to block."""

    pts: np.ndarray
    nrm: np.ndarray
    own: np.ndarray
    near: np.ndarray         # ray length of the first pass: before the stock box / the
                             # design, at most a quarter of the sample margin
    out: np.ndarray          # material left so far
    who: np.ndarray          # motion that bounds it (-1: the box or the design)


def verify_exact(motions: list[Motion], tools: dict[int, Tool], stock: Stock,
                 references: list[Reference], *, motion_op: np.ndarray | None = None,
                 accuracy: float = 0.001, spacing: float | None = None,
                 block: int = MOTION_BLOCK, progress: Progress = QUIET) -> ExactResult:
    """Gouge and material left of ``motions`` against ``references`` (see the module
    doc). ``motion_op`` gives each motion's operation (default all 0). Material left is
    measured up to twice the largest tool diameter (more is reported as that). ``spacing`` is
    the distance between material-left sample points (default a quarter of the
    smallest tool radius). Chords are made ``block`` motions at a time, so memory does
    not grow with the program's length. ``progress`` shows two bars: the motions
    checked (a block's work in about :data:`TICKS` slices of its chords and rays; a
    second pass over the chords, when material-left rays need their whole length,
    counts the motions again) and the rounds of the material-left peak search."""
    with progress.task("verifying exactly: motions checked", total=len(motions)) as bar:
        out = _check(motions, tools, stock, references, motion_op, accuracy, spacing, block,
                     bar.update)
    best_g, g_at, motion_g, mop, states, refs, lut, shapes, spacing, nchords, reach, \
        margin, chord = out
    best_l, l_at = 0.0, None
    op_left: dict[int, float] = {}
    samples: list[tuple[list[int] | None, np.ndarray, np.ndarray]] = []
    rounds = peak_rounds(float(spacing), accuracy) + 1
    with progress.task("verifying exactly: material-left peaks",
                       total=rounds * len(refs)) as bar:
        for (ref, tri, idx, _), st in zip(refs, states):
            left = medial_cap(st.pts, st.nrm, st.own, tri, idx, margin, st.out)
            if not len(left):
                bar.advance(rounds)
                continue
            left = np.where(left >= accuracy / 2, left, 0.0)
            # between the samples: the peaks near the highest ones
            measure = _LeftMeasure(motions, mop, lut, chord, block, shapes, stock, tri, idx,
                                   reach, margin, accuracy)
            done = bar.completed
            lq, X, w = refine_peaks(st.pts, st.own, left, st.who, tri, _unit_normals(tri),
                                    measure, float(spacing), accuracy,
                                    on_round=lambda: bar.advance())
            bar.update(completed=done + rounds)
            area = 0.5 * np.linalg.norm(np.cross(tri[:, 1] - tri[:, 0],
                                                 tri[:, 2] - tri[:, 0]), axis=1)
            per = np.bincount(st.own, minlength=len(tri))
            samples.append((ref.ops, left.astype(np.float32),
                            (area[st.own] / per[st.own]).astype(np.float32)))
            for o in (ref.ops if ref.ops is not None else sorted(set(mop.tolist())) or [0]):
                op_left[o] = max(op_left.get(o, 0.0), lq)
            if lq > best_l:
                best_l = lq
                l_at = {"x": float(X[0]), "y": float(X[1]), "z": float(X[2]),
                        "line": int(motions[w].line) if w >= 0 else None,
                        "operation": int(mop[w]) if w >= 0 else None}
    gouging = motion_g > accuracy
    op_g: dict[int, float] = {}
    op_n: dict[int, int] = {}
    for o in sorted(set(mop.tolist())):
        m = mop == o
        op_g[o] = float(motion_g[m].max(initial=0.0))
        op_n[o] = int(gouging[m].sum())
    return ExactResult(best_g, best_l, int(gouging.sum()), g_at, l_at, motion_g, op_g, op_n,
                       op_left, [r.name for r in references], accuracy, float(spacing),
                       nchords, reach, samples)


#: slices of a block's work between two progress updates, each at least this many
#: chords (gouge) or rays (material left)
TICKS = 20
LEAST_CHORDS = 2000
LEAST_RAYS = 5000


def _slices(n: int, least: int) -> list[slice]:
    """``range(n)`` in about :data:`TICKS` slices of at least ``least``."""
    size = max(least, -(-n // TICKS))
    return [slice(a, min(a + size, n)) for a in range(0, n, size)]


def _group_slices(count: np.ndarray, flag: np.ndarray, least: int) -> Iterator[np.ndarray]:
    """The flagged groups (a boolean per group) in pieces of about ``1 / TICKS`` of
    their chords (at least ``least``), whole groups each."""
    f = np.flatnonzero(flag)
    if not len(f):
        return
    cum = np.cumsum(count[f])
    size = max(least, -(-int(cum[-1]) // TICKS))
    cut = np.searchsorted(cum, np.arange(size, int(cum[-1]), size), side="left") + 1
    for piece in np.split(f, cut):
        if len(piece):
            sel = np.zeros(len(flag), bool)
            sel[piece] = True
            yield sel


def _check(motions, tools, stock, references, motion_op, accuracy, spacing, block,
           tick):
    """The chord pass(es) of :func:`verify_exact`: gouge and the material-left rays;
    ``tick(completed=, total=)`` in motions."""
    nm = len(motions)
    mop = np.zeros(nm, np.int64) if motion_op is None else np.asarray(motion_op, np.int64)
    numbers = sorted({int(m.tool) for m in motions if m.tool != 0 and m.kind != "dwell"})
    missing = [t for t in numbers if t not in tools]
    if missing:
        raise ValueError(f"tool {missing[0]} is not defined: give its shape")
    lut = np.zeros(max(numbers, default=0) + 1, np.int64)
    for s, t in enumerate(numbers):
        lut[t] = s
    shapes = ToolShapes.of([tools[t] for t in numbers])
    if spacing is None:
        rmin = min((tools[t].radius for t in numbers), default=1.0)
        spacing = max(rmin / 4.0, accuracy * 10)
    chord = accuracy / 4.0
    group_len = 2.0 * min((tools[t].radius for t in numbers), default=1.0)
    motion_g = np.zeros(nm)
    top: list = [0.0, None]         # the deepest gouge so far, what locates it
    g_at = None
    refs = []
    for ref in references:
        tri = np.ascontiguousarray(ref.triangles, float)
        if len(tri):
            idx = BoxIndex.build(tri.min(axis=1), tri.max(axis=1))
            refs.append((ref, tri, idx, faces_of(tri, idx)))
    # material left is measured up to twice the largest tool diameter: beyond that it
    # is uncut stock, reported as that much
    reach = float(min(max(stock.size), 2.0 * max([tools[t].diameter for t in numbers]
                                                 + [0.0])))
    margin = float(spacing) * 4.0
    states = []
    near_len = margin / 4.0
    for ref, tri, idx, _ in refs:
        pts, nrm, own = _samples(tri, spacing)
        # the first pass's rays (their whole length only where needed, below)
        near = ray_caps(pts, nrm, own, stock.box, tri, idx, min(reach, near_len))
        states.append(_LeftState(pts, nrm, own, near, near.copy(),
                                 np.full(len(pts), -1, np.int64)))
    nchords = 0
    nblocks, only = 0, None     # a program of one block keeps it for the second pass
    for ch, grp, cidx in _chord_blocks(motions, mop, lut, chord, block, accuracy, group_len,
                                       shapes):
        # the motions after the block (blocks come last first), then its share per slice
        base = nm - 1 - int(ch.motion.max())
        span = (int(ch.motion.max()) - int(ch.motion.min()) + 1) / max(len(refs), 1)
        tick(completed=base, total=nm)
        nchords += len(ch.S)
        nblocks += 1
        only = (ch, grp, cidx) if nblocks == 1 else None
        gslot = ch.slot[grp.start[:-1]]
        gop = ch.op[grp.start[:-1]]
        gdev = (np.maximum.reduceat(ch.dev, grp.start[:-1]) if len(ch.dev)
                else np.zeros(0))           # each group's largest chord bound
        single = grp.count == 1
        for r, ((ref, tri, idx, fc), st) in enumerate(zip(refs, states)):
            gsel = np.ones(len(gop), bool) if ref.ops is None else np.isin(gop, ref.ops)
            flag = gsel & single
            test = np.flatnonzero(gsel & ~single)
            if len(test):
                # (a depth from accuracy / 2 - bound: C of that depth lies within twice
                # the bound of C of accuracy / 2)
                flag[test] = near_chords(grp.S[test], grp.E[test], gslot[test], shapes, tri,
                                         idx, accuracy,
                                         grp.dev[test] + 2.0 * gdev[test] + 1e-9, fc)
            parts = list(_group_slices(grp.count, flag, LEAST_CHORDS))
            rays = _slices(len(st.pts), LEAST_RAYS)
            step = span / max(len(parts) + len(rays), 1)
            at = base + r * span
            for part in parts:
                at += step
                _gouge_part(grp, part, ch, shapes, tri, idx, accuracy, fc, motion_g, top)
                tick(completed=at)
            # material left on this reference, by all cutting chords: the rays near
            # the design first
            for sl in rays:
                at += step
                _shorten(st, np.arange(len(st.pts))[sl], ch, cidx, shapes, accuracy)
                tick(completed=at)
    tick(completed=nm)
    total = nm
    best_g, worst = top
    if worst is not None:
        S, E, slot, dv, tri, idx, res, w, o = worst
        _, X = locate(S, E, slot, shapes, tri, res, 0, accuracy, idx, dv)
        g_at = {"x": float(X[0]), "y": float(X[1]), "z": float(X[2]),
                "line": int(motions[w].line), "operation": o}
    # the full ray only where nothing cut within ``near``: a second pass over the chords
    far = []
    for (ref, tri, idx, _), st in zip(refs, states):
        c = np.flatnonzero((st.out >= st.near) & (st.near >= near_len))
        cap = (ray_caps(st.pts[c], st.nrm[c], st.own[c], stock.box, tri, idx, reach)
               if len(c) else np.zeros(0))
        f = c[cap > st.near[c]]
        st.out[f] = cap[cap > st.near[c]]
        far.append(f)
    if any(len(f) for f in far):
        again = [only] if only is not None else _chord_blocks(motions, mop, lut, chord, block,
                                                               accuracy, group_len, shapes)
        total = 2 * nm
        tick(completed=nm, total=total)
        for ch, _, cidx in again:
            base = total - 1 - int(ch.motion.max())
            span = (int(ch.motion.max()) - int(ch.motion.min()) + 1) / max(len(refs), 1)
            for r, (st, f) in enumerate(zip(states, far)):
                rays = _slices(len(f), LEAST_RAYS)
                for k, sl in enumerate(rays):
                    _shorten(st, f[sl], ch, cidx, shapes, accuracy)
                    tick(completed=base + span * (r + (k + 1) / len(rays)))
    tick(completed=total)
    return (best_g, g_at, motion_g, mop, states, refs, lut, shapes, spacing, nchords, reach,
            margin, chord)


def _gouge_part(grp: ChordGroups, part: np.ndarray, ch: "_Chords", shapes: ToolShapes,
                tri, idx, accuracy: float, fc, motion_g: np.ndarray, top: list) -> None:
    """Gouge of the chords of the groups ``part`` (a boolean per group) into
    ``motion_g``; ``top`` = [deepest so far, what locates it] is updated."""
    cs = grp.chords(part)
    if len(cs):
        flag = part
        # the groups of the part, renumbered over the chords cs
        runs = (np.concatenate([[0], np.cumsum(grp.count[flag])]), grp.S[flag], grp.E[flag],
                grp.dev[flag] + 1e-9)
        res = gouge_chords(ch.S[cs], ch.E[cs], ch.slot[cs], shapes, tri, idx, accuracy, fc,
                           runs, ch.dev[cs])
        g = np.maximum(res.gouge, 0.0)
        np.maximum.at(motion_g, ch.motion[cs], g)
        c = int(np.argmax(g))
        if g[c] > top[0]:
            # where: located once, for the worst chord of all (see _check)
            top[0] = float(g[c])
            top[1] = (ch.S[cs[c]:cs[c] + 1].copy(), ch.E[cs[c]:cs[c] + 1].copy(),
                      ch.slot[cs[c]:cs[c] + 1].copy(), float(ch.dev[cs[c]]), tri, idx,
                      GougeResult(*(None if v is None else v[c:c + 1].copy()
                                    for v in (res.gouge, res.triangle, res.shape, res.rim,
                                              res.point))),
                      int(ch.motion[cs[c]]), int(ch.op[cs[c]]))


class _LeftMeasure:
    """Material left at a few design points of one reference, measured as the samples
    are (:func:`verify_exact`): each ray capped by the stock box and the design, cut
    back by the cutting chords near it, capped where another triangle is nearer."""

    def __init__(self, motions, mop, lut, chord: float, block: int, shapes: ToolShapes,
                 stock: Stock, tri: np.ndarray, idx: BoxIndex, reach: float, margin: float,
                 accuracy: float):
        self.args = (motions, mop, lut, chord, block)
        self.shapes, self.stock, self.tri, self.idx = shapes, stock, tri, idx
        self.reach, self.margin, self.accuracy = reach, margin, accuracy
        self.sw: SweptChords | None = None
        self.motion = np.zeros(0, np.int64)

    def prepare(self, centres: np.ndarray, normals: np.ndarray, radius: float) -> None:
        """Keep the chords whose swept cutter may meet a ray from within ``radius`` of
        a centre (last first, as the samples' pass gives them)."""
        ends = centres + self.reach * normals
        lo = np.minimum(centres, ends) - radius
        hi = np.maximum(centres, ends) + radius
        keep = []
        for _, ch in _blocks(*self.args):
            if not len(ch.S):
                continue
            R = self.shapes.R[ch.slot, 0]
            clo = np.minimum(ch.S, ch.E)
            chi = np.maximum(ch.S, ch.E)
            clo[:, :2] -= R[:, None]
            chi[:, :2] += R[:, None]
            chi[:, 2] += self.shapes.L[ch.slot, 0]
            near = np.zeros(len(ch.S), bool)
            for a, b in zip(lo, hi):
                near |= np.all((clo <= b) & (chi >= a), axis=1)
            c = np.flatnonzero(near)
            keep.append((ch.S[c], ch.E[c], ch.slot[c], ch.motion[c]))
        if keep:
            S, E, slot, mo = (np.concatenate([k[i] for k in keep]) for i in range(4))
        else:
            S, E, slot, mo = np.zeros((0, 3)), np.zeros((0, 3)), np.zeros(0, np.int64), \
                np.zeros(0, np.int64)
        self.sw = swept_chords(S[::-1], E[::-1], slot[::-1], self.shapes)
        self.motion = mo[::-1]

    def __call__(self, points, normals, owners):
        cap = ray_caps(points, normals, owners, self.stock.box, self.tri, self.idx,
                       self.reach)
        out, who = shorten_rays(points, normals, cap, self.sw, self.shapes, self.accuracy,
                                self.accuracy / 2)
        who = (np.where(who >= 0, self.motion[np.maximum(who, 0)], -1) if len(self.motion)
               else who)
        left = medial_cap(points, normals, owners, self.tri, self.idx, self.margin, out)
        return np.where(left >= self.accuracy / 2, left, 0.0), who


def _unit_normals(tri: np.ndarray) -> np.ndarray:
    n = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    ln = np.linalg.norm(n, axis=1)
    return n / np.where(ln > 0, ln, 1.0)[:, None]


def _last_first(ch: _Chords, grp: ChordGroups, shapes: ToolShapes) -> SweptChords:
    """The chords and their groups in reverse order (material-left rays meet the
    later, finishing chords first)."""
    n = len(ch.S)
    return swept_chords(ch.S[::-1], ch.E[::-1], ch.slot[::-1], shapes, n - grp.start[::-1],
                        grp.S[::-1], grp.E[::-1], grp.dev[::-1] + 1e-9)


def _shorten(st: _LeftState, rows: np.ndarray, ch: _Chords, sw: SweptChords,
             shapes: ToolShapes, accuracy: float) -> None:
    """Shorten the material-left rays ``rows`` of ``st`` by the chords ``ch``."""
    # (a ray under accuracy / 2 is reported as none: not traced further)
    out, who = shorten_rays(st.pts[rows], st.nrm[rows], st.out[rows], sw, shapes, accuracy,
                            accuracy / 2)
    # (the chords were given last first, see ``_last_first``)
    who = np.where(who >= 0, len(ch.S) - 1 - who, -1)
    hit = who >= 0
    st.who[rows[hit]] = ch.motion[who[hit]]
    st.out[rows] = out


def _samples(tri: np.ndarray, spacing: float, chunk: int = 10_000):
    """Material-left sample points of ``tri``: one per (``spacing``-sized voxel, normal
    direction), the first made (tiny triangles, walls of a height-field mesh, would
    otherwise give far more points than ``spacing`` asks); made ``chunk`` triangles at
    a time, each chunk's first kept, so memory stays bounded on large meshes."""
    if not len(tri):
        return np.zeros((0, 3)), np.zeros((0, 3)), np.zeros(0, np.int64)
    lo, hi = tri.reshape(-1, 3).min(axis=0), tri.reshape(-1, 3).max(axis=0)
    parts = []
    for a in range(0, len(tri), chunk):
        p, n, o = sample_triangles(tri[a:a + chunk], spacing)
        k = sample_keys(p, n, spacing, lo, hi) if spacing > 0 else None
        if k is not None:
            first = first_of_each(k)
            p, n, o, k = p[first], n[first], o[first], k[first]
        parts.append((p, n, o + a, k))
    if len(parts) == 1:
        return parts[0][:3]
    p, n, o = (np.concatenate([q[i] for q in parts]) for i in range(3))
    if spacing > 0:
        first = first_of_each(np.concatenate([q[3] for q in parts]))
        p, n, o = p[first], n[first], o[first]
    return p, n, o
