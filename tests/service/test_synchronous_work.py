"""Issue 49 item 1: a synchronous request is bounded in work, not only in size. POST /api/trajectories stores nothing
and needs no token, and a guided case with short cycles and a tight predictor flew for 89 s in the API process (the
example: 0.63 s). Guidance settings that multiply the predictions are bounded at the door of a synchronous request,
and a wall-time limit stops what the door cannot see."""

import copy

from footprint import contracts
from footprint.contracts.doors import HTTP, HTTP_SYNC, context
from tests.authorities.report import example

GUIDED = example("fly_guided_lod189")


def guided_with(**settings) -> dict:
    """The guided example with these settings in its bank."""
    case = copy.deepcopy(GUIDED)
    case["bank"].update(settings)
    return case


SLOW = guided_with(cycle_s=0.5, iterations=20, predictor_rtol=1e-12)  # the request: 89 s


def test_a_guided_case_that_multiplies_its_predictions_is_refused_at_once(api):
    r = api.post("/api/trajectories", json=SLOW)
    assert r.status_code == 422, r.text[:300]
    detail = r.json()["detail"]
    assert r.json()["field"] == "bank.predictor_rtol" and detail.startswith("bank.predictor_rtol: 1e-12 ")
    assert "synchronous request" in detail and "allowed" in detail and "footprint fly" in detail
    assert "\n" not in detail


def test_the_example_still_flies_and_each_setting_alone_passes_the_door(api):
    r = api.post("/api/trajectories", json=GUIDED)
    assert r.status_code == 200, r.text[:300]
    assert r.json()["summary"]["guidance"]["status"] == "reached"
    sync = context(HTTP_SYNC)
    for alone in ({"cycle_s": 0.5}, {"iterations": 20}, {"predictor_rtol": 1e-12}):
        contracts.parse("case", guided_with(**alone), sync)
    contracts.parse("case", SLOW)  # the CLI and the Python API fly it
    contracts.parse("guided_dispersion", {"case": SLOW, "samples": 2}, context(HTTP))  # a job's worker may
