"""Section IV geometry (AFWAL-TR-82-3036 eqs. 8-15): ranges both ways, move, mirror, rotation shift.

Three routes to the same numbers: ours (unit vectors, closed form, footprint.core.sphere), the
report's own spherical trigonometry and iteration as printed (below, with the two sign fixes DESIGN.md
asks for), and geographiclib's geodesics on a sphere of radius R' (an outside authority). Tolerances are
angles on the earth: 1e-9 deg is 6.5 mm, 1e-6 deg is 6.4 m.
"""

import math

import numpy as np
import pytest
from geographiclib.geodesic import Geodesic
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from footprint.contracts import parse
from footprint.core.constants import OMEGA_EARTH_DEG_S
from footprint.core.sphere import (
    MEAN_RADIUS_NMI,
    Reference,
    downrange_crossrange_nmi,
    heading_for_inclination,
    inclination_for_heading,
    latlon_from_ranges,
    mirror,
    move,
    rotation_shift,
)
from tests.authorities.report import REPORT, table2_entry, table2_stop

R = MEAN_RADIUS_NMI  # R', nmi
CIRCUMFERENCE_NMI = 2.0 * math.pi * R
SPHERE = Geodesic(R, 0.0)  # geographiclib on the sphere of radius R' (lengths in nmi)
NMI_PER_DEG = math.radians(1.0) * R  # 60.04 nmi of arc per degree

ROUND_TRIP_DEG = 1e-9  # closed forms both ways: a few ulps of an angle
# the cross-range as asin(P . n) (eq. 11's form): within 0.001 deg (0.06 nmi) of the initial great circle's
# poles the arc sine's slope turns a rounding of P . n into up to 1.5e-8 rad (9 cm). The cross-range
# round trips are asserted outside that band (atan2(P . n, |P x n|) would hold everywhere)
CIRCLE_POLE_BAND_NMI = math.radians(0.001) * MEAN_RADIUS_NMI


def off_circle_pole(cross_nmi):
    return abs(cross_nmi) < math.pi / 2 * MEAN_RADIUS_NMI - CIRCLE_POLE_BAND_NMI


AUTHORITY_DEG = 1e-6  # against geographiclib and the report's trigonometry (acos near 1 keeps ~8 digits)
# The printed forms take arc cosines of numbers that tend to 1: eq. (10) for points abeam of the start,
# eq. (8) solved for the longitude difference in the iteration for points due north or south of it. A few
# ulps there are an angle of sqrt(2 * 4 eps) = 4.2e-8 rad = 2.4e-6 deg (1.5e-4 nmi): the printed forms' own
# conditioning, not ours
ACOS_NEAR_1_DEG = math.degrees(math.sqrt(8.0 * np.finfo(float).eps))
EQ10_ABEAM_NMI = math.radians(ACOS_NEAR_1_DEG) * MEAN_RADIUS_NMI

lats = st.floats(-90.0, 90.0, allow_nan=False)
lons = st.floats(-180.0, 180.0, allow_nan=False)
headings = st.floats(-360.0, 360.0, allow_nan=False)
references = st.builds(Reference, lats, lons, headings)


def arc_deg(lat1, lon1, lat2, lon2):
    """Angle between two points (deg), robust at 0 and near the poles (vector form, independent of ours)."""
    a = np.array(
        [
            math.cos(math.radians(lat1)) * math.cos(math.radians(lon1)),
            math.cos(math.radians(lat1)) * math.sin(math.radians(lon1)),
            math.sin(math.radians(lat1)),
        ]
    )
    b = np.array(
        [
            math.cos(math.radians(lat2)) * math.cos(math.radians(lon2)),
            math.cos(math.radians(lat2)) * math.sin(math.radians(lon2)),
            math.sin(math.radians(lat2)),
        ]
    )
    return math.degrees(math.atan2(np.linalg.norm(np.cross(a, b)), a @ b))


def lon_diff_deg(a, b):
    return abs((a - b + 180.0) % 360.0 - 180.0)


