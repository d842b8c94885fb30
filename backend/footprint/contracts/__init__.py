"""The request contracts: one module per kind of request, each with its pydantic model, the limits that bound the
work it asks for, `parse_request(data, ctx)` and `run(request, ...)`; one registry of kinds for the CLI, the Python
API and the service.

    parse(kind, data, ctx)  -> the validated request (pydantic's ValidationError names the field)
    module(kind).run(request, ...)
"""

import importlib
from types import ModuleType

MODULES = {"case": "case", "footprint": "footprint", "optimize": "optimization", "sweep": "sweep",
           "transform": "transform", "reach": "reach", "dispersion": "dispersion"}  # kind -> footprint.contracts.<module>
JOB_KINDS = ("footprint", "optimize", "sweep", "reach", "dispersion")  # the kinds the service runs as jobs, on Dask


def module(kind: str) -> ModuleType:
    """The contract module of a kind (imported on first use: the optimization's pulls in CasADi)."""
    return importlib.import_module(f"footprint.contracts.{MODULES[kind]}")


def parse(kind: str, data, ctx: dict | None = None):
    """A request of this kind from a dict (a parsed request passes through); ctx from case.context()."""
    return module(kind).parse_request(data, ctx)
