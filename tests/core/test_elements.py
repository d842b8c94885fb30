"""Orbits from real elements (core/elements.py, issue 28 step 1): a TLE's check digits, SGP4's published verification
vectors, the GMST at three epochs against published values, and the sub-satellite point against skyfield's own,
independent route (TEME to GCRS to ITRS with precession, nutation and polar motion, on WGS-84)."""

import math
import re
from datetime import UTC, datetime, timedelta
from pathlib import Path

import numpy as np
import pytest
from sgp4.earth_gravity import wgs72

from footprint.core import elements as el
from footprint.core.errors import InputError
from footprint.core.utc import timescale
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
    ts = timescale()
    sat = EarthSatellite(e.line1, e.line2, e.name, ts)
    for t, a, o in zip(times, lat, lon):
        point = wgs84.subpoint_of(sat.at(ts.from_datetime(t)))
        assert distance_nmi(a, o, point.latitude.degrees, point.longitude.degrees) < 0.1
    # and on the report's earth (App. A radii) the point moves by the ellipsoids' difference only
    lat_r, lon_r, _ = el.subsatellite_points(e, times)
    assert np.allclose(lon_r, lon) and np.max(np.abs(lat_r - lat)) < 0.01


def with_check_digits(text: str) -> str:
    """The element lines with their check digits recomputed by the format's rule (CelesTrak's "NORAD Two-Line
    Element Set Format": the digits summed, a minus sign 1, anything else 0, modulo 10), written here apart from
    el.checksum; only ASCII digits are digits."""

    def digit(line: str) -> str:
        return str(sum(int(ch) if ch in "0123456789" else ch == "-" for ch in line[:68]) % 10)

    return "\n".join(ln[:68] + digit(ln) if ln[:2] in ("1 ", "2 ") else ln for ln in text.split("\n"))


N_DIGIT = "(N a digit, blanks before the first)"


@pytest.mark.parametrize(
    ("old", "new", "words"),
    [  # each read by sgp4 before (the check digit recomputed): 10.8 rev/day, 999 deg, e = 0.18, the epoch's day 400
        ("10.82419157", "10.8X419157", "line 2 columns 53-63 (mean motion): '10.8X419157' is not 'NN.NNNNNNNN' "
                                       f"{N_DIGIT}"),
        (" 34.2682", "999.2682", "line 2 columns 9-16 (inclination): 999.2682 is outside the allowed range 0 to "
                                 "180 deg"),
        ("348.7242", "360.7242", "line 2 columns 18-25 (right ascension of the ascending node): 360.7242 is outside "
                                 "the allowed range 0 to 360 deg"),
        ("331.7664", "-31.7664", "line 2 columns 35-42 (argument of perigee): '-31.7664' is not 'NNN.NNNN'"),
        (" 19.3264", "719.3264", "line 2 columns 44-51 (mean anomaly): 719.3264 is outside the allowed range 0 to 360"),
        ("1859667", "18X9667", "line 2 columns 27-33 (eccentricity): '18X9667' is not 'NNNNNNN'"),
        ("1859667", "-859667", "line 2 columns 27-33 (eccentricity): '-859667' is not 'NNNNNNN'"),
        ("00179.78495062", "00400.78495062", "line 1 columns 21-32 (epoch day): 400.78495062 is outside the allowed "
                                             "range 1 to 366.99999999 (the days of 2000)"),
        (" .00000023", " .0000O023", "line 1 columns 34-43 (mean motion's first derivative / 2): ' .0000O023' is not"),
        ("28098-4", "28098*4", "line 1 columns 54-61 (BSTAR drag term): ' 28098*4' is not '+NNNNN-N' (+ a sign or a "
                               "blank, N a digit, - the exponent's sign) or blanks"),
        ("78495062 ", "78495062x", "line 1 column 33 must be blank ('x' given)"),
    ],
)  # fmt: skip
def test_a_field_out_of_the_format_is_named_by_line_columns_and_field(old, new, words):
    text = with_check_digits(VANGUARD.replace(old, new, 1))
    with pytest.raises(InputError) as info:
        el.parse_tle(text)
    assert str(info.value).startswith("tle: ") and words in str(info.value), str(info.value)
    assert "\n" not in str(info.value)