# ------------------------------------------------------------------- the report's equations, as printed
def report_ranges_nmi(lat, lon, lat0, lon0, sigma0):
    """Eqs. (8)-(11) as printed; returns (down-range, cross-range) in our convention.

    Sign fixes (DESIGN.md): eq. (11) gives cross-range positive to the right of the initial heading (xi =
    zeta - sigma0 > 0 is clockwise); ours is positive to the left. Eq. (10) takes an arc cosine and so
    loses the sign of points behind the initial point (|xi| > 90 deg). tan zeta of eq. (9) is solved in the
    quadrant its numerator and denominator give.
    """
    phi_L, theta_L, phi_L0, theta_L0, sigma_0 = map(math.radians, (lat, lon, lat0, lon0, sigma0))
    LF = math.acos(
        max(
            -1.0,
            min(
                1.0,
                math.sin(phi_L) * math.sin(phi_L0) + math.cos(phi_L) * math.cos(phi_L0) * math.cos(theta_L - theta_L0),
            ),
        )
    )  # (8)
    zeta = math.atan2(
        math.sin(theta_L - theta_L0) * math.cos(phi_L) * math.cos(phi_L0),
        math.sin(phi_L) - math.sin(phi_L0) * math.cos(LF),
    )  # (9)
    xi = zeta - sigma_0
    Y_D = R * math.asin(math.sin(LF) * math.sin(xi))  # (11)
    X_D = R * math.acos(max(-1.0, min(1.0, math.cos(LF) / math.cos(math.asin(math.sin(LF) * math.sin(xi))))))  # (10)
    return math.copysign(X_D, math.cos(xi)), -Y_D


def report_latlon(down_nmi, cross_nmi, lat0, lon0, sigma0_M, tol_rad=1e-15):
    """Eqs. (12)-(15) as printed: from the new down-range and heading, holding the cross-range, find the
    latitude by iteration (bisection on the guess of phi_LM until eq. (9) gives the zeta_M of eq. (14)).

    Sign fixes as above: PF carries the report's sign (positive right); eq. (13)'s arc sine is put in the
    quadrant behind the initial point when the down-range is negative. The guesses are bracketed by the
    lowest and highest latitudes of the circle of radius LF_M about the initial point (sin phi = sin phi_L0
    cos LF_M -+ cos phi_L0 sin LF_M): along either half of that circle latitude rises as |zeta| falls from
    180 to 0 deg, so bisection converges; defined for 0 < LF_M < 180 deg off the poles.
    """
    phi_L0, theta_L0M, sigma_OM = map(math.radians, (lat0, lon0, sigma0_M))
    PF, X_DM = -cross_nmi / R, down_nmi / R
    LF_M = math.acos(math.cos(PF) * math.cos(X_DM))  # (12)
    xi_M = math.asin(max(-1.0, min(1.0, math.sin(PF) / math.sin(LF_M))))  # (13)
    if math.sin(X_DM) < 0.0:
        xi_M = math.pi - xi_M
    zeta_M = xi_M + sigma_OM  # (14)
    zeta_M = math.atan2(math.sin(zeta_M), math.cos(zeta_M))
    east = math.sin(zeta_M) >= 0.0

    def dtheta(phi_LM):  # eq. (8) solved for (theta_L - theta_L0)_M, on the side zeta_M points to
        c = (math.cos(LF_M) - math.sin(phi_LM) * math.sin(phi_L0)) / (math.cos(phi_LM) * math.cos(phi_L0))
        d = math.acos(max(-1.0, min(1.0, c)))
        return d if east else -d

    def zeta(phi_LM):  # eq. (9)
        return math.atan2(
            math.sin(dtheta(phi_LM)) * math.cos(phi_LM) * math.cos(phi_L0),
            math.sin(phi_LM) - math.sin(phi_L0) * math.cos(LF_M),
        )

    lo = math.asin(math.sin(phi_L0) * math.cos(LF_M) - math.cos(phi_L0) * math.sin(LF_M))  # zeta = +-180 deg
    hi = math.asin(math.sin(phi_L0) * math.cos(LF_M) + math.cos(phi_L0) * math.sin(LF_M))  # zeta = 0
    while hi - lo > tol_rad:
        mid = 0.5 * (lo + hi)
        if abs(zeta(mid)) > abs(zeta_M):
            lo = mid
        else:
            hi = mid
    phi_LM = 0.5 * (lo + hi)
    return math.degrees(phi_LM), math.degrees(dtheta(phi_LM) + theta_L0M)  # (15)


