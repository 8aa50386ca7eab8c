"""Where the tool starts: the interpreter cannot know it, the simulator must.

An interpreter starts at program position (0, 0, 0) and shifts the current position by
each tool length offset (``G43``) without motion, so the first move of a program and
the first move after each tool change start from a point that says nothing about where
the tool really is (usually high above the part, at the tool-change position). For
simulation such a move is taken to start straight above its end point, at
``clear_z`` (job units) or its end Z if that is higher.
"""

from __future__ import annotations

from dataclasses import replace

from millpath.model.motion import Motion


def approach_from_above(motions, clear_z: float) -> list[Motion]:
    """Copy of ``motions`` whose first motion, and first after each change of tool or
    tool length offset, starts above its end point at ``max(clear_z, end z)``."""
    out: list[Motion] = []
    state = None
    for m in motions:
        key = (m.tool, m.tool_offset)
        if key != state and m.kind in ("traverse", "feed"):
            start = (m.end[0], m.end[1], max(clear_z, m.end[2]))
            m = replace(m, start=start)
            state = key
        elif key != state:
            state = key
        out.append(m)
    return out
