"""The circular orbit that places a footprint: period, ground track, heading, node motion (core/orbits.py)."""

import math

import numpy as np
import pytest

from footprint.core.constants import FT_PER_M, FT_PER_NMI, OMEGA_EARTH_DEG_S
from footprint.core.orbits import (
    J2,
    CircularOrbit,
    deorbit_reference,
    frames,
    inertial_heading_deg,
    node_longitude_deg,
    position,
    revolution_node_longitude_deg,
    time_s,
)
from footprint.core.sphere import MEAN_RADIUS_NMI, great_circle_frame, heading_for_inclination

LEO = CircularOrbit(inclination_deg=28.5, altitude_ft=100 * FT_PER_NMI, node_longitude_deg=-80.0)
U = np.linspace(0.0, 360.0, 721)


def test_period_from_keplers_law_against_a_hand_value():
    # a = 20,925,631 + 100 x 6,076.115 = 21,533,242.5 ft; a^3 / mu = 9.98463e21 / 1.407698e16 = 709,282 s^2;
    # T = 2 pi x 842.189 = 5,291.6 s (88.19 min). An outside check: 185.2 km with the IERS GM
    # 398,600.4418 km^3/s^2 and R_e 6,378.137 km gives 5,291.7 s.
    assert LEO.period_s == pytest.approx(5291.6, abs=0.1)  # s, the hand value's last digit
    assert LEO.period_s == pytest.approx(5291.73, abs=0.5)  # s, the report's mu and R_e vs the IERS ones
    assert LEO.mean_motion_deg_s == pytest.approx(360.0 / 5291.63, rel=1e-5)


def test_a_day_holds_17_revolutions_of_88_minutes():
    assert list(LEO.revolutions_in(24.0)) == list(range(1, 18))  # 86,400 / 5,291.6 = 16.33
    assert list(LEO.revolutions_in(LEO.period_s * 3 / 3600.0)) == [1, 2, 3]


@pytest.mark.parametrize("inclination_deg", [0.0, 28.5, 51.6, 90.0, 98.7, 150.0])
def test_latitude_never_exceeds_the_inclination_and_reaches_it_at_u_90(inclination_deg):
    orbit = CircularOrbit(inclination_deg, 100 * FT_PER_NMI)
    top = min(inclination_deg, 180.0 - inclination_deg)
    lat, _ = position(orbit, np.arange(1, 4)[:, None], U[None, :])
    assert np.all(np.abs(lat) <= top + 1e-9)
    lat90, _ = position(orbit, [1, 2, 7], 90.0)
    lat270, _ = position(orbit, [1, 2, 7], 270.0)
    np.testing.assert_allclose(lat90, top, atol=1e-9)
    np.testing.assert_allclose(lat270, -top, atol=1e-9)


@pytest.mark.parametrize("inclination_deg", [0.0, 28.5, 63.4, 90.0, 98.7])
def test_heading_at_the_ascending_node_is_90_minus_i(inclination_deg):
    orbit = CircularOrbit(inclination_deg, 100 * FT_PER_NMI)
    assert inertial_heading_deg(orbit, 0.0) == pytest.approx(90.0 - inclination_deg, abs=1e-12)
    descending = (inertial_heading_deg(orbit, 180.0) - (90.0 + inclination_deg) + 180.0) % 360.0 - 180.0
    assert descending == pytest.approx(0.0, abs=1e-12)  # 90 + i, within a turn
    if inclination_deg < 90.0:  # the plane's trace where it crosses a latitude: cos i = sin(heading) cos(lat)
        lat, _ = position(orbit, 1, 40.0)
        assert inertial_heading_deg(orbit, 40.0) == pytest.approx(
            heading_for_inclination(lat, inclination_deg), abs=1e-9
        )


@pytest.mark.parametrize("regression", [True, False])
def test_successive_node_longitudes_differ_by_omega_t_plus_regression(regression):
    orbit = CircularOrbit(28.5, 100 * FT_PER_NMI, node_longitude_deg=170.0, nodal_regression=regression)
    nodes = revolution_node_longitude_deg(orbit, np.arange(1, 18))
    steps = (np.diff(nodes) + 180.0) % 360.0 - 180.0
    # omega_p T = 0.004178 deg/s x 5,291.63 s = 22.108 deg west; the J2 regression adds 0.485 deg west
    # (-7.92 deg/day x 5,291.63 / 86,400 s)
    expected = -OMEGA_EARTH_DEG_S * orbit.period_s + (orbit.node_rate_deg_s * orbit.period_s if regression else 0)
    np.testing.assert_allclose(steps, expected, atol=1e-9)
    assert expected == pytest.approx(-22.108 - (0.485 if regression else 0.0), abs=0.002)
    assert nodes[0] == pytest.approx(170.0)
    lat, lon = position(orbit, np.arange(1, 18), 0.0)  # the ascending node is where the track crosses north
    np.testing.assert_allclose(lat, 0.0, atol=1e-12)
    np.testing.assert_allclose(lon, nodes, atol=1e-9)


