"""The files a planner hands on of one opportunity (issue 52): its coast and entry as a CCSDS OEM, read back by the
oem package itself, and as CZML, checked by czml3's model; their states against other routes: the burn from `sgp4`
itself turned by skyfield's GMST (tests.core.orbit_routes), the interface from the answer's entry state, the end
the answer's guided flight (within 5 nmi of the site, great-circle here) or, without guided flights, the case flown
again by the trajectory module, on the report's ellipsoid written out here."""

import json
import math
import re
from datetime import datetime

import numpy as np
import pytest

from footprint import contracts, parallel
from footprint.contracts import opportunity_files as files
from footprint.core.trajectory import simulate
from tests.core.orbit_routes import RE_REPORT_FT, RP_REPORT_FT, geodetic_ft, gmst_rad, sgp4_teme_km
from tests.core.test_guidance import distance_nmi
from tests.core.test_opportunities import EXAMPLE, small_study

FT_PER_KM = 1000.0 / 0.3048
ONE_FT_KM = 0.3048e-3
MS = 1e-3


@pytest.fixture(scope="module")
def planned():
    study = small_study()
    return contracts.parse("opportunities", study), parallel.run("opportunities", study)


def parse(text: str) -> datetime:
    """An ISO 8601 UTC time (the window holds no leap second)."""
    return datetime.fromisoformat(text.replace("Z", "+00:00"))


def _ecef_ft(latitude_deg, longitude_deg, altitude_ft):
    """A geodetic point on the report's ellipsoid as earth-fixed x, y, z (ft): N = a / sqrt(1 - e^2 sin^2 lat)."""
    e2 = 1.0 - (RP_REPORT_FT / RE_REPORT_FT) ** 2
    lat, lon = math.radians(latitude_deg), math.radians(longitude_deg)
    n = RE_REPORT_FT / math.sqrt(1.0 - e2 * math.sin(lat) ** 2)
    return np.array(
        [
            (n + altitude_ft) * math.cos(lat) * math.cos(lon),
            (n + altitude_ft) * math.cos(lat) * math.sin(lon),
            (n * (1.0 - e2) + altitude_ft) * math.sin(lat),
        ]
    )


def _turned(r, theta):
    """TEME to earth-fixed: turned by -theta (GMST) about the pole."""
    c, s = math.cos(theta), math.sin(theta)
    return np.array([c * r[0] + s * r[1], -s * r[0] + c * r[1], r[2]])


def read_oem(text: str, tmp_path):
    """The message read back by the oem package (it opens files): its segments and the epochs as written."""
    from oem import OrbitEphemerisMessage

    where = tmp_path / "read.oem"
    where.write_text(text)
    return list(OrbitEphemerisMessage.open(where)), re.findall(r"^(\d{4}-\S+) |<EPOCH>(.*)</EPOCH>", text, re.M)


def re_ms(epoch: str) -> bool:
    """An epoch written to the millisecond: YYYY-MM-DDThh:mm:ss.sss."""
    return len(epoch) == 23 and epoch[19] == "." and epoch[20:].isdigit()


def _state(sv):
    return np.asarray(sv.position, dtype=float), np.asarray(sv.velocity, dtype=float)


def _epoch(sv) -> str:
    """A state's epoch as the oem package read it (astropy, to the microsecond) in the answer's form."""
    return sv.epoch.isot[:23]


def _seconds(a: str, b: str) -> float:
    return (parse(b) - parse(a)).total_seconds()


def _flown_again(study, o):
    """The study's case flown by the trajectory module from the answer's entry state (the velocity relative)."""
    from dataclasses import replace

    entry = replace(study.spec.entry, **o["entry"], velocity_frame="relative")
    return simulate(replace(study.spec, entry=entry))


def _reached(answer) -> int:
    """The first opportunity whose guided flight reached its site (the guidance's own verdict: a pick, not a check)."""
    return next(i for i, o in enumerate(answer["opportunities"]) if o["guided"]["guidance"]["reached"])


def _check_coast(coast, o):
    """The coast from the burn (sgp4's own TEME state, the Δv against its velocity) to the answer's interface."""
    states = list(coast.states)
    assert _epoch(states[0]) + "Z" == o["burn_utc"]
    r, v = sgp4_teme_km(EXAMPLE["tle"].splitlines()[1:], parse(o["burn_utc"]))
    got_r, got_v = _state(states[0])
    assert np.linalg.norm(got_r - r) < ONE_FT_KM
    assert np.linalg.norm(got_v - v * (1.0 - o["delta_v_fps"] / FT_PER_KM / np.linalg.norm(v))) < 1e-6  # km/s
    # the interface: the coast's last epoch the entry's to the millisecond, its place (skyfield's GMST) the answer's
    last = states[-1]
    assert abs(_seconds(_epoch(last) + "Z", o["entry_utc"])) <= 0.5 * MS + 1e-6
    got_r, got_v = _state(last)
    back_s = o["coast_s"] - _seconds(o["burn_utc"], _epoch(last) + "Z")  # under 0.5 ms to the interface
    at_interface = _turned(got_r + got_v * back_s, gmst_rad(parse(o["burn_utc"]), o["coast_s"])) * FT_PER_KM
    e = o["entry"]
    assert np.linalg.norm(at_interface - _ecef_ft(e["latitude_deg"], e["longitude_deg"], e["altitude_ft"])) < 1.0
    return last, back_s


