"""Pocket clearing strategies on the DXF example: offset, zigzag and adaptive.

The first operation of ``millpath/examples/pocket-dxf-adaptive`` (12 mm flat end mill,
8 mm deep in 2 levels, a pocket with two islands) is planned with each ``strategy``
(same feed; offset and zigzag at the default 0.4 D stepover, adaptive at 15 %
engagement) on a full block. Printed per strategy: CPU seconds to plan, cutting (feed)
length, cycle time (millpath.simulate.cycle_time with the job's machine), and, from the
in-process stock (millpath.simulate.inprocess, cells of D/40), the air-cut share and
the largest and mean radial engagement measured on the stock. Then the planning time of
an adaptive 100 x 100 mm pocket with a 6 mm tool (target: under 10 s on 2 cores).

No peer runs side by side: FreeCAD's Adaptive (libarea) is not installed here.
Run: ``python bench/adaptive.py [--json] [--skip-large]``.
"""

from __future__ import annotations

import argparse
import json
import math
import time
from pathlib import Path

from millpath.job.jobfile import load_job
from millpath.io.schema import validate
from millpath.model import Machine, Stock, Tool
from millpath.model.toolpath import arc_geometry
from millpath.plan.base import PlanContext
from millpath.plan.pocket import operation as pocket
from millpath.simulate import cycle_time
from millpath.simulate.inprocess import InProcessStock
from millpath.simulate.path import toolpath_motions

ROOT = Path(__file__).resolve().parents[1]
EXAMPLE = ROOT / "millpath" / "examples" / "pocket-dxf-adaptive" / "job.toml"


def feed_length(tp) -> float:
    total, pos = 0.0, None
    for m in tp.moves:
        if pos is not None and m.kind == "line":
            total += math.dist(pos, m.end)
        elif pos is not None and m.kind == "arc":
            r, _, sw, dn = arc_geometry(pos, m)
            total += math.hypot(abs(sw) * r, dn)
        pos = m.end
    return total


def measure(job, tp, stock) -> dict:
    d = min(t.diameter for t in job.tools.values())
    ips = InProcessStock(stock, d / 40)
    motions, src = toolpath_motions(tp)
    entry = [False] * (len(tp.moves) + 1)
    for op in tp.ops:
        for a, b in op.info.get("entry_moves", []):
            for k in range(a, b):
                entry[k] = True
    st = ips.cut(motions, [tp.moves[k].op for k in src], [entry[k] for k in src],
                 job.tools, job.machine, len(tp.ops))
    return st[0].to_json()


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--json", action="store_true")
    ap.add_argument("--skip-large", action="store_true")
    a = ap.parse_args()
    job = load_job(EXAMPLE)
    params = dict(job.operations[0][1])
    rows = []
    for strategy in ("offset", "zigzag", "adaptive"):
        p = dict(params, strategy=strategy)
        ctx = PlanContext(job.units, job.stock, job.machine, job.tools, job.base_dir, job.path)
        t0 = time.process_time()
        res = pocket.plan(ctx, p)
        plan_s = time.process_time() - t0
        tp = res.toolpath
        ip = measure(job, tp, job.stock)
        rows.append({"strategy": strategy, "plan_cpu_s": round(plan_s, 3),
                     "feed_length_mm": round(feed_length(tp), 1),
                     "cycle_time_s": round(cycle_time(tp, job.machine), 1),
                     "air_cut_share": ip["air_cut_share"],
                     "engagement_max": ip.get("engagement", {}).get("max"),
                     "engagement_mean": ip.get("engagement", {}).get("mean")})
    large = None
    if not a.skip_large:
        tools = {1: Tool(1, "flat", 6.0)}
        stock = Stock(-5, -5, -10, 105, 105, 0)
        ctx = PlanContext("mm", stock, Machine(), tools, Path("."))
        p = validate({"tool": 1, "polygon": [[0, 0], [100, 0], [100, 100], [0, 100]],
                      "depth": 3.0, "stepdown": 3.0, "strategy": "adaptive",
                      "engagement": 0.15, "feed": 1000.0}, pocket.PARAMS, "op", None)
        pocket.plan(ctx, p)                  # numba compilation (cached) out of the timing
        t0 = time.process_time()
        res = pocket.plan(ctx, p)
        large = {"pocket": "100 x 100 mm, 6 mm tool, adaptive 15 %, one level",
                 "plan_cpu_s": round(time.process_time() - t0, 3),
                 "feed_length_mm": round(feed_length(res.toolpath), 1)}
    if a.json:
        print(json.dumps({"example": rows, "large": large}, indent=2))
        return
    print(f"{'strategy':10} {'plan CPU s':>10} {'feed mm':>10} {'cycle s':>9} {'air %':>7} "
          f"{'eng max':>8} {'eng mean':>8}")
    for r in rows:
        print(f"{r['strategy']:10} {r['plan_cpu_s']:10.3f} {r['feed_length_mm']:10.1f} "
              f"{r['cycle_time_s']:9.1f} {100 * r['air_cut_share']:7.1f} "
              f"{r['engagement_max'] or 0:8.3f} {r['engagement_mean'] or 0:8.3f}")
    if large:
        print(f"{large['pocket']}: planned in {large['plan_cpu_s']} CPU s, "
              f"feed length {large['feed_length_mm']} mm")


if __name__ == "__main__":
    main()
