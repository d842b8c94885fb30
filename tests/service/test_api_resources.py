"""Health, docs, vehicles, synchronous trajectories, geometry, landing sites and reach through the REST API, on
SQLite and Postgres."""

import copy
from pathlib import Path

import pytest

import footprint
from footprint.api import fly
from tests.authorities.report import REPORT, example

from .sample_requests import CASE, REACH, REACH_POINTS

ROOT = Path(__file__).resolve().parents[2]
GLIDER = {"aero": {"constant": {"cl": 0.5, "cd": 0.25}}, "wing_loading_psf": 50}  # L/D 2 at every alpha


def test_health_names_the_database_and_the_cluster(api):
    health = api.get("/api/health").json()
    assert health == {
        "status": "ok",
        "version": footprint.__version__,
        "database": {"ok": True, "dialect": api.database},
        "cluster": {"ok": True, "workers": 2, "expected_workers": 2},
    }  # no token set: no caller sees the scheduler's address


def test_openapi_docs_list_the_contract_paths(api):
    assert api.get("/docs").status_code == 200
    paths = set(api.get("/openapi.json").json()["paths"])
    assert {
        "/api/health",
        "/api/vehicles",
        "/api/vehicles/{vehicle_id}",
        "/api/trajectories",
        "/api/jobs",
        "/api/jobs/{job_id}",
        "/api/jobs/{job_id}/events",
        "/api/footprints",
        "/api/footprints/{footprint_id}",
        "/api/footprints/{footprint_id}/transform",
        "/api/transform",
        "/api/sites",
        "/api/sites/{site_id}",
        "/api/sites/csv",
        "/api/reach",
    } <= paths


def test_builtin_vehicles_carry_the_reports_lift_to_drag(api):
    items = {v["id"]: v for v in api.get("/api/vehicles").json()}
    assert {"lod-1.89", "lod-2.2", "lod-2.6"} <= set(items) and all(items[i]["builtin"] for i in items)
    assert items["lod-2.2"]["ld_max"] == pytest.approx(2.2, abs=0.01)  # Table B-3 at Mach 20, 200,000 ft
    glider = {"load_factor_g": 2.5, "dynamic_pressure_psf": 375.0, "heat_rate_btu_ft2_s": 70.0, "temperature_R": 3460.0}
    assert all(items[i]["limits"] == glider for i in items)  # a crewed glider's (core.limits)
    assert items["lod-1.89"]["ld_max"] == pytest.approx(REPORT["vehicle.lod-1.89.ld_max"].value, abs=0.01)
    detail = api.get("/api/vehicles/lod-2.2").json()
    aero = detail["aero"]
    assert aero["altitude_ft"] == 200_000 and len(aero["mach"]) == len(aero["ld_max"]) == len(aero["cl_max"])
    assert aero["ld_max"][aero["mach"].index(20.0)] == detail["ld_max"]
    assert all(cl > 0 for cl in aero["cl_max"])
    assert api.get("/api/vehicles/no-such-vehicle").status_code == 404


def test_a_custom_vehicle_is_stored_used_by_name_and_deleted(api):
    r = api.post("/api/vehicles", json={"id": "glider-2", "description": "constant L/D 2", "vehicle": GLIDER})
    assert r.status_code == 201, r.text
    assert r.json()["ld_max"] == pytest.approx(2.0, rel=1e-9) and r.json()["wing_loading_psf"] == 50
    assert r.json()["aero"]["ld_max"] == pytest.approx([2.0] * len(r.json()["aero"]["mach"]), rel=1e-9)
    assert "glider-2" in [v["id"] for v in api.get("/api/vehicles").json()]
    assert api.post("/api/vehicles", json={"id": "glider-2", "vehicle": GLIDER}).status_code == 409
    assert api.post("/api/vehicles", json={"id": "lod-2.2", "vehicle": GLIDER}).status_code == 409
    by_name = api.post("/api/trajectories", json={**CASE, "vehicle": {"stored": "glider-2"}}).json()
    inline = fly({**CASE, "vehicle": {**GLIDER, "name": "glider-2"}}).summary
    assert by_name["summary"]["downrange_nmi"] == pytest.approx(inline["downrange_nmi"], rel=1e-12)
    unknown = api.post("/api/trajectories", json={**CASE, "vehicle": {"stored": "nobody"}})
    assert unknown.status_code == 422 and unknown.json()["field"] == "vehicle.stored"
    assert api.delete("/api/vehicles/glider-2").status_code == 204
    assert api.get("/api/vehicles/glider-2").status_code == 404
    assert api.delete("/api/vehicles/glider-2").status_code == 404
    assert api.delete("/api/vehicles/lod-2.2").status_code == 409


