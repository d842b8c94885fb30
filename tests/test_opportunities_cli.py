"""`footprint opportunities` run as a user runs it (issue 28 items 3-5): its CSV, iCalendar and GeoJSON files, and
one line with exit 2 for each of the issue's bad inputs."""

import copy
import csv
import io
import json
import re
from datetime import datetime, timedelta

import pytest

from tests.core.test_elements import with_check_digits
from tests.core.test_opportunities import small_study
from tests.test_cli import run

TLE = small_study()["tle"]


def test_the_files_of_a_small_window(tmp_path):
    path = tmp_path / "study.json"
    path.write_text(json.dumps(small_study()))
    files = {"--csv": tmp_path / "o.csv", "--ics": tmp_path / "o.ics", "--geojson": tmp_path / "o.geojson",
             "--figure": tmp_path / "o.png"}  # fmt: skip
    r = run("opportunities", path, "--workers", 0, *[x for kv in files.items() for x in kv])
    assert r.returncode == 0, r.stderr
    got = json.loads(r.stdout)
    taken = [o for o in got["opportunities"] if o["meets_rules"]]
    rows = files["--csv"].read_text().splitlines()
    assert rows[0].startswith("site_name,rank,revolution_number,burn_utc,burn_altitude_ft")
    assert len(rows) == 1 + len(got["opportunities"])
    ics = files["--ics"].read_bytes()
    assert ics.startswith(b"BEGIN:VCALENDAR\r\n") and ics.endswith(b"END:VCALENDAR\r\n")
    lines = ics.decode().split("\r\n")[:-1]
    assert all(len(line.encode()) <= 75 for line in lines)  # RFC 5545 3.1: folded
    unfolded = "\r\n".join(lines).replace("\r\n ", "").split("\r\n")
    assert unfolded.count("BEGIN:VEVENT") == len(taken)
    first = taken[0]
    burn = datetime.fromisoformat(first["burn_utc"].replace("Z", "+00:00"))
    assert re.fullmatch(r".*T\d\d:\d\d:\d\d\.\d{3}Z", first["burn_utc"])  # to the millisecond
    nearest = (burn + timedelta(milliseconds=500)).replace(microsecond=0)
    assert f"DTSTART:{nearest:%Y%m%dT%H%M%SZ}" in unfolded  # the nearest second
    assert first["burn_utc"] in "".join(unfolded)  # the description's, to the millisecond
    table = list(csv.DictReader(io.StringIO(files["--csv"].read_text())))
    assert [r["burn_utc"] for r in table] == [o["burn_utc"] for o in got["opportunities"]]
    for column in ("burn_altitude_ft", "downrange_margin_nmi", "crossrange_margin_nmi", "revolution_number"):
        assert [float(r[column]) for r in table] == pytest.approx([o[column] for o in got["opportunities"]], rel=1e-9)
    sequences = [u for u in unfolded if u.startswith("SEQUENCE:")]  # its value: test_opportunities_calendar
    assert len(sequences) == len(taken) and len(set(sequences)) == 1
    assert any(u.startswith("SUMMARY:Landing at ") and "\\," in u for u in unfolded)  # the site's comma escaped
    features = json.loads(files["--geojson"].read_text())["features"]
    kinds = [f["properties"]["kind"] for f in features]
    coasts = [f["properties"] for f in features if f["properties"]["kind"] == "coast"]
    assert [c["revolution_number"] for c in coasts] == [o["revolution_number"] for o in got["opportunities"]]
    assert kinds.count("coast") == kinds.count("footprint") == len(got["opportunities"])
    assert kinds.count("site") == len(got["sites"]) and "ground_track" in kinds
    assert files["--figure"].read_bytes().startswith(b"\x89PNG")
    # more Δv: a steeper entry, slower and sooner (energy and angular momentum: tests/core/test_deorbit.py)
    table = got["delta_v_table"]
    assert len(table) >= 10
    for a, b in zip(table, table[1:]):
        assert (
            b["gamma_deg"] < a["gamma_deg"] < 0
            and b["velocity_fps"] < a["velocity_fps"]
            and b["coast_s"] < a["coast_s"]
        )


YEARS = "is outside the allowed range 1957-01-01T00:00:00+00:00 to 2056-12-31T23:59:59+00:00"
STATE = {"epoch": "2008-09-21T00:00:00Z", "position_km": [6778.0, 0.0, 0.0], "velocity_km_s": [0.0, 4.766, 6.01]}
BAD_TLE = TLE[:-1] + str((int(TLE[-1]) + 1) % 10)


