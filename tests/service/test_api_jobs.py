"""Jobs through the REST API on SQLite and Postgres: footprints equal the Python door's, sweeps, optimization,
reach, listing, cancelling, progress events, a job the core fails, and the stored footprints' formats."""

import csv
import io
import json
import math
import re
import time
from pathlib import Path

import numpy as np
import pytest

from footprint.api import fly
from footprint.api import footprint as fly_footprint
from footprint.contracts.footprint import POINT_FIELDS
from tests.authorities.report import betts

from .conftest import wait_for_job, wait_until
from .sample_requests import (
    FOOTPRINT,
    LONG_FOOTPRINT,
    OPTIMAL_FOOTPRINT,
    OPTIMIZE,
    REACH,
    SWEEP,
    UNKNOWN_ID,
    footprint_study,
)

ROOT = Path(__file__).resolve().parents[2]


def submit(api, kind, study, **extra):
    r = api.post("/api/jobs", json={"kind": kind, "study": study, **extra})
    assert r.status_code == 202, r.text
    job_id = r.json()["id"]
    # issue 13 item 9: the job's URL in the Location header and the body
    assert r.json() | {"id": None, "name": None} == {
        "id": None,
        "name": None,  # the job's name, given or made (issue 53 item 3), asserted where the name is the point
        "status": "queued",
        "url": f"/api/jobs/{job_id}",
        "events": f"/api/jobs/{job_id}/events",
    }
    assert r.headers["location"] == f"/api/jobs/{job_id}"
    return job_id


def run_job(api, kind, study, **extra) -> dict:
    job = wait_for_job(api, submit(api, kind, study, **extra))
    assert job["status"] == "succeeded", job["error"]
    return job


@pytest.fixture(scope="module")
def footprint_job(api):
    job = run_job(api, "footprint", FOOTPRINT, name="lod-1.89 small")
    fp_id = job["result"]["footprints"][0].rsplit("/", 1)[1]
    return job, api.get(f"/api/footprints/{fp_id}").json()


def test_a_footprint_job_equals_the_python_door(footprint_job, same_numbers):
    job, stored = footprint_job
    direct = fly_footprint(FOOTPRINT)
    assert len(job["result"]["footprints"]) == 1 and job["progress"] == 1.0 and job["error"] is None
    assert job["started_at"] <= job["finished_at"] and job["study"] == FOOTPRINT
    same_numbers(
        [{k: p[k] for k in POINT_FIELDS} for p in stored["points"]],
        [{k: p.to_dict()[k] for k in POINT_FIELDS} for p in direct.points],  # the setting in its stored form
    )
    same_numbers([p["downrange_nmi"] for p in stored["interior"]], [p.downrange_nmi for p in direct.interior])
    same_numbers(
        [stored[k] for k in ("area_nmi2", "max_crossrange_nmi", "max_downrange_nmi", "min_downrange_nmi")],
        [direct.area_nmi2, direct.max_crossrange_nmi, direct.max_downrange_nmi, direct.min_downrange_nmi],
    )
    assert stored["trajectories"] == direct.trajectories and stored["name"] == "lod-1.89 small"
    assert job["result"]["limits"] == direct.limits()  # the flights that broke a vehicle limit, counted
    assert stored["entry"] == {
        "latitude_deg": 10.0,
        "longitude_deg": 0.0,
        "heading_deg": 90.0,
        "velocity_fps": 22_000.0,
        "gamma_deg": -3.0,
        "altitude_ft": 364_800.0,
    }


@pytest.fixture(scope="module")
def optimal_direct():
    return fly_footprint(OPTIMAL_FOOTPRINT)


def watched(api, job_id):
    """The job's final state and every (progress, note) seen while it ran, polled every 0.05 s."""
    seen = []
    while (job := api.get(f"/api/jobs/{job_id}").json())["status"] in ("queued", "running"):
        if job["status"] == "running":
            seen.append((job["progress"], job["progress_note"]))
        time.sleep(0.05)
    return job, seen


