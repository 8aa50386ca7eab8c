"""Material-removal simulation and verification.

- :func:`simulate_toolpath` / :func:`simulate_motions`: sweep the tools through a
  Z-map of the stock, count rapids through material and holder contacts, compare with
  a design (gouge, material left) and time the program; return a :class:`SimResult`
  whose ``to_json()`` is report.json's ``verification`` object.
- :func:`cycle_time` (and :func:`motion_times`, :func:`operation_times`): run time
  alone, without a Z-map.
- Designs: :class:`MeshDesign` (STL), :class:`HeightFieldDesign`, :class:`PlaneDesign`,
  :class:`BoxDesign`, or anything with ``height(x, y)`` (``-inf``: no part).
- Pictures: :func:`render_stock`, :func:`render_deviation` (PNG).

Conventions (all lengths in the program's / toolpath's units):

- The stock is a Z-map (:class:`ZMap`): one height per cell at the cell centre, cells
  at most ``resolution`` wide tiling the stock box. A height field is exact for 3-axis
  motion (no undercuts) at the cell centres; volumes are sums over cells.
- Tool shapes are :class:`millpath.model.Tool` profiles (flat, ball, bull, drill cone)
  with a cylinder of radius D/2 above the profile; coordinates are the tool tip.
  Straight chords are swept exactly at every cell centre (closed form for flat, ball,
  drill; bisection for bull); arcs (any plane, helices) and cubics are chords within
  ``resolution / 20`` of the curve. A cell centre exactly on the tool's edge is cut.
- Gouge: over the cells the tool cut, the largest amount by which the cell's height is
  below the *lowest* design value over the cell (centre and 4 corners). Material left:
  the largest amount above the *highest* such value; ``left_volume`` integrates height
  above the centre value. A cell straddling a vertical wall therefore reports neither
  a false gouge nor false material of the wall's height: deviations are resolved to
  one cell horizontally and exactly vertically (a flat floor cut 0.2 too deep reports
  0.2). Design values below the stock bottom (or ``-inf``) count as the stock bottom.
- Rapids through material: traverses (rapid chords) that remove any material (more
  than ``1e-4`` of a cell width). Holder contacts: motions during which a shank or
  holder cylinder (``Tool.holder_cylinders()``: shank from the top of the flutes, then
  the holder stack) meets material still there before the motion cuts. Both count
  motions (toolpath moves for :func:`simulate_toolpath`).
- Tool 0 (empty spindle) cuts nothing. The first move, and the first after each tool
  change, start above their end point at the stock top or higher.
- Cycle time: see :mod:`millpath.simulate.cycletime` (trapezoidal speed profiles, stops
  at corners sharper than ``corner_angle`` degrees, feeds capped by the machine).
"""

from millpath.model.stock import Machine
from millpath.simulate.cycletime import cycle_time, motion_times, operation_times
from millpath.simulate.design import BoxDesign, HeightFieldDesign, MeshDesign, PlaneDesign
from millpath.simulate.simulator import (Comparison, SimResult, compare, compare_design,
                                         deviation, simulate_motions, simulate_toolpath)
from millpath.simulate.zmap import ZMap


def render_stock(zmap, path, **kw):
    """Shaded picture of the simulated stock (PNG). See :mod:`millpath.simulate.render`."""
    from millpath.simulate.render import render_stock as _r
    return _r(zmap, path, **kw)


def render_deviation(zmap, design, path, **kw):
    """Deviation map (gouge red, material left blue, scale bar) as PNG."""
    from millpath.simulate.render import render_deviation as _r
    return _r(zmap, design, path, **kw)


__all__ = ["BoxDesign", "Comparison", "compare_design", "HeightFieldDesign", "Machine", "MeshDesign", "PlaneDesign",
           "SimResult", "ZMap", "compare", "cycle_time", "deviation", "motion_times",
           "operation_times", "render_deviation", "render_stock", "simulate_motions",
           "simulate_toolpath"]
