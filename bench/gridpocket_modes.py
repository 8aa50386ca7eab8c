"""Grid pockets: the three motion modes, and tool Z against the thesis's surface Z.

The grid-pocket case study (inch: 0.25 in flat end mill, 0.125 x 0.0625 in grid, concave
pocket about 3 x 2 in, bicubic Bezier bottom, one layer) is planned in ``line``, ``arc``
and ``bezier`` mode, posted for LinuxCNC and simulated on a Z-map. Printed per mode:

- NC blocks (program lines that are not blank or comment-only) and program bytes;
- simulated cycle time (millpath.simulate, the job's machine);
- maximum surface deviation: deepest gouge below the designed bottom (Z-map, cells of
  ``--resolution`` in, and a dense check of the tool footprint along every move) and
  the largest material left above it where the flat end of the tool can reach;
- planning time.

Then the same pocket in line mode with ``z_mode = "surface"`` (tip on the surface under
the tool centre, as in the thesis) against ``"tool"`` (the tool dropped onto the
surface): gouge depth from the Z-map and from a dense check of the tool footprint along
every move. Run: ``python bench/gridpocket_modes.py [--resolution 0.005] [--json]``.
"""

from __future__ import annotations

import argparse
import copy
import json
import time
from pathlib import Path

import numpy as np
import shapely

from millpath.geometry.cutter import Cutter
from millpath.job.jobfile import load_job
from millpath.model.toolpath import sample_move
from millpath.plan.base import PlanContext
from millpath.plan.gridpocket import operation
from millpath.plan.gridpocket.cells import inward_offset
from millpath.post.writer import post
from millpath.simulate import simulate_toolpath

ROOT = Path(__file__).resolve().parents[1]
CASE = ROOT / "millpath" / "examples" / "pocket-casestudy-line" / "job.toml"


def blocks(program: str) -> int:
    n = 0
    for line in program.splitlines():
        s = line.strip()
        if s and not (s.startswith("(") and s.endswith(")")) and not s.startswith(";"):
            n += 1
    return n


def footprint_gouge(tp, tool, surface, step: float = 0.005) -> float:
    """Deepest point of the tool below the surface along all feed moves (polar samples
    of the footprint every ``step`` along the path)."""
    pts, pos = [], None
    for m in tp.moves:
        if pos is not None and m.kind in ("line", "arc", "cubic"):
            pts.append(sample_move(pos, m, step))
        pos = m.end
    P = np.concatenate(pts)
    rr, th = np.meshgrid(np.linspace(0, tool.radius, 13), np.linspace(0, 2 * np.pi, 49)[:-1])
    ox, oy = (rr * np.cos(th)).ravel(), (rr * np.sin(th)).ravel()
    prof = Cutter.of(tool).height(np.hypot(ox, oy))
    worst = 0.0
    for k in range(0, len(P), 2000):
        Q = P[k:k + 2000]
        need = (surface.height(Q[:, :1] + ox, Q[:, 1:2] + oy) - prof).max(axis=1)
        worst = max(worst, float((need - Q[:, 2]).max()))
    return worst


def run(job, params: dict, resolution: float) -> dict:
    ctx = PlanContext(units=job.units, stock=job.stock, machine=job.machine, tools=job.tools,
                      base_dir=job.base_dir, job_file=job.path)
    t0 = time.perf_counter()
    res = operation.plan(ctx, params)
    plan_s = time.perf_counter() - t0
    program = post(res.toolpath, job.tools, title="bench")
    sim = simulate_toolpath(res.toolpath, job.tools, job.stock, resolution=resolution,
                            design=res.design, machine=job.machine)
    tool = job.tools[params["tool"]]
    zm = sim.zmap
    X, Y = np.meshgrid(zm.xs(), zm.ys())
    cell = max(zm.dx, zm.dy)
    reach = inward_offset(res.design.polygon, tool.radius).buffer(
        tool.radius - tool.corner_radius - 1.5 * cell)
    inner = shapely.contains_xy(reach, X, Y)
    left = float(np.max((zm.heights - res.design.height(X, Y))[inner], initial=0.0))
    return {"blocks": blocks(program), "bytes": len(program.encode()),
            "moves": res.toolpath.counts(), "cycle_time_s": sim.cycle_time_s,
            "max_gouge": sim.max_gouge, "max_left_reachable": left,
            "footprint_gouge": footprint_gouge(res.toolpath, tool, res.design.surface),
            "plan_s": plan_s}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--resolution", type=float, default=0.005, help="Z-map cell (in)")
    ap.add_argument("--json", action="store_true", help="print JSON instead of tables")
    a = ap.parse_args()
    job = load_job(CASE)
    base = job.operations[0][1]
    out: dict[str, dict] = {}
    for mode in ("line", "arc", "bezier"):
        p = copy.deepcopy(base)
        p["motion"] = mode
        out[mode] = run(job, p, a.resolution)
    for zmode in ("surface", "tool"):
        p = copy.deepcopy(base)
        p["z_mode"] = zmode
        out[f"z_mode={zmode}"] = run(job, p, a.resolution)
    if a.json:
        print(json.dumps(out, indent=2))
        return
    print(f"Case study (inch), Z-map {a.resolution} in, tolerance {base['tolerance']} in\n")
    print("| motion | NC blocks | bytes | G1 / G2-G3 / G5 | cycle time | max gouge (Z-map) | "
          "max gouge (footprint) | max left (reachable) | plan |")
    print("|---|---:|---:|---:|---:|---:|---:|---:|---:|")
    for mode in ("line", "arc", "bezier"):
        r = out[mode]
        m = r["moves"]
        print(f"| {mode} | {r['blocks']} | {r['bytes']} | {m['line']} / {m['arc']} / "
              f"{m['cubic']} | {r['cycle_time_s']:.0f} s | {r['max_gouge']:.5f} in | "
              f"{r['footprint_gouge']:.5f} in | {r['max_left_reachable']:.4f} in | "
              f"{r['plan_s']:.1f} s |")
    print("\n| z_mode | gouge (Z-map) | gouge (tool footprint along the path) |")
    print("|---|---:|---:|")
    for zmode in ("surface", "tool"):
        r = out[f"z_mode={zmode}"]
        print(f"| {zmode} | {r['max_gouge']:.5f} in | {r['footprint_gouge']:.5f} in |")


if __name__ == "__main__":
    main()
