"""TOML tool library: ``[[tools]]`` tables carrying everything a :class:`Tool` has.

Keys: ``number`` (required), ``type`` (flat | ball | bull | drill), ``diameter``,
``corner_radius`` (bull), ``flutes``, ``flute_length``, ``stickout`` (holder face to
tip), ``holder`` (``[[diameter, length], ...]`` from the holder face upward),
``material``, ``point_angle`` (drill, degrees), ``shank_diameter``, ``length`` (gauge
length for the tool table; default stickout + holder), ``comment``. Lengths are in the
job's units.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import tomli_w

from millpath.errors import JobError, Problems
from millpath.io.schema import Param, parse_toml, validate
from millpath.model.limits import (MAX_COORDINATE, Limits, check_length,
                                   check_tool_diameter)
from millpath.model.tool import TOOL_TYPES, Tool
from millpath.model.units import length_scale

TOOL = {
    "number": Param("int", positive=True, doc="tool number (T and the tool table's P)"),
    "type": Param("str", "flat", choices=TOOL_TYPES, doc="cutter shape"),
    "diameter": Param("float", positive=True, unit="length", doc="cutting diameter"),
    "corner_radius": Param("float", 0.0, nonneg=True, unit="length",
                           doc="corner radius of a bull-nose cutter"),
    "flutes": Param("int", 2, positive=True, unit="count", doc="number of cutting edges"),
    "flute_length": Param("float", None, positive=True, unit="length",
                          doc="cutting length, from the tip up"),
    "stickout": Param("float", None, positive=True, unit="length",
                      doc="from the holder face to the tip"),
    "holder": Param("list", [], unit="length",
                    doc="[[diameter, length], ...] cylinders stacked up from the holder face"),
    "material": Param("str", "carbide", doc="tool material (for speeds and feeds)"),
    "point_angle": Param("float", 118.0, positive=True, unit="deg",
                         doc="included point angle of a drill"),
    "shank_diameter": Param("float", None, positive=True, unit="length",
                            doc="shank above the flutes (default: the diameter)"),
    "length": Param("float", None, positive=True, unit="length",
                    doc="gauge length for the tool table (default: stickout + holder)"),
    "comment": Param("str", "", doc="written in the tool table and the program"),
}


def tools_from_tables(tables: Any, file: str | Path | None = None,
                      units: str = "mm", limits: Limits | None = None,
                      problems: Problems | None = None) -> dict[int, Tool]:
    """Validate a list of ``[[tools]]`` tables and build Tools keyed by number: diameters
    within :data:`~millpath.model.limits.TOOL_DIAMETER`, the tool's whole length
    (stick-out and holder) and the holder's diameters within ``limits.max_extent``
    (default: the units' own). With ``problems``, each tool's problems are recorded
    there and the other tools are read on; without, the first raises."""
    limits = limits or Limits.default_for(units)
    if not isinstance(tables, list):
        raise JobError("tools: expected an array of tables [[tools]]", file)
    out: dict[int, Tool] = {}
    for i, t in enumerate(tables):
        if problems is None:
            _tool(t, f"tools[{i}]", out, file, units, limits)
            continue
        with problems.gather():
            _tool(t, f"tools[{i}]", out, file, units, limits)
    return out


def _tool(t: Any, where: str, out: dict[int, Tool], file: str | Path | None, units: str,
          limits: Limits) -> None:
    """Validate one ``[[tools]]`` table and add its Tool to ``out``."""
    v = validate(t, TOOL, where, file)
    holder = []
    for j, h in enumerate(v["holder"]):
        if (not isinstance(h, list) or len(h) != 2
                or not all(isinstance(x, (int, float)) and not isinstance(x, bool)
                           and 0 < x <= MAX_COORDINATE for x in h)):
            raise JobError(f"{where}.holder[{j}]: expected [diameter, length], each > 0 "
                           f"and at most {MAX_COORDINATE:g}", file)
        holder.append((float(h[0]), float(h[1])))
    if v["number"] in out:
        raise JobError(f"{where}.number: tool {v['number']} is defined twice", file)
    d = v["diameter"]
    bad = check_tool_diameter(d, units)
    if bad:
        raise JobError(f"{where}.diameter: {bad}", file)
    scale = length_scale("inch", units)
    flute = v["flute_length"] or max(3.0 * d, 0.5 * scale)
    stick = v["stickout"] or max(flute + 0.2 * scale, 1.5 * flute)
    for key, value, what in (
            ("stickout", stick, "stick-out"),
            ("length", v["length"] or 0.0, "tool length"),
            ("holder", stick + sum(h[1] for h in holder), "tool and holder length"),
            ("holder", max((h[0] for h in holder), default=0.0), "holder diameter"),
            ("shank_diameter", v["shank_diameter"] or 0.0, "shank diameter")):
        bad = check_length(value, units, limits.max_extent, what)
        if bad:
            raise JobError(f"{where}.{key}: {bad}", file)
    try:
        out[v["number"]] = Tool(
            number=v["number"], type=v["type"], diameter=d,
            corner_radius=v["corner_radius"], flutes=v["flutes"], flute_length=flute,
            stickout=stick, holder=holder, material=v["material"],
            point_angle=v["point_angle"], shank_diameter=v["shank_diameter"],
            length=v["length"], comment=v["comment"])
    except ValueError as e:
        raise JobError(f"{where}: {e}", file) from None
    if flute > stick:
        raise JobError(f"{where}.flute_length: longer than the stickout", file)


def read_tool_library(path: str | Path, units: str = "mm") -> dict[int, Tool]:
    """Read a TOML tool library file (``[[tools]]`` entries), its lengths in ``units``.

    A library's top-level ``units`` ("mm" | "inch", default ``units``) is the unit its
    lengths are written in; they are converted to ``units``."""
    p = Path(path)
    data = parse_toml(p.read_text(encoding="utf-8"), p)
    for k in data:
        if k not in ("tools", "units"):
            raise JobError(f"{k}: unknown key (allowed: tools, units)", p)
    own = data.get("units", units)
    if own not in ("mm", "inch"):
        raise JobError(f"units: expected \"mm\" or \"inch\", not {own!r}", p)
    tools = tools_from_tables(data.get("tools", []), p, own)
    k = length_scale(own, units)
    return tools if k == 1.0 else {n: t.scaled(k) for n, t in tools.items()}


def tool_to_table(t: Tool) -> dict[str, Any]:
    d: dict[str, Any] = {"number": t.number, "type": t.type, "diameter": t.diameter}
    if t.type == "bull":
        d["corner_radius"] = t.corner_radius
    d.update(flutes=t.flutes, flute_length=t.flute_length, stickout=t.stickout,
             holder=[[a, b] for a, b in t.holder], material=t.material)
    if t.type == "drill":
        d["point_angle"] = t.point_angle
    if t.shank_diameter is not None:
        d["shank_diameter"] = t.shank_diameter
    if t.length is not None:
        d["length"] = t.length
    if t.comment:
        d["comment"] = t.comment
    return d


def write_tool_library(tools: dict[int, Tool] | list[Tool], units: str = "mm") -> str:
    """TOML text of a tool library; ``read_tool_library`` gives the same tools back."""
    seq = tools.values() if isinstance(tools, dict) else tools
    return tomli_w.dumps({"units": units,
                          "tools": [tool_to_table(t) for t in sorted(seq, key=lambda t: t.number)]})
