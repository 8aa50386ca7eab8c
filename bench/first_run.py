"""The first run after an install: CPU seconds of ``millpath run`` with an empty kernel
cache (a fresh ``MILLPATH_CACHE_DIR``) and with the cache that run filled, for a few
examples, and the compile share; optionally side by side with a baseline commit (its
sources checked out in a temporary worktree, run by the same Python), interleaved.

    python bench/first_run.py [--baseline REV] [--examples a,b,c] [--repeat N]
    python bench/first_run.py --readme      # the README's first command on a fresh clone

Each measurement is one child process; CPU seconds are the child's user + system time
(its threads included). Read the ratios: on a loaded machine every figure grows.
"""

from __future__ import annotations

import argparse
import os
import resource
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
EXAMPLES = ("features-plate", "die-blanking", "surface-cavity")


def _child_cpu() -> float:
    r = resource.getrusage(resource.RUSAGE_CHILDREN)
    return r.ru_utime + r.ru_stime


def run(src: Path, example: str, cache: Path, out: Path) -> tuple[float, float]:
    """(CPU s, wall s) of ``millpath run`` of ``example`` from the sources in ``src``."""
    env = dict(os.environ, MILLPATH_CACHE_DIR=str(cache), PYTHONPATH=str(src))
    env.pop("NUMBA_CACHE_DIR", None)
    job = src / "millpath" / "examples" / example / "job.toml"
    shutil.rmtree(out, ignore_errors=True)
    c0, t0 = _child_cpu(), time.perf_counter()
    p = subprocess.run([sys.executable, "-c", "from millpath.cli.main import main; main()",
                        "run", str(job), "-o", str(out), "--no-pictures"], env=env,
                       capture_output=True, text=True)
    if p.returncode != 0:
        raise SystemExit(f"{src} {example}: {p.stderr.strip()}")
    return _child_cpu() - c0, time.perf_counter() - t0


def load() -> str:
    return " ".join(f"{x:.1f}" for x in os.getloadavg())


def table(sources: dict[str, Path], examples, repeat: int) -> None:
    rows: dict[tuple[str, str], list[tuple[float, float]]] = {}
    with tempfile.TemporaryDirectory(prefix="first-run-") as tmp:
        for r in range(repeat):
            for ex in examples:
                for label, src in sources.items():       # interleaved
                    cache = Path(tmp) / f"cache-{label}-{ex}-{r}"
                    cold = run(src, ex, cache, Path(tmp) / "out")
                    warm = run(src, ex, cache, Path(tmp) / "out")
                    rows.setdefault((ex, label), []).append((cold[0], warm[0]))
                    shutil.rmtree(cache, ignore_errors=True)
    print(f"load average at the end: {load()}")
    print(f"{'example':<18}{'source':<12}{'cold CPU s':>11}{'warm CPU s':>11}"
          f"{'cold/warm':>10}{'compile share':>14}")
    for (ex, label), v in rows.items():
        cold = min(a for a, _ in v)
        warm = min(b for _, b in v)
        print(f"{ex:<18}{label:<12}{cold:>11.1f}{warm:>11.1f}{cold / warm:>10.1f}"
              f"{(cold - warm) / cold:>13.0%}")
    if len(sources) > 1:
        labels = list(sources)
        for ex in examples:
            a = min(c for c, _ in rows[(ex, labels[0])])
            b = min(c for c, _ in rows[(ex, labels[1])])
            print(f"{ex}: cold run {labels[1]} / {labels[0]} = {b / a:.2f}")


def readme() -> None:
    """The README's first command in a fresh clone of this checkout, with an empty
    kernel cache: wall and CPU seconds."""
    text = (ROOT / "README.md").read_text()
    line = next(ln for ln in text.splitlines() if ln.startswith("python3 -m venv"))
    with tempfile.TemporaryDirectory(prefix="first-run-clone-") as tmp:
        clone = Path(tmp) / "clone"
        subprocess.run(["git", "clone", "-q", str(ROOT), str(clone)], check=True)
        env = dict(os.environ, MILLPATH_CACHE_DIR=str(Path(tmp) / "cache"))
        env.pop("NUMBA_CACHE_DIR", None)
        c0, t0 = _child_cpu(), time.perf_counter()
        subprocess.run(["bash", "-c", line], cwd=clone, env=env, check=True,
                       stdout=subprocess.DEVNULL)
        print(f"README first command: {time.perf_counter() - t0:.0f} s wall, "
              f"{_child_cpu() - c0:.0f} CPU s (load {load()}): {line}")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--baseline", help="a commit to compare with")
    ap.add_argument("--examples", default=",".join(EXAMPLES))
    ap.add_argument("--repeat", type=int, default=1)
    ap.add_argument("--readme", action="store_true")
    a = ap.parse_args()
    if a.readme:
        readme()
        return
    sources = {"this": ROOT}
    if a.baseline:
        wt = Path(tempfile.mkdtemp(prefix="first-run-base-")) / "src"
        subprocess.run(["git", "-C", str(ROOT), "worktree", "add", "-q", "--detach",
                        str(wt), a.baseline], check=True)
        sources = {a.baseline[:10]: wt, "this": ROOT}
    try:
        table(sources, a.examples.split(","), a.repeat)
    finally:
        if a.baseline:
            subprocess.run(["git", "-C", str(ROOT), "worktree", "remove", "--force",
                            str(sources[a.baseline[:10]])])


if __name__ == "__main__":
    main()