# ----------------------------------------------------------------------------------------- round trips
@settings(max_examples=400, deadline=None)
@given(lat=lats, lon=lons, ref=references)
def test_latlon_to_ranges_and_back_is_the_identity(lat, lon, ref):
    d, c = downrange_crossrange_nmi(lat, lon, ref.latitude_deg, ref.longitude_deg, ref.heading_deg)
    lat2, lon2 = latlon_from_ranges(d, c, ref.latitude_deg, ref.longitude_deg, ref.heading_deg)
    assert arc_deg(lat, lon, float(lat2), float(lon2)) < ROUND_TRIP_DEG
    assert abs(float(lat2) - lat) < ROUND_TRIP_DEG
    if abs(lat) < 90.0 - 1e-6:  # longitude means something
        assert lon_diff_deg(float(lon2), lon) * math.cos(math.radians(lat)) < ROUND_TRIP_DEG


@settings(max_examples=300, deadline=None)
@given(
    d=st.floats(-CIRCUMFERENCE_NMI / 2 * 0.999999, CIRCUMFERENCE_NMI / 2 * 0.999999),
    c=st.floats(-0.999 * math.pi / 2 * R, 0.999 * math.pi / 2 * R),
    ref=references,
)
def test_ranges_to_latlon_and_back_is_the_identity(d, c, ref):
    lat, lon = latlon_from_ranges(d, c, ref.latitude_deg, ref.longitude_deg, ref.heading_deg)
    d2, c2 = downrange_crossrange_nmi(lat, lon, ref.latitude_deg, ref.longitude_deg, ref.heading_deg)
    assert abs(float(c2) - c) < ROUND_TRIP_DEG * NMI_PER_DEG
    assert abs(float(d2) - d) * math.cos(c / R) < ROUND_TRIP_DEG * NMI_PER_DEG


def test_round_trip_of_many_points_at_once():
    rng = np.random.default_rng(82_3036)
    lat = np.degrees(np.arcsin(rng.uniform(-1, 1, 100_000)))
    lon = rng.uniform(-180, 180, lat.size)
    for ref in (Reference(0, 0, 90), Reference(-33.9, 151.2, 137.0), Reference(89.999, 10.0, 200.0)):
        d, c = downrange_crossrange_nmi(lat, lon, ref.latitude_deg, ref.longitude_deg, ref.heading_deg)
        lat2, lon2 = latlon_from_ranges(d, c, ref.latitude_deg, ref.longitude_deg, ref.heading_deg)
        assert np.max(np.abs(lat2 - lat)) < ROUND_TRIP_DEG
        assert np.max(np.abs((lon2 - lon + 180) % 360 - 180) * np.cos(np.radians(lat))) < ROUND_TRIP_DEG


# --------------------------------------------------------------------------- geographiclib on a sphere
@settings(max_examples=300, deadline=None)
@given(lat=lats, lon=lons, ref=references)
def test_ranges_agree_with_geodesics_on_the_sphere(lat, lon, ref):
    """Walk our down-range along the initial great circle (direct problem), turn left, walk our cross-range:
    that lands on the point; and the foot is the nearest point of the circle (inverse problem)."""
    d, c = (float(x) for x in downrange_crossrange_nmi(lat, lon, ref.latitude_deg, ref.longitude_deg, ref.heading_deg))
    assume(abs(c) < 0.999 * math.pi / 2 * R)  # at the circle's pole every foot is as near
    foot = SPHERE.Direct(ref.latitude_deg, ref.longitude_deg, ref.heading_deg, d)
    end = SPHERE.Direct(foot["lat2"], foot["lon2"], foot["azi2"] - 90.0, c)  # left of the heading
    assert arc_deg(end["lat2"], end["lon2"], lat, lon) < AUTHORITY_DEG
    assert abs(SPHERE.Inverse(foot["lat2"], foot["lon2"], lat, lon)["s12"] - abs(c)) < AUTHORITY_DEG * NMI_PER_DEG
    for step_nmi in (-1.0, 1.0):  # a nautical mile either way along the circle is farther
        other = SPHERE.Direct(ref.latitude_deg, ref.longitude_deg, ref.heading_deg, d + step_nmi)
        assert SPHERE.Inverse(other["lat2"], other["lon2"], lat, lon)["s12"] >= abs(c) - 1e-9


