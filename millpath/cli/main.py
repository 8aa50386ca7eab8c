"""The ``millpath`` command: a click group whose subcommands live in sibling modules.

Each module ``millpath.cli.<name>`` listed in ``COMMANDS`` defines a click command
named ``command``. Errors derived from :class:`MillpathError` (and a few expected
exception types) print one line ``millpath: error: FILE[:LINE]: message`` and exit 1;
``--debug`` shows the traceback instead.
"""

from __future__ import annotations

import importlib
import sys

import click

from millpath import __version__
from millpath.errors import MillpathError

COMMANDS = ("run", "demo", "check", "simulate", "features", "drop", "fit", "view")


class _Group(click.Group):
    def invoke(self, ctx: click.Context):
        try:
            return super().invoke(ctx)
        except (click.exceptions.Exit, click.exceptions.Abort, click.ClickException):
            raise
        except MillpathError as e:
            _fail(ctx, str(e))
        except (OSError, ValueError) as e:
            name = getattr(e, "filename", None)
            msg = getattr(e, "strerror", None) or str(e)
            _fail(ctx, f"{name}: {msg}" if name else msg)


def _fail(ctx: click.Context, message: str) -> None:
    if ctx.obj and ctx.obj.get("debug"):
        raise
    click.echo(f"millpath: error: {message}", err=True)
    sys.exit(1)


@click.group(cls=_Group)
@click.version_option(__version__, prog_name="millpath")
@click.option("--debug", is_flag=True, help="Show tracebacks instead of one-line errors.")
@click.pass_context
def cli(ctx: click.Context, debug: bool) -> None:
    """millpath: part definitions to verified RS274NGC (LinuxCNC) programs."""
    ctx.obj = {"debug": debug}


for _name in COMMANDS:
    try:
        _mod = importlib.import_module(f"millpath.cli.{_name}")
    except ModuleNotFoundError as _e:          # command not built yet in this checkout
        if _e.name != f"millpath.cli.{_name}":
            raise
        continue
    cli.add_command(_mod.command, _name)


def main() -> None:
    cli(prog_name="millpath")


if __name__ == "__main__":
    main()
