"""The fast path's quicker free-order match (``match_free``: no look-aheads, duplicates
found by counting letters) accepts exactly the lines the look-ahead regex ``_FREE``
accepts, with the same words: random word soups (fixed seed) and the free-order
benchmark program's lines."""

from __future__ import annotations

import random
import sys
from pathlib import Path

from millpath.interpret.fastpath import _FREE, match_free

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "bench"))
from programs import free_order  # noqa: E402

PIECES = ["G", "g", "X", "y", "Z", "I", "j", "K", "R", "f", "N", "n", "1", "0", "2", "3",
          "7", ".", "-", "+", " ", "\t", "(c)", "(", ";x", "\r", "E", "M", "#", "\u0661"]


def _same(line: str) -> bool:
    a, b = _FREE.fullmatch(line), match_free(line)
    return (a is None) == (b is None) and (a is None or a.groups() == b.groups())


def test_match_free_is_the_lookahead_regex_on_word_soups():
    rng = random.Random(19)
    lines = ["".join(rng.choice(PIECES) for _ in range(rng.randint(0, 12)))
             for _ in range(30000)]
    lines += ["G1 X1 Y2", "x1 G1 y2", "X1 X2", "G1 G2 X1", "N10 g2 x1 y1 i1 J0",
              "y1 x2 (c) x3", "X1 y2 ;x", "G 1 X 1", "N5 N6 X1", "X1\r", "g01 g1"]
    accepted = sum(1 for s in lines if _FREE.fullmatch(s))
    assert accepted > 2000            # the soup holds many matching lines, not only refusals
    bad = [s for s in lines if not _same(s)]
    assert not bad, bad[:5]


def test_match_free_is_the_lookahead_regex_on_free_order_lines():
    lines = free_order(20000).splitlines()
    bad = [s for s in lines if not _same(s)]
    assert not bad, bad[:5]