@settings(max_examples=200, deadline=None)
@given(lat=st.floats(-89.0, 89.0), lon=lons, heading=headings, step=st.floats(-30_000.0, 30_000.0))
def test_a_step_around_the_orbit_is_a_walk_along_the_geodesic(lat, lon, heading, step):
    ref = Reference(lat, lon, heading)
    lat2, lon2 = move(lat, lon, ref, ref, step)  # the initial point itself, stepped
    g = SPHERE.Direct(lat, lon, heading, step)
    assert arc_deg(float(lat2), float(lon2), g["lat2"], g["lon2"]) < AUTHORITY_DEG


# ------------------------------------------------------------------ the report's trigonometry (8)-(15)
@settings(max_examples=400, deadline=None)
@given(lat=st.floats(-89.0, 89.0), lon=lons, ref=st.builds(Reference, st.floats(-89.0, 89.0), lons, headings))
def test_eqs_8_to_11_as_printed_agree_with_ours(lat, lon, ref):
    ours = downrange_crossrange_nmi(lat, lon, ref.latitude_deg, ref.longitude_deg, ref.heading_deg)
    lf = arc_deg(lat, lon, ref.latitude_deg, ref.longitude_deg)
    assume(1e-3 < lf < 180.0 - 1e-3)  # eq. (9): the heading to a point at (or opposite) the start is 0/0
    assume(abs(float(ours[1])) < 0.95 * math.pi / 2 * R)  # eq. (10) divides by cos(cross-range)
    theirs = report_ranges_nmi(lat, lon, ref.latitude_deg, ref.longitude_deg, ref.heading_deg)
    assert abs(theirs[1] - float(ours[1])) < AUTHORITY_DEG * NMI_PER_DEG
    behind_or_ahead = (theirs[0] - float(ours[0]) + CIRCUMFERENCE_NMI / 2) % CIRCUMFERENCE_NMI - CIRCUMFERENCE_NMI / 2
    # +-180 deg are one place; eq. (10)'s ratio carries the rounding of cos(Y) in its denominator too
    assert abs(behind_or_ahead) < AUTHORITY_DEG * NMI_PER_DEG + EQ10_ABEAM_NMI / math.sqrt(math.cos(float(ours[1]) / R))


def test_eq_11_as_printed_is_positive_to_the_right_and_eq_10_loses_the_sign_behind():
    """The two printed signs DESIGN.md fixes: a point north of an eastbound start is to the left (ours
    +, the printed eq. 11 -), and a point west of it is behind (ours -, the printed eq. 10 +)."""
    phi_L0 = theta_L0 = 0.0
    LF = math.radians(10.0)
    for zeta_deg, want_down, want_cross in ((0.0, 0.0, 1.0), (270.0, -1.0, 0.0)):
        xi = math.radians(zeta_deg) - math.radians(90.0)
        printed_y = R * math.asin(math.sin(LF) * math.sin(xi))  # (11)
        printed_x = R * math.acos(math.cos(LF) / math.cos(math.asin(math.sin(LF) * math.sin(xi))))  # (10)
        lat, lon = (10.0, 0.0) if zeta_deg == 0.0 else (0.0, -10.0)
        d, c = downrange_crossrange_nmi(lat, lon, phi_L0, theta_L0, 90.0)
        if want_cross:
            assert float(c) == pytest.approx(10.0 * NMI_PER_DEG) and printed_y == pytest.approx(-float(c))
        if want_down:
            assert float(d) == pytest.approx(-10.0 * NMI_PER_DEG) and printed_x == pytest.approx(-float(d))


