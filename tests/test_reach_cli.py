"""The reach request (footprint.contracts.reach) and `footprint reach`, run as a user runs it: a new process, exit
status, stdout and stderr."""

import csv
import json
import subprocess
import sys
from functools import partial
from pathlib import Path

import numpy as np
import pytest
from pydantic import ValidationError

from footprint import parallel
from footprint.contracts import parse
from footprint.contracts.messages import error_line
from footprint.core.orbits import CircularOrbit, position

run_reach = partial(parallel.run, "reach")

ROOT = Path(__file__).resolve().parents[1]
EXAMPLE = ROOT / "examples" / "reach_20_sites.json"
DIAMOND = [
    {"downrange_nmi": 5000, "crossrange_nmi": 0, "flight_time_s": 3000},
    {"downrange_nmi": 3000, "crossrange_nmi": 500, "flight_time_s": 2000},
    {"downrange_nmi": 1000, "crossrange_nmi": 0, "flight_time_s": 1000},
    {"downrange_nmi": 3000, "crossrange_nmi": -500, "flight_time_s": 2000},
]
REQUEST = {
    "footprint": {"points": DIAMOND},
    "orbit": {"inclination_deg": 28.5, "altitude_nmi": 100, "node_longitude_deg": -170.0},
    "sites": [
        {"name": "KSC", "latitude_deg": 28.615, "longitude_deg": -80.695},
        {"name": "Kwajalein", "latitude_deg": 8.720, "longitude_deg": 167.732},
        {"name": "South Pole", "latitude_deg": -90.0, "longitude_deg": 0.0},
    ],
    "revolutions": {"first": 1, "last": 3},
    "u_step_deg": 1.0,
    "earth_rotation": "approximate",
}


def run(*args):
    return subprocess.run(
        [sys.executable, "-m", "footprint.cli", *map(str, args)], capture_output=True, text=True, timeout=600
    )


def write(tmp_path, data):
    path = tmp_path / "reach.json"
    path.write_text(json.dumps(data) if isinstance(data, dict) else data)
    return path


def edited(path, value):
    """REQUEST with the value at a dotted path replaced (None deletes it)."""
    data = json.loads(json.dumps(REQUEST))
    *head, last = path.split(".")
    node = data
    for k in head:
        node = node[int(k)] if isinstance(node, list) else node[k]
    if value is None:
        del node[last]
    elif isinstance(node, list):
        node[int(last)] = value
    else:
        node[last] = value
    return data


# ------------------------------------------------------------------------------------ the request contract
def test_run_reach_gives_windows_and_a_summary_per_site():
    r = run_reach(REQUEST)
    assert r["analysis"]["placements"] == 3 * 360
    assert r["footprint"]["source"] == "points" and r["footprint"]["points"] == 4
    names = [s["name"] for s in r["sites"]]
    assert names == ["KSC", "Kwajalein", "South Pole"]
    pole = r["sites"][2]
    assert not pole["reachable"] and pole["best_margin_nmi"] < -1000.0  # 28.5 deg orbit, 500 nmi wide footprint
    ksc = r["sites"][0]
    assert ksc["reachable"] and ksc["windows"] == sum(w["site"] == "KSC" for w in r["windows"])
    for w in r["windows"]:
        assert 0.0 <= w["u_start_deg"] <= w["u_end_deg"] < 360.0 and w["max_margin_nmi"] >= 0.0
        assert w["deorbit_time_end_s"] >= w["deorbit_time_start_s"]
        assert w["u_width_deg"] == w["u_end_deg"] - w["u_start_deg"]
    assert r["notes"] == []
    json.dumps(r)  # JSON-ready


def test_a_mirrored_half_is_the_whole_footprint():
    half = [p for p in DIAMOND if p["crossrange_nmi"] >= 0.0]
    a = run_reach(REQUEST)
    b = run_reach(edited("footprint", {"points": half, "mirror": True}))
    assert b["footprint"]["points"] == 4
    assert a["windows"] == b["windows"]


def test_the_node_by_right_ascension_and_sidereal_angle():
    a = run_reach(REQUEST)
    b = run_reach(
        edited(
            "orbit",
            {
                "inclination_deg": 28.5,
                "altitude_ft": 100 * 6076.115485564304,
                "right_ascension_deg": 100.0,
                "greenwich_sidereal_deg": 270.0,
            },
        )
    )
    assert b["orbit"]["node_longitude_deg"] == pytest.approx(-170.0)
    assert [(w["site"], w["revolution"], w["u_start_deg"], w["u_end_deg"]) for w in a["windows"]] == [
        (w["site"], w["revolution"], w["u_start_deg"], w["u_end_deg"]) for w in b["windows"]
    ]


