"""``millpath keys [TYPE]``: every key a job file may hold, with type, default, unit and
meaning, from the schemas the job loader validates with."""

from __future__ import annotations

import click

from millpath.errors import JobError


@click.command()
@click.argument("op_type", required=False)
@click.option("--markdown", is_flag=True, help="Print docs/jobs.md (all sections).")
def command(op_type: str | None, markdown: bool) -> None:
    """List the keys of every job section, or of operation type OP_TYPE."""
    from millpath.job.keys import markdown as md, sections
    from millpath.plan.registry import STRATEGIES

    if markdown:
        click.echo(md(), nl=False)
        return
    if op_type is not None and op_type not in STRATEGIES:
        raise JobError(f"unknown operation type {op_type!r} (known: "
                       f"{', '.join(sorted(STRATEGIES))})")
    from rich.console import Console
    from rich.markup import escape
    from rich.table import Table
    console = Console(soft_wrap=False)
    for s in sections(op_type):
        t = Table(title=escape(s.title), caption=escape(s.summary), title_justify="left",
                  caption_justify="left", show_lines=False)
        for col in ("key", "type", "default", "unit", "meaning"):
            t.add_column(col, overflow="fold")
        for k in s.keys:
            t.add_row(*(escape(c) for c in (k.name, k.kind, k.default, k.unit, k.doc)))
        console.print(t)
