"""One table from exception types to HTTP status, and the one-line bodies: {"detail": "...", "field": ...}.

Validation errors reuse footprint.contracts.messages.error_parts, so a REST user reads the same line as a CLI user,
with the field's path in the request (e.g. "study.case.entry.velocity_fps: 50 is outside the allowed range ...")."""

import logging
from collections.abc import Callable, Iterable
from typing import Any

from fastapi import FastAPI, Request
from fastapi.dependencies.utils import get_dependant
from fastapi.exceptions import RequestValidationError
from fastapi.responses import JSONResponse
from fastapi.routing import APIRoute
from pydantic import BaseModel, ValidationError
from starlette.exceptions import HTTPException as StarletteHTTPException
from starlette.routing import compile_path

from footprint.contracts.messages import (
    ECHO_CHARS,
    ERROR_MESSAGE_CHARS,
    MAX_ERROR_FIELDS,
    clip,
    error_parts,
    errors_parts,
)
from footprint.core.errors import InputError

log = logging.getLogger("footprint.service")


class RequestInvalid(ValueError):
    """A request field is out of range or inconsistent (422); `field` is its dotted path in the request."""

    def __init__(self, detail: str, field: str | None):
        super().__init__(detail)
        self.detail, self.field = detail, field


class NotFound(LookupError):
    """An unknown id (404)."""


class Conflict(Exception):
    """The request clashes with stored state: a taken id, a built-in vehicle (409)."""


class Unauthorized(PermissionError):
    """A write without the bearer token (401)."""


class CrossSiteWrite(PermissionError):
    """A write from a page of another origin (403): a form or a simple request needs no CORS preflight."""


class MisdirectedHost(PermissionError):
    """A request naming a host this service does not serve (421): DNS rebinding's page on another name."""


class UnsupportedMediaType(ValueError):
    """A body of a type the route does not read (415)."""


class BodyTooLarge(Exception):
    """A request body over the limit (413)."""


class HeadersTooLarge(Exception):
    """A request's headers over the limit (431)."""


class UrlTooLong(Exception):
    """A request's path and query over the limit (414)."""


class Unavailable(RuntimeError):
    """Something the service needs is not installed or not reachable (503)."""


class MethodNotAllowed(Exception):
    """A method the path does not answer (405, with the path's Allow)."""

    def __init__(self, allowed: list[str]):
        super().__init__(f"Method Not Allowed (allowed: {', '.join(allowed)})")
        self.allowed = allowed


class ErrorBody(BaseModel):
    """Every error the service answers (issue 14: the OpenAPI document declares this, not FastAPI's default)."""

    detail: str  # one readable line
    field: str | None = None  # a 422's offending field, its dotted path in the request


ERRORS = {
    422: "a field out of range or inconsistent, named in `field`",
    400: "a body that cannot be read",
    404: "no such id",
    401: "a write without the bearer token (when FOOTPRINT_API_TOKEN is set)",
    413: "a body over the limit",
    409: "a clash with stored state",
    503: "a part the service needs is missing",
    403: "a write from a page of another origin",
    415: "a body of a type the route does not read",
    421: "a Host this service does not serve (FOOTPRINT_ALLOWED_HOSTS)",
    414: "a path and query over the limit",
    431: "headers over the limit",
}
WRITES = {"post", "put", "patch", "delete"}
ERROR_REF = {"$ref": "#/components/schemas/ErrorBody"}


STATUS_BY_EXCEPTION = {  # the only place an exception type meets a status code
    RequestInvalid: 422,
    InputError: 422,
    ValidationError: 422,
    RequestValidationError: 422,
    NotFound: 404,
    Conflict: 409,
    Unauthorized: 401,
    BodyTooLarge: 413,
    UrlTooLong: 414,
    HeadersTooLarge: 431,
    Unavailable: 503,
    MethodNotAllowed: 405,
    CrossSiteWrite: 403,
    MisdirectedHost: 421,
    UnsupportedMediaType: 415,
}


