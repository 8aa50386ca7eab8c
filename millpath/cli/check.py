"""``millpath check PROGRAM.ngc``: interpret a G-code program as LinuxCNC would.

Prints a summary (moves by kind, bounding box, feed length, estimated cycle time) or,
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

from millpath.errors import MillpathError
from millpath.interpret import run
from millpath.interpret.store import KINDS, MotionList

#: rapid rate assumed for the cycle time estimate, units per minute
RAPID = {"mm": 5000.0, "inch": 200.0}


def _arc_points(motions: MotionList, length: np.ndarray) -> np.ndarray:
    """Quadrant points that arcs pass through (for the bounding box)."""
    a = motions.arrays()
    idx = np.nonzero(a["kind"] == KINDS.index("arc"))[0]
    if len(idx) == 0:
        return np.zeros((0, 3))
    axes = np.array([(0, 1, 2), (2, 0, 1), (1, 2, 0)])[a["plane"][idx]]
    rows = np.arange(len(idx))
    st, en, ce = a["start"][idx], a["end"][idx], a["center"][idx]
    s1 = st[rows, axes[:, 0]] - ce[rows, axes[:, 0]]
    s2 = st[rows, axes[:, 1]] - ce[rows, axes[:, 1]]
    e1 = en[rows, axes[:, 0]] - ce[rows, axes[:, 0]]
    e2 = en[rows, axes[:, 1]] - ce[rows, axes[:, 1]]
    r = np.hypot(s1, s2)
    t0 = np.arctan2(s2, s1)
    t1 = np.arctan2(e2, e1)
    rot = a["rotation"][idx]
    ccw = rot > 0
    sweep = np.where(ccw, t1 - t0, t1 - t0)
    sweep = np.where(ccw & (sweep <= 0), sweep + 2 * np.pi, sweep)
    sweep = np.where(~ccw & (sweep >= 0), sweep - 2 * np.pi, sweep)
    sweep = sweep + np.sign(rot) * 2 * np.pi * (np.abs(rot) - 1)
    # end points are in the box already; add the quadrant points the arc passes
    quads = np.array([0.0, 0.5, 1.0, 1.5]) * np.pi
    d = np.where(ccw[:, None], (quads[None, :] - t0[:, None]) % (2 * np.pi),
                 (t0[:, None] - quads[None, :]) % (2 * np.pi))
    inside = d <= np.abs(sweep)[:, None]
    frac = np.clip(d / np.maximum(np.abs(sweep), 1e-12)[:, None], 0.0, 1.0)
    pts = np.empty((len(idx), 4, 3))
    pts[rows, :, axes[:, 0]] = ce[rows, axes[:, 0]][:, None] + r[:, None] * np.cos(quads)[None, :]
    pts[rows, :, axes[:, 1]] = ce[rows, axes[:, 1]][:, None] + r[:, None] * np.sin(quads)[None, :]
    sn = st[rows, axes[:, 2]]
    pts[rows, :, axes[:, 2]] = sn[:, None] + (en[rows, axes[:, 2]] - sn)[:, None] * frac
    return pts[inside]


def _lengths(motions: MotionList) -> tuple[np.ndarray, np.ndarray]:
    """Path length of each move (arcs and helices exact, cubics by sampling)."""
    a = motions.arrays()
    start, end, center = a["start"], a["end"], a["center"]
    kind, rot, plane = a["kind"], a["rotation"], a["plane"]
    n = len(kind)
    length = np.linalg.norm(end - start, axis=1) if n else np.zeros(0)
    axes = np.array([(0, 1, 2), (2, 0, 1), (1, 2, 0)])
    for i in np.nonzero(kind == KINDS.index("arc"))[0]:
        a1, a2, an = axes[plane[i]]
        s1, s2 = start[i, a1] - center[i, a1], start[i, a2] - center[i, a2]
        e1, e2 = end[i, a1] - center[i, a1], end[i, a2] - center[i, a2]
        r = math.hypot(s1, s2)
        t0, t1 = math.atan2(s2, s1), math.atan2(e2, e1)
        turn = int(rot[i])
        if turn > 0:
            sweep = t1 - t0
            if sweep <= 0:
                sweep += 2 * math.pi
            sweep += 2 * math.pi * (turn - 1)
        else:
            sweep = t0 - t1
            if sweep <= 0:
                sweep += 2 * math.pi
            sweep += 2 * math.pi * (-turn - 1)
        length[i] = math.hypot(r * sweep, end[i, an] - start[i, an])
    for i in np.nonzero(kind == KINDS.index("cubic"))[0]:
        c = motions.controls.get(int(i))
        if c is None:
            continue
        t = np.linspace(0.0, 1.0, 65)[:, None]
        p0, p3 = start[i, :2], end[i, :2]
        p1, p2 = np.asarray(c[0]), np.asarray(c[1])
        pts = ((1 - t) ** 3 * p0 + 3 * (1 - t) ** 2 * t * p1 + 3 * (1 - t) * t ** 2 * p2
               + t ** 3 * p3)
        length[i] = float(np.sum(np.linalg.norm(np.diff(pts, axis=0), axis=1)))
    return length, kind


def summary(motions: MotionList, units: str) -> dict:
    """Moves by kind, bounding box, feed length (units) and cycle time (seconds)."""
    a = motions.arrays()
    length, kind = _lengths(motions)
    counts = {k: int(np.count_nonzero(kind == i)) for i, k in enumerate(KINDS)}
    moving = kind != KINDS.index("dwell")
    if np.any(moving):
        pts = np.vstack([a["start"][moving], a["end"][moving], _arc_points(motions, length)])
        bbox = [pts.min(axis=0).tolist(), pts.max(axis=0).tolist()]
    else:
        bbox = None
    cutting = moving & (kind != KINDS.index("traverse"))
    feed_length = float(length[cutting].sum())
    rapid_length = float(length[kind == KINDS.index("traverse")].sum())
    seconds = rapid_length / RAPID[units] * 60.0
    states = motions.states
    for i in np.nonzero(cutting)[0]:
        f = a["feed"][i]
        if states[a["state"][i]][3] == "inverse_time":
            seconds += 60.0 / f if f > 0 else 0.0
        elif f > 0:
            seconds += length[i] / f * 60.0
    for i in np.nonzero(kind == KINDS.index("dwell"))[0]:
        seconds += float(a["center"][i, 0])
    return {"units": units, "moves": counts, "bbox": bbox, "feed_length": feed_length,
            "rapid_length": rapid_length, "cycle_time_s": seconds}


@click.command()
@click.argument("program", type=click.Path(exists=True, dir_okay=False, path_type=Path))
@click.option("--tools", "tools", type=click.Path(exists=True, dir_okay=False, path_type=Path),
              help="LinuxCNC tool table (values in the machine units).")
@click.option("--machine-units", type=click.Choice(["inch", "mm"]), default=None,
              help="Units of the tool table values when its header does not state them "
              "(default inch, as LinuxCNC's rs274).")
@click.option("--json", "as_json", is_flag=True, help="Print the motion as one JSON object.")
def command(program: Path, tools: Path | None, machine_units: str | None,
            as_json: bool) -> None:
    """Interpret PROGRAM.ngc as LinuxCNC 2.9 would and summarize or dump its motion."""
    from millpath.io.tooltable import file_table_units
    machine_units = (file_table_units(tools) if tools else None) or machine_units or "inch"
    result = run(program, tools, machine_units=machine_units)
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
    s = summary(result.motions, result.units)
    u = s["units"]
    click.echo(f"{program}: {sum(s['moves'].values())} moves, units {u}")
    click.echo("  " + ", ".join(f"{k} {v}" for k, v in s["moves"].items() if v))
    if s["bbox"]:
        lo, hi = s["bbox"]
        click.echo("  bounding box: " + "  ".join(
            f"{a} {lo[i]:.4f} .. {hi[i]:.4f}" for i, a in enumerate("XYZ")))
    click.echo(f"  feed length {s['feed_length']:.3f} {u}, rapid length "
               f"{s['rapid_length']:.3f} {u}")
    t = s["cycle_time_s"]
    click.echo(f"  cycle time {int(t // 60)}:{t % 60:04.1f} (rapids at {RAPID[u]:g} {u}/min)")
