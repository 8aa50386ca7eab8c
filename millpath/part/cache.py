"""Inputs loaded once per job.

The pipeline gives every operation of a job the same :class:`PartCache` (through
``PlanContext.parts``), so a part several operations name (one STL for a roughing and
a finishing pass, one DXF, one STEP solid) is read, meshed and indexed once. A value is
stored under ``(kind, key)``; ``key`` holds everything the value depends on (the file
as given and the folder it is relative to, the placement table, units, tolerances),
nested dicts and lists included. A load that fails stores nothing (the next caller
gets the same error). Values are shared: callers must not modify them.
"""

from __future__ import annotations

from collections import Counter
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable, TypeVar

T = TypeVar("T")


def freeze(value: Any) -> Any:
    """``value`` as a hashable key: dicts as sorted item tuples, lists as tuples,
    paths as strings; numbers and strings as they are."""
    if isinstance(value, dict):
        return ("dict",) + tuple(sorted((str(k), freeze(v)) for k, v in value.items()))
    if isinstance(value, (list, tuple)):
        return ("seq",) + tuple(freeze(v) for v in value)
    if isinstance(value, Path):
        return str(value)
    if hasattr(value, "tolist"):               # numpy scalars and arrays
        return freeze(value.tolist())
    return value


@dataclass
class PartCache:
    """Loaded inputs by ``(kind, key)``; ``loads`` counts the loads done per kind."""

    items: dict = field(default_factory=dict)
    loads: Counter = field(default_factory=Counter)

    def get(self, kind: str, key: Any, load: Callable[[], T]) -> T:
        """The value stored for ``(kind, key)``, loading it with ``load()`` the first
        time."""
        k = (kind, freeze(key))
        if k in self.items:
            return self.items[k]
        value = load()
        self.items[k] = value
        self.loads[kind] += 1
        return value
