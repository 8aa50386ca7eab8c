"""Numbers as programs and tool tables write them: fixed decimals, trailing zeros and
the point dropped, never ``-0``."""

from __future__ import annotations


def plain(v: float, digits: int = 3) -> str:
    """``v`` rounded to ``digits`` decimals and written short: 1.5, 2, -0.0004, 0."""
    t = f"{v:.{digits}f}"
    if "." in t:
        t = t.rstrip("0").rstrip(".")
    return "0" if t in ("-0", "", "-") else t
