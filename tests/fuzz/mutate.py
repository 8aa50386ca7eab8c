"""Mutations of valid input texts for the fuzz tests: numbers replaced by huge,
non-finite, negative or malformed ones, characters deleted or doubled, lines dropped or
repeated, the text cut short. Used with hypothesis (fixed seeds, see the tests)."""

from __future__ import annotations

import re

from hypothesis import strategies as st

NUMBER = re.compile(r"(?<![A-Za-z_#])[-+]?\d+(?:\.\d*)?(?:[eE][-+]?\d+)?")

WEIRD = ["1e999", "-1e999", "1e308", "-1e308", "nan", "inf", "-inf", "NaN", "1" + "0" * 400,
         "0", "-0", "0.0", "-1", "1e-300", "-5e-324", "", "1e", "--1", "1.2.3", "0x10",
         "9" * 40, "1e23", "-1e23", "3.4028236e38"]


@st.composite
def mutated(draw, text: str) -> str:
    """``text`` with one to four random mutations."""
    for _ in range(draw(st.integers(1, 4))):
        kind = draw(st.sampled_from(["number", "number", "number", "delete", "dup", "line",
                                     "cut", "insert"]))
        if kind == "number":
            spans = [m.span() for m in NUMBER.finditer(text)]
            if spans:
                a, b = draw(st.sampled_from(spans))
                text = text[:a] + draw(st.sampled_from(WEIRD)) + text[b:]
        elif kind in ("delete", "dup", "insert") and text:
            i = draw(st.integers(0, len(text) - 1))
            j = min(len(text), i + draw(st.integers(1, 8)))
            if kind == "delete":
                text = text[:i] + text[j:]
            elif kind == "dup":
                text = text[:j] + text[i:j] + text[j:]
            else:
                text = text[:i] + draw(st.sampled_from(["(", ")", "[", "]", "'", '"', ",", ";",
                                                        "=", "#", "\n", "\x00", "é", "{"])) + text[i:]
        elif kind == "line":
            lines = text.splitlines(keepends=True)
            if lines:
                k = draw(st.integers(0, len(lines) - 1))
                lines = lines[:k] + lines[k + 1:] if draw(st.booleans()) else \
                    lines[:k] + [lines[k]] * draw(st.integers(2, 50)) + lines[k:]
                text = "".join(lines)
        elif kind == "cut":
            text = text[:draw(st.integers(0, len(text)))]
    return text
