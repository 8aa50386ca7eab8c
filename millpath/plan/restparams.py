"""The job keys of operations that can cut only what earlier operations left (see
:mod:`millpath.plan.restcut`, which does the cutting; kept apart so that reading a job
does not load its numba kernels)."""

from __future__ import annotations

from millpath.io.schema import Param

#: the keys of an operation that can cut only what earlier operations left
REST_PARAMS = {
    "rest": Param("bool", False, doc="cut only where earlier operations left material"),
    "rest_allowance": Param("float", None, nonneg=True, unit="length",
                            doc="rest: stock thinner than this is left (default: the "
                                "in-process stock's cell)"),
}
