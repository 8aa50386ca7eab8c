"""Where the tool starts: the interpreter cannot know it, the simulator must.

An interpreter starts at program position (0, 0, 0), which says nothing about where the
machine really is when the program starts (usually high above the part, homed). For
simulation the program's first move is taken to start straight above its end point, at
``clear_z`` (part units) or its end Z if that is higher. Every later move starts where
the one before it ended, tool changes included: the machine changes tools where it
stands, and the new tool's tip is where its length puts it
(:mod:`millpath.simulate.tip`).
"""

from __future__ import annotations

from dataclasses import replace

from millpath.model.motion import Motion


def approach_from_above(motions, clear_z: float) -> list[Motion]:
    """Copy of ``motions`` (tool tips in the part's frame) whose first traverse or feed
    starts above its end point at ``max(clear_z, end z)``, when no earlier motion (an
    arc, a curve) has fixed the position."""
    out: list[Motion] = list(motions)
    for i, m in enumerate(out):
        if m.kind in ("traverse", "feed"):
            start = (m.end[0], m.end[1], max(clear_z, m.end[2]))
            out[i] = replace(m, start=start)
            break
        if m.kind != "dwell":
            break
    return out
