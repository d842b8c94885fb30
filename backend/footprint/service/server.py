"""uvicorn as `footprint serve` runs it: one config (its timeouts and size caps, docs/api.md "Timeouts and caps")
and uvicorn's h11 protocol with read deadlines. uvicorn times out only an idle keep-alive connection: a client
that sent half its headers, or declared a body and sent ten bytes of it, held its connection (a file descriptor)
for as long as it liked (issue 24 item 6: 1,500 such connections stayed open 60 s+)."""

import asyncio
import json
import socket

import h11
import uvicorn
from uvicorn.protocols.http.h11_impl import H11Protocol

from footprint.service.settings import MAX_HEADER_BYTES, MAX_URL_BYTES, Settings

# uvicorn kills an API process that does not answer its supervisor's ping within this (default 5 s): on a loaded
# machine a new process still importing the app took longer, and was killed and started again at every ping
HEALTHCHECK_TIMEOUT_S = 30


class DeadlineProtocol(H11Protocol):
    """h11 with two deadlines on what the client sends: the request line and headers within the config's
    `header_timeout_s` of their first byte (or of the connection), the body within `body_timeout_s` of the headers.
    Past one the client gets a 408 (when no response has begun) and the connection is closed."""

    def __init__(self, config: "_Config", *args, **kwargs):
        super().__init__(config, *args, **kwargs)
        self.header_timeout_s, self.body_timeout_s = config.header_timeout_s, config.body_timeout_s
        self._deadline: asyncio.TimerHandle | None = None
        self._reading: str | None = None  # "headers" or "body": what the armed deadline waits for

    def connection_made(self, transport) -> None:
        super().connection_made(transport)
        self._expect("headers")

    def data_received(self, data: bytes) -> None:
        super().data_received(data)
        if self.transport.is_closing():
            return
        if self.conn.their_state is h11.IDLE and data:
            self._expect("headers")  # a request has begun: its headers are due
        elif self.conn.their_state is h11.SEND_BODY:
            self._expect("body")
        else:
            self._expect(None)

    def on_response_complete(self) -> None:
        super().on_response_complete()
        if self.conn.their_state is h11.IDLE and not self.transport.is_closing():
            self._expect(None)  # between requests: uvicorn's keep-alive timeout holds

    def connection_lost(self, exc) -> None:
        self._expect(None)
        super().connection_lost(exc)

    def _expect(self, part: str | None) -> None:
        """Arm the deadline for `part` unless it is armed already (a trickled byte does not renew it); None disarms."""
        if part == self._reading:
            return
        if self._deadline is not None:
            self._deadline.cancel()
        self._reading, self._deadline = part, None
        if part is not None:
            seconds = self.header_timeout_s if part == "headers" else self.body_timeout_s
            self._deadline = self.loop.call_later(seconds, self._timed_out, part, seconds)

    def _timed_out(self, part: str, seconds: float) -> None:
        self._deadline = None
        if self.transport.is_closing():
            return
        if self.cycle is None or not self.cycle.response_started or self.cycle.response_complete:
            setting = "FOOTPRINT_HEADER_TIMEOUT_S" if part == "headers" else "FOOTPRINT_BODY_TIMEOUT_S"
            body = json.dumps({"detail": f"request {part} not received within {seconds:g} s ({setting})"}).encode()
            self.transport.write(
                b"HTTP/1.1 408 Request Timeout\r\ncontent-type: application/json\r\n"
                b"connection: close\r\ncontent-length: %d\r\n\r\n%s" % (len(body), body)
            )
        if self.cycle is not None and not self.cycle.response_complete:
            self.cycle.disconnected = True  # the app waiting on the body reads a disconnect and stops
            self.cycle.message_event.set()
        self.transport.close()


def config(settings: Settings, app, **options) -> uvicorn.Config:
    """The one uvicorn configuration of the service: host, port, the deadlines, and h11's buffer for a request line and
    headers still arriving (past it: 400; GuardMiddleware answers a complete but oversized one with 414 or 431)."""
    made = _Config(
        app,
        **{
            "host": settings.host,
            "port": settings.port,
            "log_level": "info",
            "access_log": settings.access_log,
            "http": "footprint.service.server:DeadlineProtocol",  # by name: --api-processes pickles it
            "h11_max_incomplete_event_size": MAX_HEADER_BYTES + MAX_URL_BYTES,
            "timeout_worker_healthcheck": HEALTHCHECK_TIMEOUT_S,
        }
        | options,
    )
    made.header_timeout_s, made.body_timeout_s = settings.header_timeout_s, settings.body_timeout_s
    return made


class _Config(uvicorn.Config):
    header_timeout_s: float  # set by config() from the settings, read by DeadlineProtocol
    body_timeout_s: float

    def bind_socket(self) -> socket.socket:
        """uvicorn's socket for its worker processes, with TCP_NODELAY, which their connections inherit: bound
        without IPPROTO_TCP, asyncio leaves Nagle's algorithm on, and a response's second write waited for the
        client's delayed ACK (44 ms each keep-alive request)."""
        sock = super().bind_socket()
        sock.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
        return sock