@settings(max_examples=300, deadline=None)
@given(
    d=st.floats(-10_000.0, 10_000.0),
    c=st.floats(-4_000.0, 4_000.0),
    lat0=st.floats(-80.0, 80.0),
    lon0=lons,
    heading=headings,
)
def test_iteration_12_to_15_as_printed_agrees_with_our_closed_form(d, c, lat0, lon0, heading):
    lf_deg = math.degrees(math.acos(math.cos(c / R) * math.cos(d / R)))  # eq. (12)
    assume(0.01 < lf_deg < 179.99)  # eq. (13) divides by sin(LF_M)
    lat, lon = report_latlon(d, c, lat0, lon0, heading)
    ours = latlon_from_ranges(d, c, lat0, lon0, heading)
    # eq. (8) solved for the longitude difference divides by cos(phi_L) cos(phi_L0) before its arc cosine
    cos_lats = math.cos(math.radians(lat0)) * max(math.cos(math.radians(float(ours[0]))), 1e-3)
    slack = ACOS_NEAR_1_DEG / math.sqrt(cos_lats)
    assert arc_deg(lat, lon, float(ours[0]), float(ours[1])) < AUTHORITY_DEG + slack


def test_the_report_way_round_trip_moves_a_footprint_like_ours():
    """Eqs. 8-11 forward, change node, heading and down-range, eqs. 12-15 back: the report's procedure for
    "calculating a new footprint" (IV.1) against move() on a footprint-sized ring of points."""
    src, dst, step = Reference(0.0, 0.0, 90.0), Reference(0.0, -40.0, 30.0), 500.0
    ring = [
        (float(a), float(b))
        for a, b in zip(
            *latlon_from_ranges(
                3000 + 2500 * np.cos(np.linspace(0, 2 * np.pi, 37)),
                1700 * np.sin(np.linspace(0, 2 * np.pi, 37)),
                src.latitude_deg,
                src.longitude_deg,
                src.heading_deg,
            )
        )
    ]
    lat_m, lon_m = move([p[0] for p in ring], [p[1] for p in ring], src, dst, step)
    for (lat, lon), a, b in zip(ring, lat_m, lon_m):
        x, y = report_ranges_nmi(lat, lon, src.latitude_deg, src.longitude_deg, src.heading_deg)
        lat2, lon2 = report_latlon(x + step, y, dst.latitude_deg, dst.longitude_deg, dst.heading_deg)
        assert arc_deg(lat2, lon2, float(a), float(b)) < AUTHORITY_DEG + ACOS_NEAR_1_DEG


# ------------------------------------------------------------------------------------------------ move
@settings(max_examples=300, deadline=None)
@given(lat=lats, lon=lons, src=references, dst=references, step=st.floats(-25_000.0, 25_000.0))
def test_move_is_ranges_then_offset_then_inverse(lat, lon, src, dst, step):
    d, c = downrange_crossrange_nmi(lat, lon, src.latitude_deg, src.longitude_deg, src.heading_deg)
    want = latlon_from_ranges(d + step, c, dst.latitude_deg, dst.longitude_deg, dst.heading_deg)
    got = move(lat, lon, src, dst, step)
    assert arc_deg(float(got[0]), float(got[1]), float(want[0]), float(want[1])) < ROUND_TRIP_DEG


@settings(max_examples=200, deadline=None)
@given(lat=lats, lon=lons, src=references, dst=references)
def test_move_keeps_the_ranges_and_moving_back_returns_the_points(lat, lon, src, dst):
    d, c = downrange_crossrange_nmi(lat, lon, src.latitude_deg, src.longitude_deg, src.heading_deg)
    lat2, lon2 = move(lat, lon, src, dst)
    d2, c2 = downrange_crossrange_nmi(lat2, lon2, dst.latitude_deg, dst.longitude_deg, dst.heading_deg)
    if off_circle_pole(float(c)):
        assert abs(float(c2) - float(c)) < ROUND_TRIP_DEG * NMI_PER_DEG
    if abs(float(c)) < 0.999 * math.pi / 2 * R:
        wrap = (float(d2) - float(d) + CIRCUMFERENCE_NMI / 2) % CIRCUMFERENCE_NMI - CIRCUMFERENCE_NMI / 2
        assert abs(wrap) * math.cos(float(c) / R) < ROUND_TRIP_DEG * NMI_PER_DEG
    lat3, lon3 = move(lat2, lon2, dst, src)
    assert arc_deg(float(lat3), float(lon3), lat, lon) < ROUND_TRIP_DEG


