"""The doors a request comes through and the limits each sets. A request is validated with a context: the door
("python" for the CLI and the Python API, "http" for the service's jobs, which share its workers and bound the work
more tightly, "http-sync" for the requests the API process answers itself, bounded to seconds) and, over HTTP, the
stored vehicles and landing sites."""

from collections.abc import Callable
from contextvars import ContextVar
from typing import Any

from pydantic import TypeAdapter, ValidationError, ValidationInfo, ValidatorFunctionWrapHandler

HTTP = "http"
HTTP_SYNC = "http-sync"
IN_A_SYNCHRONOUS_REQUEST = " in a synchronous request (a job may ask for more: POST /api/jobs)"
# the context of the bodies the service's framework validates: FastAPI passes none to pydantic, so the route's door
# sets it for the request's task before the body is read (pydantic's own pattern for a context in __init__)
_REQUEST_CONTEXT: ContextVar[dict[str, Any] | None] = ContextVar("footprint_request_context", default=None)


def context(
    door: str = "python",
    vehicles: Callable[[str], dict[str, Any] | None] | None = None,
    sites: Callable[[], list[dict[str, Any]]] | None = None,
) -> dict[str, Any]:
    """The validation context of a door; `vehicles(id) -> definition | None` resolves {"stored": id}, `sites()`
    gives the stored landing sites a reach with none of its own is asked for."""
    return {"door": door, "vehicles": vehicles, "sites": sites}


def enter(ctx: dict[str, Any]) -> None:
    """The context of the requests validated from here on in this task (and the threads it hands work to)."""
    _REQUEST_CONTEXT.set(ctx)


def context_of(info: ValidationInfo) -> dict[str, Any]:
    """A validation's context: the one it was given (contracts.parse), else the request's (enter)."""
    if info.context is not None:
        return dict(info.context)
    return _REQUEST_CONTEXT.get() or {}


def door_limit(info: ValidationInfo, python: float, http: float, sync: float | None = None) -> tuple[float, str]:
    """The limit that applies through the request's door (`sync`: a synchronous request's, default http's), and
    how to say it."""
    door = context_of(info).get("door")
    if door == HTTP_SYNC and sync is not None:
        return sync, IN_A_SYNCHRONOUS_REQUEST
    if door in (HTTP, HTTP_SYNC):
        return http, " over HTTP"
    return python, ""


def synchronous(info: ValidationInfo) -> bool:
    """The request is answered by the API process itself, not a worker."""
    return context_of(info).get("door") == HTTP_SYNC


def validated(adapter: TypeAdapter[Any], data: Any, model: type, ctx: dict[str, Any] | None = None) -> Any:
    """One request of a kind: a model passes through; a dict is validated (pydantic's ValidationError names the
    field, an InputError from the core too; Python's arithmetic failing in a validator is one too: computable)."""
    if isinstance(data, model):
        return data
    try:
        return adapter.validate_python(data, context=ctx if ctx is not None else _REQUEST_CONTEXT.get() or context())
    except ArithmeticError as exc:
        raise _uncomputable(exc, data) from exc


def uncomputed(exc: BaseException) -> str:
    """The line for values Python could not compute in a check (the exception's own words in parentheses)."""
    return (
        f"these values cannot be computed (Python's {type(exc).__name__}: {exc}); the check that would name the "
        "allowed range is missing here: please report it"
    )


def computable(value: Any, handler: ValidatorFunctionWrapHandler) -> Any:
    """A WrapValidator around a request (a job's study): an OverflowError or ZeroDivisionError inside its validators,
    which pydantic passes on (the service answered 500, the CLI a traceback), as the request's mistake."""
    try:
        return handler(value)
    except ArithmeticError as exc:
        raise ValueError(uncomputed(exc)) from exc


def _uncomputable(exc: ArithmeticError, data: Any) -> ValidationError:
    """A validation that Python's arithmetic broke, as pydantic's error of the request as a whole."""
    error = {"type": "value_error", "loc": (), "input": data, "ctx": {"error": ValueError(uncomputed(exc))}}
    return ValidationError.from_exception_data("request", [error])  # type: ignore[list-item]
