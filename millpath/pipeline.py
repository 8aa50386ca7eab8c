"""Run a job: plan -> fit -> post -> interpret -> simulate -> report.

The program is written only if it interprets cleanly with millpath's own interpreter
(machine units = the job's units, tool table = the job's tools) and the interpreted
motion gives back the planned toolpath. All files of a run are written atomically:
after an error nothing in the output folder has changed.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any

import numpy as np

from millpath.errors import MillpathError, PlanningError, warn
from millpath.io.atomic import staged_dir
from millpath.io.tomllines import place
from millpath.io.tooltable import parse_tool_table, tool_table_text
from millpath.job.jobfile import Job, load_job
from millpath.model import Stock, Toolpath
from millpath.plan.base import PlanContext, PlanResult
from millpath.plan.registry import strategy
from millpath.program import LineMap, Program, make_program
from millpath.progress import QUIET, Progress
from millpath.model.units import default, length_scale


class MinDesign:
    """The part after several operations: the lowest of their designs at each point.
    Where every one of them designs nothing (their ``waste``, as a profile's scrap), the
    part designs nothing either."""

    def __init__(self, designs: list[Any]):
        self.designs = designs
        if all(hasattr(d, "waste") for d in designs):
            self.waste = self._waste

    def _waste(self, x: np.ndarray, y: np.ndarray) -> np.ndarray:
        w = np.asarray(self.designs[0].waste(x, y), bool)
        for d in self.designs[1:]:
            w = w & d.waste(x, y)
        return w

    def height(self, x: np.ndarray, y: np.ndarray) -> np.ndarray:
        z = np.asarray(self.designs[0].height(x, y), dtype=float)
        for d in self.designs[1:]:
            z = np.minimum(z, d.height(x, y))
        return z


@dataclass
class RunResult:
    job: Job
    toolpath: Toolpath
    program: str
    report: dict[str, Any]
    files: list[Path] = field(default_factory=list)
    seconds: float = 0.0


def plan_job(job: Job, progress: Progress = QUIET) -> tuple[Toolpath, list[PlanResult], Stock]:
    """Plan every operation of ``job`` and join their toolpaths in order. Jobs with a
    pocket or profile operation or a ``rest`` key carry the in-process stock from
    operation to operation (``ctx.remaining``, see :func:`advance_stock`). An error
    naming a key of the job file is given that key's line."""
    try:
        return _plan_all(job, progress)
    except MillpathError as e:
        if e.line is None and job.path is not None and e.file == str(job.path):
            raise place(e, Path(job.path).read_text()) from None
        raise


def _plan_all(job: Job, progress: Progress) -> tuple[Toolpath, list[PlanResult], Stock]:
    ctx = PlanContext(units=job.units, stock=job.stock, machine=job.machine, tools=job.tools,
                      base_dir=job.base_dir, job_file=job.path, progress=progress)
    carry = any(t in ("pocket", "profile") or p.get("rest") for t, p in job.operations)
    total = Toolpath(job.units)
    results: list[PlanResult] = []
    for i, (op_type, params) in enumerate(job.operations):
        check = getattr(strategy(op_type, f"operations[{i}]", job.path), "preflight", None)
        if check is not None:          # refuse an impossible request before any work
            check(ctx, params)
    with progress.task("planning operations", total=len(job.operations)) as bar:
        for i, (op_type, params) in enumerate(job.operations):
            bar.update(info=f"{i + 1}: {op_type}")
            res = _plan_one(job, ctx, i, op_type, params, carry)
            total.extend(res.toolpath)
            results.append(res)
            bar.advance()
    stock = job.stock or ctx.stock
    if stock is None:
        raise MillpathError("stock: the job gives no [stock] box and no operation implies one",
                            job.path)
    from millpath.plan.sense import check_operation
    for i, r in enumerate(results):
        check_operation(f"operations[{i}]", r.toolpath, stock, job.tools, job.path)
    if not total.moves:
        raise PlanningError("the job's operations produced no moves", job.path)
    return total, results, stock


def _plan_one(job: Job, ctx: PlanContext, i: int, op_type: str, params: dict,
              carry: bool) -> PlanResult:
    """Plan operation ``i`` (and sweep it into the in-process stock when ``carry``)."""
    if params.get("rest") and ctx.remaining is None:
        warn(f"operations[{i}]: rest = true, but no earlier operation has cut the stock; "
             "the whole operation is planned", job.path)
    res = strategy(op_type, f"operations[{i}]", job.path).plan(ctx, params)
    if res.toolpath.units != job.units:
        raise PlanningError(f"operations[{i}]: strategy returned {res.toolpath.units} "
                            f"moves for a {job.units} job", job.path)
    if ctx.stock is None and res.stock is not None:
        ctx.stock = res.stock
    try:
        res.toolpath.check_finite()
    except ValueError as e:
        raise PlanningError(f"operations[{i}]: {e}", job.path) from None
    if carry and ctx.stock is not None:
        from millpath.interpret import InterpreterError
        try:
            ctx.remaining = advance_stock(job, ctx.stock, ctx.remaining, res.toolpath)
        except InterpreterError as e:     # the operation's program, as the control reads it
            raise MillpathError(f"operations[{i}]: the generated program does not interpret: "
                                f"line {e.line}: {e.message}", job.path) from None
    return res


def advance_stock(job: Job, stock: Stock, remaining, tp: Toolpath):
    """Sweep one operation's toolpath into the in-process stock (created on first use,
    cells a 40th of the smallest tool diameter, at most about 4 million) and store
    what it measured (air cuts, engagement) in each of its operations' ``info``."""
    from millpath.simulate.inprocess import InProcessStock
    if remaining is None:
        d = min((t.diameter for t in job.tools.values()), default=1.0)
        w, h, _ = stock.size
        res = max(d / 40.0, math.sqrt(w * h / 4e6))
        if job.simulation.get("resolution"):
            res = min(res, float(job.simulation["resolution"]))
        remaining = InProcessStock(stock, res)
    if any(m.kind == "comp" for m in tp.moves):
        from millpath.interpret import interpret
        from millpath.simulate.tip import tip_motions
        written = make_program(tp, job.tools, title="in-process stock")
        motions = tip_motions(interpret(written.text, job.tools, machine_units=job.units,
                                        dialect=written.dialect), job.units)
        src = written.lines.moves_of(motions).tolist()
    else:
        from millpath.simulate.path import toolpath_motions
        motions, src = toolpath_motions(tp)
    entry = np.zeros(len(tp.moves) + 1, bool)
    for op_i, op in enumerate(tp.ops):
        for a, b in op.info.get("entry_moves", []):
            entry[a:b] = True
    stats = remaining.cut(motions, [tp.moves[k].op for k in src], [bool(entry[k]) for k in src],
                          job.tools, job.machine, len(tp.ops))
    for op, st in zip(tp.ops, stats):
        op.info["in_process"] = st.to_json()
    return remaining


def fit_job(job: Job, tp: Toolpath) -> Toolpath:
    """The tool path with arcs/cubics fitted as the job asks; for fit = none, collinear
    points merged within the fit tolerance."""
    if job.fit == "none":
        from millpath.fit.collinear import merge_collinear
        return merge_collinear(tp, job.fit_tolerance)
    from millpath.fit import fit_toolpath
    radius = max((job.tools[o.tool].radius for o in tp.ops if o.tool in job.tools), default=0.0)
    return fit_toolpath(tp, job.fit_tolerance, job.fit, min_radius=radius)


def for_control(job: Job) -> tuple[Job, list[str]]:
    """The job planned for its [post] dialect: operations that ask the control for cutter
    compensation are planned with millpath's own offset (``compensation = "cam"``) when
    the control has none. Returns the job and what was changed."""
    from millpath.model.dialect import dialect
    d = dialect(job.post.get("dialect", "linuxcnc"))
    if d.cutter_comp or not any(p.get("compensation") == "control" for _, p in job.operations):
        return job, []
    ops = [(t, {**p, "compensation": "cam"} if p.get("compensation") == "control" else p)
           for t, p in job.operations]
    return replace(job, operations=ops), [
        f"cutter compensation planned by millpath (compensation = \"cam\"): {d.title} "
        "has no G41/G42"]


def post_job(job: Job, tp: Toolpath, stock: Stock) -> Program:
    """The program in the dialect and with the options of the job's [post] table."""
    from millpath.post.writer import PostOptions
    title = f"{job.name}: {len(tp.ops)} operations, units {job.units}"
    try:
        return make_program(tp, job.tools, title=title, tolerance=job.fit_tolerance,
                            options=PostOptions(**job.post, safe_z=stock.zmax))
    except ValueError as e:
        raise PlanningError(f"cannot post the tool path: {e}", job.path) from None


def default_resolution(job: Job, stock: Stock, tp: Toolpath) -> float:
    """Simulation grid step: a tenth of the smallest tool diameter, but at most about
    1500 cells along the longest stock side (job units)."""
    if job.simulation.get("resolution"):
        return float(job.simulation["resolution"])
    d = min((job.tools[o.tool].diameter for o in tp.ops if o.tool in job.tools), default=1.0)
    return max(d / 10.0, max(stock.size[0], stock.size[1]) / 1500.0)


def run_job(job_path: str | Path, outdir: str | Path, *, progress: bool = False,
            force: bool = False, pictures: bool | None = None,
            dialect: str | None = None) -> RunResult:
    """Run the job file at ``job_path``, writing program.ngc, tools.tbl, report.json,
    preview.png, stock.png, deviation.png and view.html into ``outdir``.

    When the simulation finds a problem (see :mod:`millpath.verify.gate`) the report,
    pictures and viewer are written without the program and UnsafeProgramError is
    raised; with ``force`` the program is written as ``program.unsafe.ngc`` headed by
    the list of problems. ``progress``: bars on stderr for every stage. ``pictures``:
    draw the three PNGs (None: as the job's ``[simulation] pictures`` says, default
    true). ``dialect``: the control to write for, instead of the job's ``[post]
    dialect`` (the program is then ``program`` plus that dialect's extension, and
    tools.tbl is written only for a control with a tool table)."""
    prog = Progress(progress)
    with prog.session():
        return _run(job_path, outdir, prog, force, pictures, dialect)


def _run(job_path: str | Path, outdir: str | Path, prog: Progress, force: bool,
         pictures: bool | None = None, dialect: str | None = None) -> RunResult:
    t0 = time.perf_counter()
    with prog.task("reading the job", total=1) as bar:
        job = load_job(job_path)
        if dialect is not None:
            job = replace(job, post={**job.post, "dialect": dialect})
        job, replanned = for_control(job)
        bar.advance()
    tp, results, stock = plan_job(job, prog)
    with prog.task("fitting and posting", total=2) as bar:
        tp = fit_job(job, tp)
        bar.advance()
        posted_program = post_job(job, tp, stock)
        bar.advance()
    program, move_lines = posted_program.text, posted_program.move_lines
    tp = posted_program.toolpath        # as written: the dialect's rewrites in it
    d = posted_program.dialect

    from millpath.interpret import InterpreterError, interpret
    table = tool_table_text(job.tools, job.units, job.table_units)
    entries = parse_tool_table(table)
    try:        # the program as the machine will run it: with tools.tbl as written
        with prog.task("interpreting the program", total=1) as bar:
            motions = interpret(program, entries, machine_units=job.table_units, dialect=d)
            bar.advance()
    except InterpreterError as e:
        raise MillpathError(f"the generated program does not interpret: line {e.line}: "
                            f"{e.message}", job.path) from None
    from millpath.verify.roundtrip import compare_toolpath
    tol = default("roundtrip", job.units)
    scale = length_scale(job.table_units, job.units)
    radii = {e.number: e.diameter / 2 * scale for e in entries}
    diffs = compare_toolpath(tp, move_lines, motions, tol, radii)
    if diffs:
        raise MillpathError("interpreted program differs from the planned tool path: "
                            + diffs[0] + (f" (+{len(diffs) - 1} more)" if len(diffs) > 1 else ""),
                            job.path)

    designs = [r.design for r in results if r.design is not None]
    design = MinDesign(designs) if designs else None
    from millpath.report.document import OperationSection, PlanSection, RunReport
    report = RunReport(job=str(job.path) if job.path else None, name=job.name, units=job.units,
                       tool_table_units=job.table_units, program="program" + d.extension,
                       lines=program.count("\n"), bytes=len(program.encode()),
                       moves=tp.counts(), stock=list(stock.box),
                       fit={"mode": job.fit, "tolerance": job.fit_tolerance},
                       reference=job.reference or None,
                       post={"dialect": d.name, "control": d.title,
                             "rewritten": replanned + posted_program.fallbacks})
    from millpath.simulate import motion_times
    from millpath.simulate.approach import approach_from_above
    from millpath.simulate.tip import tip_motions
    # the proof follows the tool tip as the machine moves it: tool lengths, frames
    # (G92, G52, G10 L2 in a preamble), units switches
    motions = approach_from_above(tip_motions(motions, job.units), stock.zmax)
    times = motion_times(motions, job.machine)
    lmap = posted_program.lines
    motion_op = lmap.ops_of(motions)
    op_secs = np.bincount(motion_op, weights=times, minlength=len(tp.ops)).tolist()
    sim = None
    if job.simulation.get("enabled", True):
        from millpath.simulate import simulate_motions
        res = default_resolution(job, stock, tp)
        exact = bool(job.simulation.get("exact", True))
        user = job.simulation.get("design")
        refs = _references(job, results, stock, tp) if (exact or user) else None
        if user:
            from millpath.simulate import MeshDesign
            design = MeshDesign(refs[0].triangles)
        # chords of arcs within a tenth of the tightest tolerance: the measured gouge
        # must not carry the measurement's own chord error
        tols = [o.tolerance for o in tp.ops if o.tolerance]
        chord = min([res / 20.0] + [0.1 * t for t in tols])
        sim = simulate_motions(motions, job.tools, stock, resolution=res, design=design,
                               machine=job.machine, progress=prog, chord_tol=chord,
                               references=refs if exact else None,
                               motion_op=motion_op,
                               accuracy=_accuracy(job.units) if exact else None,
                               times=times)
        report.verification = sim.to_json({i: o.tolerance for i, o in enumerate(tp.ops)
                                           if o.tolerance})
    else:
        report.verification = {"skipped": "simulation disabled in the job"}
    report.cycle_time_s = float(np.sum(times))
    counts_by_op: dict[int, dict[str, int]] = {}
    for m in tp.moves:
        c = counts_by_op.setdefault(m.op, {"rapid": 0, "line": 0, "arc": 0, "cubic": 0,
                                          "drill": 0})
        if m.kind in c:
            c[m.kind] += 1
    op_lines = lmap.line_counts(report.lines, len(tp.ops))
    use = [None] * len(tp.ops)
    if sim is not None and sim.removes is not None:
        from millpath.simulate.airtime import time_use
        use = time_use(motions, times, sim.removes, motion_op, len(tp.ops))
    report.operations = [
        OperationSection(o.type, o.name, o.tool, o.spindle, counts_by_op.get(i, {}),
                         op_secs[i], o.info.get("in_process"), op_lines[i], use[i])
        for i, o in enumerate(tp.ops)]
    job_ops = [i for i, r in enumerate(results) for _ in r.toolpath.ops]
    _warn_time(job, report.operations, job_ops)
    report.plans = [PlanSection(i, op_type, r.report)
                    for i, ((op_type, _), r) in enumerate(zip(job.operations, results))]

    problems = _safety_gate(report.to_json(), job, tp, lmap, motions, sim)
    program_name = "program" + d.extension
    posted = program                  # as interpreted: the viewer's lines refer to it
    if problems:
        program, program_name = _unsafe_program(program, problems, force, d.extension)
    report.program = program_name if (force or not problems) else None
    report.safety = {"status": "ok" if not problems else ("forced" if force else "refused"),
                     "problems": [p.to_json() for p in problems]}

    draw = bool(job.simulation.get("pictures", True)) if pictures is None else pictures
    out = Path(outdir)
    files = []
    with staged_dir(out) as tmp, prog.task("rendering pictures and viewer", total=4) as bar:
        if force or not problems:
            (tmp / program_name).write_text(program)
            if d.tool_table:
                (tmp / d.tool_table).write_text(table)
        if draw:
            from millpath.report.preview import render_preview
            render_preview(tp, tmp / "preview.png", title=job.name, stock=stock)
        bar.advance()
        if draw and sim is not None:
            from millpath.simulate import render_deviation, render_stock
            render_stock(sim.zmap, tmp / "stock.png", units=job.units)
            if design is not None:
                ex = sim.exact
                render_deviation(sim.zmap, design, tmp / "deviation.png", units=job.units,
                                 tolerance=_accuracy(job.units),
                                 gouge_at=sim.gouge_at, left_at=sim.left_at,
                                 gouge=ex.max_gouge if ex else None,
                                 left=ex.max_left if ex else None, grid=sim.design_grid)
        bar.advance(2)
        from millpath.report.viewer import write_view
        write_view(tmp / "view.html", program=posted, motions=motions, tools=job.tools,
                   stock=stock, units=job.units, sim=sim, design=design, title=job.name,
                   toolpath=tp, move_lines=move_lines)
        bar.advance()
        from millpath.report.document import write_report
        report.seconds = time.perf_counter() - t0
        written = write_report(tmp / "report.json", report)
        files = [out / f.name for f in sorted(tmp.iterdir()) if not f.name.startswith(".")]
    if problems and not force:
        from millpath.verify.gate import UnsafeProgramError, summary
        raise UnsafeProgramError(f"program refused: {summary(problems)}; no "
                                 f"program{d.extension} written (report and pictures in "
                                 f"{out}; --force writes program.unsafe{d.extension})",
                                 job.path, written, problems)
    return RunResult(job, tp, program, written, files, time.perf_counter() - t0)


def _warn_time(job: Job, sections, job_ops: list[int]) -> None:
    """A warning for each operation feeding through air over a third of its time or
    running over two hours, at the line of the job's operation, naming its keys that
    change it."""
    from millpath.io.tomllines import key_lines, line_of
    from millpath.plan.registry import time_keys
    from millpath.simulate.airtime import time_note
    lines = None
    for k, sec in enumerate(sections):
        note = time_note(sec.to_json())
        if note is None or k >= len(job_ops):
            continue
        if lines is None:
            lines = key_lines(Path(job.path).read_text()) if job.path else {}
        text, air, long = note
        i = job_ops[k]
        op_type = job.operations[i][0]
        keys = time_keys(op_type, air=air, long=long)
        where = f"operations[{i}]"
        warn(f"{where} ({op_type}, {sec.name}): {text}"
             + (f"; {', '.join(keys)} change it" if keys else ""),
             job.path, line_of(where + ":", lines))


def _references(job: Job, results: list[PlanResult], stock: Stock, tp: Toolpath):
    """What gouge and material left are measured against: the job's ``[simulation]
    design`` (STL, STEP, Bezier net; all operations) when given, else each operation's
    own design, as triangles."""
    from millpath.simulate.exact import Reference, design_triangles, orient_outward
    spec = job.simulation.get("design")
    if spec:
        from millpath.part.surface.load import load_surface
        # a STEP design meshed within a quarter of the accuracy (its facets are the proof's)
        mesh = load_surface(str(spec), 64, job.base_dir, job.path, units=job.units,
                            chord_tolerance=_accuracy(job.units) / 4)
        tri = mesh.triangles
        lo, hi = tri.reshape(-1, 3).min(axis=0), tri.reshape(-1, 3).max(axis=0)
        b = stock.box
        if (hi[0] < b[0] or lo[0] > b[3] or hi[1] < b[1] or lo[1] > b[4]
                or hi[2] < b[2] or lo[2] > b[5]):
            raise MillpathError(f"simulation.design {spec}: the design lies wholly outside "
                                f"the stock (different units?)", job.path)
        return [Reference(orient_outward(tri), str(spec), None)]
    used = [job.tools[o.tool].radius for o in tp.ops if o.tool in job.tools]
    size = min(used + [max(stock.size[:2]) / 64]) / 2
    # a job operation's design applies to the tool path operations it planned (one per
    # tool of a features operation, ...): those numbers, not the job's, mark the motion
    first = np.cumsum([0] + [len(r.toolpath.ops) for r in results])
    # operations sharing one design (the same triangles) share one reference: the
    # material left on it is measured once
    found: list[tuple[np.ndarray, list[int], list[int], float | None]] = []
    for i, r in enumerate(results):
        if r.design is None:
            continue
        tri = design_triangles(r.design, stock, _accuracy(job.units), size)
        err = getattr(r.design, "chord_error", None)        # a B-rep meshed for the check
        ops = list(range(first[i], first[i + 1]))
        same = next((f for f in found if f[0].shape == tri.shape and f[3] == err
                     and np.array_equal(f[0], tri)), None)
        if same is None:
            found.append((tri, [i], ops, err))
        else:
            same[1].append(i)
            same[2].extend(ops)
    refs = []
    for tri, jobs_ops, ops, err in found:
        name = f"operations[{', '.join(str(i) for i in jobs_ops)}] design"
        if err is not None:
            name += f" (STEP solid, facets within {err:.2g} {job.units} of its faces)"
        refs.append(Reference(tri, name, ops))
    return refs


def _accuracy(units: str) -> float:
    """Bound on the verification's gouge / material-left figures (job units)."""
    return default("verify_accuracy", units)


def _safety_gate(report: dict, job: Job, tp: Toolpath, lmap: LineMap, motions,
                 sim) -> list:
    """Problems that forbid writing the program (millpath.verify.gate), worst first."""
    from millpath.verify.gate import GateInput, find_problems, position_map
    g = GateInput(op_names=[o.name for o in tp.ops],
                  op_tolerances=[o.tolerance for o in tp.ops],
                  fit_tolerance=job.fit_tolerance if job.fit != "none" else 0.0,
                  op_of_line=lmap.op_of_line,
                  position_of_line=position_map(motions),
                  holder_lines=sim.holder_lines if sim is not None else [],
                  rapid_lines=sim.rapid_lines if sim is not None else [],
                  gouge_xy=sim.gouge_at if sim is not None else None)
    return find_problems(report, g)


def _unsafe_program(program: str, problems: list, force: bool,
                    extension: str = ".ngc") -> tuple[str, str]:
    """With ``force``: the program headed by a comment block listing the problems, whose
    program lines are shifted to count in the written file."""
    from millpath.verify.gate import comment_block
    if not force:
        return program, "program.unsafe" + extension
    shift = comment_block(problems).count("\n")
    for p in problems:
        if p.line is not None:
            p.line += shift
    return comment_block(problems) + program, "program.unsafe" + extension


