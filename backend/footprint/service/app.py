"""create_app(settings): the FastAPI app. On start: migrations applied, the Dask cluster up, pending jobs
resubmitted, the built-in vehicle summaries computed; the API under /api, the docs at /docs, the map page
(frontend/) at /."""

import asyncio
import gc
import logging
import os
import re
import signal
import time
from contextlib import asynccontextmanager, suppress
from urllib.parse import parse_qs

from fastapi import FastAPI
from fastapi.middleware.cors import CORSMiddleware
from fastapi.responses import HTMLResponse, JSONResponse
from pydantic import TypeAdapter, ValidationError
from starlette.concurrency import run_in_threadpool
from starlette.datastructures import MutableHeaders
from starlette.requests import ClientDisconnect
from starlette.routing import Route
from starlette.types import ASGIApp, Message, Receive, Scope, Send

import footprint
from footprint import parallel
from footprint.csp import SECURITY_HEADERS, inline_script_hashes, page_policy
from footprint.service import deps, errors, nul, page, read_cache
from footprint.service.db.engine import make_engine, make_sessions, migrate
from footprint.service.jobs.engine import JobEngine, RemoteJobs
from footprint.service.routers import (
    dispersion,
    footprints,
    geometry,
    health,
    jobs,
    opportunities,
    sites,
    trajectories,
    vehicles,
)
from footprint.service.settings import MAX_BODY_BYTES, MAX_HEADER_BYTES, MAX_URL_BYTES, Settings

WRITE_METHODS = {"POST", "PUT", "PATCH", "DELETE"}
# POSTs that compute and store nothing: open like the reads when a token is set (a reach with store_verdicts writes)
COMPUTATIONS = re.compile(r"^/api/(trajectories|transform|reach|footprints/[^/]+/transform)$")
log = logging.getLogger("footprint.service")
_BOOL = TypeAdapter(bool)  # FastAPI's own parse of a bool query parameter


