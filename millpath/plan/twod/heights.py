"""Tool and heights of a 2.5D operation (pocket, profile), from its keys.

``top`` is the operation's top (default: the stock top); ``upper`` the higher of it
and the stock top; ``clear_z`` sits ``clearance`` (0.5 mm / 0.02 inch) above ``upper``;
``safe_z`` defaults to 5 mm / 0.2 inch above ``upper`` and must be above it. All
lengths in job units.
"""

from __future__ import annotations

from dataclasses import dataclass

from millpath.errors import JobError
from millpath.io.schema import Param
from millpath.model import Tool
from millpath.model.units import default
from millpath.plan.base import PlanContext


#: the feed, spindle and retract keys of a 2.5D operation (job units, units/min)
MOTION_PARAMS = {
    "feed": Param("float", positive=True, unit="feed", doc="cutting feed"),
    "plunge_feed": Param("float", None, positive=True, unit="feed",
                         doc="feed of entries (default: feed / 2)"),
    "spindle": Param("float", 0.0, unit="rpm", doc="spindle speed, clockwise (M3)"),
    "safe_z": Param("float", None, unit="length",
                    doc="retract height (default: top + 5 mm / 0.2 in)"),
}


def plunge_feed(params: dict) -> float:
    """The ``plunge_feed`` key, by default half the cutting ``feed`` (units/min)."""
    return params["plunge_feed"] or params["feed"] / 2


@dataclass(frozen=True)
class Heights:
    top: float
    upper: float
    safe_z: float
    clearance: float

    @property
    def clear_z(self) -> float:
        return self.upper + self.clearance


def end_mill(ctx: PlanContext, params: dict, what: str) -> Tool:
    """The operation's tool, refused unless a flat or bull end mill (``what``: "a
    pocket", "a profile" for the message)."""
    tool = ctx.tool(params["tool"])
    if tool.type not in ("flat", "bull"):
        raise JobError(f"tool: {what} needs a flat or bull end mill, tool {tool.number} "
                       f"is {tool.type}", ctx.job_file)
    return tool


def operation_heights(ctx: PlanContext, params: dict) -> Heights:
    """The heights the keys ``top`` and ``safe_z`` and the job's stock give."""
    file = ctx.job_file
    stock_top = ctx.stock.zmax if ctx.stock is not None else None
    top = params["top"] if params["top"] is not None else stock_top
    if top is None:
        raise JobError("top: needed when the job gives no [stock]", file)
    clearance = default("entry_clearance", ctx.units)
    upper = max(top, stock_top if stock_top is not None else top)
    safe = params["safe_z"] if params["safe_z"] is not None else \
        upper + default("safe_clearance", ctx.units)
    if safe <= upper:
        raise JobError(f"safe_z: {safe:g} is not above the stock top {upper:g}", file)
    return Heights(top, upper, safe, clearance)
