"""Arc and spline fitting: program size, cycle time and fitting speed.

Cases (tolerance 0.005 mm, 0.0002 in for inch jobs):

- ``contours``: generated curved 2.5D contours, linearized with a chord error of
  0.5 um (ellipses, rounded slots, a cam lobe, a six-lobed flower, an offset of a wavy
  outline), each cut at three Z levels with plunges and retracts;
- ``zigzag``: 3D zigzag finishing of the surface z = -12 + 6 sin(x/23) cos(y/31)
  - 0.02 y (tool tip, rows along X every 1 mm, 0.2 mm moves), the program of
  bench/sim_speed.py, with flat regions added (z clipped at -14);
- ``zigzag at 45 deg``: the same surface with rows at 45 degrees to X (84,000 moves);
- ``example:<name>``: the bundled example jobs of other strategies
  (millpath/examples), planned with millpath.pipeline.plan_job, when they plan.

For each case and mode it prints the posted program's blocks (non-empty lines) and
bytes before and after fitting, the simulated cycle time (millpath.simulate.cycle_time,
default machine of the units), and the fitting time with its rate in input moves per
minute. Targets: >= 4x fewer blocks on curved 2.5D contours, >= 2x on 3D zigzag
finishing, > 1 million input moves per minute.

Run: ``python bench/fit_bench.py [--moves N] [--no-examples] [--mode arcs|arcs+cubics]``.
The first run compiles the numba kernels (cached afterwards); a warm-up runs first.
"""

from __future__ import annotations

import argparse
import math
import time
from pathlib import Path

import numpy as np

from millpath.fit import fit_toolpath
from millpath.model import Operation, Tool, Toolpath

TOLS = {"mm": 0.005, "inch": 0.0002}


def _linearize(curve, t0: float, t1: float, chord: float, n0: int = 20000) -> np.ndarray:
    """Points of ``curve(t)`` with a chord error about ``chord``: step ~ sqrt(8 chord r)."""
    t = np.linspace(t0, t1, n0)
    P = curve(t)
    d1 = np.gradient(P, t, axis=0)
    d2 = np.gradient(d1, t, axis=0)
    speed = np.linalg.norm(d1, axis=1)
    k = np.abs(d1[:, 0] * d2[:, 1] - d1[:, 1] * d2[:, 0]) / np.maximum(speed, 1e-12) ** 3
    r = 1.0 / np.maximum(k, 1e-6)
    ds = np.sqrt(8.0 * chord * r)                 # arc length per segment
    s = np.concatenate([[0.0], np.cumsum(np.diff(t) * 0.5 * (speed[1:] + speed[:-1])
                                         / (0.5 * (ds[1:] + ds[:-1])))])
    n = max(8, int(math.ceil(s[-1])))
    ts = np.interp(np.linspace(0, s[-1], n + 1), s, t)
    return curve(ts)


def _closed(fx, fy):
    return lambda t: np.column_stack([fx(t), fy(t)])


def contour_shapes():
    """Curved closed 2.5D outlines (mm), tool-centre paths as a CAM system writes them."""
    def offset(curve, d):
        def c(t):
            P = curve(t)
            h = 1e-6
            T = (curve(t + h) - curve(t - h)) / (2 * h)
            N = np.column_stack([T[:, 1], -T[:, 0]]) / np.linalg.norm(T, axis=1)[:, None]
            return P + d * N
        return c

    wavy = _closed(lambda t: (30 + 3 * np.sin(5 * t)) * np.cos(t),
                   lambda t: (30 + 3 * np.sin(5 * t)) * np.sin(t))
    return {
        "ellipse 40x25": _closed(lambda t: 40 * np.cos(t), lambda t: 25 * np.sin(t)),
        "cam lobe": _closed(lambda t: (20 + 8 * np.cos(t) ** 3) * np.cos(t),
                            lambda t: (20 + 8 * np.cos(t) ** 3) * np.sin(t)),
        "flower r15": _closed(lambda t: (15 + 4 * np.cos(6 * t)) * np.cos(t),
                              lambda t: (15 + 4 * np.cos(6 * t)) * np.sin(t)),
        "superellipse": _closed(lambda t: 30 * np.sign(np.cos(t)) * np.abs(np.cos(t)) ** 0.6,
                                lambda t: 20 * np.sign(np.sin(t)) * np.abs(np.sin(t)) ** 0.6),
        "wavy offset 3": offset(wavy, 3.0),
    }


