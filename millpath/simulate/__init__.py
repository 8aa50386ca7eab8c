"""Material-removal simulation and verification (issue 4).

- :func:`simulate_toolpath` / :func:`simulate_motions`: sweep the tools through a
  Z-map of the stock, count rapids through material and holder contacts, compare with
  a design (gouge, material left) and time the program; return a :class:`SimResult`.
- :func:`cycle_time`: the program's run time alone (no Z-map).
- Designs: :class:`MeshDesign` (STL), :class:`HeightFieldDesign`, :class:`PlaneDesign`,
  :class:`BoxDesign`, or anything with ``height(x, y)``.
- Pictures: :func:`render_stock`, :func:`render_deviation`.
"""

from millpath.model.stock import Machine
from millpath.simulate.cycletime import cycle_time, motion_times, operation_times
from millpath.simulate.design import BoxDesign, HeightFieldDesign, MeshDesign, PlaneDesign
from millpath.simulate.simulator import (SimResult, compare, deviation, simulate_motions,
                                         simulate_toolpath)
from millpath.simulate.zmap import ZMap


def render_stock(zmap, path, **kw):
    """Shaded picture of the simulated stock (PNG). See :mod:`millpath.simulate.render`."""
    from millpath.simulate.render import render_stock as _r
    return _r(zmap, path, **kw)


def render_deviation(zmap, design, path, **kw):
    """Deviation map (gouge red, material left blue, scale bar) as PNG."""
    from millpath.simulate.render import render_deviation as _r
    return _r(zmap, design, path, **kw)


__all__ = ["BoxDesign", "HeightFieldDesign", "Machine", "MeshDesign", "PlaneDesign",
           "SimResult", "ZMap", "compare", "cycle_time", "deviation", "motion_times",
           "operation_times", "render_deviation", "render_stock", "simulate_motions",
           "simulate_toolpath"]