def invalid(exc: ValidationError | InputError, prefix: str = "") -> RequestInvalid:
    """A contract parser's error as a 422 naming the field in the request (`prefix` places it there)."""
    parts = error_parts(exc)
    detail = "; ".join(f"{prefix}{text}" for _, text in parts)
    field = next((f"{prefix}{field}" for field, _ in parts if field), None)
    return RequestInvalid(detail, field or prefix.rstrip(".") or None)


def error_body(exc: Exception, request: Request | None = None) -> dict:
    """{"detail": one line, "field": the offending field for a 422} (`request`: the one FastAPI's checks refused)."""
    if isinstance(exc, RequestInvalid):
        return {"detail": exc.detail, "field": exc.field}
    if isinstance(exc, (InputError, ValidationError)):
        inv = invalid(exc)
        return {"detail": inv.detail, "field": inv.field}
    if isinstance(exc, RequestValidationError):
        return _request_validation_body(exc, _tagged_body(request))
    return {"detail": clip(str(exc), ERROR_MESSAGE_CHARS)}


def _tagged_body(request: Request | None) -> bool:
    """The request's route reads a discriminated union (POST /api/jobs: one model per kind)."""
    field = getattr(request.scope.get("route") if request else None, "body_field", None)
    return getattr(getattr(field, "field_info", None), "discriminator", None) is not None


def _request_validation_body(exc: RequestValidationError, tagged: bool) -> dict:
    """FastAPI's checks in the same one-line form: a body's by the contracts' error_parts (the kind of a `tagged`
    body, first in the location, is pydantic's tag, not a field), the path's and query's, JSON syntax."""
    body = [e for e in exc.errors() if e.get("loc", ())[:1] == ("body",) and e.get("type") != "json_invalid"]
    if body and len(body) == len(exc.errors()) and (body[0]["loc"], body[0]["type"]) != (("body",), "missing"):
        errs = [e | {"loc": e["loc"][2 if tagged and len(e["loc"]) > 1 else 1 :]} for e in body]
        parts = [(f, t) if f else ("body", f"body: {t}") for f, t in errors_parts(errs)]  # the body as a whole
        return {"detail": "; ".join(text for _, text in parts), "field": next((f for f, _ in parts if f), None)}
    parts, field, errs = [], None, exc.errors()
    for err in errs[:MAX_ERROR_FIELDS]:
        loc = [clip(str(x), ECHO_CHARS) for x in err.get("loc", ()) if x not in ("body", "query", "path")]
        name = ".".join(loc) or "body"
        msg = clip(err.get("msg", "invalid").removeprefix("Value error, "), ERROR_MESSAGE_CHARS)
        if err.get("type") == "json_invalid":  # its loc is the offset in the body ("field 0"): name the body
            name, msg = "body", f"not valid JSON ({err.get('ctx', {}).get('error', 'syntax error')})"
        field = field or name
        parts.append(f"{name}: {msg}")
    if len(errs) > MAX_ERROR_FIELDS:
        parts[-1] += f" (and {len(errs) - MAX_ERROR_FIELDS:,} more fields with errors)"
    return {"detail": "; ".join(parts), "field": field}


def status_of(exc: Exception) -> int:
    for kind, status in STATUS_BY_EXCEPTION.items():
        if isinstance(exc, kind):
            return status
    return 500


class ApiRoute(APIRoute):
    """A route of the API that declares the ErrorBody answers it can give (issue 14), so that the generated document
    holds them: 422 (in place of FastAPI's validation schema, which the service never sends), 414, 421 and 431
    everywhere, 400 where a body is read, 404 under a path with an id, 401, 403 and 413 on writes, and the 409, 415
    and 503 a route names itself."""

    def __init__(self, path: str, endpoint: Callable[..., Any], **kwargs: Any) -> None:
        methods = {m.lower() for m in kwargs.get("methods") or ()}
        given = {int(code): answer for code, answer in (kwargs.get("responses") or {}).items()}
        reads_body = bool(get_dependant(path=path, call=endpoint).body_params) or "requestBody" in (
            kwargs.get("openapi_extra") or {}
        )
        codes = (
            {414, 421, 422, 431}
            | ({404} if "{" in path else set())
            | ({401, 403, 413} if methods & WRITES else set())
            | ({400} if reads_body else set())
            | (given.keys() & {409, 415, 503})
        )
        json_route = getattr(kwargs.get("response_class"), "media_type", "application/json") == "application/json"
        for code in codes:  # an HTML or streaming route's errors are JSON all the same: said so by reference
            body = {"model": ErrorBody} if json_route else {"content": {"application/json": {"schema": ERROR_REF}}}
            given[code] = {**body, "description": ERRORS[code]} | given.get(code, {})
        super().__init__(path, endpoint, **(kwargs | {"responses": given}))