def create_app(
    settings: Settings, *, runs_jobs: bool = True, freezes_heap: bool = False, starts_behind: bool = False
) -> FastAPI:
    """The service for these settings (nothing starts until the app's lifespan begins); without `runs_jobs`, an API
    process whose jobs an engine in another process runs (service.processes); with `freezes_heap`, the app is its
    process's only one (footprint serve), whose start-up objects are frozen out of the garbage collector's way. With
    `starts_behind` (footprint serve), the lifespan returns at once and the start runs behind the open socket, health
    saying "starting" (a failed start ends the process); else the lifespan waits for it (a TestClient's start)."""
    db = make_engine(settings.database_url)
    # the job engine's threads connect through a pool of their own: no number of requests can leave a job waiting for
    # a connection (issue 49: two dispersions failed after 30 s of "QueuePool limit ... reached" under 200 readers)
    jobs_db = (
        make_engine(settings.database_url, pool_size=settings.job_threads + 2, max_overflow=settings.job_threads)
        if runs_jobs
        else None
    )

    async def start_up(app: FastAPI) -> None:
        """The slow part of a start (minutes on a loaded machine), after the socket is open: /api/health says
        "starting" and which step meanwhile, and every other /api request is a 503 (StartingGate)."""

        def step(words: str) -> None:
            app.state.starting = words
            log.info(words)

        try:
            step("migrating the database")
            await run_in_threadpool(migrate, db, settings.migrations_dir)
            step(
                "starting the job engine ("
                + (
                    f"the Dask scheduler {settings.dask_scheduler}"
                    if settings.dask_scheduler
                    else f"a local cluster of {settings.dask_workers} workers"
                )
                + ")"
            )
            await run_in_threadpool(app.state.jobs.start)
            step(
                "loading the flight kernels (numba): a first start compiles them, about a minute; later ones "
                "load them from its cache in seconds"
            )
            t0 = time.perf_counter()
            # before ready: a synchronous request is timed on its flight, not on compiling (a first guided one was
            # stopped by the 10 s limit while its kernels compiled), and the first /api/vehicles answers at once
            await run_in_threadpool(parallel.warm_numba)
            await run_in_threadpool(vehicles.warm_builtins)
            if freezes_heap:
                freeze_heap()
            app.state.starting = None
            log.info("ready (the flight kernels took %.0f s)", time.perf_counter() - t0)
        except Exception:
            if not starts_behind:
                raise  # the lifespan's own failure
            log.exception("the start failed while %s", app.state.starting)
            app.state.start_failed = True
            os.kill(os.getpid(), signal.SIGTERM)  # a start that cannot finish ends the process, as a failed lifespan

    @asynccontextmanager
    async def lifespan(app: FastAPI):
        app.state.starting = "starting"
        starting = asyncio.create_task(start_up(app))
        if not starts_behind:
            await starting
        try:
            yield
        finally:
            if not starting.done():
                starting.cancel()
                with suppress(asyncio.CancelledError):
                    await starting
            await run_in_threadpool(app.state.jobs.close)
            db.dispose()
            if jobs_db is not None:
                jobs_db.dispose()

    app = FastAPI(
        title="Footprint",
        version=footprint.__version__,
        lifespan=lifespan,
        docs_url=None,
        redoc_url=None,
        description="Landing footprints of lifting entry vehicles (AFWAL-TR-82-3036): jobs, "
        "footprints, trajectories, geometry, landing sites. See docs/api.md.",
    )
    app.state.settings, app.state.dialect = settings, db.dialect.name
    app.state.starting = None  # the start-up step under way while the lifespan's start runs; None once ready
    app.state.start_failed = False
    app.state.sessions = make_sessions(db)
    app.state.read_sessions = make_sessions(db, reads_only=True)
    app.state.read_limiter = deps.read_limiter()
    app.state.jobs = (
        JobEngine(sessions=make_sessions(jobs_db), settings=settings)
        if jobs_db is not None
        else RemoteJobs(settings=settings)
    )
    app.state.read_cache = read_cache.ReadCache()
    app.state.revisions = deps.revisions(app)
    app.state.shared_reads = read_cache.SharedReads()
    errors.install(app)
    routers = [
        module.router
        for module in (health, vehicles, trajectories, jobs, dispersion, opportunities, footprints, geometry, sites)
    ] + [jobs.submit_router()]
    for router in routers:
        app.include_router(router, prefix="/api")
    _api_docs(app, settings.tile_url)
    app.state.api_paths = errors.ApiPaths(
        [(r.path, r.methods) for r in app.routes if isinstance(r, Route)]
        + [("/api" + r.path, r.methods) for router in routers for r in router.routes]
    )
    app.add_middleware(read_cache.CachedGets, state=app.state)  # inside the guard: its checks come first
    app.add_middleware(StartingGate, state=app.state)  # outside the cache: nothing cached while starting
    app.add_middleware(
        GuardMiddleware,
        paths=app.state.api_paths,
        token=settings.api_token,
        max_body_bytes=MAX_BODY_BYTES,
        origins=settings.cors_origin_list,
        hosts=settings.host_names,
    )
    if settings.cors_origin_list:
        app.add_middleware(
            CORSMiddleware,
            allow_origins=settings.cors_origin_list,
            allow_credentials=False,
            allow_methods=["*"],
            allow_headers=["*"],
        )
    app.add_middleware(
        errors.Unexpected
    )  # outermost of ours: whatever escapes the others is a 500 on a kept connection
    if settings.frontend_dir.is_dir():
        app.mount("/", page.PageFiles(directory=settings.frontend_dir, html=True), name="frontend")
    # outside Starlette's own outermost layer, so that its 500s carry the headers too
    build = app.build_middleware_stack
    app.build_middleware_stack = lambda: SecurityHeadersMiddleware(
        build(), content_policy=page_policy(settings.tile_url)
    )
    return app


