"""Speed of millpath's interpreter against LinuxCNC's rs274 on a 1,000,000-line program.

The program mixes G1 lines and G2/G3 arcs (I/J and R) and, one block in four, runs
a rounded-rectangle contour with cutter radius compensation (G41/G42 D1) on. Both
interpreters read the same file; rs274 writes its canonical calls to /dev/null.
Prints both times (wall clock and CPU, which is the fair measure on a loaded
machine), the ratios and millpath's peak memory (resident set of a fresh
process that only interprets the program).

A second, smaller case (``--comp-lines``, 100,000 by default) is one long compensated
path of G1 lines, the slowest kind of input for millpath.

    python bench/interp_speed.py [--lines N] [--comp-lines N] [--keep FILE]
"""

from __future__ import annotations

import argparse
import json
import math
import os
import random
import subprocess
import sys
import tempfile
import time
from pathlib import Path

TOOL_TABLE = "T1 P1 D0.25 Z1.5 ;quarter inch mill\n"


def generate(n_lines: int, seed: int = 1) -> str:
    """A valid program of about ``n_lines`` lines (mm, tool 1 of 6.35 mm)."""
    rng = random.Random(seed)
    out = ["G21 G17 G90 G94 G40 G49 G80", "T1 M6", "G43 H1", "S12000 M3", "F800",
           "G0 X0 Y0 Z5", "G1 Z-1"]
    x = y = 0.0
    while len(out) < n_lines - 2:
        if rng.random() < 0.25:
            # compensated rounded rectangle at a random place
            cx, cy = rng.uniform(-200, 200), rng.uniform(-200, 200)
            w, h, r = rng.uniform(30, 80), rng.uniform(30, 80), rng.uniform(5, 12)
            side = rng.choice(("G41", "G42"))
            out += [f"G0 X{cx - w:.3f} Y{cy - h:.3f}", f"{side} D1",
                    f"G1 X{cx - w / 2 + r:.3f} Y{cy - h / 2:.3f}",
                    f"X{cx + w / 2 - r:.3f}",
                    f"G3 X{cx + w / 2:.3f} Y{cy - h / 2 + r:.3f} I0 J{r:.3f}",
                    f"G1 Y{cy + h / 2 - r:.3f}",
                    f"G3 X{cx + w / 2 - r:.3f} Y{cy + h / 2:.3f} I{-r:.3f} J0",
                    f"G1 X{cx - w / 2 + r:.3f}",
                    f"G3 X{cx - w / 2:.3f} Y{cy + h / 2 - r:.3f} R{r:.3f}",
                    f"G1 Y{cy - h / 2 + r:.3f}",
                    f"G3 X{cx - w / 2 + r:.3f} Y{cy - h / 2:.3f} R{r:.3f}",
                    f"G40 G1 X{cx - w:.3f} Y{cy - h:.3f}"]
            x, y = cx - w, cy - h
            continue
        for _ in range(rng.randint(20, 60)):
            if rng.random() < 0.3:
                # arc of random radius and sweep from the current point
                rad = rng.uniform(1, 30)
                a0 = rng.uniform(0, 2 * math.pi)
                sweep = rng.uniform(0.2, 3.0)
                ccw = rng.random() < 0.5
                ccx, ccy = x - rad * math.cos(a0), y - rad * math.sin(a0)
                a1 = a0 + (sweep if ccw else -sweep)
                ex, ey = ccx + rad * math.cos(a1), ccy + rad * math.sin(a1)
                code = "G3" if ccw else "G2"
                out.append(f"{code} X{ex:.4f} Y{ey:.4f} I{ccx - x:.4f} J{ccy - y:.4f}")
                x, y = float(f"{ex:.4f}"), float(f"{ey:.4f}")
            else:
                x += rng.uniform(-10, 10)
                y += rng.uniform(-10, 10)
                x, y = float(f"{x:.3f}"), float(f"{y:.3f}")
                out.append(f"G1 X{x:.3f} Y{y:.3f}")
    out += ["G0 Z5", "M2"]
    return "\n".join(out) + "\n"


