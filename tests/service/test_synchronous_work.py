"""Issue 49 item 1: a synchronous request is bounded in work, not only in size. POST /api/trajectories stores nothing
and needs no token, and a guided case with short cycles and a tight predictor flew for 89 s in the API process (the
example: 0.63 s). Guidance settings that multiply the predictions are bounded at the door of a synchronous request,
and a wall-time limit stops what the door cannot see."""

import copy

import pytest
from pydantic import ValidationError

from footprint import contracts
from footprint.contracts.doors import HTTP, HTTP_SYNC, context
from footprint.contracts.messages import error_line
from tests.authorities.report import example

from .conftest import database_url, running_service
from .sample_requests import CASE, FOOTPRINT, REACH

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


def exact_transform(study: dict) -> dict:
    """POST /api/transform's body that flies `study` again from another place on the rotating earth."""
    return {
        "from": {"latitude_deg": 0, "longitude_deg": 0, "heading_deg": 90},
        "to": {"latitude_deg": 10, "longitude_deg": 20, "heading_deg": 45},
        "earth_rotation": "exact",
        "study": study,
    }


def test_a_footprint_study_flown_synchronously_keeps_its_steps_long_enough(api):
    """A footprint study's flights take steps of at most its case's integrator.max_step_s: at 0.01 s each of 100
    flights takes the integrator's 200,000 steps (an exact transform ~100 s here, 12 s at 0.1 s, 0.9 s at the
    default 50 s); the door of a synchronous request holds it to 1 s or more."""
    fine = copy.deepcopy(FOOTPRINT)
    fine["case"]["integrator"] = {"max_step_s": 0.01}
    r = api.post("/api/transform", json=exact_transform(fine))
    assert r.status_code == 422, r.text[:300]
    assert r.json()["field"] == "study.case.integrator.max_step_s"
    assert r.json()["detail"].startswith(
        "study.case.integrator.max_step_s: 0.01 is outside the allowed range 1 to 1000 s in a synchronous request"
    )
    r = api.post("/api/reach", json=REACH | {"footprint": {"study": fine}})
    assert r.status_code == 422 and r.json()["field"] == "footprint.study.case.integrator.max_step_s", r.text[:300]
    contracts.parse("footprint", fine, context(HTTP))  # a job flies it
    contracts.parse("reach", REACH | {"footprint": {"study": fine}}, context(HTTP))


def test_a_footprint_study_of_a_guided_case_is_refused_at_every_door():
    """A footprint study replaces its case's bank law with its method's, but a guided case kept its guidance: every
    point of the footprint flew guided to the case's target (three settings, three landings at 5,000 nmi), and a
    synchronous reach or transform flew up to 100 guided flights. The guided vehicle's footprint is its own kind."""
    study = {"case": GUIDED, "method": "single_parameter", "bank0_deg": [0, 45, 90]}
    for ctx in (None, context(HTTP), context(HTTP_SYNC)):
        with pytest.raises(ValidationError) as err:
            contracts.parse("footprint", study, ctx)
        assert error_line(err.value).startswith("case.bank.law: 'guided' ")
        assert "guided_footprint" in error_line(err.value)


TINY_LIMIT_S = 1e-6  # passed before any flight starts: every computation below meets it


@pytest.fixture(scope="module")
def hurried(scheduler_address, tmp_path_factory):
    """A service whose synchronous requests may compute for a microsecond."""
    with (
        database_url("sqlite", tmp_path_factory.mktemp("hurried")) as url,
        running_service(url, scheduler_address, sync_time_limit_s=TINY_LIMIT_S) as client,
    ):
        yield client


@pytest.mark.parametrize(
    "path, body",
    [
        ("/api/trajectories", GUIDED),  # passes the door; stopped in its guidance loop
        ("/api/trajectories", CASE),
        ("/api/reach", REACH | {"footprint": {"study": FOOTPRINT}}),
        ("/api/transform", exact_transform(FOOTPRINT)),
    ],
)
def test_a_synchronous_computation_past_the_time_limit_is_stopped_with_one_line(hurried, path, body):
    r = hurried.post(path, json=body)
    assert r.status_code == 422, r.text[:300]
    detail = r.json()["detail"]
    assert f"took longer than the synchronous limit of {TINY_LIMIT_S:g} s" in detail, detail
    assert "FOOTPRINT_SYNC_TIME_LIMIT_S" in detail and "\n" not in detail
    assert hurried.get("/api/health").status_code == 200  # the process answers on
