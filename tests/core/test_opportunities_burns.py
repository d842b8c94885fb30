"""Robust burns (issue 52 item 4): the burn window leads and the burn is its middle, a window cut by the search's edge
is flagged, revolutions are the elements' (NORAD's count from the TLE's epoch), the burn's altitude and place, the
margins along each axis, and calendar UIDs that a re-plan keeps.

A second plan of the same orbit (the window started 30 min earlier, a 20 s grid and 10 deg rings for 60 s and 30 deg,
the sites in reverse order) is the second formulation: before, the burn was the peak of a flat margin curve and moved
up to 315 s between the two while the margins moved <= 13 nmi; each pass's UID held the burn's second and the site's
place in the list. Revolutions and the burn's place are checked against `sgp4` and skyfield themselves."""

import math
from datetime import timedelta

import numpy as np
import pytest

from footprint import parallel
from footprint.contracts.opportunities import event_uid
from footprint.core.opportunities import Ring, axis_margins
from tests.core.orbit_routes import WGS72, geodetic_ft, gmst_rad, independent_entry, interface_state, sgp4_teme_km
from tests.core.test_guidance import distance_nmi
from tests.core.test_opportunities import EXAMPLE, SITES, _by_tle_and_by_state, _utc, small_study

TLE = EXAMPLE["tle"].splitlines()[1:]
SEARCH_START, SEARCH_END = _utc("2008-09-21T00:00:00Z"), _utc("2008-09-21T03:00:00Z")


@pytest.fixture(scope="module")
def plans():
    coarse = parallel.run("opportunities", small_study())
    fine = small_study(sites=SITES[::-1], burn_step_s=20, ring_step_deg=10)
    fine["window"] = {"start": "2008-09-20T23:30:00Z", "end": "2008-09-21T03:00:00Z"}
    return coarse, parallel.run("opportunities", fine)


def _key(o):
    return o["site_name"], o["revolution_number"]


def test_the_burn_is_its_windows_middle_and_a_second_plan_finds_it_within_a_grid_step(plans):
    """Each burn is the middle of its burn window (to the millisecond it is written with); the same pass planned again
    on a finer grid, finer rings and an earlier start has its burn within 60 s (the coarse grid's step: the window's
    ends are zero crossings interpolated on it; measured <= 30 s on the scan) and its margin within 20 nmi."""
    coarse, fine = plans
    for o in coarse["opportunities"] + fine["opportunities"]:
        middle = (
            _utc(o["burn_window_start_utc"]) + (_utc(o["burn_window_end_utc"]) - _utc(o["burn_window_start_utc"])) / 2
        )
        assert abs((_utc(o["burn_utc"]) - middle).total_seconds()) <= 0.0015
    by_key = {_key(o): o for o in fine["opportunities"]}
    whole = [o for o in coarse["opportunities"] if not o["burn_window_clipped"]]
    assert len(whole) >= 6
    for o in whole:
        again = by_key[_key(o)]
        assert abs((_utc(o["burn_utc"]) - _utc(again["burn_utc"])).total_seconds()) <= 60.0, o["site_name"]
        assert again["margin_nmi"] == pytest.approx(o["margin_nmi"], abs=20.0)


def test_a_window_cut_by_the_searchs_edge_is_flagged_and_is_cut(plans):
    """A window is flagged exactly when it reaches the search's first or last burn; the earlier search finds each pass
    that the first cut at its start with a window reaching past that cut (the site really held before; 9 and 21 min
    before for Moron and Diego Garcia)."""
    coarse, fine = plans
    for o in coarse["opportunities"]:
        at_edge = _utc(o["burn_window_start_utc"]) == SEARCH_START or _utc(o["burn_window_end_utc"]) == SEARCH_END
        assert o["burn_window_clipped"] == at_edge, o
    cut = [o for o in coarse["opportunities"] if _utc(o["burn_window_start_utc"]) == SEARCH_START]
    assert cut
    for o in cut:  # the same pass: the same site, its window about the same end
        end = _utc(o["burn_window_end_utc"])
        (again,) = [
            f
            for f in fine["opportunities"]
            if f["site_name"] == o["site_name"] and abs((_utc(f["burn_window_end_utc"]) - end).total_seconds()) < 60
        ]
        assert _utc(again["burn_window_start_utc"]) < SEARCH_START - timedelta(seconds=60)


