"""The safety gate: turn a run's report into the problems that forbid writing the program.

A program is refused (no ``program.ngc``) when the simulation of its interpreted motion
found any of:

- a holder or shank contact (the tool would be buried above its flutes),
- a rapid through material,
- a gouge deeper than the tolerance of the operation that cut it (plus the job's fit
  tolerance when arcs/cubics were fitted),
- a feature that was asked for and is not machined (``features.unmachinable``), unless
  the operation lists them on purpose (``unmachinable = "list"``).

Inputs are the report dict the pipeline builds (``verification`` keys of the
simulator; when present the exact keys ``by_operation`` and ``max_gouge_at``) plus,
as fallback for older simulators, the per-motion program lines of holder contacts and
rapids. Lengths are in the job's units.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass, field
from typing import Any, Callable, Sequence

from millpath.errors import MillpathError

#: problem kinds from the worst down: a crash before a scrapped part
KINDS = ("holder contact", "rapid through material", "gouge", "feature not machined")
PLURAL = {"holder contact": "holder contacts", "rapid through material":
          "rapids through material", "gouge": "gouges",
          "feature not machined": "features not machined"}


def counted(kind: str, n: int) -> str:
    """'1 holder contact', '2 rapids through material'."""
    return f"{n} {kind if n == 1 else PLURAL[kind]}"


@dataclass
class Problem:
    """One reason not to run the program. ``line`` is the 1-based program line,
    ``operation`` the 0-based index into the toolpath's operations."""

    kind: str
    count: int
    detail: str
    line: int | None = None
    operation: int | None = None
    operation_name: str = ""
    at: tuple[float, float, float] | None = None
    excess: float = 0.0               # gouge: depth / tolerance (ranking within the kind)

    def text(self) -> str:
        """One line: what, how many, where, program line, operation."""
        s = "gouge" if self.kind == "gouge" else counted(self.kind, self.count)
        s += f": {self.detail}" if self.detail else ""
        if self.at is not None:
            s += " at " + " ".join(f"{a}{v:.4g}" for a, v in zip("XYZ", self.at)
                                   if v is not None and v == v)
        if self.line is not None:
            s += f", program line {self.line}"
        if self.operation is not None:
            s += f", operation {self.operation + 1}"
            if self.operation_name:
                s += f" ({self.operation_name})"
        return s

    def to_json(self) -> dict[str, Any]:
        d = asdict(self)
        d["text"] = self.text()
        return d


@dataclass
class GateInput:
    """What the gate needs besides the report: per-operation tolerances and names, a
    program line -> operation map, a line -> tool position map and the fallback
    per-motion lines of the simulator."""

    op_names: list[str]
    op_tolerances: list[float | None]
    fit_tolerance: float = 0.0
    op_of_line: Callable[[int], int | None] = lambda line: None
    position_of_line: Callable[[int], tuple[float, float, float] | None] = lambda line: None
    holder_lines: Sequence[int] = field(default_factory=list)
    rapid_lines: Sequence[int] = field(default_factory=list)
    gouge_xy: tuple[float, float] | None = None


def _name(g: GateInput, op: int | None) -> str:
    return g.op_names[op] if op is not None and 0 <= op < len(g.op_names) else ""


def _allowed(g: GateInput, op: int | None) -> float:
    """Gouge allowed under operation ``op`` (None: the strictest operation)."""
    tols = [t for t in g.op_tolerances if t is not None]
    if op is not None and 0 <= op < len(g.op_tolerances) and g.op_tolerances[op] is not None:
        t = g.op_tolerances[op]
    else:
        t = min(tols) if tols else 0.0
    return float(t) + g.fit_tolerance


def _contacts(kind: str, key: str, lines: Sequence[int], ver: dict, g: GateInput) -> Problem | None:
    count = int(ver.get(key) or 0)
    if count <= 0:
        return None
    line = min(lines) if lines else None
    op = g.op_of_line(line) if line is not None else None
    if op is None and isinstance(ver.get("by_operation"), list):
        for o in ver["by_operation"]:
            if int(o.get(key) or 0) > 0:
                op = int(o["operation"])
                break
    where = "first" if count > 1 else ""
    return Problem(kind, count, where, line, op, _name(g, op),
                   g.position_of_line(line) if line is not None else None)