def contours_toolpath(chord: float = 0.0005) -> Toolpath:
    tp = Toolpath(units="mm")
    tp.begin(Operation("profile", "generated 2.5D contours", 1, spindle=12000))
    for k, (name, curve) in enumerate(contour_shapes().items()):
        P = _linearize(curve, 0.0, 2 * math.pi, chord)
        P = P + np.array([100.0 * k, 0.0])
        for z in (-1.0, -2.0, -3.0):
            tp.rapid(P[0, 0], P[0, 1], 5.0)
            tp.line(P[0, 0], P[0, 1], z, 300.0)
            for x, y in P[1:]:
                tp.line(x, y, z, 1200.0)
            tp.rapid(P[-1, 0], P[-1, 1], 5.0)
    return tp


def zigzag_toolpath(moves: int = 200_000, size: float = 200.0) -> Toolpath:
    passes = max(1, int(round(math.sqrt(moves / 5.0))))
    per = max(1, moves // passes)
    tp = Toolpath(units="mm")
    tp.begin(Operation("surface-finish", "3D zigzag finishing", 2, spindle=15000))
    ys = np.linspace(1.0, size - 1.0, passes)
    xs = np.linspace(0.0, size, per + 1)
    for k, y in enumerate(ys):
        x = xs if k % 2 == 0 else xs[::-1]
        z = np.maximum(-12.0 + 6.0 * np.sin(x / 23.0) * np.cos(y / 31.0) - 0.02 * y, -14.0)
        if k == 0:
            tp.rapid(x[0], y, 5.0)
            tp.line(x[0], y, z[0], 500.0)
        else:
            tp.line(x[0], y, z[0], 2000.0)           # step over at the row end
        for xi, zi in zip(x[1:], z[1:]):
            tp.line(xi, y, zi, 2000.0)
    tp.rapid(x[-1], ys[-1], 5.0)
    return tp


def diagonal_zigzag_toolpath(step: float = 0.2, stepover: float = 1.0) -> Toolpath:
    """The same surface finished with rows at 45 degrees to X (no XZ/YZ plane holds a
    row: only helical arcs and lines can shorten it)."""
    tp = Toolpath(units="mm")
    tp.begin(Operation("surface-finish", "3D zigzag finishing at 45 degrees", 2,
                       spindle=15000))
    s = np.arange(0.0, 140.0, step)
    c = math.sqrt(0.5)
    for k, o in enumerate(np.arange(-60.0, 60.0, stepover)):
        u = s if k % 2 == 0 else s[::-1]
        x = 100 + (u - 70) * c - o * c
        y = 100 + (u - 70) * c + o * c
        z = np.maximum(-12.0 + 6.0 * np.sin(x / 23.0) * np.cos(y / 31.0) - 0.02 * y, -14.0)
        if k == 0:
            tp.rapid(x[0], y[0], 5.0)
            tp.line(x[0], y[0], z[0], 500.0)
        for xi, yi, zi in zip(x, y, z):
            tp.line(xi, yi, zi, 2000.0)
    tp.rapid(x[-1], y[-1], 5.0)
    return tp


def example_toolpaths():
    """(name, toolpath, tools) of the bundled examples that plan."""
    from millpath.job.jobfile import load_job
    from millpath.pipeline import plan_job
    root = Path(__file__).resolve().parents[1] / "millpath" / "examples"
    for d in sorted(p for p in root.iterdir() if (p / "job.toml").is_file()):
        try:
            job = load_job(d / "job.toml")
            tp, _, _ = plan_job(job)
        except Exception as e:                      # noqa: BLE001 - report and go on
            print(f"  example {d.name}: not planned ({type(e).__name__}: {e})")
            continue
        yield f"example:{d.name}", tp, job.tools


def blocks_bytes(tp: Toolpath, tools) -> tuple[int, int]:
    from millpath.post.writer import post
    text = post(tp, tools)
    return sum(1 for l in text.splitlines() if l.strip()), len(text.encode())


def seconds(tp: Toolpath) -> float | None:
    """Simulated cycle time, or None (no simulator, or a toolpath it cannot time
    directly, e.g. one with cutter compensation)."""
    try:
        from millpath.simulate import cycle_time
        return cycle_time(tp)
    except (ImportError, ValueError):
        return None


def run_case(name: str, tp: Toolpath, tools, mode: str, min_radius: float) -> dict:
    tol = TOLS[tp.units]
    n_lines = tp.counts()["line"]
    t0, c0_ = time.perf_counter(), time.process_time()
    fitted = fit_toolpath(tp, tol, mode, min_radius=min_radius)
    dt, cpu = time.perf_counter() - t0, time.process_time() - c0_
    b0, y0 = blocks_bytes(tp, tools)
    b1, y1 = blocks_bytes(fitted, tools)
    c0, c1 = seconds(tp), seconds(fitted)
    row = dict(case=name, mode=mode, tol=tol, units=tp.units, lines=n_lines,
               blocks=(b0, b1), bytes=(y0, y1), cycle=(c0, c1), fit_s=dt,
               rate=n_lines / max(dt, 1e-9) * 60.0, cpu_rate=n_lines / max(cpu, 1e-9) * 60.0,
               counts=fitted.counts())
    cyc = (f"{c0:8.1f} -> {c1:8.1f} s" if c0 is not None and c1 is not None
           else "     n/a            ")
    print(f"{name:34s} {mode:11s} blocks {b0:7d} -> {b1:7d} ({b0 / b1:5.2f}x)  "
          f"bytes {y0:9d} -> {y1:8d} ({y0 / y1:5.2f}x)  cycle {cyc}  "
          f"fit {dt:6.3f} s = {row['rate'] / 1e6:5.2f} M moves/min "
          f"(CPU {row['cpu_rate'] / 1e6:5.2f})")
    return row


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--moves", type=int, default=200_000, help="zigzag size (line moves)")
    ap.add_argument("--no-examples", action="store_true")
    ap.add_argument("--mode", choices=["arcs", "arcs+cubics", "both"], default="both")
    a = ap.parse_args()
    modes = ["arcs", "arcs+cubics"] if a.mode == "both" else [a.mode]
    tools = {1: Tool(1, diameter=6.0), 2: Tool(2, type="ball", diameter=6.0)}
    warm = contours_toolpath(0.01)
    for m in modes:
        fit_toolpath(warm, 0.005, m)                 # compile / load the numba cache
    cases = [("2.5D contours (chord 0.5 um)", contours_toolpath(), tools, 3.0),
             (f"3D zigzag finishing ({a.moves} moves)", zigzag_toolpath(a.moves), tools, 3.0),
             ("3D zigzag at 45 deg (84000 moves)", diagonal_zigzag_toolpath(), tools, 3.0)]
    for name, tp, ts, rmin in cases:
        for m in modes:
            run_case(name, tp, ts, m, rmin)
    # the program-level filter (millpath fit) on the posted zigzag program
    from millpath.fit import fit_program
    from millpath.post.writer import post
    text = post(cases[1][1], tools)
    n_in = text.count("\n")
    t0, c0 = time.perf_counter(), time.process_time()
    out = fit_program(text, 0.005, "arcs")
    dt, cpu = time.perf_counter() - t0, time.process_time() - c0
    print(f"{'fit_program on the zigzag program':34s} arcs        blocks {n_in:7d} -> "
          f"{out.count(chr(10)):7d}  bytes {len(text):9d} -> {len(out):8d}  "
          f"fit {dt:6.3f} s = {n_in / dt * 60 / 1e6:5.2f} M lines/min "
          f"(CPU {n_in / max(cpu, 1e-9) * 60 / 1e6:5.2f})")
    if not a.no_examples:
        for name, tp, ts in example_toolpaths():
            rmin = max((ts[o.tool].radius for o in tp.ops if o.tool in ts), default=0.0)
            for m in modes:
                try:
                    run_case(name, tp, ts, m, rmin)
                except Exception as e:              # noqa: BLE001
                    print(f"  {name} {m}: failed ({type(e).__name__}: {e})")


if __name__ == "__main__":
    main()
