"""A database restart under a running job (issue 49: what survives what). Postgres is reached through a TCP proxy
that this test cuts (every connection dropped, none accepted) for a few seconds, as a server restart looks from the
service. Before: the job's next progress write raised, its failure could not be written either, and the job stayed
"running" for good with nothing watching it. Now the engine skips a progress note while the database is away and
writes the job's outcome once it answers: the job succeeds, stored once; health says "degraded" (503) meanwhile."""

import asyncio
import socket
import threading
import time

import pytest
from sqlalchemy.engine import make_url

from footprint.service.db import queries as q

from .conftest import TERMINAL, database_url, running_service, wait_until
from .test_worker_kill import SLOW_FOOTPRINT

OUTAGE_S = 8.0
WAIT_S = 180.0  # a guard against a hang on a loaded machine, never a bound on speed


class Proxy:
    """A TCP proxy to `target` on a port of its own, on its own event loop; cut() drops every connection and stops
    listening, restore() listens again on the same port."""

    def __init__(self, target: tuple[str, int]):
        self.target, self.loop = target, asyncio.new_event_loop()
        with socket.socket() as s:
            s.bind(("127.0.0.1", 0))
            self.port = s.getsockname()[1]
        self.server: asyncio.Server | None = None
        self.writers: set[asyncio.StreamWriter] = set()
        threading.Thread(target=self.loop.run_forever, daemon=True).start()
        self.restore()

    def _call(self, coro):
        return asyncio.run_coroutine_threadsafe(coro, self.loop).result(timeout=30)

    async def _pipe(self, reader, writer) -> None:
        try:
            while data := await reader.read(65536):
                writer.write(data)
                await writer.drain()
        except (ConnectionError, OSError):
            pass
        finally:
            writer.close()

    async def _serve(self, reader, writer) -> None:
        up_reader, up_writer = await asyncio.open_connection(*self.target)
        self.writers |= {writer, up_writer}
        await asyncio.gather(self._pipe(reader, up_writer), self._pipe(up_reader, writer))

    async def _start(self) -> None:
        self.server = await asyncio.start_server(self._serve, "127.0.0.1", self.port, reuse_address=True)

    async def _stop(self) -> None:
        self.server.close()
        for writer in self.writers:
            writer.transport.abort()
        self.writers.clear()

    def restore(self) -> None:
        self._call(self._start())

    def cut(self) -> None:
        self._call(self._stop())

    def close(self) -> None:
        self.cut()
        self.loop.call_soon_threadsafe(self.loop.stop)


@pytest.fixture
def api_behind_a_proxy(scheduler_address, tmp_path):
    with database_url("postgresql", tmp_path) as url:
        parsed = make_url(url)
        proxy = Proxy((parsed.host or "127.0.0.1", parsed.port or 5432))
        try:
            proxied = parsed.set(port=proxy.port).render_as_string(hide_password=False)
            with running_service(proxied, scheduler_address) as client:
                yield client, proxy
        finally:
            proxy.close()


def test_a_job_running_through_a_database_restart_succeeds_stored_once(api_behind_a_proxy):
    api, proxy = api_behind_a_proxy
    job_id = api.post("/api/jobs", json={"kind": "footprint", "study": SLOW_FOOTPRINT}).json()["id"]
    wait_until(lambda: api.get(f"/api/jobs/{job_id}").json()["status"] == "running", "the job runs", WAIT_S)
    proxy.cut()
    try:
        health = api.get("/api/health")
        assert health.status_code == 503 and health.json()["database"]["ok"] is False, health.text
        time.sleep(OUTAGE_S)
    finally:
        proxy.restore()
    job = wait_until(lambda: (j := api.get(f"/api/jobs/{job_id}").json())["status"] in TERMINAL and j, "ends", WAIT_S)
    assert job["status"] == "succeeded", job
    assert len(job["result"]["footprints"]) == 1
    with api.app.state.sessions() as session:
        assert q.count_rows(session, job_id=job_id) == {"job_results": 1, "footprints": 1}
    assert wait_until(lambda: api.get("/api/health").status_code == 200, "healthy again", WAIT_S)