def test_re_node_shifts_every_longitude_when_the_start_is_on_the_equator():
    """A change of node alone (theta_L0 -> theta_L0M of eq. 15) is a turn about the polar axis."""
    lat = np.array([0.0, 13.18, -29.88, 45.0, 89.0])
    lon = np.array([120.17, 115.44, 58.77, -170.0, 3.0])
    lat2, lon2 = move(lat, lon, Reference(0.0, 0.0, 90.0), Reference(0.0, -75.0, 90.0))
    np.testing.assert_allclose(lat2, lat, atol=ROUND_TRIP_DEG)
    np.testing.assert_allclose((lon2 - (lon - 75.0) + 180) % 360 - 180, 0.0, atol=ROUND_TRIP_DEG)


@pytest.mark.parametrize("inclination_deg", [0.0, 28.5, 30.0, 60.0, 90.0, 98.0, 150.0])
def test_re_incline_at_the_node_uses_heading_90_minus_inclination(inclination_deg):
    """At the ascending node the heading is 90 - i; the moved orbit's ground track reaches latitude i (or
    180 - i when retrograde) and passes the node with inclination i."""
    assert heading_for_inclination(0.0, inclination_deg) == pytest.approx(90.0 - inclination_deg, abs=1e-12)
    assert inclination_for_heading(0.0, 90.0 - inclination_deg) == pytest.approx(inclination_deg, abs=1e-9)
    src = Reference(0.0, 0.0, 90.0)
    dst = Reference(0.0, 20.0, float(heading_for_inclination(0.0, inclination_deg)))
    along = np.linspace(-180.0, 180.0, 3601)  # the equator: src's initial great circle
    lat, lon = move(np.zeros_like(along), along, src, dst)
    assert np.max(lat) == pytest.approx(min(inclination_deg, 180.0 - inclination_deg), abs=1e-6)
    assert np.min(np.abs(lat - 0.0) + np.abs(lon - 20.0)) < 1e-9  # through the new node


@settings(max_examples=200, deadline=None)
@given(lat=st.floats(-80.0, 80.0), inc=st.floats(0.0, 180.0), ascending=st.booleans())
def test_heading_and_inclination_are_inverse(lat, inc, ascending):
    assume(math.cos(math.radians(inc)) ** 2 <= math.cos(math.radians(lat)) ** 2 - 1e-9)  # the orbit reaches lat
    hdg = float(heading_for_inclination(lat, inc, ascending))
    assert (abs(hdg) < 90.0 + 1e-9) == ascending or abs(abs(hdg) - 90.0) < 1e-6
    assert float(inclination_for_heading(lat, hdg)) == pytest.approx(inc, abs=1e-6)


@settings(max_examples=200, deadline=None)
@given(lat=lats, lon=lons, ref=references, turns=st.integers(-3, 3))
def test_stepping_whole_circuits_of_the_orbit_returns_the_points(lat, lon, ref, turns):
    lat2, lon2 = move(lat, lon, ref, ref, turns * CIRCUMFERENCE_NMI)  # 360 deg of down-range per turn
    assert arc_deg(float(lat2), float(lon2), lat, lon) < ROUND_TRIP_DEG


# ---------------------------------------------------------------------------------------------- mirror
@settings(max_examples=300, deadline=None)
@given(lat=lats, lon=lons, ref=references)
def test_mirror_twice_is_the_identity_and_negates_only_the_cross_range(lat, lon, ref):
    mlat, mlon = mirror(lat, lon, ref)
    lat2, lon2 = mirror(mlat, mlon, ref)
    assert arc_deg(float(lat2), float(lon2), lat, lon) < ROUND_TRIP_DEG
    d, c = downrange_crossrange_nmi(lat, lon, ref.latitude_deg, ref.longitude_deg, ref.heading_deg)
    md, mc = downrange_crossrange_nmi(mlat, mlon, ref.latitude_deg, ref.longitude_deg, ref.heading_deg)
    if off_circle_pole(float(c)):
        assert abs(float(mc) + float(c)) < ROUND_TRIP_DEG * NMI_PER_DEG
    if abs(float(c)) < 0.999 * math.pi / 2 * R:
        half = math.pi * R  # down-range is an angle: +-half the circumference are the same place
        dd = (float(md) - float(d) + half) % (2 * half) - half
        assert abs(dd) * math.cos(float(c) / R) < ROUND_TRIP_DEG * NMI_PER_DEG