def _check_entry_start(entry, last, back_s, o):
    """The entry from the interface: its first epoch the coast's last, its place the answer's entry, earth-fixed."""
    flight = list(entry.states)
    assert _epoch(flight[0]) == _epoch(last)
    got_r, got_v = _state(flight[0])
    e = o["entry"]
    start = (got_r + got_v * back_s) * FT_PER_KM
    assert np.linalg.norm(start - _ecef_ft(e["latitude_deg"], e["longitude_deg"], e["altitude_ft"])) < 1.0
    return flight


def _end(flight, o, flight_time_s):
    """The entry's last state moved back to its flight's end (under 0.5 ms): geodetic latitude, longitude (deg) and
    altitude (ft) on the report's ellipsoid, by the test's own conversion; its epoch checked against the end."""
    stop_s = o["coast_s"] + flight_time_s
    assert abs(_seconds(o["burn_utc"], _epoch(flight[-1]) + "Z") - stop_s) <= 0.5 * MS + 1e-6
    got_r, got_v = _state(flight[-1])
    r = (got_r + got_v * (stop_s - _seconds(o["burn_utc"], _epoch(flight[-1]) + "Z"))) * FT_PER_KM
    lat, alt = geodetic_ft(*r)
    return lat, math.degrees(math.atan2(r[1], r[0])), alt


@pytest.mark.parametrize("data_format", ["kvn", "xml"])
def test_the_oem_read_back_by_the_oem_package_holds_the_burn_the_interface_and_the_guided_flights_end(
    planned, data_format, tmp_path
):
    """Issue 52: the entry segment is the flight guided to the site (before: the case's wings-level flight to
    50,000 ft, which ends far past it): its end within 5 nmi of the site and on the answer's guided end."""
    study, answer = planned
    index = _reached(answer)
    o = answer["opportunities"][index]
    text = files.opportunity_oem(study, answer, index, data_format)
    (coast, entry), written = read_oem(text, tmp_path)
    assert [s.metadata["REF_FRAME"] for s in (coast, entry)] == ["TEME", "GRC"]
    assert {s.metadata["TIME_SYSTEM"] for s in (coast, entry)} == {"UTC"}
    assert written and all(re_ms(a or b) for a, b in written)  # every epoch written to the millisecond
    last, back_s = _check_coast(coast, o)
    flight = _check_entry_start(entry, last, back_s, o)
    g = o["guided"]
    lat, lon, alt = _end(flight, o, g["flight_time_s"])
    site = answer["sites"][o["site"]]
    on_circle = (
        distance_nmi(lat, lon, site["latitude_deg"], site["longitude_deg"]) - g["guidance"]["interface_range_nmi"]
    )
    assert abs(on_circle) <= 5.0  # the terminal-area interface, 50 nmi before the site (issue 50 item 3)
    assert distance_nmi(lat, lon, g["final_latitude_deg"], g["final_longitude_deg"]) <= 0.01
    assert alt == pytest.approx(g["final_altitude_ft"], abs=1.0)
    assert f"guided to {o['site_name']}" in text and "hand-over" in text  # its COMMENT says which flight it is
    epochs = [parse(_epoch(s) + "Z") for seg in (coast, entry) for s in seg.states]
    assert all(b >= a for a, b in zip(epochs, epochs[1:]))  # in time order, the segments meeting at the interface


def test_without_guided_flights_the_entry_is_the_cases_own_flight_to_its_stop(planned, tmp_path):
    """A study with guided false: the entry segment is the case flown on its own controls to its stop altitude, as
    the trajectory module flies it again from the answer's entry, and its COMMENT says so."""
    study, answer = planned
    own = contracts.parse("opportunities", small_study(guided=False))
    index = 0
    o = answer["opportunities"][index]
    text = files.opportunity_oem(own, answer, index)
    (coast, entry), _ = read_oem(text, tmp_path)
    last, back_s = _check_coast(coast, o)
    flight = _check_entry_start(entry, last, back_s, o)
    again = _flown_again(own, o)
    lat, lon, alt = _end(flight, o, again.summary["flight_time_s"])
    h = again.history
    assert distance_nmi(lat, lon, h["latitude_deg"][-1], h["longitude_deg"][-1]) < 1e-3
    assert alt == pytest.approx(study.spec.stop.altitude_ft, abs=1.0)
    assert "on its own controls" in text and "not guided to" in text and "hand-over" not in text


