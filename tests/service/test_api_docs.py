"""docs/api.md matches the service (issue 13 item 9): every JSON example in it is accepted as written."""

import json
import re
from pathlib import Path

import pytest

from .conftest import wait_for_job

DOC = Path(__file__).resolve().parents[2] / "docs" / "api.md"
EXAMPLES = re.findall(r"```json (POST|PUT|PATCH) (\S+)\n(.*?)\n```", DOC.read_text(), flags=re.S)


def test_the_document_has_examples_of_every_kind_of_write():
    paths = {p for _, p, _ in EXAMPLES}
    assert {"/api/trajectories", "/api/jobs", "/api/transform", "/api/sites", "/api/reach", "/api/vehicles"} <= paths


@pytest.mark.parametrize("method, path, body", EXAMPLES, ids=[f"{m} {p} {i}" for i, (m, p, _) in enumerate(EXAMPLES)])
def test_every_example_in_the_api_document_is_accepted(api, method, path, body):
    response = api.request(method, path, json=json.loads(body))
    assert response.status_code < 300, response.text
    if path == "/api/jobs":
        job = wait_for_job(api, response.json()["id"])
        assert job["status"] == "succeeded", job["error"]