def test_a_span_in_hours_ends_inside_the_last_revolution():
    r = run_reach(edited("revolutions", {"first": 1, "hours": 3.0}))  # 10,800 s = 2.04 revolutions
    assert r["analysis"]["revolutions"] == [1, 3]
    assert r["analysis"]["time_span_end_s"] == 10_800.0
    assert all(w["deorbit_time_end_s"] <= 10_800.0 for w in r["windows"])


def test_a_site_on_the_ground_track_without_rotation():
    """The analytic window of tests/core/test_reach.py through the request: no rotation anywhere."""
    orbit = CircularOrbit(
        40.0, 100 * 6076.115485564304, node_longitude_deg=25.0, rotation_rate_deg_s=0.0, nodal_regression=False
    )
    lat, lon = position(orbit, 1, 200.0)
    r = run_reach(
        edited(
            "orbit",
            {
                "inclination_deg": 40.0,
                "altitude_nmi": 100,
                "node_longitude_deg": 25.0,
                "rotation_rate_deg_s": 0.0,
                "nodal_regression": False,
            },
        )
        | {
            "sites": [{"name": "on track", "latitude_deg": float(lat), "longitude_deg": float(lon)}],
            "earth_rotation": "none",
        }
    )
    assert [(w["revolution"], w["u_start_deg"], w["u_end_deg"]) for w in r["windows"]] == [
        (1, 117.0, 183.0),
        (2, 117.0, 183.0),
        (3, 117.0, 183.0),
    ]


def test_a_study_flown_on_a_rotating_earth_gets_a_note():
    study = {
        "case": json.loads((ROOT / "examples" / "table2_lod22.json").read_text()),
        "method": "constant_bank",
        "bank_deg": [0, 45],
        "min_range": None,
    }
    assert study["case"].get("planet", {}).get("rotating", True)
    r = run_reach(edited("footprint", {"study": study}))
    assert r["footprint"]["source"] == "study" and r["footprint"]["points"] >= 3
    assert len(r["notes"]) == 1 and "counted twice" in r["notes"][0]


def test_a_bad_study_names_its_field():
    study = json.loads(EXAMPLE.read_text())["footprint"]["study"]
    study["case"]["entry"]["gamma_deg"] = -95.0
    with pytest.raises(ValidationError) as err:
        parse("reach", edited("footprint", {"study": study}))
    assert error_line(err.value).startswith("footprint.study.case.entry.gamma_deg: -95 is outside")


# ------------------------------------------------------------------------------------------------ the CLI
def test_the_command_prints_json_and_writes_the_windows_csv(tmp_path):
    out = tmp_path / "windows.csv"
    r = run("reach", write(tmp_path, REQUEST), "--csv", out)
    assert r.returncode == 0, r.stderr
    result = json.loads(r.stdout)
    assert result == json.loads(json.dumps(run_reach(REQUEST) | {"analysis": result["analysis"]}))
    rows = list(csv.DictReader(out.open()))
    assert len(rows) == len(result["windows"]) > 0
    assert list(rows[0]) == [
        "site",
        "revolution",
        "u_start_deg",
        "u_end_deg",
        "u_width_deg",
        "samples",
        "max_margin_nmi",
        "deorbit_time_start_s",
        "deorbit_time_end_s",
    ]
    assert float(rows[0]["u_start_deg"]) == result["windows"][0]["u_start_deg"]


def test_the_example_reaches_every_site_in_a_day(tmp_path):
    r = run("reach", EXAMPLE)
    assert r.returncode == 0, r.stderr
    result = json.loads(r.stdout)
    assert result["analysis"]["revolutions"] == [1, 17] and result["analysis"]["placements"] == 17 * 360
    assert result["footprint"]["max_downrange_nmi"] > 10_807.0  # past half the circumference
    assert result["notes"] == []
    sites = {s["name"]: s for s in result["sites"]}
    assert len(sites) == 20 and all(s["reachable"] for s in sites.values())
    assert all(7 <= s["passes"] <= 17 for s in sites.values())
    lats = np.array([s["latitude_deg"] for s in sites.values()])
    assert (lats > 0).any() and (lats < 0).any()


