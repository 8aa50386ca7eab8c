"""The ``millpath`` command: a click group whose subcommands live in sibling modules.

Each module ``millpath.cli.<name>`` listed in ``COMMANDS`` defines a click command
named ``command``. One error boundary for every command:

- a failure caused by the input (:class:`MillpathError`, an ``OSError`` reading or
  writing a file the user named, or a command's option or argument click cannot take)
  prints one line ``millpath: error: FILE[:LINE]: message`` (``--option: message``) and
  exits 1; a job file's problems (:class:`JobErrors`) print one such line each, at most
  ``MAX_SHOWN`` of them and then ``... and N more``;
- any other exception is a bug in millpath: one line ``millpath: internal error: ...``
  saying so, exit 2;
- ``--debug`` shows the traceback instead, and every library warning.

Warnings: millpath's own (:class:`MillpathWarning`) print as one line
``millpath: warning: FILE: message``; warnings from libraries (numpy, shapely,
matplotlib, ...) carry no news for the user and are silenced unless ``--debug``.
"""

from __future__ import annotations

import importlib
import re
import sys
import logging
import warnings

import click

from millpath import __version__
from millpath.errors import JobErrors, MillpathError, MillpathWarning

COMMANDS = ("run", "demo", "check", "simulate", "features", "drop", "fit", "keys", "view",
            "warm")

EXIT_INPUT = 1
EXIT_BUG = 2


def _show_warning(message, category, filename, lineno, file=None, line=None) -> None:
    if issubclass(category, MillpathWarning):
        click.echo(f"millpath: warning: {message}", err=True)


class _Group(click.Group):
    # commands are imported when used: `check` does not pay for `run`'s imports
    def list_commands(self, ctx: click.Context) -> list[str]:
        return list(COMMANDS)

    def get_command(self, ctx: click.Context, name: str):
        if name not in COMMANDS:
            return None
        return importlib.import_module(f"millpath.cli.{name}").command

    def invoke(self, ctx: click.Context):
        debug = bool(ctx.params.get("debug"))
        if not debug:
            # libraries that log (ezdxf's "Ignored invalid DXF entity", numba) carry no
            # news for a user; millpath's own findings are warnings or errors
            logging.getLogger().addHandler(logging.NullHandler())
            logging.getLogger().setLevel(logging.CRITICAL)
        with warnings.catch_warnings():
            if not debug:
                warnings.simplefilter("ignore")
                warnings.simplefilter("always", MillpathWarning)
                warnings.showwarning = _show_warning
            try:
                return super().invoke(ctx)
            except click.UsageError as e:
                _fail(debug, f"error: {_usage(e)}", EXIT_INPUT)
            except (click.exceptions.Exit, click.exceptions.Abort, click.ClickException):
                raise
            except JobErrors as e:
                _fail(debug, "\nmillpath: ".join(f"error: {line}" for line in e.lines()),
                      EXIT_INPUT)
            except MillpathError as e:
                _fail(debug, f"error: {e}", EXIT_INPUT)
            except OSError as e:
                name = getattr(e, "filename", None)
                msg = getattr(e, "strerror", None) or str(e)
                _fail(debug, f"error: {name}: {msg}" if name else f"error: {msg}", EXIT_INPUT)
            except Exception as e:                     # noqa: BLE001 - the boundary
                text = " ".join(str(e).split()) or "no message"
                _fail(debug, f"internal error: {type(e).__name__}: {text} (this is a bug in "
                      f"millpath; run with --debug for the traceback)", EXIT_BUG)


def _usage(e: click.UsageError) -> str:
    """A command-line mistake as one line naming the option first, as errors name
    their file: ``--tool-length: 'abc' is not a valid float.``"""
    text = " ".join(e.format_message().split())
    m = re.match(r"Invalid value for '([^']+)': (.*)", text)
    return f"{m.group(1)}: {m.group(2)}" if m else text


def _fail(debug: bool, message: str, status: int) -> None:
    if debug:
        raise
    click.echo(f"millpath: {message}", err=True)
    sys.exit(status)


@click.group(cls=_Group)
@click.version_option(__version__, prog_name="millpath")
@click.option("--debug", is_flag=True, help="Show tracebacks and library warnings.")
@click.pass_context
def cli(ctx: click.Context, debug: bool) -> None:
    """millpath: part definitions to verified RS274NGC (LinuxCNC) programs."""
    ctx.obj = {"debug": debug}


def main() -> None:
    cli(prog_name="millpath")


if __name__ == "__main__":
    main()
