"""schemathesis (issue 14 item 3): every operation of our own OpenAPI document, fuzzed with all its checks.

The app runs its real lifespan (migrations on a SQLite file, the shared Dask cluster); schemathesis reaches it
in-process (ASGI). A bounded example count keeps the default suite quick."""

import pytest
import schemathesis
from hypothesis import HealthCheck, settings

EXAMPLES = 12  # per operation


@pytest.fixture(scope="module")
def api_schema(tmp_path_factory, scheduler_address):
    from schemathesis.python.asgi import shutdown_lifespans

    from footprint.service.app import create_app
    from footprint.service.settings import load_settings

    url = f"sqlite:///{tmp_path_factory.mktemp('fuzz') / 'footprint.db'}"
    app = create_app(load_settings(database_url=url, dask_scheduler=scheduler_address))
    yield schemathesis.openapi.from_asgi("/openapi.json", app)
    shutdown_lifespans()


schema = schemathesis.pytest.from_fixture("api_schema")


@schema.parametrize()
@settings(max_examples=EXAMPLES, deadline=None, suppress_health_check=list(HealthCheck))
def test_every_operation_answers_as_documented(case):
    case.call_and_validate()
