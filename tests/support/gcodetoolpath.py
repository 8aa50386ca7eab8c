"""The npm package ``gcode-toolpath`` (the G-code reader behind the cncjs GRBL sender),
run with node, as an independent reader of GRBL programs.

:func:`their_moves` gives its straight moves and arcs in order: kind ("G0", "G1", "G2",
"G3"), end point and, for arcs, the plane and the centre, in mm in program coordinates.
:func:`compare` sets millpath's interpretation beside them: the same kinds and end points
and arc centres (in the arc's plane) within ``tol`` mm. Moves of no length are left out
on both sides (the package reports a block without axis words as one).
"""

from __future__ import annotations

import json
import os
import shutil
import subprocess
from pathlib import Path

from millpath.model.units import length_scale

VERSION = "3.0.0"
_SCRIPT = r"""
const Toolpath = require('gcode-toolpath');
const text = require('fs').readFileSync(0, 'utf8');
const out = [];
const tp = new Toolpath({
  addLine: (m, a, b) => out.push({k: m.motion, e: [b.x, b.y, b.z]}),
  addArcCurve: (m, a, b, c) => out.push({k: m.motion, p: m.plane, e: [b.x, b.y, b.z],
                                         c: [c.x, c.y, c.z]}),
});
tp.loadFromStringSync(text);
process.stdout.write(JSON.stringify(out));
"""
#: the package permutes each plane's axes to (first, second, normal)
_UNPERMUTE = {"G17": (0, 1, 2), "G18": (1, 2, 0), "G19": (2, 0, 1)}
_IN_PLANE = {"G17": (0, 1), "G18": (2, 0), "G19": (1, 2)}
_KIND = {"traverse": "G0", "feed": "G1"}


def install(cache: Path) -> Path | None:
    """The folder holding node_modules/gcode-toolpath (installed with npm on first use),
    or None when node or npm is missing or the install fails."""
    if shutil.which("node") is None or shutil.which("npm") is None:
        return None
    cache.mkdir(parents=True, exist_ok=True)
    if not (cache / "node_modules" / "gcode-toolpath" / "package.json").exists():
        p = subprocess.run(["npm", "install", "--no-audit", "--no-fund", "--prefix",
                            str(cache), f"gcode-toolpath@{VERSION}"],
                           capture_output=True, text=True, timeout=300)
        if p.returncode != 0:
            return None
    (cache / "read.js").write_text(_SCRIPT)
    return cache


def their_moves(home: Path, program: str) -> list[tuple]:
    """(kind, end, plane, centre) of each move the package reports, in mm."""
    p = subprocess.run(["node", str(home / "read.js")], input=program, capture_output=True,
                       text=True, timeout=600, cwd=home,
                       env=dict(os.environ, NODE_PATH=str(home / "node_modules")))
    if p.returncode != 0:
        raise RuntimeError(f"gcode-toolpath failed: {p.stderr.strip()[:500]}")
    out = []
    for r in json.loads(p.stdout):
        plane = r.get("p", "G17")
        ix = _UNPERMUTE[plane]
        end = tuple(float(r["e"][ix[a]]) for a in range(3))
        centre = tuple(float(r["c"][ix[a]]) for a in range(3)) if "c" in r else None
        out.append((r["k"], end, plane, centre))
    return out


def our_moves(motions) -> list[tuple]:
    """millpath's interpreted motion in the same form (mm, program coordinates)."""
    out = []
    for m in motions:
        if m.kind not in ("traverse", "feed", "arc"):
            continue
        k = length_scale(m.frame.units, "mm") if m.frame is not None else 1.0
        end = tuple(v * k for v in m.end)
        if m.kind == "arc":
            plane = {"XY": "G17", "XZ": "G18", "YZ": "G19"}[m.plane]
            kind = "G2" if m.rotation < 0 else "G3"
            centre = tuple(v * k for v in m.center)
            out.append((kind, end, plane, centre))
        else:
            out.append((_KIND[m.kind], end, "G17", None))
    return out


def _moving(moves: list[tuple]) -> list[tuple]:
    """The moves that go somewhere (arcs always: a full circle ends where it starts)."""
    keep, last = [], None
    for mv in moves:
        if mv[0] in ("G2", "G3") or last is None or \
                max(abs(a - b) for a, b in zip(mv[1], last)) > 1e-9:
            keep.append(mv)
        last = mv[1]
    return keep


def compare(ours: list[tuple], theirs: list[tuple], tol: float) -> list[str]:
    """Differences between two move lists (empty: the same motion within ``tol`` mm)."""
    a, b = _moving(ours), _moving(theirs)
    diffs = []
    if len(a) != len(b):
        diffs.append(f"{len(a)} moves against gcode-toolpath's {len(b)}")
    for i, (x, y) in enumerate(zip(a, b)):
        if x[0] != y[0]:
            diffs.append(f"move {i}: {x[0]} against {y[0]}")
        elif max(abs(p - q) for p, q in zip(x[1], y[1])) > tol:
            diffs.append(f"move {i} ({x[0]}): end {x[1]} against {y[1]}")
        elif x[3] is not None:
            if x[2] != y[2]:
                diffs.append(f"move {i}: plane {x[2]} against {y[2]}")
            elif max(abs(x[3][j] - y[3][j]) for j in _IN_PLANE[x[2]]) > tol:
                diffs.append(f"move {i} ({x[0]}): centre {x[3]} against {y[3]}")
        if len(diffs) > 10:
            break
    return diffs
