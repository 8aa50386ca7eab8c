"""Speed of ``millpath check`` against LinuxCNC's rs274, whole processes, same files.

Programs (``--lines`` each, 1,000,000 by default; generated, fixed seeds):

* ``own-post``: millpath's own post shape: G1 lines, G2/G3 arcs (I/J and R) and, one
  block in four, a rounded-rectangle contour under G41/G42;
* ``free-order``: words in free order and case, modal moves, R and I/J arcs, line
  numbers, comments, a few G81/G83 runs (bench/programs.py);
* ``comp-heavy``: almost all under G41/G42, about 45 % arcs (bench/programs.py);
* ``all-comp-lines`` (``--comp-lines``, 100,000): one long compensated path of G1 lines.

Each is run ``--repeat`` times (3) alternately by ``millpath check --tools T.tbl`` and
``rs274 -t T.tbl -g`` (canonical calls to /dev/null); CPU seconds (user + system of the
child, the fair measure on a loaded machine) and wall seconds are printed as median and
best, with the ratios millpath/rs274, millpath's peak resident memory and the load
average. ``--keep DIR`` keeps the programs.

    python bench/interp_speed.py [--lines N] [--comp-lines N] [--repeat 3] [--only NAME]
"""

from __future__ import annotations

import argparse
import json
import math
import os
import random
import subprocess
import sys
import statistics
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from programs import TOOL_TABLE, comp_heavy, free_order  # noqa: E402


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



def _measure(cmd: list[str], env: dict) -> dict:
    """CPU, wall and peak memory of ``cmd`` (stdout to /dev/null). The child runs under
    GNU time, whose %M is the command's own peak (a child forked from this process
    would inherit this process's high-water mark in ``ru_maxrss``)."""
    with open(os.devnull, "w") as null:
        t0 = time.perf_counter()
        p = subprocess.Popen(["/usr/bin/time", "-f", "@@peak %M", *cmd], stdout=null,
                             stderr=subprocess.PIPE, stdin=subprocess.DEVNULL, env=env)
        err = p.stderr.read().decode(errors="replace")
        _, status, ru = os.wait4(p.pid, 0)
        wall = time.perf_counter() - t0
    peak = [s for s in err.splitlines() if s.startswith("@@peak ")]
    err = "\n".join(s for s in err.splitlines() if not s.startswith("@@peak ")
                    and not s.startswith("Command exited"))
    return {"cpu": ru.ru_utime + ru.ru_stime, "wall": wall,
            "rss_mb": int(peak[-1].split()[1]) / 1024 if peak else float("nan"),
            "status": os.waitstatus_to_exitcode(status), "stderr": err}


def run_case(name: str, text: str, repeat: int, keep: Path | None) -> dict:
    root = Path(__file__).resolve().parents[1]
    with tempfile.TemporaryDirectory(prefix="interp-speed-") as d, \
            tempfile.TemporaryDirectory(prefix="rs274home") as home:
        ngc = Path(d) / f"{name}.ngc"
        tbl = Path(d) / "tools.tbl"
        ngc.write_text(text)
        tbl.write_text(TOOL_TABLE)
        if keep:
            keep.mkdir(parents=True, exist_ok=True)
            (keep / ngc.name).write_text(text)
            (keep / tbl.name).write_text(TOOL_TABLE)
        n = text.count("\n")
        del text
        env = dict(os.environ, PYTHONPATH=str(root), HOME=home)
        ours_cmd = [sys.executable, "-m", "millpath.cli.main", "check", str(ngc), "--tools",
                    str(tbl)]
        rs_cmd = ["/usr/bin/rs274", "-t", str(tbl), "-g", str(ngc)]
        ours, theirs = [], []
        for _ in range(repeat):
            ours.append(_measure(ours_cmd, env))
            theirs.append(_measure(rs_cmd, env))
        if ours[0]["status"] != 0:
            sys.exit(f"millpath check failed on {name}:\n" + ours[0]["stderr"][-2000:])
        errs = [s for s in theirs[0]["stderr"].splitlines()
                if s.strip() and s.strip() != "executing"]
        if errs:
            sys.exit(f"rs274 reported on {name}: {errs[:2]}")
    out = {"name": name, "lines": n}
    for who, runs in (("millpath", ours), ("rs274", theirs)):
        for key in ("cpu", "wall"):
            vals = [r[key] for r in runs]
            out[f"{who}_{key}_median"] = statistics.median(vals)
            out[f"{who}_{key}_best"] = min(vals)
        out[f"{who}_rss_mb"] = max(r["rss_mb"] for r in runs)
    return out


def report(r: dict) -> None:
    print(f"{r['name']}: {r['lines']} lines")
    for who in ("millpath", "rs274"):
        print(f"  {who:8s} CPU median {r[f'{who}_cpu_median']:7.2f} s (best "
              f"{r[f'{who}_cpu_best']:6.2f}), wall median {r[f'{who}_wall_median']:7.2f} s "
              f"(best {r[f'{who}_wall_best']:6.2f}), peak RSS {r[f'{who}_rss_mb']:6.0f} MB")
    for stat in ("median", "best"):
        c = r[f"millpath_cpu_{stat}"] / r[f"rs274_cpu_{stat}"]
        w = r[f"millpath_wall_{stat}"] / r[f"rs274_wall_{stat}"]
        print(f"  ratio millpath/rs274 ({stat}): CPU {c:.2f}, wall {w:.2f}")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--lines", type=int, default=1_000_000)
    ap.add_argument("--comp-lines", type=int, default=100_000,
                    help="lines of the all-compensated G1 path (0: skip)")
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--only", action="append",
                    choices=["own-post", "free-order", "comp-heavy", "all-comp-lines"])
    ap.add_argument("--keep", type=Path, help="also write the programs into this folder")
    ap.add_argument("--json", action="store_true", help="print the figures as JSON too")
    ns = ap.parse_args()
    cases = {"own-post": lambda: generate(ns.lines), "free-order": lambda: free_order(ns.lines),
             "comp-heavy": lambda: comp_heavy(ns.lines),
             "all-comp-lines": lambda: generate_comp(ns.comp_lines)}
    if not ns.comp_lines:
        del cases["all-comp-lines"]
    print(f"load average at start: {' '.join(f'{v:.2f}' for v in os.getloadavg())} "
          f"({os.cpu_count()} CPUs)")
    results = []
    for name, make in cases.items():
        if ns.only and name not in ns.only:
            continue
        r = run_case(name, make(), ns.repeat, ns.keep)
        report(r)
        results.append(r)
    print(f"load average at end: {' '.join(f'{v:.2f}' for v in os.getloadavg())}")
    if ns.json:
        print(json.dumps(results))


if __name__ == "__main__":
    main()
