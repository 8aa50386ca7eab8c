"""``millpath run JOB.toml -o DIR``: plan, post, verify and report one job.

The verification summary (holder contacts, rapids through material, features not
machined, gouge against the tolerance) goes to standard output in colour; an error,
including a program refused by the safety gate, is one line on standard error.
"""

from __future__ import annotations

from pathlib import Path

import click
from rich.console import Console

from millpath.model.dialect import DIALECTS
from millpath.report.document import plan_sections


def print_verification(console: Console, report: dict) -> None:
    """The safety figures of a run, green when clean and red when not."""
    ver = report.get("verification", {})
    if "skipped" in ver:
        console.print(f"[yellow]verification skipped: {ver['skipped']}[/]")
        return

    def fig(label: str, n: int) -> str:
        return f"[{'red' if n else 'green'}]{label} {n}[/]"
    holder = int(ver.get("holder_contacts") or 0)
    rapids = int(ver.get("rapids_through_material") or 0)
    sections = [f for f in plan_sections(report, "features") if isinstance(f, dict)]
    unmachined = sum(len(f.get("unmachinable") or []) for f in sections
                     if f.get("unmachinable_policy", "refuse") == "refuse")
    left = sum(len(f.get("unmachinable") or []) for f in sections
               if f.get("unmachinable_policy") == "list")
    problems = (report.get("safety") or {}).get("problems", [])
    gouge_bad = any(p["kind"] == "gouge" for p in problems)
    tols = sorted({p["detail"] for p in problems if p["kind"] == "gouge"})
    g = ver.get("max_gouge")
    gouge = ("max gouge -" if g is None else f"max gouge {g:.4g}"
             + (f" ({'; '.join(tols)})" if tols else " (within tolerance)"))
    console.print(", ".join([fig("holder contacts", holder),
                             fig("rapids through material", rapids),
                             fig("features not machined", unmachined)
                             + (f" [yellow](+{left} left on purpose)[/]" if left else ""),
                             f"[{'red' if gouge_bad else 'green'}]{gouge}[/]"])
                  + (f", max left {ver['max_left']:.4g}"
                     + (f" (sampled every {ver['left_spacing']:.3g})"
                        if ver.get("left_spacing") else "")
                     if ver.get("max_left") is not None else ""))
    for p in problems:
        console.print(f"[red]  {p['text']}[/]")


@click.command()
@click.argument("job", type=click.Path(path_type=Path))
@click.option("-o", "--output", "outdir", type=click.Path(path_type=Path), default=None,
              help="Output folder (default: a folder named after the job, beside it).")
@click.option("--quiet", is_flag=True, help="Print nothing but errors.")
@click.option("--force", is_flag=True, help="Write a program the simulation found unsafe, "
              "as program.unsafe.ngc headed by the list of problems.")
@click.option("--no-pictures", "no_pictures", is_flag=True,
              help="Draw no PNG pictures (the job's [simulation] pictures = false).")
@click.option("--post", "dialect", type=click.Choice(sorted(DIALECTS)), default=None,
              help="The control to write for and prove the program as (default: the "
              "job's [post] dialect, linuxcnc).")
def command(job: Path, outdir: Path | None, quiet: bool, force: bool,
            no_pictures: bool, dialect: str | None) -> None:
    """Run JOB (TOML): writes the program (program.ngc for LinuxCNC, program.nc for
    GRBL), tools.tbl, report.json and pictures into DIR."""
    from millpath.io.atomic import output_lock
    from millpath.pipeline import run_job
    from millpath.verify.gate import UnsafeProgramError
    out = outdir or job.with_suffix("")
    console = Console(quiet=quiet, highlight=False)
    from millpath.cli.warm import wait_for_warm
    wait_for_warm()
    try:
        with output_lock(out):
            res = run_job(job, out, progress=not quiet, force=force,
                          pictures=False if no_pictures else None, dialect=dialect)
    except UnsafeProgramError as e:
        print_verification(console, e.report)
        raise
    rep = res.report
    console.print(f"[bold]{rep['name']}[/]: {rep['lines']} lines, moves {rep['moves']}, "
                  f"cycle time {rep['cycle_time_s']:.1f} s")
    ver = rep.get("verification", {})
    if "removed_volume" in ver:
        console.print(f"removed {ver['removed_volume']:.4g} {rep['units']}^3")
    post = rep.get("post") or {}
    for what in post.get("rewritten", []):
        console.print(f"for {post['control']}: {what}")
    print_verification(console, rep)
    if rep.get("safety", {}).get("status") == "forced":
        click.echo(f"millpath: warning: {job}: the program is unsafe and was written as "
                   f"{out / rep['program']} (--force)", err=True)
    console.print(f"wrote {', '.join(str(f) for f in res.files)}")