def _nodes_since_epoch(utc):
    """sgp4's ascending nodes (z upward through 0) from the TLE's epoch to utc, on a 20 s grid."""
    from sgp4.api import Satrec

    sat = Satrec.twoline2rv(*TLE)
    epoch = _utc("2008-01-01T00:00:00Z") + timedelta(days=float(TLE[0][20:32]) - 1.0)
    span = (utc - epoch).total_seconds()
    z = [sgp4_teme_km(TLE, epoch + timedelta(seconds=s))[0][2] for s in np.arange(0.0, span, 20.0)]
    assert sat.revnum == int(TLE[1][63:68])
    return sum(a < 0.0 <= b for a, b in zip(z, z[1:]))


@pytest.mark.parametrize("hours", [-30.0, -0.5, 0.0, 7.25])
def test_the_revolution_number_before_and_after_the_epoch_is_sgp4s_count(hours):
    """The elements' revolution at a time before or after their epoch: the number at epoch plus (minus) sgp4's
    ascending nodes between, counted on a 20 s grid from either end."""
    from sgp4.api import Satrec

    from footprint.core.elements import parse_tle
    from footprint.core.opportunities import revolution_number_at

    elements = parse_tle(EXAMPLE["tle"])
    sat = Satrec.twoline2rv(*TLE)
    t = elements.epoch + timedelta(hours=hours)
    a, b = sorted((elements.epoch, t))
    z = [sgp4_teme_km(TLE, a + timedelta(seconds=s))[0][2] for s in np.arange(0.0, (b - a).total_seconds() + 1, 20.0)]
    nodes = sum(p < 0.0 <= q for p, q in zip(z, z[1:]))
    assert revolution_number_at(elements, t) == sat.revnum + (nodes if hours >= 0 else -nodes)


def test_the_revolution_is_the_elements_count_from_their_epoch(plans):
    """The TLE's revolution number at epoch (line 2 columns 64-68) plus sgp4's ascending nodes since, at each burn."""
    coarse, _ = plans
    assert coarse["elements"]["revolution_number"] == int(TLE[1][63:68])
    for o in coarse["opportunities"][:4]:
        assert o["revolution_number"] == int(TLE[1][63:68]) + _nodes_since_epoch(_utc(o["burn_utc"]))


def test_the_burns_altitude_and_place_are_sgp4s(plans):
    """The burn's geodetic place and altitude on the report's ellipsoid from sgp4's TEME state turned by skyfield's
    GMST (orbit_routes: both written apart from the package)."""
    for o in plans[0]["opportunities"][:4]:
        burn = _utc(o["burn_utc"])
        r, _ = sgp4_teme_km(TLE, burn)
        theta = gmst_rad(burn)
        x = (math.cos(theta) * r[0] + math.sin(theta) * r[1]) * 1000.0 / 0.3048
        y = (-math.sin(theta) * r[0] + math.cos(theta) * r[1]) * 1000.0 / 0.3048
        lat, alt = geodetic_ft(x, y, r[2] * 1000.0 / 0.3048)
        assert o["burn_latitude_deg"] == pytest.approx(lat, abs=1e-4)
        assert o["burn_longitude_deg"] == pytest.approx(math.degrees(math.atan2(y, x)), abs=1e-4)
        assert o["burn_altitude_ft"] == pytest.approx(alt, abs=10.0)


def test_the_calendar_uid_survives_a_replan(plans):
    """The same pass planned again (earlier start, finer settings, the sites reversed) keeps its UID; passes differ."""
    coarse, fine = plans
    sat = coarse["elements"]["satellite_number"]
    uids = {_key(o): event_uid(sat, o) for o in fine["opportunities"]}
    assert len(set(uids.values())) == len(uids)
    for o in coarse["opportunities"]:
        if not o["burn_window_clipped"]:
            assert event_uid(sat, o) == uids[_key(o)]


def test_the_axis_margins_of_an_ellipse_are_its_closed_form():
    """Along each axis, the distance to an ellipse's boundary: a sqrt(1 - (y/b)^2) - |x| (and its transpose),
    negative outside; None where the line misses it."""
    a, b = 2_000.0, 600.0
    u = np.linspace(0.0, 2.0 * math.pi, 3_600, endpoint=False)
    ring = Ring(a * np.cos(u) + 3_000.0, b * np.sin(u), np.zeros_like(u))
    for x, y in ((500.0, 100.0), (-1_500.0, -400.0), (1_900.0, 300.0), (2_100.0, 0.0)):
        down, cross = axis_margins(ring, 3_000.0 + x, y)
        assert down == pytest.approx(a * math.sqrt(1 - (y / b) ** 2) - abs(x), abs=0.5)
        assert cross == pytest.approx(b * math.sqrt(max(0.0, 1 - (x / a) ** 2)) - abs(y), abs=0.5) or abs(x) > a
    assert axis_margins(ring, 3_000.0, 700.0)[0] is None


