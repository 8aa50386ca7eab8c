"""Which planned move, and so which operation, each line of a posted program carries out.

The post returns the program line of each planned move (None for moves it writes no
line for). A program line belongs to the last planned move written at or before it
(lines of a canned cycle or of the approach after a tool change belong to the move they
were written for); lines before the first move belong to the first. The one lookup the
pipeline, the in-process stock, the safety gate and the viewer use.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class LineMap:
    """Program line -> planned move and operation (see the module docstring)."""

    lines: np.ndarray        # program lines where planned moves are written, increasing
    moves: np.ndarray        # the move written at each of them
    ops: np.ndarray          # and its operation

    @classmethod
    def of(cls, move_ops: Sequence[int], move_lines: Sequence[int | None]) -> "LineMap":
        """From each planned move's operation and program line."""
        rows = sorted((line, i, op) for i, (op, line) in enumerate(zip(move_ops, move_lines))
                      if line is not None)
        a = np.array(rows, np.int64).reshape(-1, 3)
        return cls(a[:, 0], a[:, 1], a[:, 2])

    @classmethod
    def of_toolpath(cls, toolpath, move_lines: Sequence[int | None]) -> "LineMap":
        return cls.of([m.op for m in toolpath.moves], move_lines)

    def _index(self, lines) -> np.ndarray:
        k = np.searchsorted(self.lines, np.asarray(lines, np.int64), side="right") - 1
        return np.maximum(k, 0)

    def op_of_line(self, line: int) -> int | None:
        """The operation carried out at ``line`` (None for a program with no move)."""
        if not len(self.lines):
            return None
        return int(self.ops[self._index([line])[0]])

    def ops_of(self, motions) -> np.ndarray:
        """The operation of each motion (by its ``line``); 0 for a program with no move."""
        if not len(self.lines):
            return np.zeros(len(motions), np.int64)
        return self.ops[self._index([m.line for m in motions])]

    def moves_of(self, motions) -> np.ndarray:
        """The planned move of each motion (by its ``line``)."""
        if not len(self.lines):
            return np.zeros(len(motions), np.int64)
        return self.moves[self._index([m.line for m in motions])]

    def line_counts(self, n_lines: int, n_ops: int) -> list[int]:
        """How many of the program's lines ``1 .. n_lines`` each operation carries out."""
        if not len(self.lines) or n_lines <= 0:
            return [0] * n_ops
        ops = self.ops[self._index(np.arange(1, n_lines + 1))]
        return np.bincount(ops, minlength=n_ops)[:n_ops].tolist()

    def first_lines(self) -> dict[int, int]:
        """Each operation's first program line."""
        out: dict[int, int] = {}
        for line, op in zip(self.lines.tolist(), self.ops.tolist()):
            out.setdefault(op, line)
        return out
