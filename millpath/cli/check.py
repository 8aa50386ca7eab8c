"""``millpath check PROGRAM.ngc``: interpret a G-code program as LinuxCNC would.

Prints a summary (moves by kind, bounding box of the motion (without the point where the
machine starts), feed length, estimated cycle time) or,
with ``--json``, one JSON object ``{"units", "moves", "error"}``. Exits 1 on a G-code
error, after printing the motion before the failing block (``--json``) or the error.
"""

from __future__ import annotations

import json
import math
import sys
from pathlib import Path

import click
import numpy as np

from millpath.cli.programs import MachineSetup, setup_options
from millpath.errors import MillpathError
from millpath.interpret import run
from millpath.interpret.store import KINDS, MotionList
from millpath.model.stock import Machine
from millpath.model.toolpath import PLANE_AXES, PLANES

#: rapid rate assumed for the cycle time estimate, units per minute: the machine's default
RAPID = {u: Machine.default_for(u).rapid for u in ("mm", "inch")}


def _arc_planes(a: dict[str, np.ndarray]):
    """The arcs by plane: (indices, axes, start, end, center, s1, s2, e1, e2, radius, start
    angle, end angle) for each plane that has arcs, in the plane's (first, second)
    coordinates relative to the center."""
    idx = np.nonzero(a["kind"] == KINDS.index("arc"))[0]
    if not len(idx):
        return
    plane = a["plane"][idx]
    for p, (i1, i2, i3) in enumerate(PLANE_AXES[name] for name in PLANES):
        sel = idx if p == 0 and not plane.any() else idx[plane == p]
        if not len(sel):
            continue
        st, en, ce = a["start"][sel], a["end"][sel], a["center"][sel]
        s1, s2 = st[:, i1] - ce[:, i1], st[:, i2] - ce[:, i2]
        e1, e2 = en[:, i1] - ce[:, i1], en[:, i2] - ce[:, i2]
        yield (sel, (i1, i2, i3), st, en, ce, s1, s2, e1, e2, np.hypot(s1, s2),
               np.arctan2(s2, s1), np.arctan2(e2, e1))


def _arc_points(a: dict[str, np.ndarray], lo: np.ndarray | None = None,
                hi: np.ndarray | None = None, arcs: list | None = None) -> np.ndarray:
    """Quadrant points that arcs pass through (for the bounding box). With the box
    ``lo``, ``hi`` of the other points: only those of arcs whose circle leaves it, or
    that are helical (the others cannot change the box: their quadrant points lie
    between center - radius and center + radius, which are exactly the extreme ones).
    ``arcs``: ``_arc_planes(a)`` if already computed."""
    out = [np.zeros((0, 3))]
    quads = np.array([0.0, 0.5, 1.0, 1.5]) * np.pi
    for sel, (i1, i2, i3), st, en, ce, s1, s2, e1, e2, r, t0, t1 in (
            _arc_planes(a) if arcs is None else arcs):
        if lo is not None:
            c1, c2 = ce[:, i1], ce[:, i2]
            keep = ((st[:, i3] != en[:, i3]) | (c1 + r > hi[i1]) | (c1 - r < lo[i1])
                    | (c2 + r > hi[i2]) | (c2 - r < lo[i2]))
            if not keep.all():
                sel, st, en, ce, r, t0, t1 = (v[keep] for v in (sel, st, en, ce, r, t0, t1))
        rot = a["rotation"][sel]
        ccw = rot > 0
        sweep = t1 - t0
        sweep = np.where(ccw & (sweep <= 0), sweep + 2 * np.pi, sweep)
        sweep = np.where(~ccw & (sweep >= 0), sweep - 2 * np.pi, sweep)
        sweep = sweep + np.sign(rot) * 2 * np.pi * (np.abs(rot) - 1)
        # end points are in the box already; add the quadrant points the arc passes
        d = np.where(ccw[:, None], (quads[None, :] - t0[:, None]) % (2 * np.pi),
                     (t0[:, None] - quads[None, :]) % (2 * np.pi))
        inside = d <= np.abs(sweep)[:, None]
        frac = np.clip(d / np.maximum(np.abs(sweep), 1e-12)[:, None], 0.0, 1.0)
        pts = np.empty((len(sel), 4, 3))
        pts[:, :, i1] = ce[:, i1][:, None] + r[:, None] * np.cos(quads)[None, :]
        pts[:, :, i2] = ce[:, i2][:, None] + r[:, None] * np.sin(quads)[None, :]
        sn = st[:, i3]
        pts[:, :, i3] = sn[:, None] + (en[:, i3] - sn)[:, None] * frac
        out.append(pts[inside])
    return np.vstack(out)


