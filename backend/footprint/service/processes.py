"""`footprint serve`: uvicorn in this process, or several API processes over the one database beside this one,
which then runs the jobs (FOOTPRINT_API_PROCESSES)."""

import os

import uvicorn
from fastapi import FastAPI
from uvicorn.supervisors import Multiprocess

from footprint.service import server
from footprint.service.app import create_app
from footprint.service.db.engine import make_engine, make_sessions, migrate
from footprint.service.jobs.engine import JobEngine
from footprint.service.settings import Settings, environment, load_settings


def serve(settings: Settings) -> None:
    """One process answering HTTP and running the jobs; or, with FOOTPRINT_API_PROCESSES past 1, that many API
    processes answering HTTP (reads side by side, past one process's GIL) and this one running the cluster and the
    job engine, which polls the database for the jobs they queue."""
    if settings.api_processes == 1:
        app = create_app(settings, freezes_heap=True, starts_behind=True)  # health says "starting" at once
        uvicorn.Server(server.config(settings, app)).run()
        if app.state.start_failed:
            raise SystemExit(3)  # as uvicorn ends on a failed lifespan
        return
    db = make_engine(settings.database_url)
    migrate(db, settings.migrations_dir)  # once, before the API processes start
    jobs = JobEngine(sessions=make_sessions(db), settings=settings, polls=True)
    jobs.start()
    try:
        os.environ.update(environment(settings.model_copy(update={"dask_scheduler": jobs.client.scheduler.address})))
        config = server.config(
            settings, "footprint.service.processes:api_process", factory=True, workers=settings.api_processes
        )
        Multiprocess(config, sockets=[config.bind_socket()]).run()  # what uvicorn.run(workers=N) does
    finally:
        jobs.close()
        db.dispose()


def api_process() -> FastAPI:
    """One of serve()'s API processes (uvicorn's factory), its settings from the environment serve() set."""
    return create_app(load_settings(), runs_jobs=False, freezes_heap=True)  # started by serve(): its start is short
