"""Tool data for the interpreter: number -> (diameter, x, y, z offsets), machine units.

Accepts a LinuxCNC tool table path, a list of ``ToolEntry`` rows, or a dict of
millpath ``Tool`` (diameter, gauge length as the Z offset). Values are in the machine
units (rs274 reads them as inches; ``machine_units`` says which).
"""

from __future__ import annotations

from pathlib import Path

from millpath.io.tooltable import ToolEntry, read_tool_table


def load_tools(tools) -> dict[int, tuple[float, float, float, float]]:
    """Normalize ``tools`` to ``{number: (diameter, x_offset, y_offset, z_offset)}``."""
    if tools is None:
        return {}
    if isinstance(tools, (str, Path)):
        tools = read_tool_table(tools)
    out: dict[int, tuple[float, float, float, float]] = {}
    if isinstance(tools, dict):
        for num, t in tools.items():
            if isinstance(t, ToolEntry):
                out[int(num)] = (t.diameter, t.offsets.get("X", 0.0), t.offsets.get("Y", 0.0),
                                 t.offsets.get("Z", 0.0))
            else:
                out[int(num)] = (float(t.diameter), 0.0, 0.0, float(t.gauge_length))
        return out
    for t in tools:
        if isinstance(t, ToolEntry):
            out[t.number] = (t.diameter, t.offsets.get("X", 0.0), t.offsets.get("Y", 0.0),
                             t.offsets.get("Z", 0.0))
        else:
            out[int(t.number)] = (float(t.diameter), 0.0, 0.0, float(t.gauge_length))
    return out
