"""The benchmark's generated programs (bench/programs.py: free word order and case,
compensation-heavy, millpath's own post shape) give the same motion as LinuxCNC's
rs274, move by move within rs274's printed precision (1e-4)."""

from __future__ import annotations

import importlib.util
from pathlib import Path

import pytest

from support.difftest import differential
from millpath.io.tooltable import parse_tool_table

BENCH = Path(__file__).resolve().parents[2] / "bench"


def _load(name: str):
    spec = importlib.util.spec_from_file_location(f"bench_{name}", BENCH / f"{name}.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


programs = _load("programs")


@pytest.mark.parametrize("kind,seed", [("free_order", 11), ("free_order", 12),
                                       ("comp_heavy", 13), ("comp_heavy", 14)])
def test_benchmark_program_same_as_rs274(rs274, kind, seed):
    text = getattr(programs, kind)(3000, seed=seed)
    tools = parse_tool_table(programs.TOOL_TABLE)
    c = differential(text, tools, machine_units="inch")
    assert c.ours_error is None and c.their_error is None, str(c)
    assert c.same, str(c)


def test_free_order_program_uses_free_order():
    """The generator really writes words out of order, in both cases, with R and I/J
    arcs, modal moves and canned cycles."""
    text = programs.free_order(3000)
    lines = text.splitlines()
    assert any(s[:1] in "XYxy" for s in lines)                 # modal moves
    assert any("r" in s.lower() and "g2" in s.lower().replace(" ", "") for s in lines)
    assert any("i" in s.lower() and "j" in s.lower() for s in lines)
    assert any("G81" in s or "G83" in s for s in lines)
    assert any(s.lower().index("x") < s.lower().find("g") for s in lines if "g" in s.lower()
               and "x" in s.lower() and "(" not in s)
    assert any(c.islower() for c in text) and any(c.isupper() for c in text)


def test_comp_heavy_program_is_mostly_compensated_arcs():
    text = programs.comp_heavy(3000)
    moves = [s for s in text.splitlines() if s[:2] in ("G1", "G2", "G3")]
    arcs = [s for s in moves if s[:2] in ("G2", "G3")]
    assert 0.40 <= len(arcs) / len(moves) <= 0.50
