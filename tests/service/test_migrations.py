"""The Alembic migrations produce exactly the models' schema, on SQLite and on Postgres, and go down cleanly."""

import pytest
from alembic import command
from alembic.autogenerate import compare_metadata
from alembic.migration import MigrationContext
from alembic.script import ScriptDirectory
from sqlalchemy import inspect

from footprint.service.db.engine import alembic_config, make_engine, migrate
from footprint.service.db.models import Base
from footprint.service.settings import MIGRATIONS_DIR

from .conftest import DATABASES, database_url

TABLES = {"vehicles", "jobs", "job_results", "footprints", "footprint_points", "trajectories", "sites", "revisions"}


@pytest.fixture(params=DATABASES)
def engine(request, tmp_path):
    with database_url(request.param, tmp_path) as url:
        engine = make_engine(url)
        yield engine
        engine.dispose()


def test_upgrade_head_gives_the_models_schema(engine):
    migrate(engine, MIGRATIONS_DIR)
    with engine.connect() as connection:
        context = MigrationContext.configure(connection, opts={"compare_type": True})
        diffs = compare_metadata(context, Base.metadata)
        tables = set(inspect(connection).get_table_names())
    assert diffs == []
    assert tables == TABLES | {"alembic_version"}


def test_upgrade_twice_is_a_no_op_and_downgrade_removes_everything(engine):
    migrate(engine, MIGRATIONS_DIR)
    migrate(engine, MIGRATIONS_DIR)  # a restart applies nothing new
    cfg = alembic_config(MIGRATIONS_DIR)
    with engine.begin() as connection:
        cfg.attributes["connection"] = connection
        command.downgrade(cfg, "base")
    with engine.connect() as connection:
        assert set(inspect(connection).get_table_names()) == {"alembic_version"}


def test_revisions_are_named_by_date_and_form_one_chain():
    script = ScriptDirectory.from_config(alembic_config(MIGRATIONS_DIR))
    revisions = list(script.walk_revisions())  # head first; raises on a fork
    files = sorted(p.name for p in (MIGRATIONS_DIR / "versions").glob("*.py"))
    assert len(script.get_heads()) == 1 and len(revisions) == len(files)
    assert [r.revision[:10] for r in reversed(revisions)] == [f[:10] for f in files]
    assert revisions[-1].down_revision is None


def test_the_bank_gain_migration_renames_k_in_stored_studies_and_points_only(engine):
    """Issue 14 renamed the bank gain K from `k` to `bank_gain`: a job stored before it (a pending one is submitted
    again on restart) and a stored footprint's points keep working; the planet's zonal k is not touched."""
    import json

    from sqlalchemy import text

    cfg = alembic_config(MIGRATIONS_DIR)
    with engine.begin() as connection:
        cfg.attributes["connection"] = connection
        command.upgrade(cfg, "2026_12_02_0002")
    case = {
        "vehicle": {"builtin": "lod-2.2"},
        "planet": {"k": 0.001},
        "bank": {"law": "single_parameter", "k": 0.8, "limit_deg": 85},
    }
    study = {"case": case, "method": "two_parameter", "k": [0.5, 1.0]}
    with engine.begin() as c:
        c.execute(
            text(
                "INSERT INTO jobs (id, kind, status, progress, study, attempts, created_at) VALUES "
                "('j', 'footprint', 'queued', 0, :s, 0, CURRENT_TIMESTAMP)"
            ),
            {"s": json.dumps(study)},
        )
    migrate(engine, MIGRATIONS_DIR)
    with engine.connect() as c:
        stored = c.execute(text("SELECT study FROM jobs WHERE id = 'j'")).scalar_one()
    stored = json.loads(stored) if isinstance(stored, str) else stored
    assert stored["bank_gain"] == [0.5, 1.0] and "k" not in stored
    assert stored["case"]["bank"] == {"law": "single_parameter", "bank_gain": 0.8, "limit_deg": 85}
    assert stored["case"]["planet"] == {"k": 0.001}
