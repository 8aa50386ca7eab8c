"""CPU and wall seconds of whole ``millpath`` processes: ``run`` on every bundled
example job and ``check`` on a 10-line program (start-up cost).

Each command is run ``--repeat`` times (3) in a fresh process; the median and best
CPU (user + system of the child) and wall seconds are printed with the load average.
The numba cache is warmed by one untimed ``run`` (and ``check``) first (``--no-warm``
to time a cold first run too). Children compile and keep Python byte code as an
installed package does (``PYTHONDONTWRITEBYTECODE`` is dropped for them, the byte code
goes to a folder in the bench's temporary directory, filled by the warm run);
``--no-bytecode`` times them recompiling millpath's modules on every start instead.

    python bench/run_speed.py [--repeat 3] [--only NAME ...] [--no-warm] [--no-bytecode]
                              [--no-pictures]
"""

from __future__ import annotations

import argparse
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
EXAMPLES = ROOT / "millpath" / "examples"
TEN_LINES = ("G21 G17 G90 G94\nT1 M6\nG43 H1\nS10000 M3\nF600\nG0 X0 Y0 Z5\nG1 Z-1\n"
             "G2 X10 Y0 R5\nG1 X0\nM2\n")
TOOLS = "T1 P1 D0.25 Z1.5\n"


ENV = dict(os.environ)


def measure(cmd: list[str], cwd: Path) -> dict:
    """CPU (user + system) and wall seconds and exit status of one child process."""
    t0 = time.perf_counter()
    p = subprocess.Popen(cmd, cwd=cwd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE,
                         stdin=subprocess.DEVNULL, env=ENV)
    err = p.stderr.read().decode(errors="replace")
    _, status, ru = os.wait4(p.pid, 0)
    return {"cpu": ru.ru_utime + ru.ru_stime, "wall": time.perf_counter() - t0,
            "status": os.waitstatus_to_exitcode(status), "stderr": err}


def timed(name: str, cmd: list[str], cwd: Path, repeat: int) -> None:
    runs = [measure(cmd, cwd) for _ in range(repeat)]
    bad = [r for r in runs if r["status"] != 0]
    if bad:
        print(f"{name:28s} FAILED (exit {bad[0]['status']}): {bad[0]['stderr'].strip()[-300:]}")
        return
    cpu = [r["cpu"] for r in runs]
    wall = [r["wall"] for r in runs]
    print(f"{name:28s} CPU median {statistics.median(cpu):6.2f} s (best {min(cpu):6.2f})  "
          f"wall median {statistics.median(wall):6.2f} s (best {min(wall):6.2f})", flush=True)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--only", action="append", help="example names (and/or 'check')")
    ap.add_argument("--no-warm", action="store_true")
    ap.add_argument("--no-bytecode", action="store_true",
                    help="children do not keep byte code (PYTHONDONTWRITEBYTECODE=1)")
    ap.add_argument("--no-pictures", action="store_true",
                    help="also time each run with --no-pictures (no PNGs drawn)")
    ns = ap.parse_args()
    exe = [sys.executable, "-m", "millpath.cli.main"]
    print(f"load average at start: {' '.join(f'{v:.2f}' for v in os.getloadavg())} "
          f"({os.cpu_count()} CPUs); {ns.repeat} runs each")
    with tempfile.TemporaryDirectory(prefix="run-speed-") as d:
        work = Path(d)
        if ns.no_bytecode:
            ENV["PYTHONDONTWRITEBYTECODE"] = "1"
            ENV.pop("PYTHONPYCACHEPREFIX", None)
        else:
            ENV.pop("PYTHONDONTWRITEBYTECODE", None)
            ENV["PYTHONPYCACHEPREFIX"] = str(work / "pycache")
        print(f"byte code: {'recompiled every start' if ns.no_bytecode else 'kept'}")
        (work / "ten.ngc").write_text(TEN_LINES)
        (work / "ten.tbl").write_text(TOOLS)
        if not ns.only or "check" in ns.only:
            check = exe + ["check", "ten.ngc", "--tools", "ten.tbl"]
            if not ns.no_warm:
                measure(check, work)
            timed("check (10 lines)", check, work, ns.repeat)
        names = sorted(p.name for p in EXAMPLES.iterdir() if (p / "job.toml").exists())
        for name in names:
            if ns.only and name not in ns.only:
                continue
            cmd = exe + ["run", str(EXAMPLES / name / "job.toml"), "-o", str(work / name)]
            if not ns.no_warm:
                measure(cmd, work)
            timed(f"run {name}", cmd, work, ns.repeat)
            if ns.no_pictures:
                timed(f"run {name} --no-pictures", cmd + ["--no-pictures"], work, ns.repeat)
    print(f"load average at end: {' '.join(f'{v:.2f}' for v in os.getloadavg())}")


if __name__ == "__main__":
    main()
