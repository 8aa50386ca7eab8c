"""Material removal: sweep the tools through a Z-map and compare with the design.

Units are the program's (mm or inch). ``resolution`` is the largest cell width; arcs
and cubics are cut into chords within ``resolution / 20`` of the curve, and each chord
is swept exactly at the cell centres (see :mod:`millpath.simulate.kernel`), so the
simulated surface is the true swept surface sampled at the cell centres.

Deviation from a design (see :func:`compare`): a cell's design height is taken at its
centre and four corners; a gouge counts the lowest of the five (``max_gouge`` is how
far the tool went below the design, measured only where the tool cut), material left
counts the highest of them, so a cell straddling a vertical wall reports neither a
false gouge nor false material left: deviations are resolved horizontally to one cell.
``left_volume`` integrates material above the centre value. Designs below the stock
bottom (or ``-inf``: through holes) count as the stock bottom.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from millpath.geometry.cutter import Cutter
from millpath.model.motion import Motion
from millpath.model.stock import Machine, Stock
from millpath.model.tool import Tool
from millpath.model.toolpath import Toolpath
from millpath.progress import QUIET, Progress
from millpath.simulate.cycletime import motion_times, times_by_operation
from millpath.simulate.designgrid import DesignGrid, design_grid, row_blocks
from millpath.simulate.exact import ExactResult, Reference, design_triangles, verify_exact
from millpath.simulate.kernel import sweep_chunk
from millpath.simulate.path import Segments, motion_blocks, motion_segments, toolpath_motions
from millpath.simulate.zmap import ZMap
from millpath.threads import per_thread

BAND = 32                     # rows per band (and block width of the skip test)
CHUNK = 20_000                # chords per kernel call (progress granularity)
MOTION_BLOCK = 100_000        # motions turned into chords at a time (bounds memory)
CHORD_BLOCK = 2_000_000       # and about this many chords at most (fine arcs)


@dataclass
class SimResult:
    """What a simulation found (program units; volumes in units cubed)."""

    removed_volume: float
    max_gouge: float | None
    max_left: float | None
    left_volume: float | None
    rapids_through_material: int
    holder_contacts: int
    cycle_time_s: float
    resolution: float
    zmap: ZMap
    per_operation: list[dict] = field(default_factory=list)
    rapid_lines: list[int] = field(default_factory=list)     # source line / move index
    holder_lines: list[int] = field(default_factory=list)
    chords: int = 0
    gouge_at: tuple[float, float] | None = None    # (x, y) of the largest gouge
    left_at: tuple[float, float] | None = None     # (x, y) of the most material left
    exact: ExactResult | None = None               # grid-free gouge / material left
    motion_op: np.ndarray | None = None            # operation of each motion
    rapid_hit: np.ndarray | None = None            # per motion flags (Z-map)
    holder_hit: np.ndarray | None = None
    removes: np.ndarray | None = None              # per motion: removed material (int8)
    design_grid: DesignGrid | None = None          # the design sampled on the Z-map

    def to_json(self, tolerances: dict[int, float] | None = None) -> dict[str, Any]:
        """The verification keys of report.json / ``millpath simulate --json``.

        With an exact check (a design was given), ``max_gouge`` / ``max_left`` are the
        grid-free figures normal to the design (bounded by ``accuracy``; material left
        exact at points ``left_spacing`` apart), with ``max_gouge_at`` /
        ``max_left_at`` ({x, y, z, line, operation}), ``gouging_moves`` (motions
        gouging by more than ``accuracy``), ``reference`` (the designs used) and
        ``by_operation``. ``max_left_uncut`` says the largest figure is stock no cutter
        came near (at least ``left_measured_to`` deep). With ``tolerances`` (operation ->
        tolerance), each operation's row gives ``left_area_over_tolerance``: about how
        much of its design has more than its tolerance left (program units squared).
        ``left_volume`` stays the Z-map's."""
        def r(v):
            return None if v is None else round(float(v), 6)
        ex = self.exact
        out = {"removed_volume": r(self.removed_volume),
               "max_gouge": r(ex.max_gouge if ex else self.max_gouge),
               "max_left": r(ex.max_left if ex else self.max_left),
               "left_volume": r(self.left_volume),
               "rapids_through_material": int(self.rapids_through_material),
               "holder_contacts": int(self.holder_contacts),
               "cycle_time_s": r(self.cycle_time_s), "resolution": float(self.resolution)}
        if ex is not None:
            def at(d):
                return None if d is None else {k: (r(v) if k in "xyz" else v)
                                               for k, v in d.items()}
            out.update(max_gouge_at=at(ex.gouge_at), max_left_at=at(ex.left_at),
                       gouging_moves=int(ex.gouging_moves),
                       reference=", ".join(ex.references), accuracy=float(ex.accuracy),
                       left_spacing=r(ex.spacing), left_measured_to=r(ex.reach),
                       max_left_uncut=bool(ex.left_is_uncut))
        elif self.max_gouge is not None:
            out.update(reference="design heights on the Z-map (cell-bound)",
                       accuracy=float(self.resolution))
        ops = sorted(set(self.motion_op.tolist())) if self.motion_op is not None else []
        if ops:
            rows = []
            for o in ops:
                m = self.motion_op == o
                rows.append({"operation": int(o),
                             "max_gouge": r(ex.op_gouge.get(o, 0.0)) if ex else None,
                             "max_left": r(ex.op_left.get(o)) if ex else None,
                             **({"left_area_over_tolerance":
                                 r(ex.left_area(tolerances[o], o))}
                                if ex is not None and tolerances and tolerances.get(o)
                                else {}),
                             "gouging_moves": int(ex.op_gouging.get(o, 0)) if ex else None,
                             "holder_contacts": int(self.holder_hit[m].sum()),
                             "rapids_through_material": int(self.rapid_hit[m].sum())})
            out["by_operation"] = rows
        return out