def test_listing_custom_vehicles_rebuilds_none_of_them(api, monkeypatch):
    """Issue 15 item 8: GET /api/vehicles rebuilt every custom vehicle through a 64-entry cache walked in order
    (1.1-1.4 s a request past 64 vehicles). The list item's numbers are stored with the vehicle: listing packs no
    tables and searches no (L/D)max (bench/bench_vehicles.py: 1,000 vehicles)."""
    from footprint.service.routers import vehicles

    for i, ld in enumerate((1.5, 2.0, 3.0)):
        glider = {"aero": {"constant": {"cl": 0.5, "cd": 0.5 / ld}}, "wing_loading_psf": 40 + i}
        glider |= {"limits": {"load_factor_g": 3.0 + i}} if i < 2 else {"limits": None}
        assert api.post("/api/vehicles", json={"id": f"listed-{i}", "vehicle": glider}).status_code == 201

    def rebuilt(*_a, **_k):
        raise AssertionError("a stored vehicle was rebuilt to be listed")

    monkeypatch.setattr(vehicles, "ld_max", rebuilt)
    monkeypatch.setattr(vehicles, "_custom_vehicle", rebuilt)
    listed = {v["id"]: v for v in api.get("/api/vehicles").json()}
    assert [listed[f"listed-{i}"]["ld_max"] for i in range(3)] == pytest.approx([1.5, 2.0, 3.0], rel=1e-9)
    assert [listed[f"listed-{i}"]["wing_loading_psf"] for i in range(3)] == [40, 41, 42]
    assert [listed[f"listed-{i}"]["limits"]["load_factor_g"] for i in range(3)] == [3.0, 4.0, None]
    assert listed["listed-0"]["limits"]["dynamic_pressure_psf"] == 375.0  # the others kept
    assert set(listed["listed-2"]["limits"].values()) == {None}  # "limits": null lifts them all
    monkeypatch.undo()
    for i in range(3):
        assert api.delete(f"/api/vehicles/listed-{i}").status_code == 204


def test_a_bad_custom_vehicle_names_its_field(api):
    r = api.post(
        "/api/vehicles",
        json={"id": "bad", "vehicle": {"aero": {"constant": {"cl": 0.5, "cd": -0.1}}, "wing_loading_psf": 50}},
    )
    assert r.status_code == 422 and r.json()["field"] == "vehicle.aero.constant.cd"
    r = api.post("/api/vehicles", json={"id": "bad", "vehicle": {**GLIDER, "wing_loading_psf": 5_000}})
    assert r.status_code == 422 and r.json()["field"] == "vehicle.wing_loading_psf"
    assert "1 to 2,000" in r.json()["detail"]
    r = api.post("/api/vehicles", json={"id": "no spaces", "vehicle": GLIDER})
    assert r.status_code == 422 and r.json()["field"] == "id"


def test_a_trajectory_is_flown_at_once_and_its_history_decimated(api):
    table2 = example("table2_lod22")
    r = api.post("/api/trajectories", json=table2)
    assert r.status_code == 200
    direct = fly(table2)
    assert r.json()["summary"]["crossrange_nmi"] == pytest.approx(direct.summary["crossrange_nmi"], rel=1e-12)
    history = r.json()["history"]
    assert history["time_s"] == list(direct.history["time_s"])  # under 2,000 rows: every row
    fine = copy.deepcopy(table2) | {"integrator": {"max_step_s": 0.5}}  # more than 2,000 steps
    long = api.post("/api/trajectories", json=fine).json()
    rows = fly(fine).history["time_s"]
    assert len(rows) > 2_000 and len(long["history"]["time_s"]) == 2_000
    assert long["history"]["time_s"][0] == 0 and long["history"]["time_s"][-1] == rows[-1]
    assert {
        "altitude_ft",
        "velocity_fps",
        "latitude_deg",
        "longitude_deg",
        "downrange_nmi",
        "crossrange_nmi",
        "bank_deg",
        "alpha_deg",
    } <= set(history)


def test_transform_moves_points_along_the_parallel(api):
    body = {
        "points": [{"latitude_deg": 10, "longitude_deg": 30}, {"latitude_deg": -5, "longitude_deg": 40}],
        "from": {"latitude_deg": 0, "longitude_deg": 0, "heading_deg": 90},
        "to": {"latitude_deg": 0, "longitude_deg": -50, "heading_deg": 90},
    }
    moved = api.post("/api/transform", json=body).json()["points"]
    assert [(round(p["latitude_deg"], 9), round(p["longitude_deg"], 9)) for p in moved] == [(10, -20), (-5, -10)]


