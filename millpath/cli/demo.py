"""``millpath demo [-o DIR]``: run every example job bundled with millpath."""

from __future__ import annotations

from importlib import resources
from pathlib import Path

import click
from rich.console import Console
from rich.table import Table


def example_jobs() -> list[Path]:
    """Job files of the bundled examples: ``millpath/examples/<name>/job.toml``."""
    root = Path(str(resources.files("millpath") / "examples"))
    return sorted(p for p in root.glob("*/job.toml"))


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
def command(outdir: Path, only: str | None) -> None:
    """Run the bundled example jobs, each into DIR/<example>/, and summarise them."""
    from millpath.errors import MillpathError
    from millpath.pipeline import run_job
    console = Console()
    if not console.is_terminal:
        console = Console(width=160)
    jobs = [j for j in example_jobs() if only is None or only in j.parent.name]
    if not jobs:
        raise MillpathError("no example jobs found")
    table = Table(title=f"millpath demo: {len(jobs)} examples -> {outdir}")
    for col in ("example", "units", "ops", "lines", "moves", "cycle s", "removed",
                "max gouge", "max left", "run s"):
        table.add_column(col, justify="left" if col == "example" else "right")
    failures = 0
    views: list[tuple[str, Path]] = []
    for job in jobs:
        name = job.parent.name
        console.print(f"[bold]{name}[/] ...")
        try:
            res = run_job(job, outdir / name, progress=True)
        except MillpathError as e:
            failures += 1
            console.print(f"[red]{name}: {e}[/]")
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
    if failures:
        raise MillpathError(f"{failures} of {len(jobs)} examples failed")