@pytest.mark.parametrize(
    ("old", "new", "words"),
    [  # each accepted before: str.isdigit() is true for these digits, and int() reads them
        ("413667", "41366\u0667", "line 2 column 69: '\u0667' (U+0667) is not ASCII"),  # Arabic-Indic 7: the digit
        ("413667", "41366\uff17", "line 2 column 69: '\uff17' (U+FF17) is not ASCII"),  # fullwidth 7
        ("10.82419157", "10.8\uff12419157", "line 2 column 57: '\uff12' (U+FF12) is not ASCII"),  # sgp4 read 10.8
        ("00005U", "00005\uff35", "line 1 column 8: '\uff35' (U+FF35) is not ASCII"),
        ("58002B", "58002\u0411", "line 1 column 15: '\u0411' (U+0411) is not ASCII"),
    ],
)
def test_a_character_past_ascii_anywhere_is_refused(old, new, words):
    with pytest.raises(InputError) as info:
        el.parse_tle(VANGUARD.replace(old, new, 1))
    assert str(info.value).startswith("tle: ") and words in str(info.value), str(info.value)


@pytest.mark.parametrize("hostile", ["\u2028", "\u2029", "\x85", "\x0b", "\x0c", "\x1c", "\x00", "\x1b"])
def test_a_name_that_does_not_print_as_ascii_is_refused(hostile):
    with pytest.raises(InputError) as info:
        el.parse_tle(f"VAN{hostile}GUARD\n" + VANGUARD)
    assert "line 0 (the name) column 4: " in str(info.value) and "\n" not in str(info.value), str(info.value)


MOON_DISTANCE_KM = 384_400.0  # the Moon's mean distance (its orbit's semi-major axis)


def _rev_day_at_perigee(perigee_km: float, e: float) -> float:
    """Kepler's third law with SGP4's constants (WGS-72: sgp4.earth_gravity.wgs72): the mean motion (rev/day) whose
    orbit of eccentricity e has its perigee at this radius, a = r_p / (1 - e)."""
    return math.sqrt(wgs72.mu / (perigee_km / (1.0 - e)) ** 3) * 86_400.0 / (2.0 * math.pi)


ISS = """1 25544U 98067A   08264.51782528 -.00002182  00000-0 -11606-4 0  2927
2 25544  51.6416 247.4627 0006703 130.5360 325.0288 15.72125391563537"""


def test_a_mean_motion_whose_perigee_is_below_the_surface_or_past_the_moon_is_refused():
    """The surface's bound is 17.0265 rev/day at the ISS's e = 0.0006703 (17.0436 circular); the Moon's 0.0364."""
    e = 0.0006703
    fastest, slowest = _rev_day_at_perigee(wgs72.radiusearthkm, e), _rev_day_at_perigee(MOON_DISTANCE_KM, e)
    for n in (fastest - 0.0005, slowest + 0.00005):
        el.parse_tle(with_check_digits(ISS.replace("15.72125391", f"{n:11.8f}")))  # just inside: an orbit
    for n in (fastest + 0.0005, slowest - 0.00005):
        with pytest.raises(InputError) as info:
            el.parse_tle(with_check_digits(ISS.replace("15.72125391", f"{n:11.8f}")))
        words = f"line 2 columns 53-63 (mean motion): {n:.8f} is outside the allowed range {slowest:.6g} to "
        assert words in str(info.value) and f"to {fastest:.6g} rev/day" in str(info.value), str(info.value)
    # an eccentricity that puts the perigee below the surface at the ISS's mean motion (a = 6,728 km: e > 0.052)
    with pytest.raises(InputError) as info:
        el.parse_tle(with_check_digits(ISS.replace("0006703", "0600000")))
    assert "line 2 columns 53-63 (mean motion): 15.72125391 is outside" in str(info.value), str(info.value)