def test_mirror_about_an_eastbound_equatorial_start_negates_the_latitude():
    lat, lon = mirror([13.18, -29.88, 0.0], [115.44, 58.77, 16.26], Reference(0.0, 0.0, 90.0))
    np.testing.assert_allclose(lat, [-13.18, 29.88, 0.0], atol=1e-12)
    np.testing.assert_allclose(lon, [115.44, 58.77, 16.26], atol=1e-12)


# ------------------------------------------------------------------------------ date line and the poles
def test_points_either_side_of_the_date_line_are_neighbours():
    ref = Reference(0.0, 179.99, 90.0)  # eastbound just west of the date line
    d, c = downrange_crossrange_nmi([0.0, 0.0, 10.0], [179.99, -179.99, -179.99], 0.0, 179.99, 90.0)
    np.testing.assert_allclose(d, [0.0, 0.02 * NMI_PER_DEG, d[2]], atol=1e-9)
    assert abs(c[0]) < 1e-9 and abs(c[1]) < 1e-9 and c[2] > 0.0
    lat, lon = latlon_from_ranges(d, c, 0.0, 179.99, 90.0)
    np.testing.assert_allclose((lon - np.array([179.99, -179.99, -179.99]) + 180) % 360 - 180, 0.0, atol=1e-9)
    assert np.all((-180.0 < lon) & (lon <= 180.0))
    # a footprint moved across the date line keeps its shape
    lat2, lon2 = move([0.0, 0.0], [179.99, -179.99], ref, Reference(0.0, -179.995, 90.0))
    np.testing.assert_allclose(lat2, 0.0, atol=1e-12)
    np.testing.assert_allclose(lon2, [-179.995, -179.975], atol=1e-9)
    assert lon_diff_deg(float(rotation_shift(-179.99, 10.0)), 180.0 - 0.03178) < 1e-9  # shifted west over it


@pytest.mark.parametrize("lat0", [89.995, -89.995, 90.0])
def test_within_a_hundredth_of_a_degree_of_the_poles(lat0):
    ref = Reference(lat0, 35.0, 180.0 if lat0 > 0 else 0.0)  # toward the other side of the world
    pts_lat = np.array([89.991, 89.999, -89.992, 90.0, -90.0, 45.0])
    pts_lon = np.array([-179.99, 179.99, 12.0, 0.0, 0.0, -60.0])
    d, c = downrange_crossrange_nmi(pts_lat, pts_lon, ref.latitude_deg, ref.longitude_deg, ref.heading_deg)
    lat, lon = latlon_from_ranges(d, c, ref.latitude_deg, ref.longitude_deg, ref.heading_deg)
    for a, b, a2, b2 in zip(pts_lat, pts_lon, lat, lon):
        assert arc_deg(a, b, float(a2), float(b2)) < ROUND_TRIP_DEG
    # geographiclib's distance from the start agrees there too (spherical Pythagoras: cos LF = cos X cos Y)
    for a, b, dd, cc in zip(pts_lat, pts_lon, d, c):
        lf = SPHERE.Inverse(ref.latitude_deg, ref.longitude_deg, float(a), float(b))["s12"] / R
        assert math.cos(lf) == pytest.approx(math.cos(float(dd) / R) * math.cos(float(cc) / R), abs=1e-12)
    lat_m, lon_m = move(pts_lat, pts_lon, ref, Reference(0.0, 0.0, 90.0))
    lat_b, lon_b = move(lat_m, lon_m, Reference(0.0, 0.0, 90.0), ref)
    for a, b, a2, b2 in zip(pts_lat, pts_lon, lat_b, lon_b):
        assert arc_deg(a, b, float(a2), float(b2)) < ROUND_TRIP_DEG


# -------------------------------------------------------------------------------------- rotation shift
@pytest.mark.parametrize(
    "t_s, report_deg", [(REPORT["sec4.flight_time_min_s"].value, 8.36), (REPORT["sec4.flight_time_max_s"].value, 16.71)]
)
def test_rotation_shift_matches_the_report(t_s, report_deg):
    """Section IV.3: omega_p = .004178 deg/s; "a longitude shift of 8.4 to 16.7 degrees" for 2,000 to
    4,000 s, "toward the west, that is toward more negative values"; latitude unchanged."""
    assert OMEGA_EARTH_DEG_S == REPORT["sec4.omega_deg_s"].value
    shifted = float(rotation_shift(30.0, t_s))
    assert 30.0 - shifted == pytest.approx(report_deg, abs=0.005)  # omega_p t by hand (printed: 8.4, 16.7)
    assert shifted < 30.0


