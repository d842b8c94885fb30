"""Gravity (App. A eq. A10) against the zonal potential; frames and ranges against closed forms."""

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from footprint.core import constants as c
from footprint.core.frames import ecef_from_geodetic, flight_angles, geodetic_from_ecef, velocity_from_angles
from footprint.core.gravity import gravity_ecef
from footprint.core.sphere import MEAN_RADIUS_NMI, downrange_crossrange_nmi
from tests.authorities.report import REPORT

RE, RP, MU = c.RADIUS_EQUATORIAL_FT, c.RADIUS_POLAR_FT, c.MU_EARTH_FT3_S2


def zonal_potential(x, y, z, j2, j3, j4):
    """U = mu/r [1 - sum J_n (Re/r)^n P_n(sin phi)], the textbook zonal expansion (Vallado, eq. 8-19)."""
    r = math.sqrt(x * x + y * y + z * z)
    s = z / r
    p2 = (3 * s**2 - 1) / 2
    p3 = (5 * s**3 - 3 * s) / 2
    p4 = (35 * s**4 - 30 * s**2 + 3) / 8
    q = RE / r
    return MU / r * (1 - j2 * q**2 * p2 - j3 * q**3 * p3 - j4 * q**4 * p4)


def potential_gradient(x, y, z, j2, j3, j4, h=20.0):
    out = []
    for d in np.eye(3) * h:
        plus = zonal_potential(x + d[0], y + d[1], z + d[2], j2, j3, j4)
        minus = zonal_potential(x - d[0], y - d[1], z - d[2], j2, j3, j4)
        out.append((plus - minus) / (2 * h))
    return np.array(out)


@pytest.mark.parametrize("lat_deg", [-89.9, -60.0, -23.0, 0.0, 12.5, 45.0, 75.0, 90.0])
@pytest.mark.parametrize("alt_ft", [0.0, 300_000.0, 2_000_000.0])
def test_eq_a10_is_the_gradient_of_the_zonal_potential(lat_deg, alt_ft):
    # J = 1.5 J2, H = 2.5 J3, K = -3.75 J4 (derivation in gravity.py)
    j2, j3, j4 = c.J_ZONAL / 1.5, c.H_ZONAL / 2.5, -c.K_ZONAL / 3.75
    lon = math.radians(37.0)
    r = RE + alt_ft
    x, y, z = (
        r * math.cos(math.radians(lat_deg)) * math.cos(lon),
        r * math.cos(math.radians(lat_deg)) * math.sin(lon),
        r * math.sin(math.radians(lat_deg)),
    )
    g = np.array(gravity_ecef(x, y, z, MU, RE, c.J_ZONAL, c.H_ZONAL, c.K_ZONAL, True))
    ref = potential_gradient(x, y, z, j2, j3, j4)
    # central differences at h = 20 ft resolve 1e-8 ft/s^2; the J3 and J4 terms are ~1e-4 ft/s^2,
    # so a wrong sign or factor on any of them fails here
    assert np.max(np.abs(g - ref)) < 2e-7


def test_equatorial_surface_gravity_closed_form():
    # at the equator (phi = 0): g = mu/Re^2 (1 + J + K/2), northward component zero
    gx, gy, gz = gravity_ecef(RE, 0.0, 0.0, MU, RE, c.J_ZONAL, c.H_ZONAL, c.K_ZONAL, True)
    assert -gx == pytest.approx(MU / RE**2 * (1 + c.J_ZONAL + c.K_ZONAL / 2), rel=1e-14)
    assert gy == 0.0
    # the odd (J3) term pulls along the axis at the equator: 3H/5 mu/Re^2
    assert gz == pytest.approx(0.6 * c.H_ZONAL * MU / RE**2, rel=1e-12)


def test_spherical_gravity_is_mu_over_r_squared():
    x, y, z = 1.1e7, -1.3e7, 0.9e7
    g = np.array(gravity_ecef(x, y, z, MU, RE, c.J_ZONAL, c.H_ZONAL, c.K_ZONAL, False))
    r = math.sqrt(x * x + y * y + z * z)
    np.testing.assert_allclose(g, -MU / r**3 * np.array([x, y, z]), rtol=1e-15)


@settings(max_examples=300, deadline=None)
@given(lat=st.floats(-90, 90), lon=st.floats(-180, 180), alt=st.floats(-20_000, 3_000_000), oblate=st.booleans())
def test_geodetic_round_trip(lat, lon, alt, oblate):
    x, y, z = ecef_from_geodetic(math.radians(lat), math.radians(lon), alt, RE, RP, oblate)
    la, lo, al = geodetic_from_ecef(x, y, z, RE, RP, oblate)
    assert abs(la - math.radians(lat)) < 1e-12
    if abs(lat) < 89.9999:
        assert abs(math.remainder(lo - math.radians(lon), 2 * math.pi)) < 1e-12
    assert abs(al - alt) < 1e-12 * RE  # 2e-5 ft


