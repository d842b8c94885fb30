"""The request contracts: one module per kind of request, each with its pydantic model, the limits that bound the
work it asks for, `parse_request(data, ctx)` and its `WORK` (footprint.contracts.work: how it splits, runs and
combines, and how a job stores it); one registry of kinds for the CLI, the Python API and the service.

    parse(kind, data, ctx)  -> the validated request (pydantic's ValidationError names the field)
    footprint.parallel.run(kind, request, ...)  -> the kind's answer, in this process or on Dask

Adding a kind is its module and one line here.
"""

import importlib
from types import ModuleType
from typing import Any

MODULES = {
    "case": "footprint.contracts.case",
    "footprint": "footprint.contracts.footprint",
    "optimize": "footprint.contracts.optimization",
    "sweep": "footprint.contracts.sweep",
    "transform": "footprint.contracts.transform",
    "reach": "footprint.contracts.reach",
    "dispersion": "footprint.contracts.dispersion",
    "guided_dispersion": "footprint.contracts.guided_dispersion",
    "guided_footprint": "footprint.contracts.guided_footprint",
    "guided_reach": "footprint.contracts.guided_reach",
    "opportunities": "footprint.contracts.opportunities",
}  # kind -> its contract module


def module(kind: str) -> ModuleType:
    """The contract module of a kind (imported on first use: the optimization's pulls in CasADi)."""
    return importlib.import_module(MODULES[kind])


def parse(kind: str, data: Any, ctx: dict[str, Any] | None = None) -> Any:
    """A request of this kind from a dict (a parsed request passes through); ctx from doors.context()."""
    return module(kind).parse_request(data, ctx)


def job_kinds() -> tuple[str, ...]:
    """The kinds the service runs as jobs, on Dask: those whose work a job stores (imports every contract)."""
    return tuple(kind for kind in MODULES if module(kind).WORK.store is not None)


def stored_form(request: Any) -> dict[str, Any]:
    """A parsed request as the job store and the workers read it: JSON, by alias, what was given (stored vehicles
    resolved)."""
    form: dict[str, Any] = request.model_dump(mode="json", by_alias=True, exclude_unset=True)
    return form
