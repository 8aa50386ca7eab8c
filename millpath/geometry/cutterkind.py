"""The cutter kinds as compiled kernels take them: one set of codes for the rest filter,
the Z-map sweep and the exact check. ``CYL`` is a shank or holder cylinder."""

from __future__ import annotations

FLAT, BALL, BULL, DRILL, CYL = 0, 1, 2, 3, 4

#: a :class:`millpath.model.tool.Tool`'s ``type`` -> its code
KIND = {"flat": FLAT, "ball": BALL, "bull": BULL, "drill": DRILL}
