"""``millpath run JOB.toml -o DIR``: plan, post, verify and report one job."""

from __future__ import annotations

from pathlib import Path

import click
from rich.console import Console


@click.command()
@click.argument("job", type=click.Path(path_type=Path))
@click.option("-o", "--output", "outdir", type=click.Path(path_type=Path), default=None,
              help="Output folder (default: a folder named after the job, beside it).")
@click.option("--quiet", is_flag=True, help="Print nothing but errors.")
def command(job: Path, outdir: Path | None, quiet: bool) -> None:
    """Run JOB (TOML): writes program.ngc, tools.tbl, report.json and pictures into DIR."""
    from millpath.pipeline import run_job
    out = outdir or job.with_suffix("")
    console = Console(stderr=True, quiet=quiet)
    res = run_job(job, out, progress=not quiet)
    rep = res.report
    ver = rep.get("verification", {})
    console.print(f"[bold]{rep['name']}[/]: {rep['lines']} lines, moves {rep['moves']}, "
                  f"cycle time {rep['cycle_time_s']:.1f} s")
    if "max_gouge" in ver:
        console.print(f"verification: removed {ver['removed_volume']:.4g} {rep['units']}^3, "
                      f"max gouge {ver['max_gouge']}, max left {ver['max_left']}")
    console.print(f"wrote {', '.join(str(f) for f in res.files)}")
