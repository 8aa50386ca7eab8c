"""Refuse operations that make no sense (issue 16 item 4), before posting.

Looked at from the planned moves of each operation against the stock (job units):

- it cuts nothing: no feed move goes below the stock top (e.g. a pocket bottom above
  the stock, a design wholly outside it);
- it cuts deeper than the stock: a feed move more than a tool diameter below the stock
  bottom (a through hole's break-through is less);
- it cuts deeper than its tool reaches: a feed move further below the stock top than
  the tool's stick-out (the holder would be buried).
"""

from __future__ import annotations

from pathlib import Path

from millpath.errors import PlanningError
from millpath.model import Stock, Tool, Toolpath

FEEDS = ("line", "arc", "cubic", "drill")


def check_operation(where: str, tp: Toolpath, stock: Stock, tools: dict[int, Tool],
                    file: str | Path | None) -> None:
    """Raise PlanningError naming ``where`` (e.g. ``operations[2]``) when the moves of
    ``tp`` cut nothing or reach deeper than the stock or the tool."""
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
