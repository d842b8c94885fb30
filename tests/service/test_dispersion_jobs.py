"""Dispersion jobs (issue 16) through the service and on Dask: a job of four chunk tasks, its result the same as the
same study flown in this process (and on the tests' cluster reached as a remote scheduler over loopback), and bad
dispersions answered 422 naming the field."""

import copy

import numpy as np
import pytest

from footprint.api import disperse as run
from footprint.contracts.records import plain
from tests.authorities.report import example
from tests.service.conftest import wait_for_job
from tests.service.sample_requests import UNKNOWN_ID

STUDY = {
    "footprint": example("footprint_lod189") | {"bank0_deg": [0, 60, 120]},
    "samples": 40,
    "seed": 4,
    "chunk_samples": 10,
    "entry": {"gamma_deg": {"normal": {"std": 0.03}}},
    "vehicle": {"cd_multiplier": {"uniform": {"half_width": 0.02}}},
    "density": {"std": 0.04},
    "sites": [{"name": "Diego Garcia", "latitude_deg": -7.313, "longitude_deg": 72.411}],
}


def test_the_same_seed_and_samples_give_the_same_bits_in_this_process_and_on_two_remote_workers(scheduler_address):
    here, info_here = run(copy.deepcopy(STUDY))
    there, info_there = run(copy.deepcopy(STUDY), scheduler=scheduler_address)  # the remote-scheduler path
    assert (info_here["workers"], info_there["workers"], info_there["tasks"]) == (0, 2, 4)
    for key in here.clouds:
        np.testing.assert_array_equal(here.clouds[key], there.clouds[key])
    assert here.sites == there.sites and here.confidence == there.confidence


def test_a_dispersion_job_runs_chunk_by_chunk_and_stores_the_result(api):
    asked = STUDY | {"histories": [33]}  # a sample of the last chunk, flown again with histories by the engine
    job = wait_for_job(api, api.post("/api/jobs", json={"kind": "dispersion", "study": asked}).json()["id"])
    assert job["status"] == "succeeded", job
    got = job["result"]["dispersion"]
    assert got["samples"] == 40 and got["outcomes"] == {"flights": 240, "landed": 240}
    assert [h["sample"] for h in got["histories"]] == [33] * 6
    for j, h in enumerate(got["histories"]):  # the histories end where the worker's summary path landed
        assert h["latitude_deg"][-1] == got["clouds"]["latitude_deg"][j][33]
        assert h["longitude_deg"][-1] == got["clouds"]["longitude_deg"][j][33]
    assert got["trajectories"] == 240 and got["run"]["tasks"] == 4 and got["run"]["workers"] >= 1
    here, _ = run(copy.deepcopy(STUDY))
    assert got["sites"] == plain(here.sites)
    assert [f["mean_downrange_nmi"] for f in got["flights"]] == [f["mean_downrange_nmi"] for f in here.flights]
    assert len(got["clouds"]["latitude_deg"]) == 6 and len(got["clouds"]["latitude_deg"][0]) == 40
    listed = api.get("/api/jobs", params={"kind": "dispersion"}).json()
    assert listed["items"][0]["id"] == job["id"]


@pytest.mark.parametrize(
    "change, field",
    [
        ({"entry": {"gamma_deg": {"normal": {"std": -1}}}}, "study.entry.gamma_deg.normal.std"),
        ({"samples": 200_000}, "study.samples"),
        ({"density": {"std": [0.1, 0.1]}}, "study.density"),
        ({"footprint": STUDY["footprint"] | {"bank0_deg": [200]}}, "study.footprint.bank0_deg.0"),
    ],
)
def test_bad_dispersions_are_422_naming_the_field(api, change, field):
    r = api.post("/api/jobs", json={"kind": "dispersion", "study": STUDY | change})
    assert r.status_code == 422 and r.json()["field"].startswith(field), r.json()


SITES = [
    {"name": "Diego Garcia", "latitude_deg": -7.313, "longitude_deg": 72.411},  # deep inside
    {"name": 'Kennedy SLF, "=cmd"', "latitude_deg": 28.615, "longitude_deg": -80.695},  # behind the entry
    {"name": "Honolulu", "latitude_deg": 21.319, "longitude_deg": -157.922},  # past 180 E, near the far end
    {"name": "Kwajalein", "latitude_deg": 8.72, "longitude_deg": 167.732},
    {"name": "=1+2", "latitude_deg": -80.0, "longitude_deg": 0.0},
]  # a formula, to a spreadsheet