def test_nodal_regression_of_a_sun_synchronous_orbit():
    """An outside value: an 800 km orbit at i = 98.6 deg is sun-synchronous, its node turning east with the
    mean sun, 360 deg / 365.2422 days = 0.98565 deg/day."""
    sso = CircularOrbit(98.6, 800e3 * FT_PER_M)
    assert sso.node_rate_deg_s * 86_400 == pytest.approx(0.98565, abs=0.005)  # deg/day, i known to ~0.05 deg
    assert J2 == pytest.approx(1082.27e-6, rel=1e-5)
    assert CircularOrbit(90.0, 800e3 * FT_PER_M).node_rate_deg_s == pytest.approx(0.0, abs=1e-18)
    assert LEO.node_rate_deg_s * 86_400 == pytest.approx(-7.92, abs=0.01)  # deg/day, west (prograde orbit)


def test_a_polar_orbit_follows_a_meridian():
    still = CircularOrbit(90.0, 100 * FT_PER_NMI, node_longitude_deg=-120.0, rotation_rate_deg_s=0.0)
    u = np.linspace(-89.0, 89.0, 179)
    _, lon = position(still, 3, u)
    np.testing.assert_allclose(lon, -120.0, atol=1e-9)
    _, lon = position(still, 3, u + 180.0)
    np.testing.assert_allclose(lon, 60.0, atol=1e-9)  # the other half of the meridian
    turning = CircularOrbit(90.0, 100 * FT_PER_NMI, node_longitude_deg=-120.0)  # the earth turns beneath it
    _, lon = position(turning, 3, u)
    expected = -120.0 - OMEGA_EARTH_DEG_S * time_s(turning, 3, u)
    np.testing.assert_allclose((lon - expected + 180.0) % 360.0 - 180.0, 0.0, atol=1e-9)


def test_positions_lie_in_the_orbit_plane_in_inertial_coordinates():
    """Independent route: inertial longitude = earth-fixed + Greenwich sidereal angle (GST0 + omega t); the
    inertial plane has normal (sin Omega sin i, -cos Omega sin i, cos i) with Omega = RAAN + dOmega/dt t, and
    the satellite is u from the node along it."""
    gst0, raan = 100.0, 40.0
    orbit = CircularOrbit.from_right_ascension(51.6, 200 * FT_PER_NMI, raan, gst0)
    assert orbit.node_longitude_deg == pytest.approx(-60.0)
    rng = np.random.default_rng(7)
    rev, u = rng.integers(1, 30, 500), rng.uniform(0.0, 360.0, 500)
    lat, lon = position(orbit, rev, u)
    t = time_s(orbit, rev, u)
    ra, dec = np.radians(lon + gst0 + orbit.rotation_rate_deg_s * t), np.radians(lat)
    r = np.stack([np.cos(dec) * np.cos(ra), np.cos(dec) * np.sin(ra), np.sin(dec)], axis=-1)
    node = np.radians(raan + orbit.node_rate_deg_s * t)
    inc = math.radians(orbit.inclination_deg)
    normal = np.stack(
        [np.sin(node) * math.sin(inc), -np.cos(node) * math.sin(inc), np.full_like(node, math.cos(inc))], axis=-1
    )
    np.testing.assert_allclose(np.sum(r * normal, axis=-1), 0.0, atol=1e-12)
    to_node = np.stack([np.cos(node), np.sin(node), np.zeros_like(node)], axis=-1)
    np.testing.assert_allclose(np.sum(r * to_node, axis=-1), np.cos(np.radians(u)), atol=1e-12)


def test_time_and_node_longitude():
    assert time_s(LEO, 1, 0.0) == 0.0
    assert time_s(LEO, 3, 90.0) == pytest.approx(2.25 * LEO.period_s)
    assert node_longitude_deg(LEO, 0.0) == pytest.approx(-80.0)
    assert node_longitude_deg(LEO, 3600.0) == pytest.approx(-80.0 + LEO.node_drift_deg_s * 3600.0)


def test_the_deorbit_reference_is_the_orbit_plane_at_that_instant():
    rev, u = 5, 137.0
    ref = deorbit_reference(LEO, rev, u)
    lat, lon = position(LEO, rev, u)
    assert (ref.latitude_deg, ref.longitude_deg) == pytest.approx((float(lat), float(lon)), abs=1e-12)
    assert ref.heading_deg == pytest.approx(float(inertial_heading_deg(LEO, u)), abs=1e-12)
    p0, d0, n, t = frames(LEO, rev, u)
    q0, e0, m = great_circle_frame(ref.latitude_deg, ref.longitude_deg, ref.heading_deg)
    np.testing.assert_allclose(np.stack([p0, d0, n]), np.stack([q0, e0, m]), atol=1e-12)
    assert t == pytest.approx(time_s(LEO, rev, u))


def test_an_entry_offset_moves_the_reference_along_the_orbit():
    offset_nmi = 1_500.0
    du = math.degrees(offset_nmi / MEAN_RADIUS_NMI)
    ref = deorbit_reference(LEO, 2, 300.0, entry_offset_nmi=offset_nmi)
    there = deorbit_reference(LEO, 2, 300.0 + du)
    assert ref == there
    _, _, _, t = frames(LEO, 2, 300.0, entry_offset_nmi=offset_nmi)
    assert t == pytest.approx(time_s(LEO, 2, 300.0) + du / 360.0 * LEO.period_s)