def _lengths(a: dict[str, np.ndarray], controls: dict[int, tuple],
             arcs: list | None = None) -> np.ndarray:
    """Path length of each move (arcs and helices exact, cubics and NURBS by sampling);
    ``controls`` are the curves' control points by index into the arrays; ``arcs``:
    ``_arc_planes(a)`` if already computed."""
    start, end = a["start"], a["end"]
    kind, rot = a["kind"], a["rotation"]
    n = len(kind)
    d = end - start
    # hypot: no overflow for coordinates near the float limit
    length = np.hypot(np.hypot(d[:, 0], d[:, 1]), d[:, 2]) if n else np.zeros(0)
    for sel, (i1, i2, i3), st, en, ce, s1, s2, e1, e2, r, t0, t1 in (
            _arc_planes(a) if arcs is None else arcs):
        turn = rot[sel].astype(np.float64)
        ccw = turn > 0
        sweep = np.where(ccw, t1 - t0, t0 - t1)
        sweep = np.where(sweep <= 0, sweep + 2 * np.pi, sweep)
        sweep = sweep + 2 * np.pi * (np.abs(turn) - 1)
        length[sel] = np.hypot(r * sweep, en[:, i3] - st[:, i3])
    for i in np.nonzero(kind == KINDS.index("cubic"))[0]:
        c = controls.get(int(i))
        if c is None:
            continue
        t = np.linspace(0.0, 1.0, 65)[:, None]
        p0, p3 = start[i, :2], end[i, :2]
        p1, p2 = np.asarray(c[0]), np.asarray(c[1])
        pts = ((1 - t) ** 3 * p0 + 3 * (1 - t) ** 2 * t * p1 + 3 * (1 - t) * t ** 2 * p2
               + t ** 3 * p3)
        length[i] = float(np.sum(np.linalg.norm(np.diff(pts, axis=0), axis=1)))
    for i in np.nonzero(kind == KINDS.index("nurbs"))[0]:
        c = controls.get(int(i))
        if c is not None:
            length[i] = c.length()
    return length


def _nurbs_points(a: dict[str, np.ndarray], controls: dict[int, tuple]) -> np.ndarray:
    """Points along the NURBS moves (for the bounding box; chords within 1e-4 of
    the curve's extent)."""
    out = [np.zeros((0, 3))]
    for i in np.nonzero(a["kind"] == KINDS.index("nurbs"))[0]:
        c = controls.get(int(i))
        if c is not None:
            xy = c.sample(1e-4 * max(1e-3, c.extent()))
            out.append(np.column_stack([xy, np.full(len(xy), a["start"][i, 2])]))
    return np.vstack(out)


class Summary:
    """Moves by kind, bounding box, feed length (units) and cycle time (seconds),
    gathered block by block from motion arrays (a ``MotionList`` sink)."""

    def __init__(self, max_feed: dict[str, float] | None = None) -> None:
        # feeds above the machine's limit run at it (units/min, by the program's units
        # at the end, which a streaming summary does not know yet: both are kept)
        self.caps = dict(max_feed or {"mm": math.inf, "inch": math.inf})
        self.fast: dict[str, tuple[int, float] | None] = {u: None for u in self.caps}
        self.fast_count = {u: 0 for u in self.caps}
        self.feed_seconds = {u: 0.0 for u in self.caps}
        self.counts = np.zeros(len(KINDS), dtype=np.int64)
        self.lo = np.full(3, np.inf)
        self.first = True
        self.hi = np.full(3, -np.inf)
        self.feed_length = 0.0
        self.rapid_length = 0.0
        self.dwell_seconds = 0.0

    def add(self, a: dict[str, np.ndarray], states: list[tuple],
            controls: dict[int, tuple]) -> None:
        kind = a["kind"]
        if not len(kind):
            return
        arcs = list(_arc_planes(a))
        length = _lengths(a, controls, arcs)
        self.counts += np.bincount(kind, minlength=len(KINDS))
        moving = kind != KINDS.index("dwell")
        all_moving = bool(moving.all())
        if all_moving or np.any(moving):
            # the box of the motion: the point where the machine starts is not part of it
            # (min and max part by part: the same as over all the points at once)
            if all_moving:
                starts = a["start"][1:] if self.first else a["start"]
                ends = a["end"]
            else:
                sel = moving.copy()
                if self.first:
                    sel[np.flatnonzero(moving)[0]] = False
                starts = a["start"][sel]
                ends = a["end"][moving]
            self.first = False
            for pts in (starts, ends, None, _nurbs_points(a, controls)):
                if pts is None:
                    pts = _arc_points(a, self.lo, self.hi, arcs)
                if len(pts):
                    self.lo = np.minimum(self.lo, pts.min(axis=0))
                    self.hi = np.maximum(self.hi, pts.max(axis=0))
        traverse = kind == KINDS.index("traverse")
        cutting = moving & ~traverse
        lc = length[cutting]
        self.feed_length += float(lc.sum())
        self.rapid_length += float(length[traverse].sum())
        inverse = np.array([st[3] == "inverse_time" for st in states], dtype=bool)
        f = a["feed"][cutting]
        inv = inverse[a["state"][cutting]]
        any_inv = bool(inv.any())
        positive = f > 0
        with np.errstate(divide="ignore", invalid="ignore"):
            per_inv = 60.0 / f if any_inv else None
        for u, cap in self.caps.items():
            over = ~inv & (f > cap)
            if np.any(over):
                if self.fast[u] is None:
                    k = int(np.flatnonzero(over)[0])
                    self.fast[u] = (int(a["line"][cutting][k]), float(f[k]))
                self.fast_count[u] += int(over.sum())
            with np.errstate(divide="ignore", invalid="ignore"):
                t = lc / np.minimum(f, cap) * 60.0
                if any_inv:
                    t = np.where(inv, per_inv, t)
            self.feed_seconds[u] += float(t[positive].sum())
        self.dwell_seconds += float(a["center"][kind == KINDS.index("dwell"), 0].sum())

    def result(self, units: str) -> dict:
        moving = int(self.counts.sum() - self.counts[KINDS.index("dwell")])
        bbox = [self.lo.tolist(), self.hi.tolist()] if moving else None
        seconds = self.rapid_length / RAPID[units] * 60.0 + self.feed_seconds[units] \
            + self.dwell_seconds
        return {"units": units, "moves": {k: int(self.counts[i]) for i, k in enumerate(KINDS)},
                "bbox": bbox, "feed_length": self.feed_length,
                "rapid_length": self.rapid_length, "cycle_time_s": seconds}


