"""A fixed-seed sample of ``bench/fuzz.py`` on every run: each reader and command gets
its seeds (one case of each class of bad input found so far) and a few drawn cases, in
a worker limited to 1 GB, as the timed fuzzing runs them. No case may end in an
internal error, a message of several lines or naming something else than the input, a
signal, a hang or the memory limit. The interpreter's work limits are lowered for the
sample (the loop seeds reach them in milliseconds instead of seconds)."""

from __future__ import annotations

import importlib.util
import sys
from pathlib import Path

import pytest

BENCH = Path(__file__).resolve().parents[2] / "bench" / "fuzz.py"


def _bench():
    if "bench_fuzz" not in sys.modules:
        spec = importlib.util.spec_from_file_location("bench_fuzz", BENCH)
        mod = importlib.util.module_from_spec(spec)
        sys.modules["bench_fuzz"] = mod
        spec.loader.exec_module(mod)
    return sys.modules["bench_fuzz"]


#: run in a fresh interpreter: the fuzzer forks its worker, and a process whose numba
#: kernels already ran on GNU OpenMP threads (as a test worker's have) cannot fork
#: safely ("fork() called from a process already using GNU OpenMP"); the interpreter's
#: work limits are lowered there for the sample
SAMPLE = """
import importlib.util, json, sys
import millpath.interpret.cycles as cycles
import millpath.interpret.oword as oword
import millpath.interpret.runner as runner
oword.MAX_IDLE_ITERATIONS = 2_000
oword.MAX_LOOP_ITERATIONS = 20_000
oword.MAX_MOTIONS = 40_000
runner.MAX_FLOW_CHARS = 600_000
cycles.MAX_CYCLE_STEPS = 20_000
spec = importlib.util.spec_from_file_location("bench_fuzz", sys.argv[1])
fz = importlib.util.module_from_spec(spec)
sys.modules["bench_fuzz"] = fz
spec.loader.exec_module(fz)
name = sys.argv[2]
reader = fz.READERS[name]
n = 2 if reader.slow else 12
t = fz.fuzz(name, seed=0, cases=n, memory=1 << 30, hang=60.0, warm=False)
problems = [f"{site}\\n{data}\\n{tb[-1500:]}" for site, (tb, data) in t.crashes.items()]
problems += [f"hang: {d}" for d in t.hangs] + [f"over 1 GB: {d}" for d in t.memory]
print(json.dumps({"cases": t.cases, "expected": len(reader.seeds) + n,
                  "problems": problems}))
"""


@pytest.mark.parametrize("name", sorted(_bench().READERS))
def test_fuzz_sample(name):
    import json
    import subprocess
    if name == "solid":
        pytest.importorskip("OCP", reason="STEP solids need millpath[step-brep]")
    r = subprocess.run([sys.executable, "-c", SAMPLE, str(BENCH), name], capture_output=True,
                       text=True, timeout=1200)
    assert r.returncode == 0, r.stderr[-3000:]
    out = json.loads(r.stdout.strip().splitlines()[-1])
    assert out["cases"] == out["expected"]
    assert not out["problems"], "\n\n".join(out["problems"])
