"""Orbits from real elements (core/elements.py, issue 28 step 1): a TLE's check digits, SGP4's published verification
vectors, the GMST at three epochs against published values, and the sub-satellite point against skyfield's own,
independent route (TEME to GCRS to ITRS with precession, nutation and polar motion, on WGS-84)."""

from datetime import UTC, datetime, timedelta

import numpy as np
import pytest

from footprint.core import elements as el
from footprint.core.errors import InputError
from tests.core.test_guidance import distance_nmi

# Vallado et al., AIAA 2006-6753, the verification set's satellite 00005 (Vanguard 2: e = 0.186)
VANGUARD = """1 00005U 58002B   00179.78495062  .00000023  00000-0  28098-4 0  4753
2 00005  34.2682 348.7242 1859667 331.7664  19.3264 10.82419157413667"""
# its TEME positions (km) after 0, 360 and 720 minutes, as the paper's tcppver.out prints them
VANGUARD_KM = {
    0.0: (7022.46529266, -1400.08296755, 0.03995155),
    360.0: (-7154.03120202, -3783.17682504, -3536.19412294),
    720.0: (-7134.59340119, 6531.68641334, 3260.27186483),
}
WGS84_FT = (6378137.0 / 0.3048, 6378137.0 * (1 - 1 / 298.257223563) / 0.3048)


def test_the_check_digits_and_the_elements_are_read():
    e = el.parse_tle("VANGUARD 2\n" + VANGUARD)
    assert (e.name, e.satellite_number) == ("VANGUARD 2", 5)
    assert e.inclination_deg == pytest.approx(34.2682) and e.eccentricity == pytest.approx(0.1859667)
    assert e.right_ascension_deg == pytest.approx(348.7242) and e.mean_motion_rev_day == pytest.approx(10.82419157)
    # day 179.78495062 of 2000: 27 June, 18:50:19.73 UTC
    assert abs(e.epoch - datetime(2000, 6, 27, 18, 50, 19, 733_568, tzinfo=UTC)) < timedelta(milliseconds=1)


@pytest.mark.parametrize(
    ("text", "words"),
    [
        (VANGUARD[:-1] + "4", "line 2: its check digit is '4', its characters give 7"),
        (VANGUARD.replace("34.2682", "34.2683"), "line 2: its check digit is '7', its characters give 8"),
        (VANGUARD.splitlines()[0], "a TLE has two lines"),
        (VANGUARD.replace("2 00005", "2 00006"), "line 2: its check digit"),
        (VANGUARD.replace("0  4753", "0 4753"), "line 1 must be 69 characters"),
    ],
)
def test_a_bad_tle_is_named_and_said(text, words):
    with pytest.raises(InputError) as info:
        el.parse_tle(text)
    assert str(info.value).startswith("tle: ") and words in str(info.value), str(info.value)


def test_sgp4_reproduces_the_published_verification_vectors():
    e = el.parse_tle(VANGUARD)
    times = [e.epoch + timedelta(minutes=m) for m in VANGUARD_KM]
    r, _ = e.teme_km(times)
    assert r == pytest.approx(np.array(list(VANGUARD_KM.values())), abs=1e-3)  # 1 m: the epoch's microseconds


@pytest.mark.parametrize(
    ("utc", "published_deg"),
    [
        (datetime(1987, 4, 10, 0, 0, 0, tzinfo=UTC), 197.693195),  # Meeus, Astronomical Algorithms, ex. 12.a
        (datetime(1987, 4, 10, 19, 21, 0, tzinfo=UTC), 128.7378734),  # Meeus ex. 12.b
        (datetime(1992, 8, 20, 12, 14, 0, tzinfo=UTC), 152.578787810),  # Vallado, Fundamentals, ex. 3-5
    ],
)
def test_gmst_at_three_epochs_against_published_values(utc, published_deg):
    """The published values are at UT1; the function takes UTC, and |UT1 - UTC| < 0.9 s moves GMST by under
    0.0038 deg (360.9856 deg a day)."""
    assert abs(el.gmst_deg([utc])[0] - published_deg) < 0.9 * 360.9856 / 86400


def test_the_subsatellite_point_agrees_with_skyfields_own_route():
    from skyfield.api import EarthSatellite, wgs84

    iss = """ISS (ZARYA)
1 25544U 98067A   08264.51782528 -.00002182  00000-0 -11606-4 0  2927
2 25544  51.6416 247.4627 0006703 130.5360 325.0288 15.72125391563537"""
    e = el.parse_tle(iss)
    times = [e.epoch + timedelta(minutes=m) for m in (0.0, 47.0, 1234.5)]
    lat, lon, _ = el.subsatellite_points(e, times, *WGS84_FT)
    ts = el.timescale()
    sat = EarthSatellite(e.line1, e.line2, e.name, ts)
    for t, a, o in zip(times, lat, lon):
        point = wgs84.subpoint_of(sat.at(ts.from_datetime(t)))
        assert distance_nmi(a, o, point.latitude.degrees, point.longitude.degrees) < 0.1
    # and on the report's earth (App. A radii) the point moves by the ellipsoids' difference only
    lat_r, lon_r, _ = el.subsatellite_points(e, times)
    assert np.allclose(lon_r, lon) and np.max(np.abs(lat_r - lat)) < 0.01


def test_a_window_far_from_the_epoch_or_past_the_decay_is_refused():
    e = el.parse_tle(VANGUARD)
    el.check_window(e, e.epoch, e.epoch + timedelta(days=1))  # a day after the epoch: answered
    with pytest.raises(InputError) as info:
        el.check_window(e, e.epoch + timedelta(days=20), e.epoch + timedelta(days=21))
    assert str(info.value).startswith("window.start: ") and "20.0 days from the elements' epoch" in str(info.value)
    with pytest.raises(InputError) as info:
        el.check_window(e, e.epoch + timedelta(days=2), e.epoch + timedelta(days=1))
    assert str(info.value).startswith("window.end: ")
    # a shorter period at the same eccentricity puts the perigee inside the earth, with a large drag term: SGP4 stops
    low = VANGUARD.replace("10.82419157", "16.40000000").replace(" 28098-4 ", " 99999-1 ")
    lines = low.splitlines()
    low = "\n".join(ln[:-1] + str(el.checksum(ln)) for ln in lines)
    e = el.parse_tle(low)
    with pytest.raises(InputError) as info:
        el.check_window(e, e.epoch, e.epoch + timedelta(days=10))
    assert str(info.value).startswith("window: the orbit does not last the window"), str(info.value)
