"""Conformance of millpath's interpreter with LinuxCNC's rs274 on LinuxCNC's own programs.

Runs every ``*.ngc`` under ``../shared/linuxcnc`` (or ``--root``) through both
interpreters (with the ``test.tbl`` beside it when there is one, else tools 1-99 of
diameter 0.05 + 0.005 n in; tool tables in inches, as rs274 reads them) and prints a
table: programs, identical (same motion within 1e-4), errors matched (both fail on
the same block), different, and skipped
(with the reason: features outside millpath's RS274NGC subset).

    python bench/conformance.py [--root DIR] [--show N] [--jobs N]
"""

from __future__ import annotations

import argparse
import re
import sys
from collections import Counter
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "tests"))          # support.difftest

# (reason, pattern on the lowercased text without comments)
SKIP_RULES = [
    ("o-word calls to subroutine files, M98/M99", re.compile(r"m\s*9[89](?![\d])")),
    ("threading, probing, lathe or tapping cycles (G33 G38 G7 G8 G70-G76 G84 G86-G88)",
     re.compile(r"g\s*0*(33|38|7|8|70|71|72|73\.|74|76|84|86|87|88)(?![\d])")),
    ("G10 L0 or planes G17.1-G19.1",
     re.compile(r"g\s*10[^\n]*l\s*0(?![\d])|g\s*1[789]\s*\.\s*1")),
    ("I/O, M19, M70-M73, M98/M99, user M codes",
     re.compile(r"m\s*0*(19|6[2-8]|7[0-3]|9[89]|1\d\d)(?![\d])")),
    ("system / read-only named parameters", re.compile(r"#\s*<\s*_")),
]
def _default_tools():
    """Tools 1-99 (inches) for programs that come without a table: D 0.05-0.54, Z 0.1 n."""
    from millpath.io.tooltable import ToolEntry
    return [ToolEntry(n, n, round(0.045 + 0.005 * n, 4), {"Z": round(0.1 * n, 4)})
            for n in range(1, 100)]


DEFAULT_TOOLS = _default_tools()
COMMENT = re.compile(r"\([^)\n]*\)|;[^\n]*")


def skip_reason(path: Path, text: str) -> str | None:
    if list(path.parent.glob("*.ini")):
        return "needs an INI file (remaps, features)"
    tbl = path.parent / "test.tbl"
    if tbl.is_file() and re.search(r"\bQ\s*[1-9]", tbl.read_text(errors="replace")):
        return "lathe tool orientations (tool table Q1-Q9)"
    low = COMMENT.sub("", text.lower())
    called = set(re.findall(r"o\s*(<[^>]*>|\d+)\s*call", low))
    defined = set(re.findall(r"o\s*(<[^>]*>|\d+)\s*sub", low))
    if called - defined:
        return "o-word calls to subroutines in other files"
    for reason, pat in SKIP_RULES:
        if pat.search(low):
            return reason
    return None


def check_one(path_str: str) -> tuple[str, str, str]:
    """Return (path, outcome, detail): outcome identical|errors matched|different|skipped."""
    from support.difftest import compare_results
    from millpath.interpret import run
    from support.rs274 import run_rs274

    path = Path(path_str)
    text = path.read_text(errors="replace")
    reason = skip_reason(path, text)
    if reason:
        return path_str, "skipped", reason
    tbl = path.parent / "test.tbl"
    tools = tbl if tbl.is_file() else DEFAULT_TOOLS
    try:
        ours = run(text, tools, machine_units="inch")
    except Exception as e:                      # noqa: BLE001 - report, do not stop
        return path_str, "different", f"millpath raised {type(e).__name__}: {e}"
    try:
        theirs = run_rs274(text, tools, table_units="inch", timeout=300)
    except Exception as e:                      # noqa: BLE001
        return path_str, "skipped", f"rs274 failed to run: {type(e).__name__}"
    c = compare_results(text, ours, theirs)
    oe = c.ours_error
    if not c.same:
        return path_str, "different", c.diffs[0]
    if oe:
        return path_str, "errors matched", f"line {oe[0]}: {oe[1]}"
    return path_str, "identical", f"{len(ours.motions)} moves"


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--root", type=Path, default=ROOT.parent / "shared" / "linuxcnc")
    ap.add_argument("--show", type=int, default=40, help="list this many differences")
    ap.add_argument("--jobs", type=int, default=2)
    ns = ap.parse_args()
    if not ns.root.is_dir():
        sys.exit(f"no LinuxCNC programs at {ns.root}")
    paths = sorted(str(p) for p in ns.root.rglob("*.ngc"))
    with ProcessPoolExecutor(max_workers=ns.jobs) as ex:
        results = list(ex.map(check_one, paths, chunksize=4))
    counts = Counter(r[1] for r in results)
    reasons = Counter(r[2] for r in results if r[1] == "skipped")
    compared = len(results) - counts["skipped"]
    print(f"{'programs':>9} {'compared':>9} {'identical':>10} {'errors matched':>15} "
          f"{'different':>10} {'skipped':>8}")
    print(f"{len(results):>9} {compared:>9} {counts['identical']:>10} "
          f"{counts['errors matched']:>15} {counts['different']:>10} {counts['skipped']:>8}")
    print("\nskipped:")
    for reason, n in reasons.most_common():
        print(f"  {n:4d}  {reason}")
    diff = [r for r in results if r[1] == "different"]
    if diff:
        print(f"\ndifferent ({len(diff)}):")
        for p, _, detail in diff[:ns.show]:
            print(f"  {Path(p).relative_to(ns.root)}: {detail[:160]}")
    matched = [r for r in results if r[1] == "errors matched"]
    if matched:
        print(f"\nerrors matched ({len(matched)}):")
        for p, _, detail in matched[:ns.show]:
            print(f"  {Path(p).relative_to(ns.root)}: {detail[:120]}")


if __name__ == "__main__":
    main()