@pytest.mark.parametrize(
    "data, field, words",
    [
        (edited("orbit.inclination_deg", 200), "orbit.inclination_deg", "0 to 180 deg"),
        (edited("orbit.altitude_nmi", 5), "orbit.altitude_nmi", "16 to 16,000 nmi"),
        (edited("orbit.altitude_ft", 600_000), "orbit", "exactly one of altitude_ft or altitude_nmi"),
        (edited("orbit.right_ascension_deg", 10.0), "orbit", "greenwich_sidereal_deg"),
        (edited("sites.1.latitude_deg", 95), "sites.1.latitude_deg", "-90 to 90 deg"),
        (edited("sites", []), "sites", "at least 1"),
        (edited("u_step_deg", 0), "u_step_deg", "0.01 to 30 deg"),
        (edited("earth_rotation", "exact"), "earth_rotation", "approximate"),
        (edited("footprint.points.0.crossrange_nmi", 6000), "footprint.points.0.crossrange_nmi", "-5,400 to 5,400"),
        (edited("footprint.points", DIAMOND[:2]), "footprint.points", "at least 3"),
        (
            edited("footprint.study", json.loads(EXAMPLE.read_text())["footprint"]["study"]),
            "footprint",
            "exactly one of 'points'",
        ),
        (edited("revolutions", {"first": 5, "last": 2}), "revolutions", "at least first 5"),
        (edited("revolutions", {"first": 1, "last": 20_000}), "revolutions and u_step_deg", "1 to 2,000,000"),
        (edited("revolutions", {"first": 1, "last": 2, "hours": 3}), "revolutions", "exactly one of 'last'"),
        (edited("orbit", None), "orbit", "required"),
        ({**REQUEST, "colour": "red"}, "colour", "not permitted"),
        (
            edited("footprint", {"study": {"method": "single_parameter", "case": {"vehicle": {"builtin": "lod-2.2"}}}}),
            "footprint.study.case.entry",
            "required",
        ),
        ('{"orbit": ', "reach.json", "not valid JSON"),
    ],
)
def test_bad_input_gets_one_line_and_exit_status_2(tmp_path, data, field, words):
    r = run("reach", write(tmp_path, data))
    assert r.returncode == 2, r.stdout + r.stderr
    assert r.stdout == ""
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("error: "), r.stderr
    assert field in lines[0] and words in lines[0], lines[0]
    assert "Traceback" not in r.stderr


def test_each_window_carries_the_deorbit_points_that_reach_its_site():
    """Issue 13 item 6: the map draws where the vehicle deorbits to reach a site. Each window's points are
    one per grid value of u in the window, under the orbit: by hand, a window that opens at the ascending node
    of revolution 1 starts on the equator at the node's longitude, and every point lies within the orbit's
    latitude band."""
    result = run_reach(json.loads(EXAMPLE.read_text()))
    for w in result["windows"]:
        pts = w["deorbit_points"]
        assert len(pts["latitude_deg"]) == len(pts["longitude_deg"]) == w["samples"]
        assert max(abs(a) for a in pts["latitude_deg"]) <= 28.5 + 1e-9
    first = next(w for w in result["windows"] if w["revolution"] == 1 and w["u_start_deg"] == 0.0)
    assert first["deorbit_points"]["latitude_deg"][0] == pytest.approx(0.0, abs=1e-9)
    assert first["deorbit_points"]["longitude_deg"][0] == pytest.approx(-170.0, abs=1e-9)


def test_a_site_name_a_spreadsheet_would_run_is_written_as_text(tmp_path):
    """Text from users is escaped for where it lands: a CSV opened in a spreadsheet runs a cell starting with = + - @
    as a formula (OWASP CSV injection); the name keeps its text behind an apostrophe, the JSON keeps it as given."""
    formula = '=HYPERLINK("http://example.invalid","KSC")'
    request = json.loads(json.dumps(REQUEST))
    request["sites"][0]["name"] = formula
    out = tmp_path / "windows.csv"
    r = run("reach", write(tmp_path, request), "--csv", out)
    assert r.returncode == 0, r.stderr
    names = {row["site"] for row in csv.DictReader(out.open())}
    assert "'" + formula in names and formula not in names
    assert formula in {s["name"] for s in json.loads(r.stdout)["sites"]}