def test_an_optimal_footprint_job_is_stored_like_the_others(api, optimal_direct, same_numbers):
    job, seen = watched(api, submit(api, "footprint", OPTIMAL_FOOTPRINT))
    assert job["status"] == "succeeded", job["error"]
    # IPOPT's iterations reached the row while the single task ran: rising, short of the end, said
    notes = [(p, n) for p, n in seen if n is not None]
    assert notes and all(0.0 <= p < 1.0 for p, _ in notes) and max(p for p, _ in notes) > 0.0, seen
    assert [p for p, _ in seen] == sorted(p for p, _ in seen)
    # 8 solves for the 4 extremes (the widest from two starts, the farthest from three, one by way of 20 deg) and
    # 3 down-ranges, the right half mirrored
    assert all(re.fullmatch(r"solve \d+ of 11: IPOPT iteration \d+", n) for _, n in notes), notes
    assert job["progress"] == 1.0 and job["progress_note"] is None
    stored = api.get(f"/api/footprints/{job['result']['footprints'][0].rsplit('/', 1)[1]}").json()
    assert stored["method"] == "collocation" and len(stored["points"]) == 1 + 2 * 5
    assert not any("inverted_s" in p["parameter"] for p in stored["points"])  # alpha_bounds_deg reached the NLP
    same_numbers(
        [[p["downrange_nmi"], p["crossrange_nmi"], p["latitude_deg"], p["longitude_deg"]] for p in stored["points"]],
        [[p.downrange_nmi, p.crossrange_nmi, p.latitude_deg, p.longitude_deg] for p in optimal_direct.points],
    )
    geometry = api.get(f"/api/footprints/{stored['id']}", params={"format": "geojson"}).json()["features"][0][
        "geometry"
    ]
    assert geometry["type"] in ("Polygon", "MultiPolygon")


def test_the_ground_track_is_the_zero_bank_flight(footprint_job):
    _, stored = footprint_job
    track = stored["ground_track"]
    zero_bank = next(p for p in stored["points"] if p["parameter"].get("bank0_deg") == 0)  # the axis point
    assert 100 < len(track) <= 500
    assert track[0]["time_s"] == 0 and track[0]["latitude_deg"] == pytest.approx(10, abs=1e-9)
    assert track[-1]["time_s"] == pytest.approx(zero_bank["flight_time_s"], rel=1e-12)
    assert track[-1]["latitude_deg"] == pytest.approx(zero_bank["latitude_deg"], abs=1e-9)
    assert track[-1]["longitude_deg"] == pytest.approx(zero_bank["longitude_deg"], abs=1e-9)
    assert all(b["time_s"] > a["time_s"] for a, b in zip(track, track[1:]))


def test_footprint_list_csv_and_geojson(api, footprint_job):
    job, stored = footprint_job
    listed = api.get("/api/footprints", params={"job_id": job["id"]}).json()
    assert listed["total"] == 1 and listed["items"][0]["id"] == stored["id"]
    assert "points" not in listed["items"][0]
    rows = list(csv.DictReader(io.StringIO(api.get(f"/api/footprints/{stored['id']}?format=csv").text)))
    assert [float(r["crossrange_nmi"]) for r in rows] == [p["crossrange_nmi"] for p in stored["points"]]
    gj = api.get(f"/api/footprints/{stored['id']}", params={"format": "geojson"}).json()
    kinds = [f["properties"]["kind"] for f in gj["features"]]
    assert kinds == ["footprint", "entry", "ground_track"] + ["point"] * len(stored["points"])
    ring = gj["features"][0]["geometry"]["coordinates"][0]  # 11-83 deg E: no antimeridian, one polygon
    assert gj["features"][0]["geometry"]["type"] == "Polygon" and ring[0] == ring[-1]
    # the outline (the chart's edges sampled) to 1e-6 deg, through every stored boundary point
    o = stored["outline"]
    assert ring[:-1] == [[round(x, 6), round(y, 6)] for x, y in zip(o["longitude_deg"], o["latitude_deg"])]
    for p in stored["points"]:
        assert min(abs(x - p["longitude_deg"]) + abs(y - p["latitude_deg"]) for x, y in ring) < 2e-6


