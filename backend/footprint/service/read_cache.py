"""GET responses serialized once: each kept with the revision of the stored things it shows (db.models.Revision)
and a strong ETag of its bytes, answered again from memory while the revision holds (304 to an If-None-Match that
names it). A write bumps the revision in its own transaction, so every API process over the database sees a
cached response go stale at the write's commit."""

import asyncio
import functools
import hashlib
import threading
from collections import OrderedDict
from collections.abc import Awaitable, Callable
from dataclasses import dataclass
from typing import Generic, TypeVar

from pydantic import TypeAdapter
from starlette.requests import Request
from starlette.responses import Response

T = TypeVar("T")
MAX_BYTES = 64 * 1024 * 1024  # the cached bodies and keys of one process, least recently used dropped first
MAX_ENTRIES = 4_096  # and at most this many responses: a key's overhead is not only its text
REVALIDATE = "no-cache"  # a browser keeps the body but asks again (If-None-Match) before each use
NOT_MODIFIED = {304: {"description": "Not Modified: the If-None-Match names the current ETag"}}  # a route's responses


@dataclass(frozen=True)
class Serialized:
    body: bytes
    media_type: str
    etag: str
    headers: tuple[tuple[str, str], ...] = ()


def serialized(body: bytes, media_type: str, headers: dict[str, str] | None = None) -> Serialized:
    """A response body with its strong ETag (a hash of the bytes: the same content keeps its tag across
    revisions and processes)."""
    return Serialized(
        body, media_type, f'"{hashlib.blake2b(body, digest_size=16).hexdigest()}"', tuple((headers or {}).items())
    )


@functools.cache
def _adapter(schema) -> TypeAdapter:
    return TypeAdapter(schema)


def as_json(schema, value) -> Serialized:
    """`value` validated and serialized by its response schema, as FastAPI's response_model does (by alias)."""
    adapter = _adapter(schema)
    return serialized(adapter.dump_json(adapter.validate_python(value), by_alias=True), "application/json")


class ReadCache:
    """Serialized responses by request key, each valid for one revision."""

    def __init__(self, max_bytes: int = MAX_BYTES, max_entries: int = MAX_ENTRIES):
        self._max_bytes, self._max_entries, self._bytes = max_bytes, max_entries, 0
        self._entries: OrderedDict[tuple, tuple[int, Serialized, int]] = OrderedDict()  # revision, value, size
        self._lock = threading.Lock()
        self._building: dict[tuple, threading.Lock] = {}  # one build per key at a time: the others wait for it

    def get(self, key: tuple, revision: int, build: Callable[[], Serialized]) -> Serialized:
        """The cached response for `key` at `revision`, built (once, whatever the number of callers) if missing."""
        hit = self.hit(key, revision)
        if hit is not None:
            return hit
        with self._lock:
            building = self._building.setdefault(key, threading.Lock())
        with building:
            hit = self.hit(key, revision)
            if hit is not None:
                return hit
            value = build()
            self._put(key, revision, value)
        with self._lock:
            self._building.pop(key, None)
        return value

    def hit(self, key: tuple, revision: int) -> Serialized | None:
        """The cached response for `key` at `revision`, or None."""
        with self._lock:
            entry = self._entries.get(key)
            if entry is None or entry[0] != revision:
                return None
            self._entries.move_to_end(key)
            return entry[1]

    def _put(self, key: tuple, revision: int, value: Serialized) -> None:
        size = len(value.body) + len(repr(key))  # a key holds the request's text: it counts (issue 24 item 4)
        with self._lock:
            old = self._entries.pop(key, None)
            if old is not None:
                self._bytes -= old[2]
            if size > self._max_bytes:
                return
            self._entries[key] = (revision, value, size)
            self._bytes += size
            while self._bytes > self._max_bytes or len(self._entries) > self._max_entries:
                _, (_, _, dropped) = self._entries.popitem(last=False)
                self._bytes -= dropped

    @property
    def size(self) -> tuple[int, int]:
        """(entries, bytes of bodies and keys) held now."""
        with self._lock:
            return len(self._entries), self._bytes