def summary(motions: MotionList, units: str, max_feed: float = math.inf) -> dict:
    """Moves by kind, bounding box, feed length (units) and cycle time (seconds, feeds
    capped at ``max_feed`` units/min)."""
    s = Summary({units: max_feed})
    s.add(motions.arrays(), motions.states, motions.controls)
    return s.result(units)


@click.command()
@click.argument("program", type=click.Path(exists=True, dir_okay=False, path_type=Path))
@click.option("--tools", "tools", type=click.Path(exists=True, dir_okay=False, path_type=Path),
              help="LinuxCNC tool table (values in the machine units).")
@click.option("--machine-units", type=click.Choice(["inch", "mm"]), default=None,
              help="Units of the tool table values when its header does not state them "
              "(default inch, as LinuxCNC's rs274).")
@click.option("--tool", "spindle_tool", type=click.IntRange(min=0), default=0,
              help="The tool already in the spindle when the program starts.")
@click.option("--max-feed", type=float, default=None,
              help="Machine's feed limit for the cycle time, program units/min (default "
                   "3000 mm/min, 120 in/min); faster feeds are capped with a warning.")
@click.option("--json", "as_json", is_flag=True, help="Print the motion as one JSON object.")
@setup_options
def command(program: Path, tools: Path | None, machine_units: str | None,
            spindle_tool: int, max_feed: float | None, as_json: bool,
            setup: MachineSetup) -> None:
    """Interpret PROGRAM as its control would (LinuxCNC 2.9 unless --dialect names
    another) and summarize or dump its motion."""
    from millpath.io.tooltable import file_table_units
    if max_feed is not None and not (max_feed > 0 and math.isfinite(max_feed)):
        raise MillpathError(f"--max-feed must be a positive feed, not {max_feed}")
    machine_units = (file_table_units(tools) if tools else None) or machine_units or "inch"
    if max_feed is None:
        caps = {u: Machine.default_for(u).max_feed for u in ("mm", "inch")}
    else:
        caps = {"mm": max_feed, "inch": max_feed}
    acc = None if as_json else Summary(caps)
    # the summary streams: memory stays bounded whatever the program's length
    try:
        result = run(program, tools, machine_units=machine_units,
                     sink=None if acc is None else acc.add, spindle_tool=spindle_tool,
                     units=setup.units, params=setup.for_machine(machine_units),
                     dialect=setup.dialect)
    except ValueError:
        raise MillpathError(f"--tool {spindle_tool}: no such tool in the tool table "
                            "(give --tools with it)", program) from None
    err = result.error
    if as_json:
        out = {"units": result.units,
               "moves": [m.to_json() for m in result.motions],
               "error": None if err is None else {"line": err.line, "message": err.message}}
        sys.stdout.write(json.dumps(out))
        sys.stdout.write("\n")
        if err is not None:
            sys.exit(1)
        return
    if err is not None:
        raise MillpathError(err.message, program, err.line)
    result.motions.flush(force=True)
    s = acc.result(result.units)
    u = s["units"]
    fast = acc.fast[u]
    if fast is not None:
        from millpath.cli.programs import feed_warning
        click.echo(feed_warning(program, fast[0], fast[1], acc.fast_count[u], acc.caps[u], u),
                   err=True)
    click.echo(f"{program}: {sum(s['moves'].values())} moves, units {u}")
    click.echo("  " + ", ".join(f"{k} {v}" for k, v in s["moves"].items() if v))
    if s["bbox"]:
        lo, hi = s["bbox"]
        click.echo("  bounding box: " + "  ".join(
            f"{a} {lo[i]:.4f} .. {hi[i]:.4f}" for i, a in enumerate("XYZ")))
    click.echo(f"  feed length {s['feed_length']:.3f} {u}, rapid length "
               f"{s['rapid_length']:.3f} {u}")
    t = s["cycle_time_s"]
    clock = f"{int(t // 60)}:{t % 60:04.1f}" if math.isfinite(t) else "too long to express"
    click.echo(f"  cycle time {clock} (rapids at {RAPID[u]:g} {u}/min, feeds at most "
               f"{acc.caps[u]:g} {u}/min)")