def freeze_heap() -> None:
    """Move every object made so far (numba's, Dask's, SQLAlchemy's, the app's: some 300,000) to the garbage
    collector's permanent generation, which its full collections skip. Each of those scanned them all: 170-670 ms with
    the event loop stopped, every second or two at 200 readers, the p99's tail (issue 49); after, 15-60 ms."""
    gc.collect()
    gc.freeze()


def _api_docs(app: FastAPI, tile_url: str) -> None:
    """/docs (Swagger UI) and /redoc from the page's vendor/ copies (npm swagger-ui-dist and redoc, `npm ci`):
    FastAPI's defaults load them from a CDN, which a machine without the internet cannot reach."""
    from fastapi.openapi.docs import get_redoc_html, get_swagger_ui_html

    @app.get("/docs", include_in_schema=False)
    def swagger_ui() -> HTMLResponse:
        page = get_swagger_ui_html(
            openapi_url=app.openapi_url,
            title="Footprint API",
            swagger_js_url="/vendor/swagger-ui/swagger-ui-bundle.js",
            swagger_css_url="/vendor/swagger-ui/swagger-ui.css",
            swagger_favicon_url="data:,",
        )
        # FastAPI's inline SwaggerUIBundle(...) set-up, allowed by its hash: it holds no user text
        page.headers["Content-Security-Policy"] = page_policy(tile_url, inline_script_hashes(page.body.decode()))
        return page

    @app.get("/redoc", include_in_schema=False)
    def redoc() -> HTMLResponse:
        return get_redoc_html(
            openapi_url=app.openapi_url,
            title="Footprint API",
            redoc_js_url="/vendor/redoc/redoc.standalone.js",
            redoc_favicon_url="data:,",
            with_google_fonts=False,
        )


class StartingGate:
    """Until the start-up is done, every /api request but /api/health is a 503 saying so (issue 53 item 11: the
    socket opens at once, and health answers "starting" from the first second)."""

    def __init__(self, app: ASGIApp, *, state) -> None:
        self.app, self.state = app, state

    async def __call__(self, scope: Scope, receive: Receive, send: Send) -> None:
        step = self.state.starting
        if step is None or scope["type"] != "http" or not scope["path"].startswith("/api/") or scope["path"] == HEALTH:
            return await self.app(scope, receive, send)
        body = {"detail": f"the service is starting ({step}); ask again once GET {HEALTH} says ok"}
        await JSONResponse(body, status_code=503, headers={"Retry-After": "5"})(scope, receive, send)


HEALTH = "/api/health"


class SecurityHeadersMiddleware:
    """Every response's Content-Security-Policy (unless its route set its own, as the folium map and /docs
    do), X-Content-Type-Options and Referrer-Policy (footprint.csp)."""

    def __init__(self, app: ASGIApp, *, content_policy: str):
        self.app, self.content_policy = app, content_policy

    async def __call__(self, scope: Scope, receive: Receive, send: Send) -> None:
        if scope["type"] != "http":
            await self.app(scope, receive, send)
            return

        async def send_with_headers(message: Message) -> None:
            if message["type"] == "http.response.start":
                headers = MutableHeaders(raw=list(message.get("headers", [])))
                headers.setdefault("Content-Security-Policy", self.content_policy)
                for name, value in SECURITY_HEADERS.items():
                    headers.setdefault(name, value)
                message = {**message, "headers": headers.raw}
            await send(message)

        await self.app(scope, receive, send_with_headers)


def _stores(scope: Scope) -> bool:
    """The request may change stored state: the bearer token guards it."""
    if scope["method"] not in WRITE_METHODS:
        return False
    if scope["method"] == "POST" and COMPUTATIONS.match(scope["path"]):
        return scope["path"] == "/api/reach" and _asks(scope, "store_verdicts")
    return True


