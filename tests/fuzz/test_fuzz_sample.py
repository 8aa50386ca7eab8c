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


@pytest.fixture
def small_limits(monkeypatch):
    import millpath.interpret.cycles as cycles
    import millpath.interpret.oword as oword
    import millpath.interpret.runner as runner
    monkeypatch.setattr(oword, "MAX_IDLE_ITERATIONS", 2_000)
    monkeypatch.setattr(oword, "MAX_LOOP_ITERATIONS", 20_000)
    monkeypatch.setattr(oword, "MAX_MOTIONS", 40_000)
    monkeypatch.setattr(runner, "MAX_FLOW_LINES", 30_000)
    monkeypatch.setattr(cycles, "MAX_CYCLE_STEPS", 20_000)


@pytest.mark.parametrize("name", sorted(_bench().READERS))
def test_fuzz_sample(name, small_limits):
    fz = _bench()
    reader = fz.READERS[name]
    if name == "solid":
        pytest.importorskip("OCP", reason="STEP solids need millpath[step-brep]")
    t = fz.fuzz(name, seed=0, cases=2 if reader.slow else 12, memory=1 << 30, hang=60.0,
                warm=False)
    assert t.cases == len(reader.seeds) + (2 if reader.slow else 12)
    problems = [f"{site}\n{data}\n{tb[-1500:]}" for site, (tb, data) in t.crashes.items()]
    problems += [f"hang: {d}" for d in t.hangs] + [f"over 1 GB: {d}" for d in t.memory]
    assert not problems, "\n\n".join(problems)
