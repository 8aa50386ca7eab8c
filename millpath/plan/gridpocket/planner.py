"""Plan a free-form pocket: layers of window-frame paths, wall pass, zigzag clean-up.

Job units throughout (mm or inch); feeds in units per minute; Z is the tool tip.

Order of cutting: the roughing layers, the finish layer (the last layer, at the bottom
everywhere, with ``finish_feed``), the wall pass (one lap of the offset outline per
layer floor, ending at the bottom, starting at the outline corner nearest to where the
finish layer ended; each lap is entered straight down at the nearest cell its layer
cleared and then across to the outline, never by a descent into the band of material
left along the wall), then the X zigzag and the Y zigzag runs at the bottom.

A layer with floor ``f`` puts each point at ``max(tip Z on the bottom, f)`` and skips
the cells whose bottom is above ``f``; the finish layer visits every cell, so it takes
the skipped cells down to the bottom (at most one step of material). Links between
cuts go over an upper bound of the material the plan has left (:mod:`.material`: the
stock top wherever no cutter has provably swept) at a short clearance, or at ``safe_z``
when that is no lower; descents into material are helices or ramps.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
import shapely
from shapely.geometry import LineString, Polygon

from millpath.errors import JobError
from millpath.geometry.cutter import Cutter
from millpath.model import Operation, Tool, Toolpath
from millpath.model.toolpath import sample_move
from millpath.plan.gridpocket.cells import PocketGrid, build_grid, check_grid
from millpath.plan.gridpocket.fitmotion import Chain, Fitter
from millpath.plan.material import MaterialBound
from millpath.plan.gridpocket.navigate import adjacent, joined_edges, main_path, zigzag_runs
from millpath.plan.gridpocket.zfield import ZField, sample_chain
from millpath.plan.entry import helix_entry, ramp_entry
from millpath.model.units import default


@dataclass
class PocketSpec:
    """Everything the planner needs (job units)."""

    polygon: Polygon
    surface: object                 # height(x, y) and to_mesh(nu, nv)
    tool: Tool
    units: str
    dx: float
    dy: float
    top: float                      # stock top: Z where the material starts
    feed: float
    finish_feed: float
    plunge_feed: float
    safe_z: float
    tolerance: float
    depths: list[float] | None = None
    step: float | None = None
    motion: str = "line"
    zigzag: bool = True
    spindle: float = 0.0
    z_mode: str = "tool"
    name: str = "grid-pocket"
    force_grid: bool = False
    navigation: str = "wall-first"  # direction priority rule (navigate.PRIORITIES)
    grid_anchor: tuple[float, float] | None = None  # a cell centre of the grid
    bezier_parameters: str = "chord"    # "chord" | "uniform" (the thesis's u1 = 1/(n-1))
    file: object = None


def layer_floors(top: float, zmin: float, depths: list[float] | None, step: float | None,
                 file=None) -> list[float]:
    """Floors of the layers, top down; the last is ``-inf`` (the finish at the bottom).

    ``depths`` are absolute floor Z values (strictly descending, below ``top``); ``step``
    is a uniform depth of cut from ``top``. Floors at or below the lowest bottom point
    ``zmin`` are replaced by the finish layer.
    """
    if depths is not None and step is not None:
        raise JobError("depths, stepdown: give either a list of depths or a stepdown, "
                       "not both", file)
    floors: list[float] = []
    eps = 1e-9 * max(1.0, abs(top), abs(zmin))
    if depths is not None:
        prev = top
        for k, d in enumerate(depths):
            if not d < prev:
                raise JobError(f"depths[{k}]: {d:g} must be below {prev:g} (the stock top or "
                               "the previous depth)", file)
            prev = d
            if d > zmin + eps:
                floors.append(float(d))
    elif step is not None:
        n = int(math.ceil((top - zmin) / step - 1e-9))
        if n > 10_000:
            raise JobError(f"stepdown: {step:g} makes {n} layers", file)
        floors = [top - k * step for k in range(1, n) if top - k * step > zmin + eps]
    return floors + [-math.inf]


@dataclass
class _Stats:
    phases: dict[str, float] = field(default_factory=dict)    # feed length per phase
    retracts: int = 0
    plunges: int = 0                # straight descents (into cleared space, or no helix fits)
    helices: int = 0                # helical entries into material
    ramps: int = 0                  # zigzag ramp entries (where no helix fits)
    feed_moves: dict[str, int] = field(default_factory=dict)   # fitted blocks per phase


class _Builder:
    """Appends fitted motion to a toolpath, tracking where the tool is."""

    def __init__(self, spec: PocketSpec, grid: PocketGrid, zf: ZField, fitter: Fitter):
        self.spec = spec
        self.grid = grid
        self.zf = zf
        self.fitter = fitter
        self.tp = Toolpath(spec.units)
        self.pos: np.ndarray | None = None
        # clearance above cleared material: a tenth of the diameter plus the highest cusp
        # a ball or bull leaves between cell centres (half a cell diagonal from a pass)
        half_diag = min(spec.tool.radius, math.hypot(spec.dx, spec.dy) / 2.0)
        self.clear = 0.1 * spec.tool.diameter + Cutter.of(spec.tool).height(half_diag)
        self.stats = _Stats()
        self.phase = ""
        # what the plan has left: links go over it (fit deviation and rounding lifted)
        lift = spec.tolerance + 10.0 ** -_decimals(spec.units)
        self.bound = MaterialBound(spec.polygon.bounds, spec.tool, spec.top,
                                   min(spec.dx, spec.dy, spec.tool.radius) / 4.0, lift,
                                   _decimals(spec.units))

    def begin(self, phase: str, label: str) -> None:
        self.phase = phase
        self.tp.begin(Operation("grid-pocket", f"{self.spec.name}: {label}", self.spec.tool.number,
                                spindle=self.spec.spindle, info={"phase": phase},
                                tolerance=self.spec.tolerance))

    def _rapid(self, p) -> None:
        self.tp.rapid(*p)
        self.pos = np.asarray(p, float)

    def _line(self, p, feed: float) -> None:
        self.tp.line(*p, feed)
        self.pos = np.asarray(p, float)

    def travel(self, target: np.ndarray) -> None:
        """Go from the current position to ``target`` (a cutting point) without cutting
        on the way; descend the last stretch by :meth:`_descend`.

        The links go over the material bound (:mod:`.material`: the stock top wherever
        the plan has not proven air) at a short clearance, or at ``safe_z`` when that is
        no lower.
        """
        s = self.spec
        tx, ty, tz = map(float, target)
        above = min(max(self.bound.need_at((tx, ty)), tz) + self.clear, s.safe_z)
        if self.pos is None:
            self._rapid((tx, ty, s.safe_z))
        else:
            px, py, pz = self.pos
            if math.hypot(tx - px, ty - py) <= 1e-9:
                if tz < pz:
                    self._descend((tx, ty, tz))
                elif tz > pz:
                    self._rapid((tx, ty, tz))
                return
            h = self.bound.need_segment((px, py), (tx, ty)) + self.clear
            h = min(max(h, pz, tz, above), s.safe_z)
            self.stats.retracts += 1
            if pz < h:
                self._rapid((px, py, h))
            self._rapid((tx, ty, max(h, self.pos[2])))
        if self.pos[2] > above:
            self._rapid((tx, ty, above))
        if self.pos[2] > tz:
            self._descend((tx, ty, tz))

    def _count(self, length: float) -> None:
        self.stats.phases[self.phase] = self.stats.phases.get(self.phase, 0.0) + length

    def _descend(self, target) -> None:
        """Down to ``target`` from straight above: a helix where the last stretch goes
        into material (millpath.plan.entry), a straight feed where it is cleared."""
        s = self.spec
        tx, ty, tz = map(float, target)
        solid = self.bound.need_at((tx, ty))
        if s.tool.type != "drill" and tz < solid - 1e-9:
            slack = self.grid.region.buffer(1e-9 * max(s.dx, s.dy))

            def centre_ok(xs, ys):
                return bool(np.all(shapely.covers(slack, shapely.points(xs, ys))))
            z0 = float(self.pos[2])
            hx = helix_entry((tx, ty, tz), z0, s.tool.radius, centre_ok=centre_ok,
                             floor=self.zf.z)
            if hx is not None:
                self.tp.arc((tx, ty, tz), (hx.center[0], hx.center[1], tz), False,
                            s.plunge_feed, turns=hx.turns)
                self.pos = np.array([tx, ty, tz])
                self.stats.helices += 1
                self._count(math.hypot(2 * math.pi * hx.radius * hx.turns, z0 - tz))
                return
            rp = ramp_entry((tx, ty, tz), z0, s.tool.radius, centre_ok=centre_ok,
                            floor=self.zf.z)
            if rp is not None:
                for p in rp.points(z0):
                    self._line(p, s.plunge_feed)
                self.stats.ramps += 1
                leg = math.hypot(rp.far[0] - tx, rp.far[1] - ty)
                self._count(math.hypot(leg * rp.legs, z0 - tz))
                return
        self._line((tx, ty, tz), s.plunge_feed)
        self.stats.plunges += 1

    def cut(self, xy: np.ndarray, floor: float, feed: float, region=None) -> None:
        """Feed through the XY points at ``max(tip Z, floor)``, arriving by :meth:`travel`."""
        s = self.spec

        def zfun(x, y):
            return np.maximum(self.zf.z(x, y), floor)

        spacing = min(s.dx, s.dy) / 6.0 if s.z_mode == "tool" else None
        pts, pos, checks, cpos = sample_chain(np.asarray(xy, float), zfun, spacing,
                                              s.tolerance / 2.0)
        pts = np.round(pts, _decimals(s.units))     # as the program will say
        self.travel(pts[0])
        if s.z_mode != "tool":
            checks = cpos = None
        chain = Chain(pts, pos, checks, cpos, region)
        segs = self.fitter.fit(chain)
        self.stats.feed_moves[self.phase] = self.stats.feed_moves.get(self.phase, 0) + len(segs)
        for seg in segs:
            if seg.kind == "line":
                self.tp.line(*seg.end, feed)
            elif seg.kind == "arc":
                self.tp.arc(tuple(seg.end), tuple(seg.center), seg.clockwise, feed, seg.plane)
            else:
                self.tp.cubic(seg.c1, seg.c2, tuple(seg.end), feed)
        self.pos = pts[-1].copy()
        self.bound.cut(pts)
        length = float(np.linalg.norm(np.diff(pts, axis=0), axis=1).sum())
        self.stats.phases[self.phase] = self.stats.phases.get(self.phase, 0.0) + length

    def retract(self) -> None:
        if self.pos is not None and self.pos[2] < self.spec.safe_z:
            self._rapid((self.pos[0], self.pos[1], self.spec.safe_z))


def _decimals(units: str) -> int:
    """Decimals of coordinates in the posted program (the post's: 5 inch, 4 mm)."""
    return int(default("decimals", units))


def _cells_xy(grid: PocketGrid, cells) -> np.ndarray:
    c = np.asarray(cells, int).reshape(-1, 2)
    x, y = grid.centre(c[:, 0], c[:, 1])
    return np.column_stack([x, y])


def _path_chunks(grid: PocketGrid, path) -> list[list]:
    """Split a cell path where the straight move from one cell centre to the next
    would leave the offset outline (a jump, or a step between neighbours that passes
    a corner of the walls pointing into the pocket)."""
    chunks: list[list] = []
    cur: list = []
    for c in path:
        if cur:
            a = _cells_xy(grid, [cur[-1]])[0]
            b = _cells_xy(grid, [c])[0]
            if not grid.segment_inside(a, b):
                chunks.append(cur)
                cur = []
        cur.append(c)
    if cur:
        chunks.append(cur)
    return chunks


def _wall_entry(grid: PocketGrid, path, start: np.ndarray, tries: int = 24):
    """The centre (x, y) of the cell of ``path`` nearest to the wall-lap start ``start``
    from which a straight move to it keeps the tool centre inside the offset outline;
    None when the layer cut no cell or none qualifies."""
    if not path:
        return None
    xy = _cells_xy(grid, path)
    d = np.hypot(xy[:, 0] - start[0], xy[:, 1] - start[1])
    for k in np.argsort(d, kind="stable")[:tries]:
        if grid.segment_inside(xy[k], start):
            return xy[k]
    return None


def _ring_from(ring: np.ndarray, pos, spacing: float) -> np.ndarray:
    """The closed ring starting at its vertex nearest to ``pos``, edges subdivided to at
    most ``spacing``."""
    k = 0 if pos is None else int(np.argmin(np.hypot(ring[:, 0] - pos[0], ring[:, 1] - pos[1])))
    r = np.concatenate([ring[k:], ring[:k], ring[k:k + 1]])
    out = [r[0]]
    for a, b in zip(r[:-1], r[1:]):
        n = max(1, int(math.ceil(np.hypot(*(b - a)) / spacing)))
        for t in np.arange(1, n + 1) / n:
            out.append(a + (b - a) * t)
    return np.array(out)


def plan_pocket(spec: PocketSpec) -> tuple[Toolpath, dict]:
    """Plan the pocket; return the toolpath and the ``pocket`` report section."""
    tool = spec.tool
    check_grid(spec.dx, spec.dy, tool.diameter, spec.force_grid, spec.file)
    grid = build_grid(spec.polygon, tool.radius, spec.dx, spec.dy, spec.file,
                      anchor=spec.grid_anchor)
    zf = ZField(spec.surface, tool, spec.z_mode, spec.polygon.bounds, spec.tolerance, spec.file)
    max_radius = default("max_arc_radius", spec.units)
    fitter = Fitter(spec.motion, spec.tolerance, max_radius, _decimals(spec.units),
                    spec.bezier_parameters)
    b = _Builder(spec, grid, zf, fitter)

    ii, jj = np.nonzero(grid.inside)
    xy = _cells_xy(grid, np.column_stack([ii, jj]))
    zc = np.full(grid.shape, np.nan)
    if len(xy):
        zc[ii, jj] = zf.z(xy[:, 0], xy[:, 1])
    rings = grid.rings()
    ring_z = np.concatenate([zf.z(r[:, 0], r[:, 1]) for r in rings])
    zmin = float(min(np.nanmin(zc) if len(xy) else np.inf, ring_z.min()))
    floors = layer_floors(spec.top, zmin, spec.depths, spec.step, spec.file)
    eps = 1e-9 * max(1.0, abs(spec.top))

    layers = []
    final_path: list = []
    layer_paths: list[list] = []        # the cells each floor's layer cut (wall entries)
    for k, floor in enumerate(floors):
        finish = k == len(floors) - 1
        # a roughing layer skips cells whose bottom is above its floor (the finish layer
        # takes them down to the bottom); the finish layer visits every cell
        mask = grid.inside & (zc < (spec.top if finish else floor) - eps)
        path = main_path(mask, spec.dx, spec.dy, spec.navigation)
        phase = "finish" if finish else "rough"
        layer_paths.append(path)
        layers.append({"floor": None if math.isinf(floor) else floor, "finish": finish,
                       "cells": len(path), "length": 0.0})
        if not path:
            continue
        b.begin(phase, "finish layer" if finish else f"rough layer {k + 1} (floor {floor:g})")
        before = b.stats.phases.get(phase, 0.0)
        feed = spec.finish_feed if finish else spec.feed
        for chunk in _path_chunks(grid, path):
            b.cut(_cells_xy(grid, chunk), floor, feed)
        layers[-1]["length"] = b.stats.phases.get(phase, 0.0) - before
        if finish:
            final_path = path

    # wall pass: one lap per floor, down to the bottom
    b.begin("wall", "wall pass")
    spacing = min(spec.dx, spec.dy)
    # the fitted laps may leave the offset outline toward the wall by nine tenths of the
    # tolerance less the post's rounding of both coordinates (the last tenth: a fitted
    # arc between the points it is checked at)
    rounding = math.sqrt(2.0) * 10.0 ** -_decimals(spec.units)
    wall_region = grid.region.buffer(max(0.9 * spec.tolerance - 2.0 * rounding, 0.0),
                                     quad_segs=16)
    shapely.prepare(wall_region)
    for floor, path in zip(floors, layer_paths):
        # each lap is entered from a cell its layer cleared to this floor: straight down
        # there (cleared space), then across to the outline at the floor (no
        # descent into the band of material the layer left along the wall)
        for ring in rings:
            pts = _ring_from(ring, b.pos, spacing)
            entry = _wall_entry(grid, path, pts[0])
            if entry is not None:
                b.cut(np.array([entry, pts[0]]), floor, spec.finish_feed, wall_region)
            b.cut(pts, floor, spec.finish_feed, wall_region)

    zig = {"x": 0, "y": 0}
    zig_steps = {"x": 0, "y": 0}
    if spec.zigzag:
        joined = joined_edges(final_path)
        for axis, label in ((0, "x"), (1, "y")):
            runs = zigzag_runs(grid.inside, joined, axis)
            if not runs:
                continue
            zig[label] = len(runs)
            zig_steps[label] = sum(len(r) - 1 for r in runs)
            b.begin(f"zigzag_{label}", f"{label.upper()} zigzag")
            last = None
            for run in runs:
                if last is not None and (adjacent(last, run[0]) or last == run[0]):
                    run = [last] + run if last != run[0] else run
                for chunk in _path_chunks(grid, run):
                    b.cut(_cells_xy(grid, chunk), -math.inf, spec.finish_feed)
                last = run[-1]
    b.retract()

    report = {
        "grid": {"dx": spec.dx, "dy": spec.dy, "nx": grid.shape[0], "ny": grid.shape[1],
                 "cells_inside": int(grid.inside.sum())},
        "motion": spec.motion, "z_mode": spec.z_mode, "tolerance": spec.tolerance,
        "navigation": spec.navigation,
        "layers": layers,
        "main_path_jumps": sum(not adjacent(a, b) for a, b in zip(final_path, final_path[1:])),
        "zigzag_runs": zig,
        "zigzag_cell_steps": zig_steps,
        "feed_moves": dict(b.stats.feed_moves),
        "feed_length": {k: round(v, 6) for k, v in b.stats.phases.items()},
        "retracts": b.stats.retracts,
        "plunges": b.stats.plunges,
        "helical_entries": b.stats.helices,
        "ramp_entries": b.stats.ramps,
        "bottom_min_tip_z": zmin,
        "mesh_error": zf.mesh_error,
        "moves": b.tp.counts(),
    }
    if spec.motion == "bezier":
        report["bezier"] = fitter.bezier_report()
    if spec.z_mode == "tool" and len(xy):
        h = np.asarray(spec.surface.height(xy[:, 0], xy[:, 1]), float)
        report["surface_mode_gouge_at_centres"] = float(np.max(zc[ii, jj] - h))
    report["path_length"] = round(_length(b.tp), 6)
    return b.tp, report


def _length(tp: Toolpath) -> float:
    """Total length of feed moves (lines, arcs, cubics)."""
    total = 0.0
    pos = None
    for m in tp.moves:
        if pos is not None and m.kind in ("line", "arc", "cubic"):
            p = sample_move(pos, m, default("sample_step", tp.units))
            total += float(np.linalg.norm(np.diff(p, axis=0), axis=1).sum())
        pos = m.end
    return total
