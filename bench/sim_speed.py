"""Material-removal simulation speed: a 200,000-move 3D finishing program.

A 6 mm ball end mill rasters a 200 x 200 mm block (Z -30..0) along X, following the
surface ``z = -12 + 6 sin(x / 23) cos(y / 31) - 0.02 y`` (tool tip), with 200 passes of
1000 feed moves each (1 mm stepover, 0.2 mm moves) and a rapid retract between passes:
about 200,000 moves. The block is simulated at 0.1 mm (2000 x 2000 cells) with the
tip surface as the design (not a drop-cutter path: beside the tip a ball whose tip
follows a sloped surface dips below it, so the gouge figure is real but expected).
Prints wall and CPU time of each stage and peak memory (the machine is shared: CPU
time shows the work, wall time what a user waits). The target is under 10 s for the
simulation on the 2-core machine.

Run: ``python bench/sim_speed.py [--moves N] [--resolution R] [--threads T] [--ngc]``.
``--ngc`` also posts the program as RS274NGC, interprets it with millpath's interpreter
and simulates the interpreted motion (what ``millpath simulate`` does).
The first run compiles the numba kernels (cached afterwards); a warm-up on a small
program is done before timing.
"""

from __future__ import annotations

import argparse
import os
import resource
import time

import numpy as np


def surface(x, y):
    return -12.0 + 6.0 * np.sin(x / 23.0) * np.cos(y / 31.0) - 0.02 * y


def finishing_toolpath(moves: int, size: float = 200.0):
    from millpath.model import Operation, Toolpath
    passes = max(1, int(round(np.sqrt(moves / 5.0))))         # 200 passes for 200k
    per = max(1, moves // passes)
    tp = Toolpath(units="mm")
    tp.begin(Operation("surface-finish", "bench finishing", 1))
    ys = np.linspace(1.0, size - 1.0, passes)
    xs = np.linspace(0.0, size, per + 1)
    for k, y in enumerate(ys):
        x = xs if k % 2 == 0 else xs[::-1]
        z = surface(x, np.full_like(x, y))
        tp.rapid(x[0], y, 5.0)
        tp.line(x[0], y, z[0], 800.0)
        for xi, zi in zip(x[1:], z[1:]):
            tp.line(xi, y, zi, 2000.0)
        tp.rapid(x[-1], y, 5.0)
    return tp


class _Surface:
    def height(self, x, y):
        return surface(np.asarray(x, float), np.asarray(y, float))


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--moves", type=int, default=200_000)
    ap.add_argument("--resolution", type=float, default=0.1)
    ap.add_argument("--threads", type=int, default=0, help="numba threads (0: all)")
    ap.add_argument("--ngc", action="store_true", help="also time post + interpret + simulate")
    args = ap.parse_args()
    import numba
    if args.threads:
        numba.set_num_threads(args.threads)
    from millpath.model import Stock, Tool
    from millpath.simulate import simulate_toolpath
    from millpath.simulate.simulator import compare, sweep
    from millpath.simulate.cycletime import motion_times
    from millpath.simulate.path import motion_segments, toolpath_motions
    from millpath.simulate.zmap import ZMap
    from millpath.model import Machine

    tools = {1: Tool(1, "ball", 6.0, flute_length=25, stickout=40, holder=[(32.0, 40.0)])}
    stock = Stock(0.0, 0.0, -30.0, 200.0, 200.0, 0.0)
    simulate_toolpath(finishing_toolpath(2000, 20.0), tools, Stock(0, 0, -30, 20, 20, 0),
                      resolution=0.5, design=_Surface())                 # warm-up
    tp = finishing_toolpath(args.moves)
    print(f"program: {len(tp)} moves; stock 200 x 200 mm at {args.resolution} mm; "
          f"threads {numba.get_num_threads()} of {os.cpu_count()} cores")

    t0 = time.perf_counter()
    c0 = time.process_time()
    res = simulate_toolpath(tp, tools, stock, resolution=args.resolution, design=_Surface())
    total = time.perf_counter() - t0
    total_cpu = time.process_time() - c0

    # the same stages timed one by one
    t = time.perf_counter()
    motions, src = toolpath_motions(tp)
    t_exp = time.perf_counter() - t
    t = time.perf_counter()
    segs = motion_segments(motions, args.resolution / 20)
    t_seg = time.perf_counter() - t
    zmap = ZMap.from_stock(stock, args.resolution)
    t = time.perf_counter()
    c = time.process_time()
    sweep(zmap, segs, tools, len(motions))
    t_sweep = time.perf_counter() - t
    c_sweep = time.process_time() - c
    t = time.perf_counter()
    motion_times(motions, Machine())
    t_cyc = time.perf_counter() - t
    t = time.perf_counter()
    compare(zmap, _Surface())
    t_cmp = time.perf_counter() - t

    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0
    ny, nx = res.zmap.heights.shape
    print(f"grid {nx} x {ny} = {nx * ny / 1e6:.1f} M cells, {res.chords} chords")
    print(f"simulate_toolpath total: {total:.2f} s wall, {total_cpu:.2f} s CPU "
          f"(all threads); load average {os.getloadavg()[0]:.1f}")
    print(f"  expand moves {t_exp:.2f} s, chords {t_seg:.2f} s, sweep {t_sweep:.2f} s "
          f"({c_sweep:.2f} s CPU), "
          f"cycle time {t_cyc:.2f} s, design compare {t_cmp:.2f} s")
    print(f"peak memory (max RSS): {peak:.0f} MB")
    j = res.to_json()
    if args.ngc:
        from millpath.interpret import interpret
        from millpath.post.writer import post
        from millpath.simulate import simulate_motions
        text = post(tp, tools)
        t = time.perf_counter()
        motions = interpret(text, tools, machine_units="mm")
        t_int = time.perf_counter() - t
        t = time.perf_counter()
        c = time.process_time()
        r2 = simulate_motions(motions, tools, stock, resolution=args.resolution,
                              design=_Surface(), machine=Machine())
        t_sim = time.perf_counter() - t
        print(f"RS274NGC: {text.count(chr(10))} lines; interpret {t_int:.2f} s; "
              f"simulate_motions {t_sim:.2f} s wall, {time.process_time() - c:.2f} s CPU; "
              f"removed {r2.removed_volume:.0f} mm^3")
        peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0
        print(f"peak memory after the NGC run (max RSS): {peak:.0f} MB")
    print(f"result: removed {j['removed_volume']:.0f} mm^3, max gouge {j['max_gouge']}, "
          f"max left {j['max_left']}, cycle {j['cycle_time_s']:.0f} s, "
          f"holder contacts {j['holder_contacts']}, rapids through material "
          f"{j['rapids_through_material']}")


if __name__ == "__main__":
    main()