def test_a_near_miss_is_listed_with_the_delta_v_that_would_make_it():
    """A pass screened and flown again outside its footprint is listed apart (not an opportunity: no rank, no calendar
    event) with the Δv change that moves the footprint down-range onto the site; flown by the independent route
    (sgp4's state, a WGS-72 coast by scipy), that change moves the entry point by the down-range shortfall within 2%
    (measured 0.01%: Moron, -9.3 ft/s for 146.7 nmi). Before, such passes were dropped."""
    got = parallel.run("opportunities", small_study(deorbit={"delta_v_fps": 350.0}))
    fixable = [o for o in got["near_misses"] if "delta_v_change_fps" in o]
    assert fixable and all(o["margin_nmi"] < 0.0 and "rank" not in o for o in got["near_misses"])
    assert sum(s["near_misses"] for s in got["sites"]) == len(got["near_misses"])
    for o in fixable:
        burn = _utc(o["burn_utc"])
        r, v = sgp4_teme_km(TLE, burn)
        _, lat0, lon0 = independent_entry(r, v, 350.0, WGS72, burn)
        _, lat1, lon1 = independent_entry(r, v, 350.0 + o["delta_v_change_fps"], WGS72, burn)
        assert distance_nmi(lat0, lon0, lat1, lon1) == pytest.approx(-o["downrange_margin_nmi"], rel=0.02)


def test_the_tles_own_state_vector_keeps_the_revolutions_and_uids_given_its_numbers():
    """The TLE's TEME state at the window's start (sgp4) given as a state vector with the satellite's number and its
    revolution there (the TLE's at epoch plus sgp4's nodes since): the same revolutions, burns within 5 s and the
    same calendar UIDs as the TLE's own plan (the UID said "state" in place of the satellite before)."""
    numbers = {"satellite_number": 25544, "revolution_number": int(TLE[1][63:68]) + _nodes_since_epoch(SEARCH_START)}
    by_tle, by_state = _by_tle_and_by_state(2, numbers)
    assert by_state["elements"]["revolution_number"] == numbers["revolution_number"]
    a = {_key(o): o for o in by_tle["opportunities"]}
    b = {_key(o): o for o in by_state["opportunities"]}
    assert a.keys() == b.keys() and a
    for k in a:
        assert abs((_utc(a[k]["burn_utc"]) - _utc(b[k]["burn_utc"])).total_seconds()) <= 5.0
        assert event_uid(25544, a[k]) == event_uid(by_state["elements"]["satellite_number"], b[k])


OMEGA_RAD_S = 7.2921151467e-5  # the earth's rotation (WGS-72 and WGS-84 alike: NIMA TR8350.2 table 3.1)


def _relative_gamma_deg(r_km, v_km_s, delta_v_fps):
    """The earth-relative flight-path angle at the interface of the independent coast (geocentric vertical: the
    tests take its differences only, which a geodetic vertical shifts alike)."""
    _, r, v = interface_state(r_km, v_km_s, delta_v_fps, WGS72)
    v = v - np.cross([0.0, 0.0, OMEGA_RAD_S], r)
    return math.degrees(math.asin(float(r @ v) / (np.linalg.norm(r) * np.linalg.norm(v))))


def test_a_near_miss_for_a_target_entry_angle_is_given_the_angle_that_would_make_it():
    """For a target entry angle, the change of that angle: flown by the independent route (the Δv that gives the
    angle changed so, found by brentq on the independent coast), it moves the entry point by the down-range
    shortfall within 2% (Banjul and Christchurch on the example's first three hours: -0.74 deg for 1,087 nmi moves it
    1,084; a first difference alone, -0.64 deg, moved it 953)."""
    from scipy.optimize import brentq

    names = ("Banjul", "Christchurch")
    sites = [s for s in EXAMPLE["sites"] if s["name"].startswith(names)]
    got = parallel.run("opportunities", small_study(sites=sites))
    fixable = [o for o in got["near_misses"] if "entry_gamma_change_deg" in o]
    assert fixable
    for o in fixable:
        burn = _utc(o["burn_utc"])
        r, v = sgp4_teme_km(TLE, burn)
        dv0 = o["delta_v_fps"]
        target = _relative_gamma_deg(r, v, dv0) + o["entry_gamma_change_deg"]
        dv1 = brentq(lambda dv: _relative_gamma_deg(r, v, dv) - target, 0.75 * dv0, 2.0 * dv0, xtol=1e-3)
        _, lat0, lon0 = independent_entry(r, v, dv0, WGS72, burn)
        _, lat1, lon1 = independent_entry(r, v, dv1, WGS72, burn)
        assert distance_nmi(lat0, lon0, lat1, lon1) == pytest.approx(-o["downrange_margin_nmi"], rel=0.02)
