"""view.html: an interactive 3D view of a program, its stock and the simulation.

:func:`write_view` writes one self-contained page (three.js inlined, no network): the
tool path coloured by operation or feed with rapids dashed, the stock box, the
simulated stock coloured by deviation from the design (gouge red, material left blue,
within tolerance neutral) with the worst of each marked, the design as a translucent
overlay, and a player that runs the program move by move with the tool and holder drawn
at the current move and its program line shown.
"""

from millpath.report.viewer.motionpack import ViewOperation, operations_from_program
from millpath.report.viewer.scene import default_tolerance, scene_data, write_view

__all__ = ["ViewOperation", "default_tolerance", "operations_from_program", "scene_data",
           "write_view"]