def test_the_offline_map_page_of_a_footprint(api, footprint_job):
    from footprint.pictures.folium_page import FRONTEND_DIR

    _, stored = footprint_job
    r = api.get(f"/api/footprints/{stored['id']}/map")
    if not (FRONTEND_DIR / "vendor" / "leaflet" / "leaflet.js").is_file():  # `npm ci` has not copied Leaflet there
        assert r.status_code == 503 and "npm ci" in r.json()["detail"]
        return
    assert r.status_code == 200 and r.headers["content-type"].startswith("text/html")
    assert stored["name"] in r.text
    assert not re.search(r'<(script|link)[^>]+(src|href)="(https?:)?//', r.text)  # nothing from the internet
    # issue 15 item 1: folium's inline scripts allowed by hash, nothing else (and the page's policy on the 404)
    from footprint.csp import inline_script_hashes, standalone_policy

    assert r.headers["content-security-policy"] == standalone_policy(inline_script_hashes(r.text), header=True)
    assert "frame-ancestors 'none'" in r.headers["content-security-policy"]
    missing = api.get(f"/api/footprints/{UNKNOWN_ID}/map")
    assert missing.status_code == 404 and "script-src 'self';" in missing.headers["content-security-policy"]


def _shoelace(ring) -> float:
    x, y = np.array(ring, float).T
    return 0.5 * abs(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1)))


def test_a_footprint_across_the_date_line_is_split_there(api):
    job = run_job(api, "footprint", footprint_study(longitude_deg=150.0))  # lands 161-233 deg E
    stored = api.get(job["result"]["footprints"][0]).json()
    lon = [p["longitude_deg"] for p in stored["points"]]
    assert min(lon) < -90 and max(lon) > 90  # the stored points wrap: some east of 180 are negative
    geometry = api.get(job["result"]["footprints"][0], params={"format": "geojson"}).json()["features"][0]["geometry"]
    assert geometry["type"] == "MultiPolygon" and len(geometry["coordinates"]) == 2
    pieces = [poly[0] for poly in geometry["coordinates"]]
    for ring in pieces:
        assert ring[0] == ring[-1] and all(-180 <= x <= 180 for x, _ in ring)
        assert all(abs(b[0] - a[0]) < 180 for a, b in zip(ring, ring[1:]))  # no jump inside a piece
    (west_lo, _), (_, east_hi) = sorted((min(x for x, _ in r), max(x for x, _ in r)) for r in pieces)
    assert (west_lo, east_hi) == (-180.0, 180.0)  # the cut lies on the antimeridian
    whole = list(zip(stored["outline"]["longitude_deg"], stored["outline"]["latitude_deg"]))  # continuous
    assert sum(_shoelace(r) for r in pieces) == pytest.approx(_shoelace(whole), rel=1e-8)  # nothing lost or added
    track = api.get(job["result"]["footprints"][0], params={"format": "geojson"}).json()["features"][2]["geometry"]
    assert track["type"] == "MultiLineString"
    assert all(abs(b[0] - a[0]) < 180 for line in track["coordinates"] for a, b in zip(line, line[1:]))


def test_deleting_a_footprint_deletes_its_points_and_track(api):
    from sqlalchemy import create_engine, text

    job = run_job(api, "footprint", FOOTPRINT)
    link = job["result"]["footprints"][0]
    fp_id = link.rsplit("/", 1)[1]
    assert api.get(link).json()["points"] and api.get(link).json()["ground_track"]
    assert api.delete(link).status_code == 204
    assert api.get(link).status_code == 404 and api.delete(link).status_code == 404
    assert api.get(f"/api/jobs/{job['id']}").json()["result"]["footprints"] == []
    engine = create_engine(api.database_url)
    with engine.connect() as c:
        left = [
            c.execute(text(f"SELECT COUNT(*) FROM {t} WHERE footprint_id = :i"), {"i": fp_id}).scalar()
            for t in ("footprint_points", "trajectories")
        ]
    engine.dispose()
    assert left == [0, 0]


