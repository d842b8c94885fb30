"""The files a planner hands on of one opportunity (issue 52): its coast and entry as a CCSDS OEM, read back by the
ccsds-ndm package itself, and as CZML, checked by czml3's model; their states against other routes: the burn from
`sgp4` itself turned by skyfield's GMST (tests.core.orbit_routes), the interface and the stop from the answer's
entry state and the flight flown again by the trajectory module, on the report's ellipsoid written out here."""

import json
import math
from datetime import datetime

import numpy as np
import pytest

from footprint import contracts, parallel
from footprint.contracts import opportunity_files as files
from footprint.core.trajectory import simulate
from tests.core.orbit_routes import RE_REPORT_FT, RP_REPORT_FT, geodetic_ft, gmst_rad, sgp4_teme_km
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


def _state(sv):
    return np.array([sv.x.value, sv.y.value, sv.z.value]), np.array([sv.x_dot.value, sv.y_dot.value, sv.z_dot.value])


def _seconds(a: str, b: str) -> float:
    return (parse(b) - parse(a)).total_seconds()


def _flown_again(study, o):
    """The study's case flown by the trajectory module from the answer's entry state (the velocity relative)."""
    from dataclasses import replace

    entry = replace(study.spec.entry, **o["entry"], velocity_frame="relative")
    return simulate(replace(study.spec, entry=entry))


def test_the_oem_read_back_by_ccsds_ndm_holds_the_burn_the_interface_and_the_stop(planned):
    from ccsds_ndm.ndm_io import NdmIo

    study, answer = planned
    index = 0
    o = answer["opportunities"][index]
    for data_format in ("kvn", "xml"):
        oem = NdmIo().from_string(files.opportunity_oem(study, answer, index, data_format))
        coast, entry = oem.body.segment
        assert [s.metadata.ref_frame for s in (coast, entry)] == ["TEME", "GRC"]
        assert {s.metadata.time_system for s in (coast, entry)} == {"UTC"}
        states = coast.data.state_vector
        # the burn: the epoch written, the state sgp4's own in TEME with the Δv against its velocity
        assert states[0].epoch + "Z" == o["burn_utc"] and re_ms(states[0].epoch)
        r, v = sgp4_teme_km(EXAMPLE["tle"].splitlines()[1:], parse(o["burn_utc"]))
        got_r, got_v = _state(states[0])
        assert np.linalg.norm(got_r - r) < ONE_FT_KM
        assert np.linalg.norm(got_v - v * (1.0 - o["delta_v_fps"] / FT_PER_KM / np.linalg.norm(v))) < 1e-6  # km/s
        # the interface: the coast's last epoch the entry's to the millisecond, its place the answer's entry
        last = states[-1]
        assert abs(_seconds(last.epoch + "Z", o["entry_utc"])) <= 0.5 * MS + 1e-6
        got_r, got_v = _state(last)
        back_s = o["coast_s"] - _seconds(o["burn_utc"], last.epoch + "Z")  # under 0.5 ms to the interface
        theta = gmst_rad(parse(o["burn_utc"]), o["coast_s"])
        at_interface = _turned(got_r + got_v * back_s, theta) * FT_PER_KM
        e = o["entry"]
        assert np.linalg.norm(at_interface - _ecef_ft(e["latitude_deg"], e["longitude_deg"], e["altitude_ft"])) < 1.0
        # the entry: from the interface (its first epoch the coast's last) to the case's stop, earth-fixed
        flight = entry.data.state_vector
        assert flight[0].epoch == last.epoch and all(re_ms(s.epoch) for s in flight)
        got_r, got_v = _state(flight[0])
        start = (got_r + got_v * back_s) * FT_PER_KM
        assert np.linalg.norm(start - _ecef_ft(e["latitude_deg"], e["longitude_deg"], e["altitude_ft"])) < 1.0
        again = _flown_again(study, o)
        stop_s = o["coast_s"] + again.summary["flight_time_s"]
        assert abs(_seconds(o["burn_utc"], flight[-1].epoch + "Z") - stop_s) <= 0.5 * MS + 1e-6
        h = again.history
        end_r = _ecef_ft(h["latitude_deg"][-1], h["longitude_deg"][-1], h["altitude_ft"][-1])
        got_r, got_v = _state(flight[-1])
        back_s = stop_s - _seconds(o["burn_utc"], flight[-1].epoch + "Z")
        assert np.linalg.norm((got_r + got_v * back_s) * FT_PER_KM - end_r) < 1.0
        assert geodetic_ft(*(got_r * FT_PER_KM))[1] == pytest.approx(study.spec.stop.altitude_ft, abs=1.0)
        epochs = [parse(s.epoch + "Z") for seg in (coast, entry) for s in seg.data.state_vector]
        assert all(b >= a for a, b in zip(epochs, epochs[1:]))  # in time order, the segments meeting at the interface


