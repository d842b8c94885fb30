"""The doors a request comes through and the limits each sets. A request is validated with a context: the door
("python" for the CLI and the Python API, "http" for the service's jobs, which share its workers and bound the work
more tightly, "http-sync" for the requests the API process answers itself, bounded to seconds) and, over HTTP, the
stored vehicles."""

from collections.abc import Callable
from typing import Any

from pydantic import TypeAdapter, ValidationInfo

HTTP = "http"
HTTP_SYNC = "http-sync"


def context(door: str = "python", vehicles: Callable[[str], dict[str, Any] | None] | None = None) -> dict[str, Any]:
    """The validation context of a door; `vehicles(id) -> definition | None` resolves {"stored": id}."""
    return {"door": door, "vehicles": vehicles}


def door_limit(info: ValidationInfo, python: float, http: float, sync: float | None = None) -> tuple[float, str]:
    """The limit that applies through the request's door (`sync`: a synchronous request's, default http's), and
    how to say it."""
    door = (info.context or {}).get("door")
    if door == HTTP_SYNC and sync is not None:
        return sync, " in a synchronous request (a job may ask for more: POST /api/jobs)"
    if door in (HTTP, HTTP_SYNC):
        return http, " over HTTP"
    return python, ""


def synchronous(info: ValidationInfo) -> bool:
    """The request is answered by the API process itself, not a worker."""
    return (info.context or {}).get("door") == HTTP_SYNC


def validated(adapter: TypeAdapter[Any], data: Any, model: type, ctx: dict[str, Any] | None = None) -> Any:
    """One request of a kind: a model passes through; a dict is validated (pydantic's ValidationError names the
    field, an InputError from the core too)."""
    return data if isinstance(data, model) else adapter.validate_python(data, context=ctx or context())
