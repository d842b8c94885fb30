"""What the routers take from the running app: the session factory, the job engine and the settings."""

import hmac
import time
from collections.abc import Callable, Iterator
from typing import Annotated, TypeVar

import anyio
from fastapi import Depends, FastAPI
from sqlalchemy.orm import Session, sessionmaker
from starlette.requests import Request
from starlette.responses import Response

from footprint.service import read_cache
from footprint.service.db import queries as q
from footprint.service.jobs.engine import JobEngine

# a GET's database work runs in one of this many threads at once (its own limiter, not the thread pool's 40): each
# holds one connection, well within the pool (db.engine.REQUEST_POOL_SIZE), and on 2 cores more threads only wait
# for the GIL. Issue 49: sync routes held their connection across FastAPI's hops (route, response model, the
# dependency's exit), so 200 readers held more than the pool's 50; requests and jobs waited 30 s for one and failed.
READ_THREADS = 8
T = TypeVar("T")


def sessions(request: Request) -> sessionmaker[Session]:
    """GET requests only read: their sessions begin deferred (db.engine.make_sessions)."""
    return request.app.state.read_sessions if request.method in ("GET", "HEAD") else request.app.state.sessions


def _transaction(request: Request) -> Iterator[Session]:
    with sessions(request).begin() as session:
        yield session


# a route's one transaction: begun at its first statement, committed when the route returns and before the response
# is sent (scope "function": a client that reads next sees the write), rolled back when it raises. A route that must
# commit before it does something else (hand a job to the engine) or computes for long keeps its own `with`.
Transaction = Annotated[Session, Depends(_transaction, scope="function")]


async def read(request: Request, work: Callable[[Session], T]) -> T:
    """`work(session)` in a read transaction of its own, in one of the READ_THREADS: a GET holds its connection there
    only, never on the event loop nor between threads."""
    return await read_on(request.app, work)


async def read_on(app: FastAPI, work: Callable[[Session], T], limiter: anyio.CapacityLimiter | None = None) -> T:
    def run() -> T:
        with app.state.read_sessions.begin() as session:
            return work(session)

    return await anyio.to_thread.run_sync(run, limiter=limiter or app.state.read_limiter)


def read_limiter() -> anyio.CapacityLimiter:
    """The READ_THREADS tokens of an app's GET reads."""
    return anyio.CapacityLimiter(READ_THREADS)


def revisions(app: FastAPI) -> read_cache.SharedRead[dict[str, int]]:
    """The stored revisions as the app's cached reads check them: one query for the requests waiting together, in a
    thread of its own (never queued behind the routes' reads; one connection more than theirs)."""
    own = anyio.CapacityLimiter(1)
    return read_cache.SharedRead(lambda: read_on(app, q.revisions, own))


async def shared(request: Request, key: tuple, work: Callable[[Session], T]) -> T:
    """`work(session)`'s answer, read after the request came, by one read for all the requests of the same `key` that
    wait together (read_cache.SharedReads): a GET that no revision covers (a job list, a pending job)."""
    return await request.app.state.shared_reads.current(key, lambda: read(request, work))


async def cached_hit(request: Request, key: tuple, shows: str) -> read_cache.Serialized | None:
    """This process's cached answer for `key` if it is current: the stored `shows` (db.models.REVISIONS) unchanged
    since the request came (read_cache.SharedRead: one revision read answers every request that waits for it)."""
    current = await request.app.state.revisions.current()
    return request.app.state.read_cache.hit((shows, *key), current.get(shows, 0))


async def cached(
    request: Request, key: tuple, shows: str, build: Callable[[Session], read_cache.Serialized]
) -> Response:
    """A GET answered from this process's read cache while the stored `shows` (db.models.REVISIONS) are unchanged;
    `build` serializes it from the database otherwise (in the transaction that read the revision, after it: a
    response is never older than the revision it is kept for). A hit waits only for the revisions' shared read (no
    query of its own, nothing on the event loop but the answer: issue 49); a miss builds in a read thread."""
    hit = await cached_hit(request, key, shows)
    answered(request, key, shows)
    if hit is not None:
        return read_cache.response(request, hit)
    cache, key = request.app.state.read_cache, (shows, *key)

    def load(session: Session) -> read_cache.Serialized:
        return cache.get(key, q.revision(session, name=shows), lambda: build(session))

    return read_cache.response(request, await read(request, load))


def answered(request: Request, key: tuple, shows: str) -> None:
    """Note that this GET's answer is the read cache's `key` whenever the cache holds it at the current revision:
    read_cache.CachedGets answers the same path and query from there next time."""
    request.scope[read_cache.ANSWERED] = (shows, (shows, *key))