VERIFICATION = Path(__file__).parents[1] / "authorities" / "sgp4_verification.tle"
NOT_ORBITS = ("28872", "33333", "33334")  # a sub-orbital flight (perigee -51 km), e = 0.995 and 0.00001 rev/day


def verification_sets() -> list[tuple[str, str, str]]:
    """(comments, line 1, line 2) of each element set of AIAA 2006-6753's verification file, each line cut at 69."""
    out, notes, first = [], "", None
    for line in VERIFICATION.read_text().splitlines():
        if line.startswith("#"):
            notes += line
        elif line.startswith("1 "):
            first = line[:69]
        elif line.startswith("2 "):
            out.append((notes, first, line[:69]))
            notes = ""
    return out


def test_the_verification_element_sets_parse_but_those_that_are_no_earth_orbit():
    sets = verification_sets()
    assert len(sets) == 33
    for _, line1, line2 in sets:
        text = f"{line1}\n{line2}"
        if with_check_digits(text) != text:  # 3333x: other sets' lines, their numbers changed, not their check digits
            with pytest.raises(InputError) as info:
                el.parse_tle(text)
            assert line1[2:7] in ("33333", "33334", "33335") and "its check digit is" in str(info.value)
            line1, line2 = with_check_digits(text).split("\n")
        if line1[2:7] in NOT_ORBITS:
            with pytest.raises(InputError) as info:
                el.parse_tle(f"{line1}\n{line2}")
            assert "line 2 columns 53-63 (mean motion)" in str(info.value) and "perigee" in str(info.value)
        else:
            e = el.parse_tle(f"{line1}\n{line2}")
            assert e.inclination_deg == pytest.approx(float(line2[8:16]))


def test_the_perigee_heights_the_verification_file_states():
    """Its comments give six perigee heights (SGP4's own, from its un-Kozai'd semi-major axis): two-body from the
    Kozai mean motion meets each within 3 km (J2's share of the semi-major axis, 0.05 %)."""
    stated = {}
    for notes, _, line2 in verification_sets():
        if found := re.search(r"perigee = (-?\d+(?:\.\d+)?)", notes):
            stated[line2[2:7]] = (float(found.group(1)), float(line2[52:63]), float("0." + line2[26:33]))
    assert len(stated) == 6
    for height_km, n, e in stated.values():
        assert el.perigee_radius_km(n, e) - wgs72.radiusearthkm == pytest.approx(height_km, abs=3.0)


def test_a_window_far_from_the_epoch_or_past_the_decay_is_refused():
    e = el.parse_tle(VANGUARD)
    el.check_window(e, e.epoch, e.epoch + timedelta(days=1))  # a day after the epoch: answered
    with pytest.raises(InputError) as info:
        el.check_window(e, e.epoch + timedelta(days=20), e.epoch + timedelta(days=21))
    assert str(info.value).startswith("window.start: ") and "20.0 days from the elements' epoch" in str(info.value)
    with pytest.raises(InputError) as info:
        el.check_window(e, e.epoch + timedelta(days=2), e.epoch + timedelta(days=1))
    assert str(info.value).startswith("window.end: ")
    # the ISS 160 km up (16.4 rev/day: an orbit, its perigee above the surface) with a large drag term: SGP4 stops
    e = el.parse_tle(with_check_digits(ISS.replace("15.72125391", "16.40000000").replace("-11606-4", " 10000-2")))
    with pytest.raises(InputError) as info:
        el.check_window(e, e.epoch, e.epoch + timedelta(days=10))
    assert str(info.value).startswith("window: the orbit does not last the window"), str(info.value)
