"""Cutting data: material classes, cutting speeds and chip loads, spindle and feed.

Tables hold starting values for carbide tools, as handbooks and tool makers publish
them for general machining (not for a particular machine): cutting speed ``vc``
(m/min) and, for a 10 mm tool, the chip load per tooth ``fz`` (mm/tooth) of end mills
and the feed per revolution ``fr`` (mm/rev) of twist drills. Chip loads scale with the
tool diameter (linearly, between 0.2x and 2x the 10 mm value). High speed steel tools
run at 35 % of the carbide cutting speed.

Spindle speed ``n = 1000 vc / (pi D)`` (rpm, D in mm), milling feed ``F = fz z n`` and
drilling feed ``F = fr n`` (mm/min), converted to the job's units (inch/min for inch
jobs) and clamped to ``max_rpm`` and the machine's maximum feed.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from millpath.model import Tool
from millpath.model.units import default, length_scale


@dataclass(frozen=True)
class CuttingData:
    vc_mill: float      # m/min, carbide end mill
    fz_mill: float      # mm/tooth at D = 10 mm
    vc_drill: float     # m/min, carbide drill
    fr_drill: float     # mm/rev at D = 10 mm
    chip_breaking: bool  # long chips: peck with chip breaking (G73) up to 6 D


MATERIALS: dict[str, CuttingData] = {
    "aluminium": CuttingData(300.0, 0.08, 120.0, 0.25, True),
    "brass-bronze": CuttingData(150.0, 0.05, 70.0, 0.20, False),
    "copper": CuttingData(180.0, 0.05, 80.0, 0.15, True),
    "steel": CuttingData(120.0, 0.05, 70.0, 0.18, True),
    "alloy-steel": CuttingData(90.0, 0.04, 50.0, 0.15, True),
    "stainless": CuttingData(70.0, 0.03, 35.0, 0.12, True),
    "cast-iron": CuttingData(100.0, 0.05, 60.0, 0.25, False),
    "titanium": CuttingData(45.0, 0.03, 25.0, 0.10, True),
    "plastic": CuttingData(250.0, 0.10, 80.0, 0.20, True),
}

#: keywords (lower case) of material designations, tried in order
_KEYWORDS: list[tuple[str, tuple[str, ...]]] = [
    ("stainless", ("stainless", "inox", "304", "316", "17-4", "x5crni")),
    ("titanium", ("titanium", "ti-6al", "ti6al", "grade 5")),
    ("brass-bronze", ("bronze", "brass", "cuzn", "cusn", "latao", "pb 102", "pb102")),
    ("copper", ("copper", "cu-etp", "c101", "c110")),
    ("aluminium", ("alumin", "alu ", "6061", "6082", "7075", "2024", "5083", "almg", "alsi")),
    ("cast-iron", ("cast iron", "grey iron", "gray iron", "ductile", "gg25", "en-gjl", "en-gjs")),
    ("alloy-steel", ("4140", "4340", "42crmo", "alloy steel", "tool steel", "d2", "h13")),
    ("steel", ("steel", "aco", "sae 10", "aisi 10", "c45", "s235", "s355", "1018", "1020",
               "1045", "en8", "mild")),
    ("plastic", ("plastic", "pom", "delrin", "acetal", "nylon", "polyamide", "abs", "acrylic",
                 "pmma", "hdpe", "peek", "pvc", "polycarbonate")),
]


def material_class(designation: str, default: str = "steel") -> str:
    """The material class of a designation such as 'phosphor bronze to BS 2874 PB 102'."""
    d = f" {designation.lower()} "
    for cls, words in _KEYWORDS:
        if any(w in d for w in words):
            return cls
    return default


@dataclass(frozen=True)
class Speeds:
    rpm: float          # spindle speed, rev/min
    feed: float         # cutting feed, job units/min
    plunge: float       # axial feed for plunges and ramps, job units/min
    vc: float           # cutting speed actually used, m/min
    chip: float         # fz (mm/tooth) for mills, fr (mm/rev) for drills


def speeds(tool: Tool, material: str, units: str, *, max_rpm: float = 24000.0,
           max_feed: float | None = None, speed_scale: float = 1.0,
           feed_scale: float = 1.0) -> Speeds:
    """Spindle speed and feeds for ``tool`` (job ``units``) in material class ``material``;
    ``speed_scale`` and ``feed_scale`` multiply the table's cutting speed and chip load."""
    data = MATERIALS[material]
    scale = length_scale(units, "mm")
    d_mm = tool.diameter * scale
    hss = tool.material.lower() in ("hss", "hss-co", "hsse", "high speed steel")
    factor = (0.35 if hss else 1.0) * speed_scale
    size = min(max(d_mm / 10.0, 0.2), 2.0) * feed_scale
    if tool.type == "drill":
        vc = data.vc_drill * factor
        chip = data.fr_drill * size
    else:
        vc = data.vc_mill * factor
        chip = data.fz_mill * size
    rpm = 1000.0 * vc / (math.pi * d_mm)
    if rpm > max_rpm:
        rpm = max_rpm
        vc = rpm * math.pi * d_mm / 1000.0
    feed_mm = chip * rpm if tool.type == "drill" else chip * max(tool.flutes, 1) * rpm
    feed = feed_mm / scale
    if max_feed is not None:
        feed = min(feed, max_feed)
    plunge = feed if tool.type == "drill" else 0.3 * feed
    return Speeds(rpm=round(rpm), feed=_round_feed(feed, units), plunge=_round_feed(plunge, units),
                  vc=vc, chip=chip)


def _round_feed(f: float, units: str) -> float:
    q = default("feed_step", units)
    return max(q, round(round(f / q) * q, 4))