def _asks(scope: Scope, flag: str) -> bool:
    """The query's `flag` as the route parses it (percent-decoded name and value, pydantic's bool: 1, yes, on, t, y...):
    the raw text's "store_verdicts=true" let every other spelling of true write without the token. A value the route
    would refuse counts as asked (it stores nothing, and needs the token all the same)."""
    values = parse_qs(scope["query_string"].decode("latin-1"), keep_blank_values=True).get(flag, [])
    try:
        return any(_BOOL.validate_python(v) for v in values)
    except ValidationError:
        return True


class GuardMiddleware:
    """Before any route runs: a Host this service does not serve (421), a path and query or headers over their caps
    (414, 431: uvicorn's h11 holds a complete request of any size), a path under /api that no route has (404) or a
    method its routes do not answer (405, never the page's static files), the bearer token on writes (401; reads stay
    open), the body limit (413) and the NUL character in any text (service.nul)."""

    def __init__(
        self,
        app: ASGIApp,
        *,
        paths: errors.ApiPaths,
        token: str,
        max_body_bytes: int,
        hosts: frozenset[str],
        origins=(),
    ):
        self.app, self.paths, self.token, self.max_body_bytes = app, paths, token, max_body_bytes
        self.origins = set(origins)  # FOOTPRINT_CORS_ORIGINS: other origins whose pages may write
        self.hosts = hosts  # Settings.host_names

    async def __call__(self, scope: Scope, receive: Receive, send: Send) -> None:
        if scope["type"] != "http":
            await self.app(scope, receive, send)
            return
        oversized = _oversized(scope)
        if oversized is not None:
            await _reply(scope, receive, send, oversized)
            return
        host = dict(scope["headers"]).get(b"host", b"").decode("latin-1")
        if "*" not in self.hosts and host_name(host) not in self.hosts:
            await _reply(
                scope,
                receive,
                send,
                errors.MisdirectedHost(
                    f"Host: {host[:100]!r} is not served here "
                    "(FOOTPRINT_ALLOWED_HOSTS lists the names besides localhost)"
                ),
            )
            return
        if scope["path"].startswith("/api/"):
            methods = self.paths.allowed(scope["path"])
            if not methods:
                await _reply(scope, receive, send, errors.NotFound(f"no such path: {scope['path'][:200]}"))
                return
            if scope["method"] not in methods:
                await _reply(scope, receive, send, errors.MethodNotAllowed(methods))
                return
        if scope["method"] in WRITE_METHODS and not self._same_site(scope):
            await _reply(
                scope,
                receive,
                send,
                errors.CrossSiteWrite(
                    "cross-site write refused: the request's Origin is not this service's "
                    "(FOOTPRINT_CORS_ORIGINS lists the others allowed)"
                ),
            )
            return
        if self.token and _stores(scope) and not self._authorized(scope):
            await _reply(
                scope,
                receive,
                send,
                errors.Unauthorized(
                    "missing or wrong bearer token: writes need the header "
                    "'Authorization: Bearer <FOOTPRINT_API_TOKEN>'"
                ),
            )
            return
        declared = dict(scope["headers"]).get(b"content-length")
        if declared is not None and declared.isdigit() and int(declared) > self.max_body_bytes:
            await _reply(scope, receive, send, _too_large(int(declared), self.max_body_bytes))
            return
        body = None
        if scope["method"] in WRITE_METHODS:
            try:
                body = await self._buffered(receive)
            except ClientDisconnect:
                return  # gone (or cut off by the body deadline, which answered 408): nothing to answer, nothing done
            if body is None:
                await _reply(scope, receive, send, _too_large(None, self.max_body_bytes))
                return
            receive = _replay(body)
        refused = nul.refusal(
            scope["path"],
            scope["query_string"],
            body,
            dict(scope["headers"]).get(b"content-type", b"").decode("latin-1"),
        )
        if refused is not None:
            await _reply(scope, receive, send, refused)
            return
        if scope["method"] == "HEAD" and "GET" in self.paths.allowed(scope["path"]):
            await _head_as_get(self.app, scope, receive, send)
            return
        await self.app(scope, receive, send)

    def _same_site(self, scope: Scope) -> bool:
        """No Origin (a tool, not a browser page), this service's own, or an allowed one: a browser sends Origin
        with every cross-site POST, and a form or a text/plain fetch needs no preflight that CORS could refuse."""
        headers = dict(scope["headers"])
        origin = headers.get(b"origin", b"").decode("latin-1")
        if not origin or origin in self.origins:
            return True
        host = headers.get(b"host", b"").decode("latin-1")
        return bool(host) and origin.split("://", 1)[-1] == host

    def _authorized(self, scope: Scope) -> bool:
        return deps.bearer_matches(dict(scope["headers"]).get(b"authorization", b"").decode("latin-1"), self.token)

    async def _buffered(self, receive: Receive) -> bytes | None:
        """The whole body (a chunked one is counted as it comes); None past the limit. A client gone mid-body raises
        ClientDisconnect: its part of a body is not a request."""
        chunks, size = [], 0
        while True:
            message = await receive()
            if message["type"] == "http.disconnect":
                raise ClientDisconnect
            chunks.append(message.get("body", b""))
            size += len(chunks[-1])
            if size > self.max_body_bytes:
                return None
            if not message.get("more_body", False):
                break
        return b"".join(chunks)


