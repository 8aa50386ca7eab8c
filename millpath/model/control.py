"""Facts of the control that planners plan for and the interpreter follows.

LinuxCNC's cutter radius compensation (G41/G42) takes a corner between two compensated
straight moves as concave only when the path turns towards the tool by more than
:data:`CONCAVE_CORNER` radians; a smaller turn towards the tool is a tangent join: the
next move starts from where the previous one's offset ended (see
:mod:`millpath.interpret.corners`).
"""

from __future__ import annotations

CONCAVE_CORNER = 0.05           # radians: LinuxCNC's TOLERANCE_CONCAVE_CORNER
