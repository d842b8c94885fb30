"""A new kind of work is one contract module and one line in the registry (issue 26): the toy kind in
tests/kinds/squares.py, registered here and nowhere else, runs through the Python API (in this process and on
Dask), the CLI, and the service as a job with progress and a cancel. Its answer is checked against the closed form
sum k^2 = n (n + 1) (2 n + 1) / 6, not against the code."""

import json

import pytest
from typer.testing import CliRunner

from footprint import api, contracts, parallel
from footprint.cli import app as cli
from tests.service.conftest import WAIT_S, wait_for_job, wait_until

KIND, MODULE = "squares", "tests.kinds.squares"


def closed_form(n: int) -> int:
    return n * (n + 1) * (2 * n + 1) // 6


@pytest.fixture(autouse=True, scope="module")
def registered():
    """Registered before the module's service is made (an autouse fixture comes first in its scope): POST
    /api/jobs's body holds the kinds registered when the app is made."""
    with pytest.MonkeyPatch.context() as patch:
        patch.setitem(contracts.MODULES, KIND, MODULE)
        yield


def test_the_python_api_runs_it_here_and_on_dask(scheduler_address):
    assert KIND in contracts.job_kinds()
    assert api.run(KIND, {"n": 1_000, "parts": 3}) == {"sum": closed_form(1_000), "parts": 3}
    assert api.run(KIND, {"n": 12_345, "parts": 7}, scheduler=scheduler_address) == {
        "sum": closed_form(12_345),
        "parts": 7,
    }


def test_the_cli_runs_it_and_names_a_bad_field(tmp_path):
    good, bad = tmp_path / "good.json", tmp_path / "bad.json"
    good.write_text(json.dumps({"n": 100, "parts": 4}))
    bad.write_text(json.dumps({"n": 0}))
    out = CliRunner().invoke(cli, ["run", KIND, str(good)])
    assert out.exit_code == 0, out.output
    assert json.loads(out.stdout) == {"result": {"squares": {"sum": closed_form(100), "parts": 4}}, "footprints": []}
    out = CliRunner().invoke(cli, ["run", KIND, str(bad)])
    assert out.exit_code == 2 and out.stderr.startswith("error: n:") and len(out.stderr.splitlines()) == 1
    out = CliRunner().invoke(cli, ["run", "nonesuch", str(good)])
    assert out.exit_code == 2 and "not a kind of job" in out.stderr


def test_a_job_of_it_reports_progress_succeeds_and_stops_when_cancelled(api):
    jobs = api.get("/openapi.json").json()["paths"]["/api/jobs"]["post"]["requestBody"]["content"]
    assert KIND in jobs["application/json"]["schema"]["discriminator"]["mapping"]  # its typed body, generated
    bad = api.post("/api/jobs", json={"kind": KIND, "study": {"n": 0}})
    assert bad.status_code == 422 and bad.json()["field"] == "study.n", bad.text
    r = api.post("/api/jobs", json={"kind": KIND, "study": {"n": 5_000, "parts": 2}})
    assert r.status_code == 202, r.text
    job = wait_for_job(api, r.json()["id"])
    assert job["status"] == "succeeded" and job["result"]["squares"] == {"sum": closed_form(5_000), "parts": 2}

    slow = api.post("/api/jobs", json={"kind": KIND, "study": {"n": 10, "parts": 2, "seconds_per_part": 300}})
    url = f"/api/jobs/{slow.json()['id']}"
    seen = wait_until(lambda: (j := api.get(url).json())["progress"] > 0 and j, "the parts report progress")
    assert seen["status"] == "running" and seen["progress_note"].startswith("range ")
    assert api.delete(url).json()["status"] == "cancelled"
    busy = lambda: any(api.app.state.jobs.client.run(parallel.running_keys).values())  # noqa: E731
    wait_until(lambda: not busy(), "the cancelled parts stop", WAIT_S)
    assert api.get(url).json()["status"] == "cancelled"
