"""Alembic environment: the service's models are the target; the connection comes from the caller
(footprint.service.db.engine.migrate) or, from the alembic command line, FOOTPRINT_DATABASE_URL."""

import os

from alembic import context
from sqlalchemy import create_engine

from footprint.service.db.models import Base

target_metadata = Base.metadata


def _run(connection) -> None:
    context.configure(connection=connection, target_metadata=target_metadata, render_as_batch=True, compare_type=True)
    with context.begin_transaction():
        context.run_migrations()


def run_online() -> None:
    connection = context.config.attributes.get("connection")
    if connection is not None:
        _run(connection)
        return
    url = os.environ.get("FOOTPRINT_DATABASE_URL", "sqlite:///footprint.db")
    with create_engine(url).connect() as connection:
        _run(connection)
        connection.commit()


def run_offline() -> None:
    context.configure(
        url=os.environ.get("FOOTPRINT_DATABASE_URL", "sqlite:///footprint.db"),
        target_metadata=target_metadata,
        literal_binds=True,
        render_as_batch=True,
    )
    with context.begin_transaction():
        context.run_migrations()


if context.is_offline_mode():
    run_offline()
else:
    run_online()
