"""Operation types of job files and the modules that plan them.

Modules are imported only when a job uses their type, so a missing optional
dependency of one strategy does not break the others.
"""

from __future__ import annotations

import importlib
from types import ModuleType

from millpath.errors import JobError

STRATEGIES: dict[str, str] = {
    "grid-pocket": "millpath.plan.gridpocket.operation",
    "die-cavity": "millpath.plan.diecavity.operation",
    "features": "millpath.plan.features.operation",
    "surface-finish": "millpath.plan.surface.operation",
    "surface-rough": "millpath.plan.surface.rough",
    "pocket": "millpath.plan.pocket.operation",
    "profile": "millpath.plan.profile.operation",
}


def strategy(op_type: str, where: str = "operations", file=None) -> ModuleType:
    """The module planning ``op_type``; JobError if the type is unknown."""
    if op_type not in STRATEGIES:
        raise JobError(f"{where}.type: unknown operation type {op_type!r} "
                       f"(known: {', '.join(sorted(STRATEGIES))})", file)
    return importlib.import_module(STRATEGIES[op_type])


#: keys that change an operation's air time, then its length, in the order to try them
AIR_KEYS = ("strategy", "region", "rest", "entry", "safe_z")
LONG_KEYS = ("scallop", "side_step", "stepover", "stepdown", "feed")


def time_keys(op_type: str, *, air: bool, long: bool) -> list[str]:
    """The keys of ``op_type`` that change its air time (``air``) and its length
    (``long``), as its schema has them."""
    params = strategy(op_type).PARAMS
    want = (AIR_KEYS if air else ()) + (LONG_KEYS if long else ())
    return [k for k in dict.fromkeys(want) if k in params]
