"""The sun's place for a landing site (core/sun.py) against published solutions: NREL's SPA example (Reda & Andreas,
Solar Energy 76(5), 2004, and its spa_tester.c: elevation, hour angle, sunrise and sunset at Golden, Colorado),
Meeus, Astronomical Algorithms 2nd ed., Examples 25.a (apparent right ascension and declination) and 28.a (equation
of time); local apparent solar time against mean solar time plus the equation of time; the subsolar point."""

from datetime import UTC, datetime, timedelta, timezone

import numpy as np
import pytest

from footprint.core import sun

# SPA's example: 2003-10-17 12:30:30 at timezone -7 h, 39.742476 N, 105.1786 W (spa_tester.c)
GOLDEN = (39.742476, -105.1786)
SPA_TIME = [datetime(2003, 10, 17, 12, 30, 30, tzinfo=timezone(timedelta(hours=-7)))]
SPA_ZENITH_DEG = 50.111622  # topocentric, with 0.016 deg of refraction (820 mbar, 11 C) and 0.002 deg of parallax
SPA_HOUR_ANGLE_DEG = 11.105902  # H, the observer's (geocentric) local hour angle
SPA_RISE_SET_DEG = -0.8333  # SPA's sunrise and sunset: the geometric centre 50' below the horizon
# Meeus Example 25.a: 1992 October 13.0 TD; TD - UT = 59 s in 1992
MEEUS_TIME = [datetime(1992, 10, 12, 23, 59, 1, tzinfo=UTC)]

# 22 instants over 2024-2026 (every 37.3 days, 5.1 h later each time)
INSTANTS = [datetime(2024, 1, 1, tzinfo=UTC) + timedelta(days=37.3 * k, hours=5.1 * k) for k in range(22)]


def test_elevation_and_hour_angle_of_the_spa_example():
    # geometric against SPA's topocentric refracted elevation: ours has no refraction (0.016 deg) nor parallax
    assert sun.elevation_deg(SPA_TIME, *GOLDEN)[0] == pytest.approx(90.0 - SPA_ZENITH_DEG, abs=0.1)
    assert sun.hour_angle_deg(SPA_TIME, GOLDEN[1])[0] == pytest.approx(SPA_HOUR_ANGLE_DEG, abs=0.02)


@pytest.mark.parametrize(
    "utc",
    [datetime(2003, 10, 17, 13, 12, 43, tzinfo=UTC), datetime(2003, 10, 17, 0, 20, 19, tzinfo=UTC)],
    ids=["sunrise 06:12:43 local", "sunset 17:20:19 local"],
)
def test_elevation_at_the_spa_sunrise_and_sunset(utc):
    # SPA's rise and set are those of the UT day (spa.c limits each to [0, 1) of 2003-10-17 0 h UT): its 17:20:19
    # sunset is at 00:20:19 UT on the 17th, the evening before (that of the 17th local is 84 s earlier).
    # Printed to the second ("+/- 30 seconds" in spa.h): 30 s is 0.09 deg of elevation there.
    assert sun.elevation_deg([utc], *GOLDEN)[0] == pytest.approx(SPA_RISE_SET_DEG, abs=0.1)


def test_apparent_right_ascension_and_declination_of_meeus_25a():
    ra, dec = sun.right_ascension_declination_deg(MEEUS_TIME)
    assert ra[0] == pytest.approx(198.38083, abs=0.01)  # 13h 13m 31.4s
    assert dec[0] == pytest.approx(-7.78507, abs=0.01)  # -7 deg 47' 06"


def test_equation_of_time_of_meeus_28a():
    assert sun.equation_of_time_min(MEEUS_TIME)[0] == pytest.approx(13.0 + 42.6 / 60.0, abs=0.05)  # +13m 42.6s


def test_local_solar_time_is_noon_at_the_meridian_and_an_hour_per_15_deg():
    hour_angle = sun.hour_angle_deg(INSTANTS, 0.0)
    noon = -hour_angle  # the longitude whose meridian the sun crosses at each instant
    np.testing.assert_allclose(sun.local_solar_time_h(INSTANTS, noon), 12.0, atol=1e-9)
    for lon in (-170.0, -105.1786, 0.0, 37.5, 165.0):
        lst = sun.local_solar_time_h(INSTANTS, lon)
        np.testing.assert_allclose(lst, (12.0 + sun.hour_angle_deg(INSTANTS, lon) / 15.0) % 24.0, atol=1e-12)
        east = sun.local_solar_time_h(INSTANTS, lon + 15.0)
        np.testing.assert_allclose((east - lst - 1.0 + 12.0) % 24.0 - 12.0, 0.0, atol=1e-9)


@pytest.mark.parametrize("lon", [-150.0, -105.1786, 0.0, 37.0, 179.0])
def test_local_apparent_time_is_mean_solar_time_plus_the_equation_of_time(lon):
    # apparent solar time = UT + longitude / 15 + E (Meeus ch. 28): two routes, sidereal time from UT1 against the
    # mean sun's longitude; they part by UT1 - UTC (< 0.9 s) and the two mean-sun formulas (< 0.1 s this decade)
    ut_h = np.array([(u - u.replace(hour=0, minute=0, second=0, microsecond=0)).total_seconds() for u in INSTANTS])
    mean_solar_h = ut_h / 3600.0 + lon / 15.0 + sun.equation_of_time_min(INSTANTS) / 60.0
    gap_h = (sun.local_solar_time_h(INSTANTS, lon) - mean_solar_h + 12.0) % 24.0 - 12.0
    np.testing.assert_allclose(gap_h * 3600.0, 0.0, atol=1.5)  # s


def test_the_sun_is_at_the_zenith_of_the_subsolar_point_and_90_deg_less_the_arc_on_its_meridian():
    # 2024's equinoxes and solstices, to the minute
    utc = [datetime(2024, 3, 20, 3, 6, tzinfo=UTC), datetime(2024, 6, 20, 20, 51, tzinfo=UTC)]
    utc += [datetime(2024, 9, 22, 12, 44, tzinfo=UTC), datetime(2024, 12, 21, 9, 21, tzinfo=UTC)]
    _, dec = sun.right_ascension_declination_deg(utc)
    lon = -sun.hour_angle_deg(utc, 0.0)  # hour angle 0
    # arcsin next to 1 resolves sqrt(2 eps) rad: 0.85e-6 deg one ulp below 1, 1.21e-6 deg two ulps below
    np.testing.assert_allclose(sun.elevation_deg(utc, dec, lon), 90.0, atol=2e-6)
    for arc in (0.5, -1.0, 10.0, -30.0):  # along the meridian: the zenith distance is the arc
        np.testing.assert_allclose(sun.elevation_deg(utc, dec + arc, lon), 90.0 - abs(arc), atol=1e-10)


def test_the_elevation_at_the_subsolar_point_is_never_nan():
    many = [datetime(2024, 1, 1, tzinfo=UTC) + timedelta(hours=7 * k) for k in range(400)]  # about 5 % round over
    _, dec = sun.right_ascension_declination_deg(many)
    with np.errstate(invalid="ignore"):
        elevation = sun.elevation_deg(many, dec, -sun.hour_angle_deg(many, 0.0))
    assert not np.isnan(elevation).any()
