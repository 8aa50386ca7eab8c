"""The model: tools, stock, machine and toolpaths as plain dataclasses."""

from millpath.model.stock import Machine, Stock
from millpath.model.tool import Tool
from millpath.model.toolpath import Move, Operation, Toolpath

__all__ = ["Machine", "Move", "Operation", "Stock", "Tool", "Toolpath"]
