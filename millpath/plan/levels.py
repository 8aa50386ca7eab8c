"""Depth levels of layered cutting (pockets, profiles, features), in job units."""

from __future__ import annotations

import math


def levels(top: float, floor: float, stepdown: float) -> list[float]:
    """Z of each level from ``top`` (excluded) down to ``floor`` (the last level), in
    equal steps no larger than ``stepdown``; one level when ``floor`` is within a step."""
    depth = top - floor
    n = max(1, int(math.ceil(depth / stepdown - 1e-9)))
    return [top - depth * (k + 1) / n for k in range(n)]
