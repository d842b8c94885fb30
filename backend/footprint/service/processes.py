"""`footprint serve`: uvicorn in this process, or several API processes over the one database beside this one,
which then runs the jobs (FOOTPRINT_API_PROCESSES)."""

import os
import socket

import uvicorn
from fastapi import FastAPI
from uvicorn.supervisors import Multiprocess

from footprint.service.app import create_app
from footprint.service.db.engine import make_engine, make_sessions, migrate
from footprint.service.jobs.engine import JobEngine
from footprint.service.settings import Settings, environment, load_settings


# uvicorn kills an API process that does not answer its supervisor's ping within this (default 5 s): on a loaded
# machine a new process still importing the app took longer, and was killed and started again at every ping
HEALTHCHECK_TIMEOUT_S = 30


def serve(settings: Settings) -> None:
    """One process answering HTTP and running the jobs; or, with FOOTPRINT_API_PROCESSES past 1, that many API
    processes answering HTTP (reads side by side, past one process's GIL) and this one running the cluster and the
    job engine, which polls the database for the jobs they queue."""
    if settings.api_processes == 1:
        uvicorn.run(create_app(settings), host=settings.host, port=settings.port, log_level="info")
        return
    db = make_engine(settings.database_url)
    migrate(db, settings.migrations_dir)  # once, before the API processes start
    jobs = JobEngine(sessions=make_sessions(db), settings=settings, polls=True)
    jobs.start()
    try:
        os.environ.update(environment(settings.model_copy(update={"dask_scheduler": jobs.client.scheduler.address})))
        config = _Config("footprint.service.processes:api_process", factory=True, workers=settings.api_processes,
                         host=settings.host, port=settings.port, log_level="info",
                         timeout_worker_healthcheck=HEALTHCHECK_TIMEOUT_S)
        Multiprocess(config, sockets=[config.bind_socket()]).run()  # what uvicorn.run(workers=N) does
    finally:
        jobs.close()
        db.dispose()


def api_process() -> FastAPI:
    """One of serve()'s API processes (uvicorn's factory), its settings from the environment serve() set."""
    return create_app(load_settings(), runs_jobs=False)


class _Config(uvicorn.Config):
    def bind_socket(self) -> socket.socket:
        """uvicorn's socket for its worker processes, with TCP_NODELAY, which their connections inherit: bound
        without IPPROTO_TCP, asyncio leaves Nagle's algorithm on, and a response's second write waited for the
        client's delayed ACK (44 ms each keep-alive request)."""
        sock = super().bind_socket()
        sock.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
        return sock
