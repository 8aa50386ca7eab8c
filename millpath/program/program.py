"""A posted program as a value: its text in one control dialect, the tool path it was
written from (after the dialect's rewrites), which planned move and operation each line
carries out, and what was written otherwise than planned."""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

from millpath.model import Tool, Toolpath
from millpath.model.dialect import Dialect, dialect
from millpath.post.lower import lower
from millpath.post.writer import PostOptions, write
from millpath.program.linemap import LineMap


@dataclass(frozen=True)
class Program:
    """``text`` for ``dialect``; ``toolpath``: the moves as written (cycles, splines and
    multi-turn arcs rewritten where the dialect lacks them); ``move_lines``: each of its
    moves' 1-based program line (None: no line); ``fallbacks``: what the dialect made
    the post write otherwise, one sentence each."""

    text: str
    dialect: Dialect
    toolpath: Toolpath
    move_lines: list[int | None]
    fallbacks: list[str]

    @cached_property
    def lines(self) -> LineMap:
        """Program line -> planned move and operation (made once)."""
        return LineMap.of_toolpath(self.toolpath, self.move_lines)


def make_program(tp: Toolpath, tools: dict[int, Tool], *, title: str = "",
                 options: PostOptions | None = None, tolerance: float = 0.001) -> Program:
    """The program of ``tp`` in the dialect ``options`` name (LinuxCNC by default);
    ``tolerance``: how far lines written for a spline may stray from it (tool path
    units). ValueError for what the dialect cannot carry."""
    options = options or PostOptions()
    d = dialect(options.dialect)
    lowered, rewritten = lower(tp, d, tolerance)
    w = write(lowered, tools, title=title, options=options)
    return Program(w.text, d, lowered, w.move_lines, rewritten + w.fallbacks)
