"""STEP Part 21 parsing and AP224 feature extraction throughput.

Generates an AP224 file with the project's builder (a large plate with a grid of holes
of every bottom kind, slots and pockets: at least ``--instances`` instances), then times
(best of ``--repeat``) the Part 21 parse, the feature extraction (units, stock,
material, features through the instance graph) and the shapes, and prints instances
per second. No peer STEP library is installed in the project environment, so there is
no side-by-side figure. Run: ``python bench/step_parse.py [--instances N]``.
"""

from __future__ import annotations

import argparse
import time

from millpath.part.step.ap224 import read_part
from millpath.part.step.build import Ap224Builder
from millpath.part.step.p21 import parse
from millpath.part.step.shapes import feature_shapes


def generate(min_instances: int) -> tuple[str, int]:
    b = Ap224Builder("BENCH-PLATE", units="mm", material="aluminium 6061-T6")
    b.block(2000.0, 2000.0, 50.0)
    bottoms = [("through", {}), ("flat", {}), ("conical", {"tip_angle": 118.0}),
               ("spherical", {"radius": 5.0}), ("flat with radius", {"corner_radius": 1.0})]
    k = 0
    while len(b.sf.instances) < min_instances:
        x, y = 20.0 + 40.0 * (k % 45), 20.0 + 40.0 * (k // 45)
        kind = k % 7
        if kind < 5:
            bottom, extra = bottoms[kind]
            b.hole((x, y, 50.0), 10.0, 12.0, bottom=bottom, **extra)
        elif kind == 5:
            b.slot((x - 15.0, y, 50.0), (1.0, 0.0), 30.0, 8.0, 4.0, ends=("radiused", "flat"))
        else:
            b.pocket((x, y, 50.0), 5.0, "rectangular", length=30.0, width=20.0,
                     corner_radius=3.0)
        k += 1
    return b.text(), k


def best(fn, repeat: int) -> tuple[float, object]:
    t_best, out = float("inf"), None
    for _ in range(repeat):
        t0 = time.perf_counter()
        out = fn()
        t_best = min(t_best, time.perf_counter() - t0)
    return t_best, out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--instances", type=int, default=20000)
    ap.add_argument("--repeat", type=int, default=3)
    a = ap.parse_args()
    text, nfeat = generate(a.instances)
    t_parse, sf = best(lambda: parse(text, "bench.stp"), a.repeat)
    n = len(sf)
    t_feat, part = best(lambda: read_part(parse(text, "bench.stp")), a.repeat)
    t_extract = t_feat - t_parse
    t_shapes, shapes = best(lambda: feature_shapes(part), a.repeat)
    print(f"file: {n} instances, {len(text) / 1e6:.2f} MB, {nfeat} features")
    print(f"parse:               {t_parse:.3f} s  {n / t_parse:,.0f} instances/s")
    print(f"parse + features:    {t_feat:.3f} s  {n / t_feat:,.0f} instances/s "
          f"(extraction {t_extract:.3f} s, {len(part.features)} features)")
    print(f"machinable shapes:   {t_shapes:.3f} s  ({len(shapes.shapes)} shapes)")


if __name__ == "__main__":
    main()
