"""What every strategy receives and returns.

A strategy module (see :mod:`millpath.plan.registry`) defines

- ``PARAMS: dict[str, Param]``: its job-file keys (besides ``type``), validated by the
  job loader; unknown keys are errors;
- ``plan(ctx: PlanContext, params: dict) -> PlanResult``: a pure function.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Protocol

import numpy as np

from millpath.model import Machine, Stock, Tool, Toolpath
from millpath.part.cache import PartCache
from millpath.progress import QUIET, Progress


class Design(Protocol):
    """The designed part as a height field seen from above (3-axis, no undercuts).

    ``height(x, y)`` returns the Z of the finished part's top surface at each point
    (arrays of equal shape, job units); ``-inf`` where the part has no material
    (through holes). Material above it should be removed; the tool must never go below
    it (that is a gouge).
    """

    def height(self, x: np.ndarray, y: np.ndarray) -> np.ndarray: ...


class Remaining(Protocol):
    """The in-process stock left by the earlier operations of the job (read-only).

    ``height(x, y)``: Z of the top of the material at each point (arrays of equal
    shape, job units), the stock bottom where nothing is left; ``resolution``: the
    width of the cells it is known on (a Z-map from the simulator).
    """

    resolution: float

    def height(self, x: np.ndarray, y: np.ndarray) -> np.ndarray: ...


@dataclass
class PlanContext:
    units: str                     # "mm" | "inch"
    stock: Stock | None
    machine: Machine
    tools: dict[int, Tool]
    base_dir: Path                 # folder of the job file: relative paths start here
    job_file: Path | None = None
    remaining: Remaining | None = None   # in-process stock; None: the full stock block
    progress: Progress = QUIET     # bars on stderr for long steps (millpath.progress)
    parts: PartCache = field(default_factory=PartCache)   # inputs loaded once per job

    def tool(self, number: int, where: str = "tool") -> Tool:
        from millpath.errors import JobError
        if number not in self.tools:
            raise JobError(f"{where}: tool {number} is not in the job's [[tools]]",
                           self.job_file)
        return self.tools[number]


@dataclass
class PlanResult:
    toolpath: Toolpath
    design: Design | None = None   # for the simulator's gouge / left-over checks
    report: dict[str, Any] = field(default_factory=dict)   # extra report.json sections
    stock: Stock | None = None     # stock the operation implies (e.g. from a STEP file)
