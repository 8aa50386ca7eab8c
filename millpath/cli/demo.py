"""``millpath demo [-o DIR] [--all] [-k TEXT]``: run the example jobs bundled with millpath.

By default one example of each family (:data:`SHORT`: features from a STEP file, a
die-blanking contour, a grid-navigation pocket, an adaptive pocket from a DXF drawing, a
3-axis surface); ``--all`` runs every example, ``-k TEXT`` those whose name contains TEXT.
Without ``-k``, the kernels are compiled first, once per install, on two processes (see
:mod:`millpath.cli.warm`).

An example the proof refuses (see :mod:`millpath.verify.gate`) is listed in red with
its report and pictures written and no program; it does not make the demo fail, since
refusing is the run doing its job. Any other error does (exit 1)."""

from __future__ import annotations

from importlib import resources
from pathlib import Path

import click
from rich.console import Console
from rich.markup import escape
from rich.table import Table


def example_jobs() -> list[Path]:
    """Job files of the bundled examples: ``millpath/examples/<name>/job.toml``."""
    root = Path(str(resources.files("millpath") / "examples"))
    return sorted(p for p in root.glob("*/job.toml"))


#: the default set: one example of each family
SHORT = ("features-plate", "die-blanking", "pocket-casestudy-line", "pocket-dxf-adaptive",
         "surface-cavity")


def chosen_jobs(only: str | None, every: bool) -> list[Path]:
    """The examples ``millpath demo`` runs: those whose name contains ``only`` (of every
    example), else every example if ``every``, else the :data:`SHORT` set."""
    jobs = example_jobs()
    if only is not None:
        return [j for j in jobs if only in j.parent.name]
    if every:
        return jobs
    return [j for j in jobs if j.parent.name in SHORT]


def _fmt(v, digits=4):
    if v is None:
        return "-"
    if isinstance(v, float):
        return f"{v:.{digits}g}"
    return str(v)


@click.command()
@click.option("-o", "--output", "outdir", type=click.Path(path_type=Path),
              default=Path("millpath-demo"), show_default=True, help="Output folder.")
@click.option("-k", "--only", "only", default=None, help="Run only examples whose name "
              "contains this text.")
@click.option("--all", "every", is_flag=True, help="Run every example (default: one of "
              "each family).")
def command(outdir: Path, only: str | None, every: bool) -> None:
    """Run bundled example jobs (one of each family; --all: every one), each into
    DIR/<example>/, and summarise them."""
    from millpath.errors import MillpathError
    from millpath.pipeline import run_job
    console = Console()
    if not console.is_terminal:
        console = Console(width=160)
    jobs = chosen_jobs(only, every)
    if not jobs:
        raise MillpathError("no example jobs found")
    table = Table(title=f"millpath demo: {len(jobs)} examples -> {outdir}")
    for col in ("example", "units", "ops", "lines", "moves", "cycle s", "removed",
                "max gouge", "max left", "run s"):
        table.add_column(col, justify="left" if col == "example" else "right")
    from millpath.cli.warm import cache_dir, compile_kernels, wait_for_warm
    if only is None and cache_dir() is not None:
        console.print(compile_kernels(console.print), highlight=False)
    else:
        wait_for_warm()
    failures = 0
    refused: list[str] = []
    views: list[tuple[str, Path]] = []
    for k, job in enumerate(jobs, 1):
        name = job.parent.name
        console.print(f"[bold]{name}[/] ({k} of {len(jobs)}) ...")
        from millpath.verify.gate import UnsafeProgramError
        try:
            res = run_job(job, outdir / name, progress=True)
        except UnsafeProgramError as e:
            # the proof doing its job: the program is not written, the report is
            refused.append(name)
            console.print(f"[red]{name}: {escape(str(e))}[/]")
            table.add_row(name, "", "", "", "", "", "",
                          f"[red]refused: {e.problems[0].kind}[/]", "", "")
            continue
        except MillpathError as e:
            from millpath.part.brep.reader import STEP_BREP_EXTRA
            if STEP_BREP_EXTRA in str(e):          # a STEP solid without OpenCASCADE
                console.print(f"[yellow]{name}: skipped: {escape(e.message)}[/]")
                table.add_row(name, "", "", "", "", "", "", "[yellow]skipped[/]", "", "")
                continue
            failures += 1
            console.print(f"[red]{name}: {escape(str(e))}[/]")
            table.add_row(name, "", "", "", "", "", "", "[red]failed[/]", "", "")
            continue
        r = res.report
        views += [(name, f) for f in res.files if f.name == "view.html"]
        v = r.get("verification", {})
        table.add_row(name, r["units"], str(len(r["operations"])), str(r["lines"]),
                      str(sum(r["moves"].values())), f"{r['cycle_time_s']:.0f}",
                      _fmt(v.get("removed_volume")), _fmt(v.get("max_gouge")),
                      _fmt(v.get("max_left")), f"{res.seconds:.1f}")
    console.print(table)
    if views:
        console.print("3D views (open in a browser, no network needed):")
        for name, f in views:
            console.print(f"  {name}: {f.resolve()}", soft_wrap=True, highlight=False)
    rest = len(example_jobs()) - len(jobs)
    if only is None and not every and rest > 0:
        console.print(f"{rest} more examples: millpath demo --all")
    if refused:
        console.print(f"[red]{len(refused)} of {len(jobs)} examples refused by the proof "
                      f"(no program.ngc; see their report.json): {', '.join(refused)}[/]",
                      soft_wrap=True)
    if failures:
        raise MillpathError(f"{failures} of {len(jobs)} examples failed")
