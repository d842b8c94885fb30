"""Dispersion jobs (issue 16) through the service and on Dask: a job of four chunk tasks, its result the same as the
same study flown in this process (and on the tests' cluster reached as a remote scheduler over loopback), and bad
dispersions answered 422 naming the field."""

import copy

import numpy as np
import pytest

from footprint.contracts.dispersion import run
from footprint.service.jobs.tasks import plain
from tests.authorities.report import example
from tests.service.conftest import wait_for_job

STUDY = {"footprint": example("footprint_lod189") | {"bank0_deg": [0, 60, 120]}, "samples": 40, "seed": 4,
         "chunk_samples": 10, "entry": {"gamma_deg": {"normal": {"std": 0.03}}},
         "vehicle": {"cd_multiplier": {"uniform": {"half_width": 0.02}}}, "density": {"std": 0.04},
         "sites": [{"name": "Diego Garcia", "latitude_deg": -7.313, "longitude_deg": 72.411}]}


def test_the_same_seed_and_samples_give_the_same_bits_in_this_process_and_on_two_remote_workers(scheduler_address):
    here, info_here = run(copy.deepcopy(STUDY))
    there, info_there = run(copy.deepcopy(STUDY), scheduler=scheduler_address)  # the remote-scheduler path
    assert (info_here["workers"], info_there["workers"], info_there["tasks"]) == (0, 2, 4)
    for key in here.clouds:
        np.testing.assert_array_equal(here.clouds[key], there.clouds[key])
    assert here.sites == there.sites and here.confidence == there.confidence


def test_a_dispersion_job_runs_chunk_by_chunk_and_stores_the_result(api):
    job = wait_for_job(api, api.post("/api/jobs", json={"kind": "dispersion", "study": STUDY}).json()["id"])
    assert job["status"] == "succeeded", job
    got = job["result"]["dispersion"]
    assert got["samples"] == 40 and got["outcomes"] == {"flights": 240, "landed": 240}
    assert got["trajectories"] == 240 and got["run"] == {"tasks": 4}
    here, _ = run(copy.deepcopy(STUDY))
    assert got["sites"] == plain(here.sites)
    assert [f["mean_downrange_nmi"] for f in got["flights"]] == [f["mean_downrange_nmi"] for f in here.flights]
    assert len(got["clouds"]["latitude_deg"]) == 6 and len(got["clouds"]["latitude_deg"][0]) == 40
    listed = api.get("/api/jobs", params={"kind": "dispersion"}).json()
    assert listed["items"][0]["id"] == job["id"]


@pytest.mark.parametrize("change, field", [
    ({"entry": {"gamma_deg": {"normal": {"std": -1}}}}, "study.entry.gamma_deg.normal.std"),
    ({"samples": 200_000}, "study.samples"),
    ({"density": {"std": [0.1, 0.1]}}, "study.density"),
    ({"footprint": STUDY["footprint"] | {"bank0_deg": [200]}}, "study.footprint.bank0_deg.0"),
])
def test_bad_dispersions_are_422_naming_the_field(api, change, field):
    r = api.post("/api/jobs", json={"kind": "dispersion", "study": STUDY | change})
    assert r.status_code == 422 and r.json()["field"].startswith(field), r.json()
