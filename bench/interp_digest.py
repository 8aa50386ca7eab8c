"""Before/after check of the interpreter's motion: a SHA-256 digest of every motion
record (the packed bytes of :class:`millpath.interpret.store.MotionList`, states and
curve controls) of generated programs, to compare two versions of the interpreter
byte for byte (a faster interpreter must not change any motion).

Programs (``--lines`` each, 100,000 by default; fixed seeds): ``comp-heavy``,
``comp-heavy-xz`` (the same in G18: X->Z, Y->X, I->K, J->I), ``comp-heavy-inch``
(G20, coordinates / 25.4: it stops at a gouge error on line 115, rs274 2.9's
tighter arc check in inch programs), ``free-order``, ``own-post`` (and its XZ and inch
variants) and ``all-comp-lines`` (bench/programs.py, bench/interp_speed.py).

    python bench/interp_digest.py [--lines N] [--ngc DIR] > before.txt
    ... change the interpreter ...
    python bench/interp_digest.py [--lines N] --against before.txt
"""

from __future__ import annotations

import argparse
import hashlib
import re
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from interp_speed import generate, generate_comp  # noqa: E402
from programs import TOOL_TABLE, comp_heavy, free_order  # noqa: E402

from millpath.interpret import run  # noqa: E402
from millpath.io.tooltable import parse_tool_table  # noqa: E402


def to_xz(text: str) -> str:
    """comp_heavy in the XZ plane: (first, second) = (Z, X) takes the place of (X, Y)."""
    swap = {"X": "Z", "Y": "X", "Z": "Y", "I": "K", "J": "I"}
    text = text.replace("G17", "G18")
    return re.sub(r"(?<![A-Z])([XYZIJ])(?=[-\d.])", lambda m: swap[m.group(1)], text)


def to_inch(text: str) -> str:
    """The program in inches: G21 -> G20, lengths and feeds / 25.4."""
    text = text.replace("G21", "G20")
    return re.sub(r"([XYZIJKRF])(-?\d+(?:\.\d*)?)",
                  lambda m: f"{m.group(1)}{float(m.group(2)) / 25.4:.10f}", text)


def programs(n: int) -> dict[str, str]:
    heavy = comp_heavy(n)
    own = generate(n)
    return {"comp-heavy": heavy, "comp-heavy-xz": to_xz(heavy),
            "comp-heavy-inch": to_inch(heavy), "free-order": free_order(n),
            "own-post": own, "own-post-xz": to_xz(own), "own-post-inch": to_inch(own),
            "all-comp-lines": generate_comp(n)}


def digest(text: str, tools) -> str:
    h = hashlib.sha256()

    def sink(arrays, states, controls):
        for key in sorted(arrays):
            h.update(arrays[key].tobytes())
        h.update(repr(sorted(controls.items())).encode())

    res = run(text, tools, machine_units="inch", sink=sink)
    m = res.motions
    m.flush(force=True)
    h.update(repr(m.states).encode())
    h.update(repr(res.error.__dict__ if res.error else None).encode())
    return f"{h.hexdigest()} {len(m)} motions, error {res.error}"


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--lines", type=int, default=100_000)
    ap.add_argument("--ngc", type=Path, action="append", default=[],
                    help="also every *.ngc under this folder (tool table TOOL_TABLE)")
    ap.add_argument("--against", type=Path, help="digests printed by an earlier run")
    ns = ap.parse_args()
    tools = parse_tool_table(TOOL_TABLE)
    lines = []
    for name, text in programs(ns.lines).items():
        lines.append(f"{name} {ns.lines}: {digest(text, tools)}")
        print(lines[-1], flush=True)
    for root in ns.ngc:
        for path in sorted(root.rglob("*.ngc")):
            text = path.read_text(encoding="utf-8", errors="replace")
            lines.append(f"{path.relative_to(root)}: {digest(text, tools)}")
            print(lines[-1], flush=True)
    print(f"{len(lines)} digests", flush=True)
    if ns.against:
        before = ns.against.read_text().split("\n")
        diff = [s for s in lines if s not in before]
        print("identical" if not diff else f"DIFFERENT: {len(diff)} programs")
        sys.exit(1 if diff else 0)


if __name__ == "__main__":
    main()
