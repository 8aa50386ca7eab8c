"""Differential testing against LinuxCNC's rs274: same motion, or an error on the same
block (test support: used by tests/ and bench/conformance.py).

Motion is compared move by move: same kinds (our ``cubic`` is rs274's ``nurbs``, whose
end point rs274 does not print), every end point and arc center within ``tol`` program
units, same turn counts. Dwells are not compared (rs274 does not report them as moves).
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field

from millpath.interpret import run

KINDS = ("traverse", "feed", "arc", "cubic", "nurbs")


@dataclass
class Comparison:
    same: bool
    diffs: list[str] = field(default_factory=list)
    ours_error: tuple[int, str] | None = None
    their_error: tuple[int | None, str] | None = None

    def __str__(self) -> str:
        lines = [f"ours error={self.ours_error} rs274 error={self.their_error}"]
        lines += self.diffs[:12]
        return "\n".join(lines)


def compare_motions(ours, theirs, tol: float = 1e-4) -> list[str]:
    """Differences between two motion sequences (ours first)."""
    a = [m for m in ours if m.kind in KINDS]
    b = [m for m in theirs if m.kind in KINDS]
    diffs = []
    if len(a) != len(b):
        diffs.append(f"motion count {len(a)} vs {len(b)}")
    for n, (x, y) in enumerate(zip(a, b)):
        kx = "nurbs" if x.kind == "cubic" else x.kind
        if kx != y.kind:
            diffs.append(f"#{n} line {x.line}: kind {x.kind} vs {y.kind}")
            break
        if y.kind == "nurbs":
            continue
        if max(abs(p - q) for p, q in zip(x.end, y.end)) > tol:
            diffs.append(f"#{n} line {x.line}: end {x.end} vs {y.end}")
        if x.kind == "arc":
            if y.center is None or max(abs(p - q) for p, q in zip(x.center, y.center)) > tol:
                diffs.append(f"#{n} line {x.line}: center {x.center} vs {y.center}")
            if x.rotation != y.rotation:
                diffs.append(f"#{n} line {x.line}: rotation {x.rotation} vs {y.rotation}")
        if len(diffs) > 20:
            break
    return diffs


def _norm_block(text: str) -> str:
    t = "".join(text.split()).lower()
    t = t.lstrip("/")
    return re.sub(r"^n\d+(\.\d*)?", "", t)


def same_block(program: str, line: int, rs274_block: str | None) -> bool:
    """Whether rs274's failing block text is our failing line ``line`` (1-based)."""
    if rs274_block is None:
        return False
    lines = program.splitlines()
    if not 1 <= line <= len(lines):
        return False
    return _norm_block(lines[line - 1]) == _norm_block(rs274_block)


def compare_results(program: str, ours, theirs, tol: float = 1e-4) -> Comparison:
    """Compare an InterpretResult with an Rs274Result for ``program``.

    Errors must be on the same block (compared by its text, since rs274 reports the
    block it failed on); motion is then compared up to that block (rs274 may print
    part of the failing block's motion before failing)."""
    oe = (ours.error.line, ours.error.message) if ours.error else None
    te = (theirs.error_line, theirs.error) if theirs.error else None
    a, b = list(ours.motions), theirs.motions
    diffs = []
    if (oe is None) != (te is None):
        diffs.append(f"error mismatch: ours {oe} vs rs274 {te}")
    elif oe and te:
        eof = theirs.error_block is None and te[1] == oe[1] and te[1].startswith("File ended")
        if not eof and not same_block(program, oe[0], theirs.error_block):
            diffs.append(f"error block mismatch: ours {oe} vs rs274 {te} "
                         f"block {theirs.error_block!r}")
        a = [m for m in a if m.line < oe[0]]
        b = [m for m in b if m.kind in KINDS][:len([m for m in a if m.kind in KINDS])]
    diffs += compare_motions(a, b, tol)
    return Comparison(not diffs, diffs, oe, te)


def differential(program: str, tools=None, *, machine_units: str = "inch",
                 tol: float = 1e-4) -> Comparison:
    """Run our interpreter and rs274 on ``program``; tool values in ``machine_units``."""
    from support.rs274 import run_rs274
    ours = run(program, tools, machine_units=machine_units)
    theirs = run_rs274(program, tools, table_units=machine_units)
    return compare_results(program, ours, theirs, tol)