def generate_comp(n_lines: int, seed: int = 3) -> str:
    """A program that is all one compensated path of G1 lines (worst case for us)."""
    rng = random.Random(seed)
    out = ["G21 G17 G90 G94", "T1 M6", "G43 H1", "F800", "G0 X-10 Y-10 Z5", "G1 Z-1",
           "G41 D1", "G1 X0 Y0"]
    x = y = ang = 0.0
    while len(out) < n_lines - 2:
        ang += rng.uniform(-0.6, 0.9)
        step = rng.uniform(5, 15)
        x += step * math.cos(ang)
        y += step * math.sin(ang)
        out.append(f"G1 X{x:.3f} Y{y:.3f}")
    out += ["G40 G1 X-10 Y-10", "M2"]
    return "\n".join(out) + "\n"


_CHILD = r"""
import json, sys, time
def hwm():
    # peak resident set of this process image (VmHWM is reset by exec, unlike ru_maxrss)
    for line in open("/proc/self/status"):
        if line.startswith("VmHWM:"):
            return int(line.split()[1])
    return 0
t0 = time.perf_counter()
from millpath.interpret import interpret
base = hwm()
t1 = time.perf_counter()
c1 = time.process_time()
ms = interpret(open(sys.argv[1]).read(), sys.argv[2])
c2 = time.process_time()
t2 = time.perf_counter()
peak = hwm()
print(json.dumps({"seconds": t2 - t1, "cpu": c2 - c1, "import": t1 - t0, "moves": len(ms),
                  "peak_kb": peak, "base_kb": base}))
"""


def _child_cpu() -> float:
    import resource
    r = resource.getrusage(resource.RUSAGE_CHILDREN)
    return r.ru_utime + r.ru_stime


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--lines", type=int, default=1_000_000)
    ap.add_argument("--keep", type=Path, help="also write the program here")
    ap.add_argument("--comp-lines", type=int, default=100_000,
                    help="also time a program that is one compensated path (0: skip)")
    ns = ap.parse_args()
    run_case("mixed program", generate(ns.lines), ns.keep)
    if ns.comp_lines:
        print()
        run_case("all-compensated program", generate_comp(ns.comp_lines), None)


def run_case(name: str, text: str, keep: Path | None) -> None:
    root = Path(__file__).resolve().parents[1]
    with tempfile.TemporaryDirectory(prefix="interp-speed-") as d:
        ngc = Path(d) / "program.ngc"
        tbl = Path(d) / "tools.tbl"
        ngc.write_text(text)
        tbl.write_text(TOOL_TABLE)
        if keep:
            keep.write_text(text)
        n = text.count("\n")
        print(f"{name}: {n} lines, {len(text) / 1e6:.1f} MB")
        del text
        env = dict(os.environ, PYTHONPATH=str(root))
        p = subprocess.run([sys.executable, "-c", _CHILD, str(ngc), str(tbl)],
                           capture_output=True, text=True, env=env)
        if p.returncode != 0:
            sys.exit("millpath failed:\n" + p.stderr[-2000:])
        ours = json.loads(p.stdout.strip().splitlines()[-1])
        exe = "/usr/bin/rs274"
        with tempfile.TemporaryDirectory(prefix="rs274home") as home:
            c0 = _child_cpu()
            t0 = time.perf_counter()
            with open(os.devnull, "w") as null:
                q = subprocess.run([exe, "-t", str(tbl), "-g", str(ngc)], stdout=null,
                                   stderr=subprocess.PIPE, text=True,
                                   env=dict(os.environ, HOME=home), stdin=subprocess.DEVNULL)
            t_rs = time.perf_counter() - t0
            c_rs = _child_cpu() - c0
        errs = [l for l in q.stderr.splitlines() if l.strip() and l.strip() != "executing"]
        if errs:
            print("rs274 reported:", errs[:2])
    t_ours, c_ours = ours["seconds"], ours["cpu"]
    print(f"millpath: {t_ours:.2f} s wall, {c_ours:.2f} s CPU for {ours['moves']} moves "
          f"({c_ours / n * 1e6:.2f} us CPU/line; import {ours['import']:.2f} s not counted)")
    print(f"rs274:    {t_rs:.2f} s wall, {c_rs:.2f} s CPU (output to /dev/null)")
    print(f"ratio millpath/rs274: wall {t_ours / t_rs:.2f}, CPU {c_ours / c_rs:.2f} "
          f"({'faster' if c_ours < c_rs else 'slower'} than rs274 in CPU time; wall time "
          f"depends on the machine's load)")
    print(f"millpath peak memory: {ours['peak_kb'] / 1024:.0f} MB resident "
          f"({ours['base_kb'] / 1024:.0f} MB after imports; program text, its lines and "
          f"the compact motion arrays make the rest)")


if __name__ == "__main__":
    main()
