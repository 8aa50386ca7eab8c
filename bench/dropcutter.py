"""Drop-cutter throughput: millpath against OpenCAMLib's BatchDropCutter.

Same mesh (about 100,000 triangles: the mould test surface, 100 x 100 mm), same
160,000 points (a 400 x 400 grid), cutters ball 6, flat 6 and bull 6 r1 (mm), both
libraries on all cores. Prints points per second for each, the ratio and the largest
difference in Z. Run: ``python bench/dropcutter.py [--points N] [--ocl-every K]
[--skip-ocl]``. The pip build of OpenCAMLib does about 150 points per second here
(2 cores), 18 minutes per cutter for all 160,000 points: ``--ocl-every 10`` gives it
every tenth of the same points (its rate is per point and does not depend on how many).
"""

from __future__ import annotations

import argparse
import os
import time

import numpy as np

from millpath.part.surface.mesh import function_mesh, mould_surface
from millpath.geometry.cutter import Cutter
from millpath.plan.surface.dropcutter import build_index, drop


def ocl_drop(mesh, kind: str, xy: np.ndarray, zmin: float) -> tuple[np.ndarray, float]:
    import opencamlib as ocl
    s = ocl.STLSurf()
    for t in mesh.triangles:
        s.addTriangle(ocl.Triangle(*[ocl.Point(float(p[0]), float(p[1]), float(p[2]))
                                     for p in t]))
    cutter = {"ball": ocl.BallCutter(6.0, 30.0), "flat": ocl.CylCutter(6.0, 30.0),
              "bull": ocl.BullCutter(6.0, 1.0, 30.0)}[kind]
    b = ocl.BatchDropCutter()
    b.setSTL(s)
    b.setCutter(cutter)
    b.setThreads(os.cpu_count() or 1)
    for x, y in xy:
        b.appendPoint(ocl.CLPoint(float(x), float(y), zmin))
    t0 = time.perf_counter()
    b.run()
    dt = time.perf_counter() - t0
    return np.array([p.z for p in b.getCLPoints()]), dt


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--points", type=int, default=160_000)
    ap.add_argument("--skip-ocl", action="store_true")
    ap.add_argument("--ocl-every", type=int, default=1,
                    help="OpenCAMLib gets every K-th point of the same set (default 1: all)")
    args = ap.parse_args()
    mesh = function_mesh(mould_surface, (0.0, 100.0), (0.0, 100.0), 225, 225, "mould")
    k = int(round(np.sqrt(args.points)))
    g = np.linspace(3.0, 97.0, k)
    X, Y = np.meshgrid(g, g)
    xy = np.stack([X.ravel(), Y.ravel()], axis=1)
    print(f"mesh: {len(mesh)} triangles; points: {len(xy)}; cores: {os.cpu_count()}")
    t0 = time.perf_counter()
    index = build_index(mesh, cell=1.0)
    print(f"millpath index build: {time.perf_counter() - t0:.3f} s")
    for kind, cutter in (("ball", Cutter(3.0, 3.0)), ("flat", Cutter(3.0, 0.0)),
                         ("bull", Cutter(3.0, 1.0))):
        drop(index, cutter, xy[:10])          # compile or load the numba cache
        t0 = time.perf_counter()
        r = drop(index, cutter, xy)
        dt = time.perf_counter() - t0
        line = f"{kind:5s} millpath {len(xy) / dt:12.0f} points/s"
        if not args.skip_ocl:
            sub = slice(None, None, max(1, args.ocl_every))
            zo, dto = ocl_drop(mesh, kind, xy[sub], float(mesh.bounds[0][2]) - 100.0)
            diff = float(np.max(np.abs(zo - r.z[sub])))
            rate = len(zo) / dto
            line += (f" | OpenCAMLib {rate:10.0f} points/s ({len(zo)} points) | ratio "
                     f"{len(xy) / dt / rate:7.1f}x | max |dz| {diff:.2e} mm")
        print(line, flush=True)


if __name__ == "__main__":
    main()