class SharedRead(Generic[T]):
    """One read for every request that waits together. A request waits for a read begun after it came, so it sees
    every write committed before it (through any process); the requests that come while a read runs share the next
    one. At 200 readers one query answers dozens, and none runs on the event loop. The stored revisions are read so
    for the cached answers (app.state.revisions): each cached read had read its revision row on the event loop, a
    Postgres round trip or four (checkout, BEGIN, SELECT, COMMIT) during which the loop answered nothing, and a wait
    of up to the pool's 30 s when the pool was empty (issue 49)."""

    def __init__(self, read: Callable[[], Awaitable[T]], on_idle: Callable[[], object] | None = None):
        self._read, self._on_idle = read, on_idle  # on_idle: called when no read runs and none is awaited
        self._loop: asyncio.AbstractEventLoop | None = None
        self._next: asyncio.Future[T] | None = None  # the read the requests now coming wait for
        self._reading: asyncio.Task[None] | None = None

    async def current(self) -> T:
        """The read's answer, read after this call began."""
        loop = asyncio.get_running_loop()
        if loop is not self._loop:  # an app served again on another loop (tests): nothing of the old one is kept
            self._loop, self._next, self._reading = loop, None, None
        if self._next is None:
            self._next = loop.create_future()
        if self._reading is None:
            self._reading = loop.create_task(self._reads())
        return await asyncio.shield(self._next)

    async def _reads(self) -> None:
        try:
            while self._next is not None:
                waiting, self._next = self._next, None  # from here on, a request that comes waits for the next read
                try:
                    waiting.set_result(await self._read())
                except asyncio.CancelledError:
                    waiting.cancel()
                    raise
                except Exception as exc:  # noqa: BLE001 -- each waiter gets the error (health says the database's)
                    waiting.set_exception(exc)
                    waiting.exception()  # retrieved: waiters that have gone leave no "never retrieved" warning
        finally:
            self._reading = None
            if self._next is None and self._on_idle is not None:
                self._on_idle()


class SharedReads:
    """A SharedRead per request key while its reads run (the uncached GETs: the job lists, a pending job), dropped when
    idle: at 200 readers of the page, the few jobs and lists read dozens of times a second each, once per batch."""

    def __init__(self):
        self._reads: dict[tuple, SharedRead] = {}

    async def current(self, key: tuple, read: Callable[[], Awaitable[T]]) -> T:
        """`read()`'s answer for `key`, read after this call began (by this request's `read` or an equal one)."""
        shared = self._reads.get(key)
        if shared is None:
            shared = self._reads[key] = SharedRead(read, on_idle=lambda: self._reads.pop(key, None))
        return await shared.current()


ANSWERED = "footprint.read_cache"  # the scope's note of a GET answered from the read cache: (kind shown, key)
MAX_TARGET_BYTES = 4 * 1024 * 1024  # the request targets CachedGets remembers, their text together


class CachedGets:
    """ASGI, inside the service's guard: a GET whose exact path and query an earlier GET was answered from the read
    cache (deps.cached notes it in the scope) is answered again from there while the revision it was kept for holds,
    before FastAPI routes it, parses its query and solves its dependencies: more than half of the event loop's time
    per cached read at 200 readers (issue 49). The answer is the route's own: the same body, headers, ETag and 304.
    Anything else, and a hit that is no longer current, goes to the app as before."""

    def __init__(self, app, *, state):
        self.app, self.state = app, state  # the FastAPI app's state: read_cache, revisions
        self._targets: OrderedDict[tuple[str, bytes], tuple[str, tuple]] = OrderedDict()
        self._bytes = 0

    async def __call__(self, scope, receive, send) -> None:
        if scope["type"] != "http" or scope["method"] != "GET":
            await self.app(scope, receive, send)
            return
        target = (scope["path"], scope["query_string"])
        known = self._targets.get(target)
        if known is not None:
            shows, key = known
            try:
                hit = self.state.read_cache.hit(key, (await self.state.revisions.current()).get(shows, 0))
            except Exception:  # noqa: BLE001 -- the route answers (and its error table says what went wrong)
                hit = None
            if hit is not None:
                self._targets.move_to_end(target)
                await response(Request(scope), hit)(scope, receive, send)
                return
        await self.app(scope, receive, send)
        answered = scope.get(ANSWERED)
        if answered is not None and known is None:
            self._remember(target, answered)

    def _remember(self, target: tuple[str, bytes], answered: tuple[str, tuple]) -> None:
        self._targets[target] = answered
        self._bytes += len(target[0]) + len(target[1])
        while len(self._targets) > MAX_ENTRIES or self._bytes > MAX_TARGET_BYTES:
            (path, query), _ = self._targets.popitem(last=False)
            self._bytes -= len(path) + len(query)


def response(request: Request, value: Serialized) -> Response:
    """200 with the body, or 304 when the request's If-None-Match names its ETag or is "*" (RFC 9110 13.1.2: the
    weak comparison, so a W/ tag matches too)."""
    headers = {"ETag": value.etag, "Cache-Control": REVALIDATE}
    tags = {t.strip().removeprefix("W/") for t in request.headers.get("if-none-match", "").split(",")}
    if value.etag in tags or "*" in tags:
        return Response(status_code=304, headers=headers)
    return Response(value.body, media_type=value.media_type, headers=headers | dict(value.headers))


def plain(value: Serialized) -> Response:
    """200 with the body, no ETag: an answer read anew for each request."""
    return Response(value.body, media_type=value.media_type, headers=dict(value.headers))
