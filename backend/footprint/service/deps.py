"""What the routers take from the running app: the session factory, the job engine and the settings."""

from sqlalchemy.orm import Session, sessionmaker
from starlette.requests import Request

from footprint.service.jobs.engine import JobEngine


def sessions(request: Request) -> sessionmaker[Session]:
    return request.app.state.sessions


def engine(request: Request) -> JobEngine:
    return request.app.state.jobs