def _tool_arrays(numbers: list[int], tools: dict[int, Tool]):
    n = len(numbers)
    ttype = np.zeros(n, np.int64)
    tR = np.zeros(n)
    trc = np.zeros(n)
    tk = np.zeros(n)
    cyl = [tools[t].holder_cylinders() for t in numbers]
    mh = max([len(c) for c in cyl] + [1])
    hR = np.zeros((n, mh))
    hZ = np.zeros((n, mh))
    hN = np.zeros(n, np.int64)
    for s, t in enumerate(numbers):
        ttype[s], tR[s], trc[s], tk[s] = Cutter.of(tools[t]).row
        hN[s] = len(cyl[s])
        for c, (r, zb, _zt) in enumerate(cyl[s]):
            hR[s, c] = r
            hZ[s, c] = zb
    return ttype, tR, trc, tk, hR, hZ, hN


def sweep(zmap: ZMap, segs: Segments, tools: dict[int, Tool], n_motions: int, *,
          progress: "bool | Progress" = False, lines: list[int] | None = None
          ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Cut ``segs`` into ``zmap`` in place. Returns per-motion flags (rapid through
    material, holder contact, removes material) as int8 arrays of length
    ``n_motions``. Chords of tool 0
    (no tool in the spindle) cut nothing; other tools missing from ``tools`` are a
    ValueError."""
    if len(segs) and (segs.tool == 0).any():          # empty spindle: nothing cuts
        keep = segs.tool != 0
        segs = Segments(segs.start[keep], segs.end[keep], segs.motion[keep],
                        segs.rapid[keep], segs.tool[keep])
    numbers = sorted({int(t) for t in np.unique(segs.tool)}) if len(segs) else []
    for t in numbers:
        if t not in tools:
            k = int(segs.motion[np.argmax(segs.tool == t)])
            where = f" (line {lines[k]})" if lines is not None else ""
            raise ValueError(f"tool {t}{where} is not defined: give its shape "
                             "(tool table or tool library)")
    slot = {t: s for s, t in enumerate(numbers)}
    arrays = _tool_arrays(numbers, tools)
    seg_tool = np.zeros(len(segs), np.int64)
    if numbers:
        lut = np.zeros(max(numbers) + 1, np.int64)
        for t, s in slot.items():
            lut[t] = s
        seg_tool = lut[segs.tool]
    removes = np.zeros(max(n_motions, 1), np.int8)
    holder_hit = np.zeros(max(n_motions, 1), np.int8)
    eps = 1e-4 * min(zmap.dx, zmap.dy)
    H = zmap.heights
    n = len(segs)
    bars = progress if isinstance(progress, Progress) else Progress(bool(progress))
    if not isinstance(progress, Progress) and n <= CHUNK:
        bars = QUIET
    with bars.task("simulating: chords swept", total=n) as bar:
        for a in range(0, n, CHUNK):
            b = min(n, a + CHUNK)
            per_thread(sweep_chunk, H, zmap.zmin, zmap.x0, zmap.y0, zmap.dx, zmap.dy, BAND,
                       segs.start[a:b], segs.end[a:b], seg_tool[a:b],
                       segs.motion[a:b], *arrays, eps, removes, holder_hit)
            bar.update(completed=b)
    rapid = np.zeros(max(n_motions, 1), np.int8)
    rapid[segs.motion[segs.rapid != 0]] = 1
    return ((removes & rapid)[:n_motions], holder_hit[:n_motions], removes[:n_motions])


def _cut_mask(zmap: ZMap, h: np.ndarray, j0: int = 0) -> np.ndarray:
    """Cells of rows ``j0 ..`` (``h``) that a tool lowered (never the air around a bar)."""
    eps = 1e-9 * max(1.0, abs(zmap.ztop))
    if zmap.initial is None:
        return h < zmap.ztop - eps
    return h < zmap.initial[j0:j0 + len(h)] - eps


@dataclass
class Comparison:
    """Deviation of a Z-map from a design (see the module docstring)."""

    max_gouge: float
    max_left: float
    left_volume: float
    gouge_at: tuple[float, float] | None      # cell centre of the largest gouge
    left_at: tuple[float, float] | None       # cell centre of the most material left


def compare_design(zmap: ZMap, design) -> Comparison:
    """Gouge and material left of ``zmap`` against ``design`` (or its
    :class:`DesignGrid` on ``zmap``), with their places."""
    grid = design if isinstance(design, DesignGrid) else design_grid(zmap, design)
    gouge, left, vol = 0.0, 0.0, 0.0
    g_at = l_at = None
    xs, ys = zmap.xs(), zmap.ys()
    for j0, j1 in row_blocks(zmap):
        h = zmap.heights[j0:j1]
        dc, lo, hi = grid.rows(j0, j1, h)
        g = np.where(_cut_mask(zmap, h, j0), lo - h, 0.0)
        k = int(np.argmax(g))
        if g.flat[k] > gouge:
            gouge = float(g.flat[k])
            j, i = np.unravel_index(k, g.shape)
            g_at = (float(xs[i]), float(ys[j0 + j]))
        lft = h - hi
        k = int(np.argmax(lft))
        if lft.flat[k] > left:
            left = float(lft.flat[k])
            j, i = np.unravel_index(k, lft.shape)
            l_at = (float(xs[i]), float(ys[j0 + j]))
        vol += float(np.sum(np.maximum(h - dc, 0.0)))
    return Comparison(gouge, left, vol * zmap.cell_area, g_at, l_at)


def compare(zmap: ZMap, design) -> tuple[float, float, float]:
    """(max gouge, max material left, volume left) of the Z-map against ``design``.

    See the module docstring for the per-cell convention."""
    c = compare_design(zmap, design)
    return c.max_gouge, c.max_left, c.left_volume


def deviation(zmap: ZMap, design) -> np.ndarray:
    """Signed deviation per cell (ny, nx): positive = material left above the design
    (highest design value over the cell), negative = gouge (lowest value, cut cells),
    0 within the cell's own design range and in the design's waste. ``design``: a
    design or its :class:`DesignGrid` on ``zmap``."""
    grid = design if isinstance(design, DesignGrid) else design_grid(zmap, design)
    out = np.zeros_like(zmap.heights)
    for j0, j1 in row_blocks(zmap):
        h = zmap.heights[j0:j1]
        _, lo, hi = grid.rows(j0, j1, h)
        o = out[j0:j1]
        above = h > hi
        o[above] = (h - hi)[above]
        below = (h < lo) & _cut_mask(zmap, h, j0)
        o[below] = (h - lo)[below]
    return out


def _finish(zmap, design, motions, flags, times, resolution, lines, nseg) -> SimResult:
    rapid_hit, holder_hit = flags[:2]
    grid = design_grid(zmap, design) if design is not None else None
    c = compare_design(zmap, grid) if grid is not None else None
    g = c.max_gouge if c else None
    l = c.max_left if c else None
    lv = c.left_volume if c else None
    return SimResult(
        removed_volume=zmap.removed_volume(), max_gouge=g, max_left=l, left_volume=lv,
        rapids_through_material=int(rapid_hit.sum()), holder_contacts=int(holder_hit.sum()),
        cycle_time_s=float(times.sum()), resolution=float(resolution), zmap=zmap,
        rapid_lines=[lines[i] for i in np.flatnonzero(rapid_hit)],
        holder_lines=[lines[i] for i in np.flatnonzero(holder_hit)], chords=nseg,
        gouge_at=c.gouge_at if c else None, left_at=c.left_at if c else None,
        design_grid=grid)


def _lift_start(motions: list[Motion], stock: Stock) -> list[Motion]:
    """Where the tool is before the first move and after each tool change is unknown
    (an interpreter starts at machine zero and jumps by tool length offsets): those
    moves start above their end point at the stock top or higher (the pipeline's
    :func:`millpath.simulate.approach.approach_from_above`)."""
    from millpath.simulate.approach import approach_from_above
    return approach_from_above(motions, stock.zmax)


def _exact(res: SimResult, motions, tools, stock, design, references, motion_op,
           accuracy, progress: "bool | Progress" = False) -> SimResult:
    """Run the grid-free check (when a design or references are given) into ``res``,
    with bars of the motions checked and the material-left peak search."""
    nm = len(motions)
    mop = np.zeros(nm, np.int64) if motion_op is None else np.asarray(motion_op, np.int64)
    res.motion_op = mop
    if accuracy is None:
        return res
    if references is None and design is not None:
        used = {m.tool for m in motions if m.tool != 0 and m.tool in tools}
        size = min([tools[t].radius / 2 for t in used] + [max(stock.size[:2]) / 64])
        references = [Reference(design_triangles(design, stock, accuracy, size), "design")]
    if references:
        bars = progress if isinstance(progress, Progress) else Progress(bool(progress))
        res.exact = verify_exact(motions, tools, stock, references, motion_op=mop,
                                 accuracy=accuracy, progress=bars)
        ga, la = res.exact.gouge_at, res.exact.left_at
        res.gouge_at = (ga["x"], ga["y"]) if ga else None
        res.left_at = (la["x"], la["y"]) if la else None
    return res


def simulate_motions(motions: list[Motion], tools: dict[int, Tool], stock: Stock, *,
                     resolution: float, design=None, machine: Machine | None = None,
                     progress: "bool | Progress" = False, corner_angle: float = 10.0,
                     chord_tol: float | None = None,
                     references: list[Reference] | None = None,
                     motion_op=None, accuracy: float | None = 0.001,
                     times: np.ndarray | None = None) -> SimResult:
    """Simulate interpreted motion (tool tip = motion coordinates, program units).

    The first motion, and the first after each tool change, start above their end
    point at the stock top (where the machine is then is unknown).
    ``tools`` maps tool numbers (``Motion.tool``) to shapes; ``machine`` defaults to
    ``Machine()`` (mm rates: pass ``Machine.default_for("inch")`` for inch programs).
    Counts are per motion: ``rapids_through_material`` traverses that removed material,
    ``holder_contacts`` motions where the shank or holder met material. ``chord_tol``:
    how far the chords of arcs and cubics may stray from them in the Z-map sweep
    (default ``resolution / 20``).

    Gouge and material left are grid-free (:mod:`millpath.simulate.exact`) against
    ``references`` (triangle meshes with the operations they apply to; ``motion_op``
    gives each motion's operation), or against ``design`` meshed (its ``mesh()``, else
    a height-field mesh); ``accuracy`` bounds them (None: Z-map figures only).
    ``times``: the motions' seconds if already known (:func:`motion_times` of these
    motions, started from above, on ``machine`` at ``corner_angle``).
    """
    machine = machine or Machine()
    motions = _lift_start(list(motions), stock)
    zmap = ZMap.from_stock(stock, resolution)
    lines = [m.line for m in motions]
    flags, nseg = sweep_motions(zmap, motions, tools, chord_tol or resolution / 20.0,
                                progress=progress, lines=lines)
    if times is None:
        times = motion_times(motions, machine, corner_angle=corner_angle)
    res = _finish(zmap, design, motions, flags, times, resolution, lines, nseg)
    res.rapid_hit, res.holder_hit, res.removes = flags
    return _exact(res, motions, tools, stock, design, references, motion_op, accuracy,
                  progress)


def sweep_motions(zmap: ZMap, motions: list[Motion], tools: dict[int, Tool],
                  chord_tol: float, *, progress: "bool | Progress" = False,
                  lines: list[int] | None = None, block: int = MOTION_BLOCK
                  ) -> tuple[tuple[np.ndarray, np.ndarray], int]:
    """Cut ``motions`` into ``zmap`` in order, ``block`` motions (and about ``CHORD_BLOCK``
    chords) at a time (their chords
    are made and swept one block after another, so memory does not grow with the
    program's length). Returns the per-motion flags of :func:`sweep` and the number of
    chords swept."""
    n = len(motions)
    flags = np.zeros((3, max(n, 1)), np.int8)
    nseg = 0
    bars = progress if isinstance(progress, Progress) else Progress(bool(progress))
    with bars.task("simulating: motions swept", total=n) as bar:
        for a, b in motion_blocks(motions, chord_tol, block, CHORD_BLOCK):
            segs = motion_segments(motions[a:b], chord_tol)
            segs.motion += a                      # indices into the whole program
            for f, new in zip(flags, sweep(zmap, segs, tools, b, lines=lines)):
                np.maximum(f[:b], new, out=f[:b])
            nseg += len(segs)
            bar.update(completed=b)
    return (flags[0, :n], flags[1, :n], flags[2, :n]), nseg


def simulate_toolpath(toolpath: Toolpath, tools: dict[int, Tool], stock: Stock, *,
                      resolution: float, design=None, machine: Machine | None = None,
                      progress: "bool | Progress" = False, corner_angle: float = 10.0,
                      accuracy: float | None = 0.001) -> SimResult:
    """Simulate a Toolpath directly (units: the toolpath's).

    The tool starts above the first move's end point at the stock top or higher, and
    likewise after each tool change.
    Canned drilling cycles are expanded as LinuxCNC runs them; ``comp`` moves raise
    ValueError (simulate the interpreted motion instead). Counts are per toolpath move
    (``rapid_lines``/``holder_lines`` hold move indices); ``per_operation`` gives each
    operation's cycle time. ``machine`` defaults to the toolpath units' default.
    """
    machine = machine or Machine.default_for(toolpath.units)
    motions, src = toolpath_motions(toolpath)
    motions = _lift_start(motions, stock)
    zmap = ZMap.from_stock(stock, resolution)
    (rapid_hit, holder_hit, removes), nseg = sweep_motions(
        zmap, motions, tools, resolution / 20.0, progress=progress, lines=src)
    # fold motion flags onto source moves
    nm = len(toolpath.moves)
    srca = np.asarray(src, np.int64)
    rm = np.zeros(max(nm, 1), np.int8)
    hm = np.zeros(max(nm, 1), np.int8)
    if len(srca):
        np.maximum.at(rm, srca, rapid_hit)
        np.maximum.at(hm, srca, holder_hit)
    times = motion_times(motions, machine, corner_angle=corner_angle)
    res = _finish(zmap, design, motions, (rm[:nm], hm[:nm]), times, resolution,
                  list(range(nm)), nseg)
    res.per_operation = times_by_operation(toolpath, src, times)
    res.rapid_hit, res.holder_hit, res.removes = rapid_hit, holder_hit, removes
    _exact(res, motions, tools, stock, design, None,
           np.array([toolpath.moves[i].op for i in src], np.int64), accuracy, progress)
    # by_operation counts toolpath moves like the totals
    mop = np.array([m.op for m in toolpath.moves], np.int64)
    res.motion_op, res.rapid_hit, res.holder_hit = mop, rm[:nm], hm[:nm]
    if res.exact is not None:
        mg = np.zeros(max(nm, 1))
        if len(src):
            np.maximum.at(mg, np.asarray(src, np.int64), res.exact.motion_gouge)
        res.exact.gouging_moves = int((mg[:nm] > res.exact.accuracy).sum())
    return res