def test_polar_radius_and_flattening():
    # on the ellipsoid, the pole lies at R_p and the equator at R_e
    assert ecef_from_geodetic(math.pi / 2, 0.0, 0.0, RE, RP, True)[2] == pytest.approx(RP, abs=1e-6)
    assert geodetic_from_ecef(0.0, 0.0, RP + 1000.0, RE, RP, True)[2] == pytest.approx(1000.0, abs=1e-6)
    assert 1 / (1 - RP / RE) == pytest.approx(300.4, abs=0.05)  # paper_results.md A: f = 1/300.4


@settings(max_examples=200, deadline=None)
@given(
    lat=st.floats(-89, 89),
    lon=st.floats(-180, 180),
    v=st.floats(1000, 40000),
    gamma=st.floats(-89, 89),
    heading=st.floats(0, 359.999),
)
def test_flight_angles_round_trip(lat, lon, v, gamma, heading):
    x, y, z = ecef_from_geodetic(math.radians(lat), math.radians(lon), 300_000.0, RE, RP, True)
    vel = velocity_from_angles(x, y, z, v, math.radians(gamma), math.radians(heading))
    speed, g, h = flight_angles(x, y, z, *vel)
    assert speed == pytest.approx(v, rel=1e-13)
    assert abs(g - math.radians(gamma)) < 1e-12
    assert abs(math.remainder(h - math.radians(heading), 2 * math.pi)) < 1e-9


def test_table2_inertial_speed():
    # paper_results.md F.1: the Table 2 entry (relative, east at the equator) -> V_I 26,031.6 ft/s (Table 2: 26,031)
    t2 = {k: REPORT[f"table2.{k}"].value for k in ("altitude_ft", "velocity_fps", "gamma_deg", "heading_deg")}
    r = RE + t2["altitude_ft"]
    x, y, z = r, 0.0, 0.0
    vx, vy, vz = velocity_from_angles(
        x, y, z, t2["velocity_fps"], math.radians(t2["gamma_deg"]), math.radians(t2["heading_deg"])
    )
    vy_inertial = vy + c.OMEGA_EARTH_RAD_S * r
    assert math.hypot(vx, vy_inertial, vz) == pytest.approx(26_031.6, abs=0.1)


def test_ranges_closed_forms():
    # eastbound along the equator: 10 deg of longitude is 10 deg of down-range; north is positive cross-range
    arc = MEAN_RADIUS_NMI * math.radians(10.0)
    d, cross = downrange_crossrange_nmi([0.0, 10.0, 0.0, -10.0], [10.0, 0.0, -10.0, 0.0], 0.0, 0.0, 90.0)
    np.testing.assert_allclose(d, [arc, 0.0, -arc, 0.0], atol=1e-9)
    np.testing.assert_allclose(cross, [0.0, arc, 0.0, -arc], atol=1e-9)
    # a path that goes 3/4 of the way around the equator unwraps past half a circumference
    lon = np.linspace(0.0, 270.0, 28)
    d, _ = downrange_crossrange_nmi(np.zeros_like(lon), lon, 0.0, 0.0, 90.0, unwrap=True)
    assert d[-1] == pytest.approx(MEAN_RADIUS_NMI * math.radians(270.0), rel=1e-12)


def test_ranges_match_report_spherical_triangles():
    # eqs. (8)-(11) as printed (with the cross-range sign taken so that left is positive)
    lat0, lon0, sig0 = math.radians(20.0), math.radians(-30.0), math.radians(60.0)
    rng = np.random.default_rng(7)
    for lat, lon in rng.uniform([-60, -80], [60, 20], size=(50, 2)):
        la, lo = math.radians(lat), math.radians(lon)
        lf = math.acos(math.sin(la) * math.sin(lat0) + math.cos(la) * math.cos(lat0) * math.cos(lo - lon0))  # (8)
        zeta = math.atan2(
            math.sin(lo - lon0) * math.cos(la) * math.cos(lat0), math.sin(la) - math.sin(lat0) * math.cos(lf)
        )  # (9), quadrant by atan2
        xi = zeta - sig0
        yd = math.asin(math.sin(lf) * math.sin(xi))  # (11)
        xd = math.acos(math.cos(lf) / math.cos(yd))  # (10)
        d, cross = downrange_crossrange_nmi([lat], [lon], 20.0, -30.0, 60.0)
        assert cross[0] == pytest.approx(-MEAN_RADIUS_NMI * yd, abs=1e-6)  # printed eq. (11) is positive to the right
        assert abs(d[0]) == pytest.approx(MEAN_RADIUS_NMI * xd, abs=1e-6)