@pytest.mark.parametrize(
    ("change", "words"),
    [
        ({"tle": BAD_TLE}, "tle: line 2: its check digit is"),
        (
            {"tle": with_check_digits(TLE.replace("15.72125391", "15.7X125391"))},  # sgp4 read 15.7 rev/day
            "tle: line 2 columns 53-63 (mean motion): '15.7X125391' is not 'NN.NNNNNNNN'",
        ),
        ({"window": {"start": "2008-10-21T00:00:00Z", "hours": 3}}, "window.start: 2008-10-21T00:00:00+00:00 is 30.5"),
        ({"window": {"start": "2008-09-21T00:00:00Z"}}, "give exactly one of 'end' or 'hours'"),
        ({"deorbit": {"delta_v_fps": 20}}, "deorbit: the coast does not reach the interface"),
        ({"deorbit": {"delta_v_fps": 300, "entry_gamma_deg": -2}}, "give exactly one of 'delta_v_fps'"),
        ({"burn_step_s": 0.5}, "burn_step_s"),
        ({"state": STATE}, "give exactly one of 'tle' or 'state'"),
        (
            {"tle": None, "state": STATE | {"epoch": "2008-09-21T01:00:00Z"}},
            "window.start: 2008-09-21T00:00:00.000Z is before",
        ),
        # issue 49 item 2: an OverflowError's traceback before (the window's end past year 9999)
        (
            {"window": {"start": "9999-12-31T00:00:00Z", "hours": 24}},
            f"window.start: 9999-12-31T00:00:00+00:00 {YEARS}",
        ),
        (
            {"window": {"start": "0001-01-01T00:00:00+01:00", "hours": 1}},
            f"window.start: 0001-01-01T00:00:00+01:00 {YEARS}",
        ),
        (
            {
                "tle": None,
                "state": STATE | {"epoch": "9999-12-31T00:00:00Z"},
                "window": {"start": "9999-12-31T01:00:00Z", "end": "9999-12-31T23:59:59Z"},
            },
            "state.epoch: 9999-12-31T00:00:00+00:00 is outside the allowed range 1972-01-01T00:00:00+00:00 to "
            "2056-12-31T23:59:59+00:00",
        ),  # fmt: skip
    ],
)
def test_bad_input_is_one_line_and_exit_2(tmp_path, change, words):
    path = tmp_path / "study.json"
    study = {k: v for k, v in (copy.deepcopy(small_study()) | change).items() if v is not None}
    path.write_text(json.dumps(study))
    r = run("opportunities", path, "--workers", 0)
    assert r.returncode == 2, r.stdout + r.stderr
    said = r.stderr.strip().splitlines()
    assert len(said) == 1 and words in said[0] and "Traceback" not in r.stderr, r.stderr


def test_the_chosen_opportunitys_oem_and_czml(tmp_path):
    """Issue 52: --oem and --czml write the opportunity at --opportunity (its index in landing order), read back by
    the oem package and as JSON; an index the answer does not hold is one line naming the option."""
    from oem import OrbitEphemerisMessage

    path = tmp_path / "study.json"
    path.write_text(json.dumps(small_study()))
    oem, czml = tmp_path / "o.oem", tmp_path / "o.czml"
    r = run("opportunities", path, "--workers", 0, "--opportunity", 1, "--oem", oem, "--czml", czml, "--json")
    assert r.returncode == 0, r.stderr
    chosen = json.loads(r.stdout)["opportunities"][1]
    segments = list(OrbitEphemerisMessage.open(oem))
    assert [s.metadata["REF_FRAME"] for s in segments] == ["TEME", "GRC"]
    assert next(segments[0].states).epoch.isot[:23] + "Z" == chosen["burn_utc"]
    vehicle = json.loads(czml.read_text())[1]
    assert vehicle["availability"].startswith(chosen["burn_utc"] + "/")
    r = run("opportunities", path, "--workers", 0, "--opportunity", 99, "--oem", oem)
    last = r.stderr.splitlines()[-1]  # after the run's progress: the answer sets the range
    assert r.returncode == 2 and re.fullmatch(
        r"error: --opportunity: 99 is outside the allowed range of 0 to \d+", last
    )
