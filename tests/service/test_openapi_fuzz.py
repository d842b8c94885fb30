"""schemathesis (issue 14 item 3): every operation of our own OpenAPI document, fuzzed with all its checks.

The app runs its real lifespan (migrations on a SQLite file, the shared Dask cluster); schemathesis reaches it
in-process (ASGI). A bounded example count keeps the default suite quick.

One check is narrowed, and replaced: a contract's request (a case, a study, a transform, a reach, a vehicle) has
rules between its fields that JSON Schema cannot state (the stop altitude below the entry altitude, exactly one of
points or study, a heading or an inclination), and a CSV upload has a header; so a schema-valid body may be refused
there, and the refusal must then be the documented 422 that names a field (or line) of the body."""

import json

import pytest
import schemathesis
from hypothesis import HealthCheck, settings
from schemathesis.config import SchemathesisConfig
from schemathesis.specs.openapi.checks import positive_data_acceptance

EXAMPLES = 12  # per operation; the default suite's runs are derandomized (the same cases each run: CI stays green
# or red for a reason), the slow one's are not
# the deep contract bodies (a job's study, a reach, a transform): their coverage phase (an example for every bound
# of every field, the largest reach among them) takes minutes, so the default suite fuzzes them without it and
# `-m slow` runs it
HEAVY = ["POST /api/jobs", "POST /api/reach", "POST /api/transform"]
NO_NUL = SchemathesisConfig.from_dict({"generation": {"allow-x00": False}})
QUICK = SchemathesisConfig.from_dict(
    {
        # the NUL character is refused at the edge in every text, with a 422 naming the field (service.nul, by
        # design: Postgres stores none; tests/service/test_bad_input.py): not part of the data an operation accepts
        "generation": {"allow-x00": False},
        "operations": [{"include-name": name, "phases": {"coverage": {"enabled": False}}} for name in HEAVY],
    }
)
CONTRACT_BODIES = {
    ("POST", "/api/jobs"),
    ("POST", "/api/trajectories"),
    ("POST", "/api/transform"),
    ("POST", "/api/reach"),
    ("POST", "/api/footprints/{footprint_id}/transform"),
    ("POST", "/api/vehicles"),
    ("POST", "/api/sites/csv"),
}


@pytest.fixture(scope="module")
def app(tmp_path_factory, scheduler_address):
    from schemathesis.python.asgi import shutdown_lifespans

    from footprint.service.app import create_app
    from footprint.service.settings import load_settings

    url = f"sqlite:///{tmp_path_factory.mktemp('fuzz') / 'footprint.db'}"
    yield create_app(load_settings(database_url=url, dask_scheduler=scheduler_address))
    shutdown_lifespans()


@pytest.fixture(scope="module")
def api_schema(app):
    return schemathesis.openapi.from_asgi("/openapi.json", app, config=QUICK)


@pytest.fixture(scope="module")
def full_schema(app):
    return schemathesis.openapi.from_asgi("/openapi.json", app, config=NO_NUL)


schema = schemathesis.pytest.from_fixture("api_schema")
full = schemathesis.pytest.from_fixture("full_schema")


def answers_as_documented(case):
    contract = (case.method.upper(), case.operation.path) in CONTRACT_BODIES
    response = case.call_and_validate(excluded_checks=[positive_data_acceptance] if contract else [])
    if contract and response.status_code == 422:
        body = json.loads(response.content)
        assert body["field"] and body["detail"].split(": ")[0], body


@schema.exclude(name=HEAVY).parametrize()
@settings(max_examples=EXAMPLES, deadline=None, suppress_health_check=list(HealthCheck), derandomize=True)
def test_every_operation_answers_as_documented(case):
    answers_as_documented(case)


@schema.include(name=HEAVY).parametrize()
@settings(max_examples=EXAMPLES, deadline=None, suppress_health_check=list(HealthCheck), derandomize=True)
def test_the_deep_bodies_answer_as_documented(case):
    answers_as_documented(case)


@pytest.mark.slow
@full.include(name=HEAVY).parametrize()
@settings(max_examples=EXAMPLES, deadline=None, suppress_health_check=list(HealthCheck))
def test_the_deep_bodies_answer_as_documented_at_every_bound(case):
    answers_as_documented(case)