def test_sites_crud_and_csv_upload(api):
    created = api.post("/api/sites", json={"name": "White Sands", "latitude_deg": 32.9, "longitude_deg": -106.4})
    assert created.status_code == 201
    site = created.json()
    assert api.get(f"/api/sites/{site['id']}").json() == site
    moved = api.put(f"/api/sites/{site['id']}", json={"name": "WSSH", "latitude_deg": 32.94, "longitude_deg": -106.42})
    assert moved.json() == {
        "id": site["id"],
        "name": "WSSH",
        "latitude_deg": 32.94,
        "longitude_deg": -106.42,
        "last_reach": None,
    }
    assert api.delete(f"/api/sites/{site['id']}").status_code == 204
    for method in ("get", "delete"):
        assert getattr(api, method)(f"/api/sites/{site['id']}").status_code == 404
    assert (
        api.put(f"/api/sites/{site['id']}", json={"name": "x", "latitude_deg": 0, "longitude_deg": 0}).status_code
        == 404
    )
    csv_text = "name,latitude_deg,longitude_deg\nKSC,28.6,-80.6\nEdwards,34.9,-117.9\n"
    r = api.post("/api/sites/csv", content=csv_text, headers={"content-type": "text/csv"})
    assert r.status_code == 201 and r.json() == {"created": 2, "updated": 0}
    bad = api.post("/api/sites/csv", content=csv_text + "Pole,95,0\n", headers={"content-type": "text/csv"})
    assert bad.status_code == 422 and bad.json()["detail"].startswith("line 4: latitude_deg: 95 is outside")
    assert bad.json()["field"] == "line 4"
    header = api.post("/api/sites/csv", content="site,lat,lon\nA,1,2\n", headers={"content-type": "text/csv"})
    assert header.status_code == 422 and header.json()["field"] == "line 1"
    names = [s["name"] for s in api.get("/api/sites").json()]
    assert names.count("KSC") == 1 and "Pole" not in names  # the bad upload stored nothing


def test_reach_uses_the_stored_sites_when_none_are_given(api):
    stored = [s["name"] for s in api.get("/api/sites").json()]
    if not stored:
        api.post("/api/sites", json={"name": "Kwajalein", "latitude_deg": 9.4, "longitude_deg": 167.5})
        stored = ["Kwajalein"]
    body = {k: v for k, v in REACH.items() if k != "sites"}
    result = api.post("/api/reach", json=body).json()
    assert [s["name"] for s in result["sites"]] == stored
    given = api.post("/api/reach", json=REACH).json()
    assert [s["name"] for s in given["sites"]] == ["KSC", "Edwards"]
    assert given["footprint"]["points"] == len(REACH_POINTS)


def test_a_reach_may_keep_each_stored_sites_verdict(api):
    """Issue 13 item 6: verdicts stored with the sites, shown again after a reload; only when asked, and only for
    the stored sites (a reach that gives its own sites stores nothing)."""
    from .sample_requests import REACH

    for site in REACH["sites"]:
        assert api.post("/api/sites", json=site).status_code == 201
    request = {k: v for k, v in REACH.items() if k != "sites"} | {"description": "four-point footprint"}
    plain = api.post("/api/reach", json=request)
    assert plain.status_code == 200 and all(s["last_reach"] is None for s in api.get("/api/sites").json())
    kept = api.post("/api/reach", params={"store_verdicts": "true"}, json=request).json()
    stored = {s["name"]: s["last_reach"] for s in api.get("/api/sites").json()}
    for site in kept["sites"]:
        v = stored[site["name"]]
        assert (v["reachable"], v["windows"], v["footprint"]) == (
            site["reachable"],
            site["windows"],
            "four-point footprint",
        )
        assert v["orbit"] == {"inclination_deg": 28.5, "node_longitude_deg": 0.0}
    refused = api.post("/api/reach", params={"store_verdicts": "true"}, json=REACH)
    assert refused.status_code == 422 and refused.json()["field"] == "store_verdicts"
    site = next(s for s in api.get("/api/sites").json() if s["last_reach"] is not None)
    renamed = api.put(
        f"/api/sites/{site['id']}",
        json={"name": "renamed", "latitude_deg": site["latitude_deg"], "longitude_deg": site["longitude_deg"]},
    ).json()
    assert renamed["last_reach"] == site["last_reach"]  # a new name keeps the verdict; a new place does not
    moved = api.put(f"/api/sites/{site['id']}", json={"name": "renamed", "latitude_deg": 0.0, "longitude_deg": 0.0})
    assert moved.json()["last_reach"] is None
