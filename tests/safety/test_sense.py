"""Operations that make no sense are refused before anything is written:
the figures come from the stock box and the tool, not from a planner."""

import pytest

from millpath.errors import PlanningError
from millpath.model import Operation, Stock, Tool, Toolpath
from millpath.plan.sense import check_operation

STOCK = Stock.from_box([0, 0, -20, 100, 100, 0])
TOOLS = {1: Tool(1, "flat", 6.0, flute_length=20, stickout=30)}


def _op(*zs):
    tp = Toolpath("mm")
    tp.begin(Operation("pocket", "p", 1))
    tp.rapid(10, 10, 5)
    for z in zs:
        tp.line(10, 10, z, 100)
    return tp


def test_an_operation_above_the_stock_cuts_nothing():
    # e.g. a pocket bottom at z 2 above a stock whose top is z 0
    with pytest.raises(PlanningError, match=r"operations\[1\]: the operation cuts nothing"):
        check_operation("operations[1]", _op(2.0), STOCK, TOOLS, "job.toml")


def test_depth_beyond_the_stock_is_refused():
    with pytest.raises(PlanningError, match=r"operations\[0\]: T1 cuts down to z -500"):
        check_operation("operations[0]", _op(-5, -500), STOCK,
                        {1: Tool(1, "flat", 6.0, flute_length=20, stickout=600)}, "job.toml")


def test_depth_beyond_the_tool_reach_is_refused():
    with pytest.raises(PlanningError, match="cuts 31 below the stock top but reaches only 30"):
        check_operation("operations[0]", _op(-31 + 0.0), Stock.from_box([0, 0, -40, 100, 100, 0]),
                        TOOLS, "job.toml")


def test_sensible_operations_and_break_through_pass():
    check_operation("operations[0]", _op(-10, -20.5), STOCK, TOOLS, "job.toml")
