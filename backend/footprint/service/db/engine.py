"""The database engine and sessions, and Alembic migrations applied through alembic's API."""

from pathlib import Path

from alembic import command
from alembic.config import Config
from sqlalchemy import Engine, create_engine, event, make_url
from sqlalchemy.orm import Session, sessionmaker

SQLITE_BUSY_TIMEOUT_S = 30.0  # writers wait for each other this long before "database is locked"
POSTGRES_CONNECT_TIMEOUT_S = 5  # a new connection to an unreachable server fails after this (libpq connect_timeout)
# a request process's connections: its read threads (deps.READ_THREADS) and the thread pool's writes and event
# streams (anyio's 40 threads) with room to spare, opened as they are needed
REQUEST_POOL_SIZE, REQUEST_POOL_OVERFLOW = 10, 40


def make_engine(
    database_url: str, *, pool_size: int = REQUEST_POOL_SIZE, max_overflow: int = REQUEST_POOL_OVERFLOW
) -> Engine:
    """An engine for SQLite (a file, foreign keys on, write transactions serialized) or Postgres, whose pool opens
    up to `pool_size` + `max_overflow` connections (SQLAlchemy's own default, 5 + 10, is fewer than the thread pool's
    40 threads: issue 49's requests waited 30 s for one and failed, and the jobs beside them)."""
    if database_url.startswith("sqlite"):
        in_memory = make_url(database_url).database in (None, "", ":memory:")  # one connection (SingletonThreadPool)
        engine = create_engine(
            database_url,
            connect_args={"check_same_thread": False, "timeout": SQLITE_BUSY_TIMEOUT_S},
            **({} if in_memory else {"pool_size": pool_size, "max_overflow": max_overflow}),
        )
        _sqlite_pragmas(engine)
        return engine
    return create_engine(
        database_url,
        pool_pre_ping=True,
        pool_size=pool_size,
        max_overflow=max_overflow,
        connect_args={"connect_timeout": POSTGRES_CONNECT_TIMEOUT_S},
    )


def _sqlite_pragmas(engine: Engine) -> None:
    """WAL (readers never block the writer), enforced foreign keys, and BEGIN IMMEDIATE: pysqlite's deferred
    transactions fail at once (not after the timeout) when a reader later tries to write."""

    @event.listens_for(engine, "connect")
    def _connect(dbapi_connection, _record):
        dbapi_connection.isolation_level = None  # let SQLAlchemy's begin event emit BEGIN
        cursor = dbapi_connection.cursor()
        cursor.execute("PRAGMA journal_mode=WAL")
        cursor.execute("PRAGMA foreign_keys=ON")
        cursor.close()

    @event.listens_for(engine, "begin")
    def _begin(connection):
        reads_only = connection.get_execution_options().get(READS_ONLY, False)
        connection.exec_driver_sql("BEGIN" if reads_only else "BEGIN IMMEDIATE")  # WAL: readers run side by side


READS_ONLY = "footprint_reads_only"  # execution option: a transaction that never writes (deferred BEGIN)


def make_sessions(engine: Engine, *, reads_only: bool = False) -> sessionmaker[Session]:
    """Sessions on the engine; reads_only ones (GET requests) begin deferred on SQLite, so concurrent readers
    do not queue behind the one-writer lock (WAL lets them read beside it)."""
    bind = engine.execution_options(**{READS_ONLY: True}) if reads_only else engine
    return sessionmaker(bind, expire_on_commit=False)


def alembic_config(migrations_dir: Path) -> Config:
    cfg = Config()
    cfg.set_main_option("script_location", str(migrations_dir))
    return cfg


def migrate(engine: Engine, migrations_dir: Path) -> None:
    """Bring the database to the newest revision (alembic upgrade head) on the given engine."""
    cfg = alembic_config(migrations_dir)
    with engine.begin() as connection:
        cfg.attributes["connection"] = connection
        command.upgrade(cfg, "head")