def _gouges(ver: dict, g: GateInput) -> list[Problem]:
    out = []
    by_op = ver.get("by_operation")
    at = ver.get("max_gouge_at") or {}
    if isinstance(by_op, list) and any(o.get("max_gouge") is not None for o in by_op):
        for o in by_op:
            op = int(o["operation"])
            depth = o.get("max_gouge")
            if depth is None:
                continue
            allowed = _allowed(g, op)
            if depth > allowed + 1e-9:
                n = int(o.get("gouging_moves") or 1)
                pos = line = None
                if at and at.get("operation") == op:
                    pos = (at.get("x"), at.get("y"), at.get("z"))
                    line = at.get("line")
                out.append(Problem("gouge", n, f"{depth:.4g} deep, tolerance {allowed:.4g}",
                                   line, op, _name(g, op), pos, depth / max(allowed, 1e-12)))
        return out
    depth = ver.get("max_gouge")
    if depth is None:
        return out
    op = at.get("operation") if at else None
    allowed = _allowed(g, op)
    if depth > allowed + 1e-9:
        line = at.get("line") if at else None
        pos = (at.get("x"), at.get("y"), at.get("z")) if at else None
        if pos is None and g.gouge_xy is not None:
            pos = (g.gouge_xy[0], g.gouge_xy[1], float("nan"))
        n = int(ver.get("gouging_moves") or 1)
        out.append(Problem("gouge", n, f"{depth:.4g} deep, tolerance {allowed:.4g}", line, op,
                           _name(g, op), pos, depth / max(allowed, 1e-12)))
    return out


def _unmachined(report: dict) -> list[Problem]:
    """The features no operation of the run could machine (each plan's ``features``
    section of report.json)."""
    left = [f for p in report.get("plans", []) if isinstance(p.get("features"), dict)
            and p["features"].get("unmachinable_policy", "refuse") == "refuse"
            for f in p["features"].get("unmachinable") or []]
    if not left:
        return []
    first = left[0]
    what = f"{first.get('type', 'feature')} #{first.get('id')}"
    reason = first.get("reason") or first.get("kind") or ""
    detail = f"{what}" + (f" ({reason})" if reason else "")
    if len(left) > 1:
        detail = "first " + detail
    detail += (f"; add a tool that can machine it, leave it out with exclude = "
               f"[{first.get('id')}], or write the rest with unmachinable = \"list\"")
    return [Problem("feature not machined", len(left), detail)]


def find_problems(report: dict, g: GateInput) -> list[Problem]:
    """Every problem of the run, the worst first (see :data:`KINDS`)."""
    ver = report.get("verification") or {}
    probs: list[Problem] = []
    for kind, key, lines in (("holder contact", "holder_contacts", g.holder_lines),
                             ("rapid through material", "rapids_through_material",
                              g.rapid_lines)):
        p = _contacts(kind, key, lines, ver, g)
        if p:
            probs.append(p)
    probs += sorted(_gouges(ver, g), key=lambda p: -p.excess)
    probs += _unmachined(report)
    probs.sort(key=lambda p: KINDS.index(p.kind))
    return probs


def summary(problems: list[Problem]) -> str:
    """One line: the worst problem in full, then how many other kinds there are."""
    if not problems:
        return "no problems"
    s = problems[0].text()
    rest = problems[1:]
    if rest:
        s += "; also " + ", ".join(
            counted(p.kind, p.count) if p.kind != "gouge" else f"gouge {p.detail}"
            for p in rest)
    return s


def comment_block(problems: list[Problem]) -> str:
    """RS274NGC comment lines listing the problems (for ``program.unsafe.ngc``)."""
    lines = ["(UNSAFE PROGRAM: written with --force although the simulation found:)"]
    for p in problems:
        lines.append("(- " + p.text().replace("(", "[").replace(")", "]") + ")")
    lines.append("(DO NOT RUN THIS PROGRAM UNATTENDED)")
    return "\n".join(lines) + "\n"


def position_map(motions) -> Callable[[int], tuple[float, float, float] | None]:
    """A function program line -> tool tip at the end of the first motion of that line."""
    ends: dict[int, tuple[float, float, float]] = {}
    for m in motions:
        ends.setdefault(m.line, tuple(float(v) for v in m.end))
    return ends.get


class UnsafeProgramError(MillpathError):
    """The simulation found problems: no program was written (report and pictures were).
    ``report`` is the run's report, ``problems`` the list, worst first."""

    def __init__(self, message: str, file=None, report: dict | None = None,
                 problems: list[Problem] | None = None):
        super().__init__(message, file)
        self.report = report or {}
        self.problems = problems or []