def test_moving_a_footprint_along_its_parallel_shifts_every_longitude(api, footprint_job):
    _, stored = footprint_job
    moved = api.post(
        f"/api/footprints/{stored['id']}/transform",
        json={"to": {"latitude_deg": 10, "longitude_deg": 25, "heading_deg": 90}},
    ).json()
    # from (10 N, 0 E, heading 90) to (10 N, 25 E, heading 90): a rotation about the polar axis by 25 deg
    assert len(moved["points"]) == len(stored["points"])
    for a, b in zip(stored["points"], moved["points"]):
        assert b["latitude_deg"] == pytest.approx(a["latitude_deg"], abs=1e-9)
        assert b["longitude_deg"] == pytest.approx(a["longitude_deg"] + 25, abs=1e-9)
    assert moved["ground_track"][-1]["longitude_deg"] == pytest.approx(
        stored["ground_track"][-1]["longitude_deg"] + 25, abs=1e-9
    )
    same_place = {"latitude_deg": 10, "longitude_deg": 0, "heading_deg": 90}
    again = api.post(f"/api/footprints/{stored['id']}/transform", json={"to": same_place, "earth_rotation": "exact"})
    flown = [p for p in again.json()["points"] if p["on_boundary"]]  # the study flown again, from the same place
    assert [p["crossrange_nmi"] for p in flown] == pytest.approx(
        [p["crossrange_nmi"] for p in stored["points"]], abs=1e-6
    )  # nmi
    bad = api.post(
        f"/api/footprints/{stored['id']}/transform",
        json={"to": {"latitude_deg": 95, "longitude_deg": 0, "heading_deg": 0}},
    )
    assert bad.status_code == 422 and bad.json()["field"] == "to.latitude_deg"


def test_a_job_may_name_a_stored_vehicle(api):
    glider = {"aero": {"constant": {"cl": 0.5, "cd": 0.25}}, "wing_loading_psf": 50}
    assert api.post("/api/vehicles", json={"id": "job-glider", "vehicle": glider}).status_code == 201
    study = {**FOOTPRINT, "case": {**FOOTPRINT["case"], "vehicle": {"stored": "job-glider"}}}
    job = run_job(api, "footprint", study)
    # resolved when submitted, with the limits every vehicle carries unless its definition changes them (issue 50)
    limits = {"load_factor_g": 2.5, "dynamic_pressure_psf": 375.0, "heat_rate_btu_ft2_s": 70.0, "temperature_R": 3460.0}
    assert job["study"]["case"]["vehicle"] == glider | {"name": "job-glider", "limits": limits}
    stored = api.get(job["result"]["footprints"][0]).json()
    direct = fly_footprint({**FOOTPRINT, "case": {**FOOTPRINT["case"], "vehicle": glider}})
    assert stored["vehicle"] == "job-glider"
    assert stored["max_downrange_nmi"] == pytest.approx(direct.max_downrange_nmi, rel=1e-12)


def test_a_sweep_job_is_one_footprint_per_task(api, same_numbers):
    job = run_job(api, "sweep", SWEEP)
    assert len(job["result"]["footprints"]) == 2 and job["result"]["sweep"]["errors"] == []
    for link, velocity in zip(job["result"]["footprints"], SWEEP["entry_velocity_fps"]):
        stored = api.get(link).json()
        assert stored["entry"]["velocity_fps"] == velocity
        study = {
            "case": {
                "vehicle": {"builtin": "lod-1.89"},
                "entry": {"altitude_ft": 364_800, "heading_deg": 90, "velocity_fps": velocity, "gamma_deg": -3},
                "stop": {"altitude_ft": 50_000},
            },
            "method": "single_parameter",
            "bank0_deg": [0, 90],
        }
        same_numbers(
            [p["downrange_nmi"] for p in stored["points"]], [p.downrange_nmi for p in fly_footprint(study).points]
        )