def re_ms(epoch: str) -> bool:
    """An epoch written to the millisecond: YYYY-MM-DDThh:mm:ss.sss."""
    return len(epoch) == 23 and epoch[19] == "." and epoch[20:].isdigit()


def test_the_czml_fits_czml3s_model_and_starts_at_the_burn_and_ends_at_the_stop(planned):
    from czml3 import Document

    study, answer = planned
    index = len(answer["opportunities"]) - 1
    o = answer["opportunities"][index]
    packets = json.loads(files.opportunity_czml(study, answer, index))
    Document.model_validate({"packets": packets})  # czml3's own model of every packet
    document, vehicle, site = packets
    assert document["id"] == "document" and document["version"] == "1.0"
    again = _flown_again(study, o)
    start, end = vehicle["availability"].split("/")
    assert start == o["burn_utc"]
    assert abs(_seconds(o["burn_utc"], end) - (o["coast_s"] + again.summary["flight_time_s"])) <= 0.5 * MS + 1e-6
    position = vehicle["position"]
    assert position["epoch"] == start and position["referenceFrame"] == "FIXED"
    samples = np.array(position["cartesian"]).reshape(-1, 4)
    assert samples[0, 0] == 0.0 and np.all(np.diff(samples[:, 0]) > 0)
    r, _ = sgp4_teme_km(EXAMPLE["tle"].splitlines()[1:], parse(o["burn_utc"]))
    burn_ft = _turned(r, gmst_rad(parse(o["burn_utc"]))) * FT_PER_KM
    assert np.linalg.norm(samples[0, 1:] / 0.3048 - burn_ft) < 1.0
    h = again.history
    end_ft = _ecef_ft(h["latitude_deg"][-1], h["longitude_deg"][-1], h["altitude_ft"][-1])
    moved_ft = 0.5 * MS * h["velocity_fps"][-1]  # the stop's row moved to its millisecond (CZML has no velocity)
    assert np.linalg.norm(samples[-1, 1:] / 0.3048 - end_ft) < moved_ft + 1.0
    assert o["site_name"] in vehicle["label"]["text"] and vehicle["path"]["show"]
    assert site["name"] == o["site_name"]


def test_an_index_outside_the_answer_is_one_line_naming_it(planned):
    from footprint.core.errors import InputError

    study, answer = planned
    with pytest.raises(InputError, match=r"^opportunity: 99 is outside the allowed range of 0 to \d+$"):
        files.opportunity_oem(study, answer, 99)


def test_an_epoch_in_a_leap_second_is_written_as_second_60():
    """UTC across the leap second of 2016-12-31 (SI seconds from the burn, labelled by the true UTC): the OEM's
    epochs to the millisecond, 23:59:60.500 between 23:59:59.500 and 00:00:00.500, as CCSDS 301 writes UTC."""
    from footprint.core.utc import parse_iso

    burn = parse_iso("2016-12-31T23:59:58.500Z")
    got = files._epochs(burn, np.array([0.0, 1.0, 2.0, 3.0]))
    assert got == [
        "2016-12-31T23:59:58.500",
        "2016-12-31T23:59:59.500",
        "2016-12-31T23:59:60.500",
        "2017-01-01T00:00:00.500",
    ]