def test_the_czml_fits_czml3s_model_and_starts_at_the_burn_and_ends_at_the_guided_flights_end(planned):
    from czml3 import Document

    study, answer = planned
    index = _reached(answer)
    o = answer["opportunities"][index]
    packets = json.loads(files.opportunity_czml(study, answer, index))
    Document.model_validate({"packets": packets})  # czml3's own model of every packet
    document, vehicle, site = packets
    assert document["id"] == "document" and document["version"] == "1.0"
    g = o["guided"]
    start, end = vehicle["availability"].split("/")
    assert start == o["burn_utc"]
    assert abs(_seconds(o["burn_utc"], end) - (o["coast_s"] + g["flight_time_s"])) <= 0.5 * MS + 1e-6
    position = vehicle["position"]
    assert position["epoch"] == start and position["referenceFrame"] == "FIXED"
    samples = np.array(position["cartesian"]).reshape(-1, 4)
    assert samples[0, 0] == 0.0 and np.all(np.diff(samples[:, 0]) > 0)
    r, _ = sgp4_teme_km(EXAMPLE["tle"].splitlines()[1:], parse(o["burn_utc"]))
    burn_ft = _turned(r, gmst_rad(parse(o["burn_utc"]))) * FT_PER_KM
    assert np.linalg.norm(samples[0, 1:] / 0.3048 - burn_ft) < 1.0
    end_ft = _ecef_ft(g["final_latitude_deg"], g["final_longitude_deg"], g["final_altitude_ft"])
    moved_ft = 0.5 * MS * g["final_velocity_fps"]  # the end's row moved to its millisecond (CZML has no velocity)
    assert np.linalg.norm(samples[-1, 1:] / 0.3048 - end_ft) < moved_ft + 1.0
    lat, _ = geodetic_ft(*(samples[-1, 1:] / 0.3048))
    lon = math.degrees(math.atan2(samples[-1, 2], samples[-1, 1]))
    to_site = distance_nmi(
        lat, lon, site["position"]["cartographicDegrees"][1], site["position"]["cartographicDegrees"][0]
    )
    assert abs(to_site - g["guidance"]["interface_range_nmi"]) <= 5.0  # on the terminal-area interface circle
    assert o["site_name"] in vehicle["label"]["text"] and vehicle["path"]["show"]
    assert f"guided to {o['site_name']}" in vehicle["description"]
    assert site["name"] == o["site_name"]


@pytest.mark.parametrize("data_format", ["kvn", "xml"])
def test_a_site_name_with_line_breaks_and_control_characters_gives_a_comment_the_oem_package_reads_past(
    planned, data_format, tmp_path
):
    """A site's name is any text: written raw, its LF would end the KVN COMMENT line (the rest an invalid entry) and
    its VT or NUL would make the XML unreadable; the comment keeps its visible words on one line."""
    study, answer = planned
    o = dict(answer["opportunities"][0], site_name="Moron\nAir\x0bBase\x00 \u2028Spain")
    text = files.opportunity_oem(study, answer | {"opportunities": [o]}, 0, data_format)
    (coast, entry), _ = read_oem(text, tmp_path)
    assert [s.metadata["REF_FRAME"] for s in (coast, entry)] == ["TEME", "GRC"]
    assert text.count("Moron Air Base Spain") == 2 and "\x0b" not in text and "\x00" not in text


def test_an_index_outside_the_answer_is_one_line_naming_it(planned):
    from footprint.core.errors import InputError

    study, answer = planned
    with pytest.raises(InputError, match=r"^opportunity: 99 is outside the allowed range of 0 to \d+$"):
        files.opportunity_oem(study, answer, 99)


def test_an_epoch_in_a_leap_second_is_written_as_second_60_and_read_back_by_the_oem_package(tmp_path):
    """UTC across the leap second of 2016-12-31 (SI seconds from the burn, labelled by the true UTC): the OEM's
    epochs to the millisecond, 23:59:60.500 between 23:59:59.500 and 00:00:00.500, as CCSDS 301 writes UTC; the oem
    package writes them so and reads them back as one SI second apart (astropy's UTC)."""
    from footprint.core.utc import parse_iso

    burn = parse_iso("2016-12-31T23:59:58.500Z")
    got = files._epochs(burn, np.array([0.0, 1.0, 2.0, 3.0]))
    assert got == [
        "2016-12-31T23:59:58.500",
        "2016-12-31T23:59:59.500",
        "2016-12-31T23:59:60.500",
        "2017-01-01T00:00:00.500",
    ]
    r = np.array([[7000.0 + i, 0.0, 0.0] for i in range(4)])
    v = np.array([[0.0, 7.5, 0.0]] * 4)
    segment = files._oem_segment("GRC", got, r, v, {"object_name": "test", "object_id": "1"})
    for data_format in ("kvn", "xml"):
        text = files._written([segment], "2016-12-31T00:00:00.000", data_format)
        (read,), written = read_oem(text, tmp_path)
        assert [a or b for a, b in written] == got
        states = list(read.states)
        assert [s.epoch.isot for s in states] == [t + "000" for t in got]
        assert np.diff([(s.epoch - states[0].epoch).sec for s in states]) == pytest.approx([1.0] * 3, abs=1e-6)
        assert [s.position[0] for s in states] == [7000.0, 7001.0, 7002.0, 7003.0]