def test_optimize_and_reach_jobs_store_their_results(api):
    opt = run_job(api, "optimize", OPTIMIZE)["result"]["optimization"]
    assert opt["trajectories"] <= 20 and set(opt["parameters"]) and opt["history"]
    again = fly(
        {
            **OPTIMIZE["case"],
            "bank": {
                "law": "table",
                "heading_deg": [-15, 0, 15, 30, 45, 60, 75, 90],
                "bank_deg": list(opt["parameters"].values()),
            },
        }
    )
    assert opt["summary"]["crossrange_nmi"] == pytest.approx(again.summary["crossrange_nmi"], abs=1e-6)  # nmi
    flight = opt["flight"]  # the optimum's flight for the map: it ends where the Python door's flight does
    assert flight["latitude_deg"][-1] == pytest.approx(again.summary["final_latitude_deg"], abs=1e-9)
    assert flight["longitude_deg"][-1] == pytest.approx(again.summary["final_longitude_deg"], abs=1e-9)
    assert flight["time_s"][-1] == pytest.approx(again.summary["flight_time_s"], rel=1e-12)
    assert set(flight) >= {"alpha_deg", "bank_deg", "altitude_ft", "velocity_fps"} and "temperature_R" not in flight
    reach = run_job(api, "reach", REACH)["result"]["reach"]
    assert [s["name"] for s in reach["sites"]] == ["KSC", "Edwards"]
    assert reach["analysis"]["revolutions"] == [1, 3]


def test_a_collocation_optimization_job_reports_iterations_and_returns_its_flight(api):
    """Betts' shuttle by IPOPT over REST: IPOPT's iterations reach the job row while it runs, and the stored
    flight is the re-flight of the optimum, ending within 0.01 deg of Betts' 34.1412 deg."""
    study = json.loads((ROOT / "examples" / "optimize_betts_collocation.json").read_text())
    job, seen = watched(api, submit(api, "optimize", study))
    assert job["status"] == "succeeded", job["error"]
    # each mesh's iterations, then the polish's (the mesh is refined until the optimum settles: issue 29)
    assert any(n and re.fullmatch(r"100 intervals: IPOPT iteration \d+", n) for _, n in seen), seen
    flight = job["result"]["optimization"]["flight"]
    assert flight["latitude_deg"][-1] == pytest.approx(betts()["final_latitude_deg"], abs=0.01)
    assert flight["altitude_ft"][-1] == pytest.approx(80_000, abs=50)
    assert min(flight["bank_deg"]) >= -1.0 - 1e-6 and max(flight["bank_deg"]) <= 89.0 + 1e-6  # Betts' bounds


def test_jobs_are_listed_newest_first_with_filters(api):
    first, second = submit(api, "footprint", FOOTPRINT), submit(api, "reach", REACH)
    for job_id in (first, second):
        wait_for_job(api, job_id)
    every = api.get("/api/jobs", params={"limit": 500}).json()
    ids = [j["id"] for j in every["items"]]
    assert every["total"] == len(ids) and ids.index(second) < ids.index(first)
    assert "study" not in every["items"][0]
    reach_only = api.get("/api/jobs", params={"kind": "reach"}).json()
    assert {j["kind"] for j in reach_only["items"]} == {"reach"} and second in [j["id"] for j in reach_only["items"]]
    page = api.get("/api/jobs", params={"limit": 1, "offset": 1}).json()
    assert page["items"][0]["id"] == ids[1] and page["total"] == every["total"]
    succeeded = api.get("/api/jobs", params={"status": "succeeded", "limit": 500}).json()
    assert succeeded["total"] >= 2 and {j["status"] for j in succeeded["items"]} == {"succeeded"}
    bad = api.get("/api/jobs", params={"status": "done"})
    assert bad.status_code == 422 and bad.json()["field"] == "status"


def test_progress_events_end_when_the_job_does(api):
    job_id = submit(api, "sweep", SWEEP)
    with api.stream("GET", f"/api/jobs/{job_id}/events") as r:
        assert r.headers["content-type"].startswith("text/event-stream")
        text = "".join(r.iter_text())
    events = [
        (b.split("\n")[0].removeprefix("event: "), json.loads(b.split("\n")[1].removeprefix("data: ")))
        for b in text.strip().split("\n\n")
    ]
    assert events[-1][0] == "end" and events[-1][1]["status"] == "succeeded"
    progress = [data["progress"] for name, data in events if name == "progress"]
    assert progress == sorted(progress) and progress[-1] == 1.0
    assert api.get(f"/api/jobs/{UNKNOWN_ID}/events").status_code == 404