def test_rotation_shift_is_per_point_and_wraps_west_over_the_date_line():
    lon = rotation_shift([0.0, 0.0, -175.0, 10.0], [0.0, 2_000.0, 2_000.0, 4_000.0])
    np.testing.assert_allclose(lon, [0.0, -8.356, 176.644, 10.0 - 16.712], atol=1e-9)
    assert float(rotation_shift(0.0, 0.0)) == 0.0  # the initial point (t = 0) does not move


# ------------------------------------------------------------- rotation: the first-order shift vs flying
ROTATION_STUDY = table2_entry()


def l189_spec():

    return parse(
        "case",
        {
            "vehicle": {"builtin": "lod-1.89"},
            "planet": {"rotating": False},
            "entry": ROTATION_STUDY,
            "stop": table2_stop(),
        },
    ).to_spec()


@settings(max_examples=100, deadline=None)
@given(ref=st.builds(Reference, st.floats(-80.0, 80.0), lons, headings), step=st.floats(-30_000.0, 30_000.0))
def test_stepped_reference_is_geographiclibs_direct_problem(ref, step):
    from footprint.core.rotation import stepped_reference

    got = stepped_reference(ref, step)
    g = SPHERE.Direct(ref.latitude_deg, ref.longitude_deg, ref.heading_deg, step)
    assert arc_deg(got.latitude_deg, got.longitude_deg, g["lat2"], g["lon2"]) < AUTHORITY_DEG
    if abs(g["lat2"]) < 89.0:  # the heading is defined
        assert lon_diff_deg(got.heading_deg, g["azi2"]) < AUTHORITY_DEG


def test_at_geometry_changes_only_the_entry_point_heading_rotation_and_frame():
    from footprint.core.rotation import at_geometry

    spec = l189_spec()
    moved = at_geometry(spec, Reference(10.0, -20.0, 30.0), rotating=True, velocity_frame="inertial")
    e = moved.entry
    assert (e.latitude_deg, e.longitude_deg, e.heading_deg, e.velocity_frame) == (10.0, -20.0, 30.0, "inertial")
    assert (e.altitude_ft, e.velocity_fps, e.gamma_deg) == tuple(
        REPORT[f"table2.{k}"].value for k in ("altitude_ft", "velocity_fps", "gamma_deg")
    )
    assert moved.planet.rotating and not spec.planet.rotating
    assert moved.vehicle is spec.vehicle and np.array_equal(moved.ctrl, spec.ctrl)


@pytest.mark.parametrize("heading_deg, change", [(90.0, "compacted"), (-90.0, "stretched")])
def test_first_order_shift_against_the_footprint_flown_on_the_rotating_earth(heading_deg, change):
    """Section IV.3: the westward shift compacts an eastbound footprint and stretches a westbound one.
    With the inertial entry state kept (the approximation's premise) the flown footprint does the same, and
    the shifted points land within 300 nmi of the flown ones (4-5 % of the L/D 1.89 footprint's 6,200 nmi
    length; docs/maps.md has the whole footprints)."""
    from footprint.core.method_settings import SingleParameter
    from footprint.core.rotation import approximate_vs_exact

    settings = SingleParameter(bank0_deg=(0.0, 45.0, 90.0, 135.0), min_range="zero_lift", mirror=True)
    c = approximate_vs_exact(l189_spec(), settings, Reference(0.0, 0.0, heading_deg))
    assert c.unmatched == 0 and len(c.rows) == 8  # front, 3 left, zero lift, 3 right
    assert c.max_error_nmi < 300.0
    assert c.move_error_nmi["max_nmi"] < 1.0  # on the equator moving east or west is a symmetry
    ext = c.downrange_extent_nmi
    for after in (ext["approximate"], ext["exact"]):
        assert (after < 0.95 * ext["nonrotating"]) if change == "compacted" else (after > 1.05 * ext["nonrotating"])