def _holds(geometry, lon, lat) -> bool:
    """Even-odd in longitude and latitude (RFC 7946 pieces each lie within -180..180, so plain in degrees)."""
    from matplotlib.path import Path

    polygons = geometry["coordinates"] if geometry["type"] == "MultiPolygon" else [geometry["coordinates"]]
    return any(Path(np.asarray(p[0])).contains_point((lon, lat)) for p in polygons)


def test_a_dispersion_is_read_as_geojson_and_its_sites_as_csv(api):
    """GET /api/jobs/{id}/dispersion: the footprints cut at the antimeridian, every site where the chart's own test
    (inside_nominal, in down-range and cross-range) puts it; the CSV's rows are the result's sites."""
    import csv
    import io

    job = wait_for_job(
        api, api.post("/api/jobs", json={"kind": "dispersion", "study": STUDY | {"sites": SITES}}).json()["id"]
    )
    assert job["status"] == "succeeded", job
    result = job["result"]["dispersion"]
    r = api.get(f"/api/jobs/{job['id']}/dispersion")
    assert r.status_code == 200 and r.headers["content-type"] == "application/geo+json"
    features = r.json()["features"]
    by_kind = {}
    for f in features:
        by_kind.setdefault(f["properties"]["kind"], []).append(f)
        coords = np.array(
            [
                xy
                for ring in (
                    f["geometry"]["coordinates"]
                    if f["geometry"]["type"] == "MultiPolygon"
                    else [f["geometry"]["coordinates"]]
                )
                for xy in np.reshape(ring, (-1, 2))
            ]
            if f["geometry"]["type"] != "Point"
            else [f["geometry"]["coordinates"]]
        )
        assert (np.abs(coords[:, 0]) <= 180).all() and (np.abs(coords[:, 1]) <= 90).all()
    nominal = by_kind["nominal_footprint"][0]["geometry"]
    assert nominal["type"] == "MultiPolygon"  # the L/D 1.89 footprint runs past 180 E
    assert len(by_kind["ellipse"]) == 2 * len(result["flights"])
    assert len(by_kind["confidence_footprint"]) == sum(len(c["rings"]) for c in result["confidence"])
    for site, feature in zip(result["sites"], by_kind["site"], strict=True):
        lon, lat = feature["geometry"]["coordinates"]
        assert (lat, lon) == pytest.approx((site["latitude_deg"], site["longitude_deg"]))
        assert _holds(nominal, lon, lat) == site["inside_nominal"], site["name"]
        assert feature["properties"]["probability"] == site["probability"]
    deep = by_kind["site"][0]
    assert deep["properties"]["probability"] == 1.0
    assert all(_holds(f["geometry"], *deep["geometry"]["coordinates"]) for f in by_kind["confidence_footprint"])
    behind = by_kind["site"][1]["geometry"]["coordinates"]
    assert not any(_holds(f["geometry"], *behind) for f in by_kind["confidence_footprint"] + by_kind["ellipse"])

    r = api.get(f"/api/jobs/{job['id']}/dispersion", params={"format": "csv"})
    assert r.status_code == 200 and r.headers["content-type"].startswith("text/csv")
    assert "attachment" in r.headers["content-disposition"]
    rows = list(csv.DictReader(io.StringIO(r.text)))
    assert [row["name"] for row in rows] == [s["name"] for s in SITES[:-1]] + ["'=1+2"]  # kept text
    assert [float(row["probability"]) for row in rows] == [s["probability"] for s in result["sites"]]
    assert all(int(row["samples"]) == 40 for row in rows)


def test_only_a_succeeded_dispersion_job_has_a_dispersion(api):
    assert api.get(f"/api/jobs/{UNKNOWN_ID}/dispersion").status_code == 404
    assert api.get("/api/jobs/nope/dispersion").status_code == 422  # cannot be an id
    job = api.post(
        "/api/jobs", json={"kind": "footprint", "study": example("footprint_lod189") | {"bank0_deg": [0]}}
    ).json()
    r = api.get(f"/api/jobs/{job['id']}/dispersion")
    assert r.status_code == 404 and "is a footprint job" in r.json()["detail"], r.json()
    assert api.get(f"/api/jobs/{job['id']}/dispersion", params={"format": "kml"}).status_code == 422
    wait_for_job(api, job["id"])