def test_cancel_a_running_job_and_keep_a_finished_ones_status(api):
    long = {
        **OPTIMIZE,
        "max_trajectories": 100_000,
        "constraints": [{"quantity": "downrange_nmi", "equals": 4_000}],
    }  # many seconds of work
    job_id = submit(api, "optimize", long)
    r = api.delete(f"/api/jobs/{job_id}")
    assert r.status_code == 200 and r.json()["status"] == "cancelled" and r.json()["result"] is None
    assert wait_for_job(api, job_id)["status"] == "cancelled"
    done = run_job(api, "reach", REACH)
    assert api.delete(f"/api/jobs/{done['id']}").json()["status"] == "succeeded"
    assert api.delete(f"/api/jobs/{UNKNOWN_ID}").status_code == 404


def _break_core():
    from footprint.core import footprint_methods

    def broken(*_args, **_kwargs):
        raise FloatingPointError("the integrator diverged (injected in the worker)")

    footprint_methods.original_footprint = footprint_methods.footprint
    footprint_methods.footprint = broken


def _mend_core():
    from footprint.core import footprint_methods

    footprint_methods.footprint = footprint_methods.original_footprint


def test_a_job_the_core_fails_ends_failed_and_the_service_goes_on(api, scheduler_address):
    from distributed import Client

    with Client(scheduler_address, set_as_default=False) as client:
        client.run(_break_core)
        try:
            job = wait_for_job(api, submit(api, "footprint", FOOTPRINT))
        finally:
            client.run(_mend_core)
    assert job["status"] == "failed" and job["result"] is None
    assert job["error"] == "FloatingPointError: the integrator diverged (injected in the worker)"
    wait_until(lambda: api.get("/api/health").json()["status"] == "ok", "health ok after the failed job")
    assert run_job(api, "footprint", FOOTPRINT)["status"] == "succeeded"


@pytest.fixture(scope="module")
def long_footprint(api):
    job = run_job(api, "footprint", LONG_FOOTPRINT)
    return api.get(job["result"]["footprints"][0]).json()


def test_a_move_keeps_the_flown_ranges_and_draws_the_polar_cap(api, long_footprint):
    """Issue 13 defects 1, 2 and 4 over REST: on a polar orbit the L/D 1.89 footprint keeps each point's flown
    down-range (14,869 nmi came back as -6,746) and cross-range, its outline closes the north polar cap, and
    its GeoJSON is the stored one's kind: cut at the antimeridian, closed along the pole, 6 decimals."""
    stored = long_footprint
    assert max(p["downrange_nmi"] for p in stored["points"]) > 14_000
    moved = api.post(
        f"/api/footprints/{stored['id']}/transform",
        json={"to": {"latitude_deg": 0, "longitude_deg": -60, "inclination_deg": 90}, "step_downrange_nmi": 1_000},
    ).json()
    assert [p["downrange_nmi"] for p in moved["points"]] == pytest.approx(
        [p["downrange_nmi"] for p in stored["points"]], abs=1e-6
    )
    assert [p["crossrange_nmi"] for p in moved["points"]] == pytest.approx(
        [p["crossrange_nmi"] for p in stored["points"]], abs=1e-6
    )
    assert moved["outline"]["pole"] == "north" and stored["outline"]["pole"] is None
    area = next(f for f in moved["geojson"]["features"] if f["properties"]["kind"] == "footprint")["geometry"]
    rings = [poly[0] for poly in area["coordinates"]] if area["type"] == "MultiPolygon" else area["coordinates"]
    assert all(-180 <= x <= 180 for r in rings for x, _ in r)
    assert any(y == 90.0 for r in rings for _, y in r)  # the cap runs along the pole