def error_response(exc: Exception, request: Request | None = None) -> JSONResponse:
    """The one-line body with the exception's status (and the headers that go with a 401 or a 405)."""
    headers = {"WWW-Authenticate": "Bearer"} if isinstance(exc, Unauthorized) else None
    if isinstance(exc, MethodNotAllowed):
        headers = {"Allow": ", ".join(exc.allowed)}
    return JSONResponse(error_body(exc, request), status_code=status_of(exc), headers=headers)


HTTP_METHODS = ("GET", "HEAD", "POST", "PUT", "PATCH", "DELETE", "OPTIONS", "TRACE")


class ApiPaths:
    """Every path pattern of the service's routes and the methods they answer, compiled once per app: matching each
    route of FastAPI's nested routers for every method took 43% of a read's time at 200 concurrent readers."""

    def __init__(self, routes: Iterable[tuple[str, Iterable[str]]]) -> None:
        table: dict[str, set[str]] = {}
        for path, methods in routes:
            table.setdefault(path, set()).update(methods)
        self._patterns = [(compile_path(path)[0], frozenset(methods)) for path, methods in table.items()]

    def allowed(self, path: str) -> list[str]:
        """The methods some route answers at this path (none: no such path), HEAD wherever GET is (GuardMiddleware
        answers HEAD); the page's static files are not the API's."""
        found = set().union(*(methods for pattern, methods in self._patterns if pattern.match(path)))
        return [m for m in HTTP_METHODS if m in found or (m == "HEAD" and "GET" in found)]


def install(app: FastAPI) -> None:
    """Answer every exception type of the table with its status and a one-line body."""

    async def handle(request: Request, exc: Exception) -> JSONResponse:
        return error_response(exc, request)

    async def http_error(request: Request, exc: StarletteHTTPException) -> JSONResponse:
        methods = app.state.api_paths.allowed(request.url.path) if exc.status_code == 405 else []
        if methods:  # Starlette's Allow names the first matching route's methods, not the path's
            return error_response(MethodNotAllowed(methods))
        return JSONResponse({"detail": str(exc.detail)}, status_code=exc.status_code, headers=exc.headers)

    for kind in STATUS_BY_EXCEPTION:
        app.add_exception_handler(kind, handle)
    app.add_exception_handler(StarletteHTTPException, http_error)


class Unexpected:
    """The last resort for an exception no handler takes: logged with its traceback, answered with a one-line 500, and
    not raised on. Starlette's ServerErrorMiddleware raises it again after its 500, and uvicorn then closes the
    keep-alive connection, so the client's next request failed with a reset. Only a response cut off mid-body
    raises on: that connection cannot carry another request."""

    BODY = {"detail": "internal error (the server's log has the traceback)"}  # never the exception's text: SQL

    def __init__(self, app):
        self.app = app

    async def __call__(self, scope, receive, send) -> None:
        if scope["type"] != "http":
            await self.app(scope, receive, send)
            return
        state = {"started": False, "complete": False}

        async def tracked(message) -> None:
            if message["type"] == "http.response.start":
                state["started"] = True
            elif message["type"] == "http.response.body" and not message.get("more_body", False):
                state["complete"] = True
            await send(message)

        try:
            await self.app(scope, receive, tracked)
        except Exception as exc:  # noqa: BLE001 -- the one place an unexpected error is logged and answered
            log.error("%s %s failed", scope["method"], scope["path"][:200], exc_info=exc)
            if not state["started"]:
                await JSONResponse(self.BODY, status_code=500)(scope, receive, send)
            elif not state["complete"]:
                raise