def _oversized(scope: Scope) -> Exception | None:
    url = len(scope.get("raw_path", b"")) + len(scope["query_string"])
    if url > MAX_URL_BYTES:
        return errors.UrlTooLong(f"url: the path and query are limited to {MAX_URL_BYTES:,} bytes (got {url:,})")
    headers = sum(len(name) + len(value) + 4 for name, value in scope["headers"])  # "name: value\r\n"
    if headers > MAX_HEADER_BYTES:
        return errors.HeadersTooLarge(
            f"headers: a request's headers are limited to {MAX_HEADER_BYTES:,} bytes (got {headers:,})"
        )
    return None


def host_name(host: str) -> str:
    """A Host header's name without its port, lower case: "[::1]:8000" -> "[::1]", "LocalHost:80" -> "localhost"."""
    host = host.strip().lower()
    if host.startswith("["):
        return host[: host.find("]") + 1] if "]" in host else host
    return host.rsplit(":", 1)[0] if host.count(":") == 1 else host


def _too_large(size: int | None, limit: int) -> errors.BodyTooLarge:
    got = f" (got {size:,} bytes)" if size is not None else ""
    return errors.BodyTooLarge(f"body: request bodies are limited to {limit:,} bytes{got}")


def _replay(body: bytes) -> Receive:
    sent = False

    async def receive() -> Message:
        nonlocal sent
        if sent:
            return {"type": "http.disconnect"}
        sent = True
        return {"type": "http.request", "body": body, "more_body": False}

    return receive


class _HeadAnswered(OSError):
    """A HEAD's response is complete; a streamed GET body (a job's events) is stopped as a client gone."""


async def _head_as_get(app: ASGIApp, scope: Scope, receive: Receive, send: Send) -> None:
    """HEAD answered as the GET it mirrors (status and headers, Content-Length included) without the body: FastAPI's
    routes answer no HEAD."""
    complete = False

    async def headers_only(message: Message) -> None:
        nonlocal complete
        if message["type"] != "http.response.body":
            await send(message)
            return
        if complete:
            raise _HeadAnswered
        complete = True
        await send({"type": "http.response.body", "body": b"", "more_body": False})

    try:
        await app(dict(scope, method="GET"), receive, headers_only)
    except (_HeadAnswered, ClientDisconnect):
        if not complete:
            raise


async def _reply(scope: Scope, receive: Receive, send: Send, exc: Exception) -> None:
    await errors.error_response(exc)(scope, receive, send)
