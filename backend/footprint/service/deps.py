"""What the routers take from the running app: the session factory, the job engine and the settings."""

from sqlalchemy.orm import Session, sessionmaker
from starlette.requests import Request

from footprint.service.jobs.engine import JobEngine


def sessions(request: Request) -> sessionmaker[Session]:
    """GET requests only read: their sessions begin deferred (db.engine.make_sessions)."""
    return request.app.state.read_sessions if request.method in ("GET", "HEAD") else request.app.state.sessions


def engine(request: Request) -> JobEngine:
    return request.app.state.jobs