def bearer_matches(authorization: str, token: str) -> bool:
    """Whether an Authorization header carries the token (compared in constant time: no timing oracle)."""
    return bool(token) and hmac.compare_digest(authorization.encode("latin-1"), f"Bearer {token}".encode())


def has_token(request: Request) -> bool:
    """The caller sent the service's bearer token (never, when none is set)."""
    return bearer_matches(request.headers.get("authorization", ""), request.app.state.settings.api_token)


def engine(request: Request) -> JobEngine:
    return request.app.state.jobs


def _stored_vehicle(request: Request) -> Callable[[str], dict | None]:
    def stored(vehicle_id: str) -> dict | None:
        with sessions(request).begin() as session:
            row = q.get_vehicle(session, vehicle_id=vehicle_id)
            return None if row is None else row.definition

    return stored


def body_context(request: Request, *, synchronous: bool, sites=None) -> dict:
    """The validation context of a body that came through the service (footprint.contracts.doors.context)."""
    from footprint.contracts.doors import HTTP, HTTP_SYNC, context

    return context(HTTP_SYNC if synchronous else HTTP, _stored_vehicle(request), sites)


async def job_door(request: Request) -> None:
    """A job's body is validated with the HTTP door's limits and the stored vehicles (a route's dependency: it runs
    in the request's task before FastAPI reads the body, footprint.contracts.doors.enter)."""
    from footprint.contracts.doors import enter

    enter(body_context(request, synchronous=False))


async def sync_door(request: Request) -> None:
    """A body this process answers itself: the synchronous door's tighter limits, and the stored vehicles."""
    from footprint.contracts.doors import enter

    enter(body_context(request, synchronous=True))


def parse_body(request: Request, kind: str, data, prefix: str = "", *, synchronous: bool = False):
    """A request of a contract kind (footprint.contracts) that a route assembles (not its body: FastAPI parses
    that), parsed here with the HTTP door's limits (a job's, or with `synchronous` the tighter ones of work this
    process does itself) and the stored vehicles; a mistake is a 422 naming the field (below `prefix`)."""
    from pydantic import ValidationError

    from footprint import contracts
    from footprint.core.errors import InputError
    from footprint.service.errors import invalid

    try:
        return contracts.parse(kind, data, body_context(request, synchronous=synchronous))
    except (ValidationError, InputError) as exc:
        raise invalid(exc, prefix) from None


def answer_now(request: Request, kind: str, data, prefix: str = ""):
    """A contract kind's answer computed in this process (footprint.parallel.run) for a body, with the synchronous
    door's limits: a mistake, in the body or one only the numbers show (an inclination the latitude cannot fly), is a
    422 naming the field; a computation past the synchronous time limit is stopped, and a 422 says what to do."""
    from footprint import parallel
    from footprint.core.errors import InputError, Stopped
    from footprint.service.errors import RequestInvalid, invalid

    parsed = parse_body(request, kind, data, prefix, synchronous=True)
    try:
        return parallel.run(kind, parsed, on_progress=_within_time_limit(request))
    except InputError as exc:
        raise invalid(exc, prefix) from None
    except Stopped:
        limit_s = request.app.state.settings.sync_time_limit_s
        raise RequestInvalid(
            f"the request took longer than the synchronous limit of {limit_s:g} s (FOOTPRINT_SYNC_TIME_LIMIT_S) and "
            f"was stopped: {TOO_LONG_ADVICE.get(kind, 'ask for less work')}",
            None,
        ) from None


# what a request stopped by the synchronous time limit can do instead, by its kind
TOO_LONG_ADVICE = {
    "case": "a guided case asks less with a longer bank.cycle_s or a looser bank.predictor_rtol; the CLI (footprint "
    "fly) and the Python API (footprint.fly) fly it whole",
    "transform": "fewer footprint points or a longer study.case.integrator.max_step_s ask less; a footprint job from "
    "the destination's entry (POST /api/jobs) flies it whole",
    "reach": "the same request as a reach job (POST /api/jobs) runs whole",
}


def _within_time_limit(request: Request) -> Callable[[float, str], bool]:
    """on_progress of a synchronous computation: True (stop) once the request has computed for the synchronous time
    limit, counted from its first computation (a route may compute several)."""
    deadline = getattr(request.state, "sync_deadline", None)
    if deadline is None:
        deadline = request.state.sync_deadline = time.monotonic() + request.app.state.settings.sync_time_limit_s
    return lambda fraction, note: time.monotonic() > deadline
