"""Refuse operations that make no sense, before posting.

Looked at from the planned moves of each operation against the stock (job units):

- it cuts nothing: no feed move goes below the stock top (e.g. a pocket bottom above
  the stock, a design wholly outside it);
- it cuts deeper than the stock: a feed move more than a tool diameter below the stock
  bottom (a through hole's break-through is less);
- it cuts deeper than its tool reaches: a feed move further below the stock top than
  the tool's stick-out (the holder would be buried);
- a 2.5D operation (pocket, profile) whose bottom (its operations' ``info["bottom"]``:
  the key, the top and the depth below it) is more than a cut-through's
  ``breakthrough`` (0.5 mm / 0.02 in) below the stock bottom: refused naming the key.
"""

from __future__ import annotations

from pathlib import Path

from millpath.errors import PlanningError
from millpath.model import Stock, Tool, Toolpath
from millpath.model.units import default

FEEDS = ("line", "arc", "cubic", "drill")


def check_operation(where: str, tp: Toolpath, stock: Stock, tools: dict[int, Tool],
                    file: str | Path | None) -> None:
    """Raise PlanningError naming ``where`` (e.g. ``operations[2]``) when the moves of
    ``tp`` cut nothing or reach deeper than the stock or the tool."""
    _bottoms(where, tp, stock, file)
    lowest: dict[int, float] = {}
    for m in tp.moves:
        if m.kind in FEEDS:
            t = tp.ops[m.op].tool
            lowest[t] = min(lowest.get(t, float("inf")), m.end[2])
    if not lowest:
        return                   # nothing but rapids: "no moves" is reported elsewhere
    if min(lowest.values()) >= stock.zmax - 1e-9:
        raise PlanningError(f"{where}: the operation cuts nothing: no feed move goes below "
                            f"the stock top z {stock.zmax:g} (its lowest is "
                            f"{min(lowest.values()):g})", file)
    for n, z in sorted(lowest.items()):
        tool = tools.get(n)
        if tool is None:
            continue
        if z < stock.zmin - tool.diameter:
            raise PlanningError(f"{where}: T{n} cuts down to z {z:g}, "
                                f"{stock.zmin - z:g} below the stock bottom z "
                                f"{stock.zmin:g}: the depth is beyond the stock", file)
        if stock.zmax - z > tool.stickout + 1e-9:
            raise PlanningError(f"{where}: T{n} cuts {stock.zmax - z:g} below the stock "
                                f"top but reaches only {tool.stickout:g} (stick-out): the "
                                f"holder would be buried", file)


def _bottoms(where: str, tp: Toolpath, stock: Stock, file) -> None:
    """PlanningError naming the depth key of an operation whose bottom lies more than a
    cut-through below the stock bottom."""
    through = default("breakthrough", tp.units)
    for op in tp.ops:
        b = op.info.get("bottom")
        if not b:
            continue
        z = b["top"] - b["depth"]
        if z < stock.zmin - through - 1e-9:
            most = b["top"] - stock.zmin + through
            raise PlanningError(f"{where}.{b['key']}: {b['depth']:g} below z {b['top']:g} "
                                f"reaches z {z:g}, {stock.zmin - z:g} below the stock "
                                f"bottom z {stock.zmin:g}: the depth is beyond the stock "
                                f"(a cut through it goes at most {through:g} below: "
                                f"{b['key']} {most:g} or less)", file)
