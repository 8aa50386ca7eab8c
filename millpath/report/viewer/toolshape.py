"""The tool as the viewer draws it: a lathe profile of the cutter and the holder stack.

Lengths in the tool's units (the program's), measured up from the tool tip along the
tool axis. The cutter profile is a list of ``(r, z)`` points from the tip (``r = 0``)
out and up the flank to the top of the flutes (``Tool.flute_length``, at least the
height of the tip shape); revolving it about the axis gives the cutting part (flat,
ball, bull-nose or drill point). The shank and holder are cylinders
``(radius, z_bottom, z_top)`` from :meth:`millpath.model.tool.Tool.holder_cylinders`.
"""

from __future__ import annotations

from millpath.geometry.cutter import Cutter
from millpath.model.tool import Tool


def cutter_profile(tool: Tool, steps: int = 12) -> list[tuple[float, float]]:
    """``(r, z)`` outline of the cutting part from the tip to the top of the flutes: the
    cutter's profile (:meth:`millpath.geometry.cutter.Cutter.outline`, a corner sampled
    every ``90 / steps`` degrees), then the flank up to ``Tool.flute_length``."""
    cutter = Cutter.of(tool)
    out = cutter.outline(steps)
    if tool.flute_length > cutter.tip_height:
        out.append((float(cutter.radius), float(tool.flute_length)))
    return out


def tool_shape(tool: Tool) -> dict:
    """What the page needs to draw ``tool``: type, diameter, cutter profile and the
    cylinders above the flutes, ``[radius, z_bottom, z_top, "shank" | "holder"]`` (the
    shank when the stickout exceeds the flutes, then the holder stack), from the tip up."""
    cyl = tool.holder_cylinders()
    shank = 1 if tool.stickout > tool.flute_length else 0
    return {
        "number": tool.number,
        "type": tool.type,
        "diameter": float(tool.diameter),
        "corner_radius": float(tool.corner_radius),
        "comment": tool.comment,
        "profile": [[r, z] for r, z in cutter_profile(tool)],
        "cylinders": [[float(r), float(z0), float(z1), "shank" if k < shank else "holder"]
                      for k, (r, z0, z1) in enumerate(cyl)],
    }