def test_an_exact_move_flies_the_track_again_and_measures_the_approximate_shift(api, long_footprint):
    """Issue 13 defect 3: with "exact" the dashed track is flown again too, so it ends at the exact footprint's
    far tip (the zero-bank point, the same flight); the approximate shift's distance from the exact points is
    reported (Section IV.3) and agrees with the two transforms' own points."""
    stored = long_footprint
    to = {"latitude_deg": 20, "longitude_deg": 30, "heading_deg": 45}
    exact = api.post(f"/api/footprints/{stored['id']}/transform", json={"to": to, "earth_rotation": "exact"}).json()
    tip = next(p for p in exact["points"] if p["on_boundary"] and p["parameter"].get("bank0_deg") == 0)
    end = exact["ground_track"][-1]
    assert end["latitude_deg"] == pytest.approx(tip["latitude_deg"], abs=1e-9)
    assert end["longitude_deg"] == pytest.approx(tip["longitude_deg"], abs=1e-9)
    approximate = api.post(
        f"/api/footprints/{stored['id']}/transform", json={"to": to, "earth_rotation": "approximate"}
    ).json()
    a_tip = next(q for p, q in zip(stored["points"], approximate["points"]) if p["parameter"].get("bank0_deg") == 0)
    assert approximate["ground_track"][-1]["longitude_deg"] == pytest.approx(a_tip["longitude_deg"], abs=1e-6)
    error = exact["approximate_error_nmi"]
    boundary = [p for p in exact["points"] if p["on_boundary"]]
    assert error["points"] == len(stored["points"]) == len(boundary)
    # the far tip's own distance, by the spherical law of cosines on R' (the largest is at least this)
    (a1, o1), (a2, o2) = [(math.radians(p["latitude_deg"]), math.radians(p["longitude_deg"])) for p in (tip, a_tip)]
    gap = 3_440.065 * math.acos(min(1.0, math.sin(a1) * math.sin(a2) + math.cos(a1) * math.cos(a2) * math.cos(o1 - o2)))
    assert error["max"] >= gap - 1e-6 and error["mean"] > 0 and gap > 10.0  # nmi


def test_footprints_get_unique_names_and_can_be_renamed(api):
    """Issue 13 item 5: the same study twice gave two footprints of one name; a planner renames them."""
    study = footprint_study(latitude_deg=-33.0)
    first, second = (
        api.get(run_job(api, "footprint", study, name="twin")["result"]["footprints"][0]).json() for _ in range(2)
    )
    assert (first["name"], second["name"]) == ("twin", "twin (2)")
    renamed = api.patch(f"/api/footprints/{second['id']}", json={"name": "  Vandenberg south  "})
    assert renamed.status_code == 200 and renamed.json()["name"] == "Vandenberg south"
    again = api.patch(f"/api/footprints/{first['id']}", json={"name": "Vandenberg south"}).json()
    assert again["name"] == "Vandenberg south (2)"
    assert (
        api.patch(f"/api/footprints/{first['id']}", json={"name": "Vandenberg south (2)"}).json()["name"]
        == "Vandenberg south (2)"
    )  # its own name is not taken by itself
    blank = api.patch(f"/api/footprints/{first['id']}", json={"name": "   "})
    assert blank.status_code == 422 and "name" in blank.json()["detail"]
    assert api.patch(f"/api/footprints/{UNKNOWN_ID}", json={"name": "x"}).status_code == 404


def test_a_footprint_jobs_default_name_is_set_when_it_is_created(api):
    """Issue 14 item 2 (part): the name was computed by the engine, parsing the study again, when the job ran."""
    r = api.post("/api/jobs", json={"kind": "footprint", "study": FOOTPRINT})
    job_id = r.json()["id"]
    queued = api.get(f"/api/jobs/{job_id}").json()
    # the study's vehicle, method in words and entry (issue 53 item 3: not "single_parameter", not a job id)
    altitude_kft = FOOTPRINT["case"]["entry"]["altitude_ft"] / 1000
    assert queued["name"] == f"lod-1.89 · single parameter · {altitude_kft:g} kft 22,000 ft/s -3°", queued["name"]
    assert r.json()["name"] == queued["name"]  # said when it is queued, for the page's job list
    done = wait_for_job(api, job_id)
    stored = api.get(done["result"]["footprints"][0]).json()
    assert stored["name"].startswith(queued["name"])  # numbered when another footprint has it
