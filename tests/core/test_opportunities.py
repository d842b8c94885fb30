"""Landing opportunities from a TLE (issue 28): an opportunity re-flown end to end by other routes than the scan's.

The burn state comes from `sgp4` itself and the coast from an inertial propagation in WGS-72's gravity written apart
from the package (tests.core.orbit_routes), and must meet the reported entry point; the footprint flown again from
the reported entry by the footprint study's own door, and placed by the reach module's placement
(core.reach.placement_margins), gives the reported margin. Small windows: three hours, four sites."""

import copy
import json
import math
import re
from datetime import UTC, datetime, timedelta, timezone

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from pydantic import ValidationError

from footprint import contracts, parallel
from footprint.contracts.footprint import fly as fly_footprint
from footprint.contracts.messages import error_line
from footprint.core.errors import InputError
from footprint.core.reach import placement_margins
from footprint.core.sphere import Reference
from tests.core.orbit_routes import WGS72, independent_entry, sgp4_teme_km
from tests.core.test_elements import with_check_digits
from tests.core.test_guidance import distance_nmi
from tests.core.test_utc import AFTER_LEAP, tai_minus_utc_s

EXAMPLE = json.loads(open("examples/opportunities_iss_20_sites.json").read())
SITES = [
    s
    for s in EXAMPLE["sites"]
    if s["name"].split(",")[0] in ("Diego Garcia", "Woomera", "Moron Air Base", "Edwards AFB")
]


def small_study(**change):
    study = copy.deepcopy(EXAMPLE) | {"sites": SITES, "burn_step_s": 60, "ring_step_deg": 30}
    study["window"] = {"start": "2008-09-21T00:00:00Z", "hours": 3}
    return study | change


@pytest.fixture(scope="module")
def answer():
    return parallel.run("opportunities", small_study())


def _utc(text):
    return datetime.fromisoformat(text.replace("Z", "+00:00"))


def test_an_opportunity_reflown_end_to_end_meets_its_stated_entry_and_margin(answer):
    taken = [o for o in answer["opportunities"] if o["meets_rules"]]
    assert taken, answer["sites"]
    o = max(taken, key=lambda o: o["margin_nmi"] < 1_000)  # one near the boundary, where the margin means most
    # 1. the burn state from sgp4 itself, the retrograde Δv in inertial axes, the coast in WGS-72 to the interface
    burn = _utc(o["burn_utc"])
    r, v = sgp4_teme_km(EXAMPLE["tle"].splitlines()[1:], burn)
    _, lat, lon = independent_entry(r, v, o["delta_v_fps"], WGS72, burn)
    e = o["entry"]
    assert distance_nmi(lat, lon, e["latitude_deg"], e["longitude_deg"]) < 0.001  # the burn flown is the one written
    # 2. the footprint flown again from the reported entry, the site placed by the reach module
    study = contracts.parse("footprint", small_study()["footprint"] | {})
    spec_entry = study.case.entry.model_copy(update={**e, "velocity_frame": "relative"})
    again = fly_footprint(study.model_copy(update={"case": study.case.model_copy(update={"entry": spec_entry})}))
    site = SITES[[s["name"] for s in SITES].index(o["site_name"])]
    margin, inside = placement_margins(
        Reference(e["latitude_deg"], e["longitude_deg"], e["heading_deg"]),
        [p.downrange_nmi for p in again.points], [p.crossrange_nmi for p in again.points],
        [p.flight_time_s for p in again.points], site["latitude_deg"], site["longitude_deg"],
    )  # fmt: skip
    assert bool(inside[0]) and margin[0] == pytest.approx(o["margin_nmi"], abs=0.5)
    # the nearest landing of the footprint flown again is no nearer the site than the margin to its edges
    nearest = min(
        distance_nmi(p.latitude_deg, p.longitude_deg, site["latitude_deg"], site["longitude_deg"]) for p in again.points
    )
    assert nearest >= o["margin_nmi"] - 1.0
    # 3. the landing time follows from the entry and the flight time, and lies within the footprint's times
    elapsed = (_utc(o["landing_utc"]) - _utc(o["entry_utc"])).total_seconds()
    assert elapsed == pytest.approx(o["flight_time_s"], abs=0.001)  # each written to the nearest millisecond
    times = [p.flight_time_s for p in again.points]
    assert min(times) <= o["flight_time_s"] <= max(times)


MILLISECONDS = re.compile(r"\d{4}-\d\d-\d\dT\d\d:\d\d:\d\d\.\d{3}Z")


def test_every_burn_is_written_to_the_millisecond_it_is_flown_at(answer):
    """Issue 52 item 2: the burn times were cut to the whole second, 0-1 s early (up to 3.8 nmi along the orbit).
    Each burn now carries its milliseconds, and from the time written sgp4's own state, the Δv and the coast in
    WGS-72 written apart (tests.core.orbit_routes) meet the entry written within 0.001 nmi (measured 3e-5) and its
    coast within 1e-4 s; the entry's time is the burn's plus the coast to the millisecond."""
    lines = EXAMPLE["tle"].splitlines()[1:]
    assert len(answer["opportunities"]) >= 5
    for o in answer["opportunities"]:
        times = [o[k] for k in o if k.endswith("_utc") and o[k] is not None]  # (no interface: not reached)
        assert all(MILLISECONDS.fullmatch(t) for t in times), times
        burn = _utc(o["burn_utc"])
        coast_s, lat, lon = independent_entry(*sgp4_teme_km(lines, burn), o["delta_v_fps"], WGS72, burn)
        assert distance_nmi(lat, lon, o["entry"]["latitude_deg"], o["entry"]["longitude_deg"]) < 0.001
        assert o["coast_s"] == pytest.approx(coast_s, abs=1e-4)
        assert (_utc(o["entry_utc"]) - burn).total_seconds() == pytest.approx(o["coast_s"], abs=0.001)


@pytest.mark.parametrize("given", ["tle", "state"])
def test_a_landing_across_the_leap_second_is_labelled_by_the_true_utc(given):
    """The ISS's elements moved to 2016-12-30 12:00 UTC (check digits recomputed), or their SGP4 state at 22:00 as a
    state vector, a window from 22:00 to past midnight: some coasts and flights span the leap second 2016-12-31
    23:59:60. Each time written is a UTC label; TAI is that label plus 36 s before the leap and 37 s after (IERS
    Bulletin C 52, tests.core.test_utc), so the seconds from the burn to the entry and to the landing are the coast's
    and the coast's plus the flight's, to the millisecond (the labels were 1 s late across it: measured +1.03 and
    +1.02 s)."""
    tle = with_check_digits(EXAMPLE["tle"].replace("08264.51782528", "16365.50000000"))
    study = small_study(tle=tle, window={"start": "2016-12-31T22:00:00Z", "hours": 2.5})
    if given == "state":
        r, v = sgp4_teme_km(tle.splitlines()[1:], datetime(2016, 12, 31, 22, tzinfo=UTC))
        del study["tle"]
        study["state"] = {"epoch": "2016-12-31T22:00:00Z", "position_km": r.tolist(), "velocity_km_s": v.tolist()}
    opportunities = parallel.run("opportunities", study)["opportunities"]

    def tai(text):
        label = _utc(text)
        return label + timedelta(seconds=tai_minus_utc_s(label))

    across = [o for o in opportunities if _utc(o["burn_utc"]) < AFTER_LEAP <= _utc(o["landing_utc"])]
    assert across, [o["landing_utc"] for o in opportunities]
    for o in opportunities:
        burn = tai(o["burn_utc"])
        assert (tai(o["entry_utc"]) - burn).total_seconds() == pytest.approx(o["coast_s"], abs=0.001)
        since_burn = (tai(o["landing_utc"]) - burn).total_seconds()
        assert since_burn == pytest.approx(o["coast_s"] + o["flight_time_s"], abs=0.001)


def test_the_rules_rank_and_filter(answer):
    rule = answer["rules"]["sun_elevation_min_deg"]
    for o in answer["opportunities"]:
        assert o["margin_nmi"] >= 0.0
        assert o["meets_rules"] == (o["sun_elevation_deg"] >= rule)
        assert o["daylight"] == (o["sun_elevation_deg"] >= -0.833)
        assert 0.0 <= o["local_solar_time_h"] < 24.0
    for s in range(len(SITES)):
        ranked = sorted(
            (o for o in answer["opportunities"] if o["site"] == s and o["meets_rules"]), key=lambda o: o["rank"]
        )
        assert [o["rank"] for o in ranked] == list(range(1, len(ranked) + 1))
        assert all(a["margin_nmi"] >= b["margin_nmi"] for a, b in zip(ranked, ranked[1:]))
    landings = [o["landing_utc"] for o in answer["opportunities"]]
    assert landings == sorted(landings)


def test_the_ascending_nodes_are_where_the_track_crosses_the_equator_northward(answer):
    track = answer["ground_track"]
    lat = np.array(track["latitude_deg"])
    ups = np.flatnonzero((lat[:-1] < 0) & (lat[1:] >= 0))
    assert len(ups) == len(answer["ascending_nodes_utc"])
    for i, node in zip(ups, answer["ascending_nodes_utc"]):
        assert _utc(track["utc"][i]) <= _utc(node) <= _utc(track["utc"][i + 1])


def test_the_ascending_nodes_to_the_millisecond_against_sgp4(answer):
    """Each node where sgp4's own z crosses zero upward (brentq to a microsecond about the node written), within the
    half millisecond of its writing (they were cut to the second, 0.1-0.98 s early; a linear crossing on the 60 s grid
    is 4 ms off)."""
    from scipy.optimize import brentq

    lines = EXAMPLE["tle"].splitlines()[1:]
    assert answer["ascending_nodes_utc"]
    for node in answer["ascending_nodes_utc"]:
        t = _utc(node)
        root_s = brentq(lambda s: sgp4_teme_km(lines, t + timedelta(seconds=s))[0][2], -30.0, 30.0, xtol=1e-6)
        assert abs(root_s) <= 0.0005 + 1e-6


def _by_tle_and_by_state(hours, numbers=None):
    """The opportunities of a window from 2008-09-21 00:00 UTC by the TLE, and by the TLE's own TEME state at the
    window's start (sgp4) given as a state vector (with `numbers`: its satellite and revolution numbers)."""
    from sgp4.api import Satrec, jday

    sat = Satrec.twoline2rv(*EXAMPLE["tle"].splitlines()[1:])
    _, r_km, v_kms = sat.sgp4(*jday(2008, 9, 21, 0, 0, 0))
    window = {"start": "2008-09-21T00:00:00Z", "hours": hours}
    state = {"epoch": "2008-09-21T00:00:00Z", "frame": "teme", "position_km": list(r_km), "velocity_km_s": list(v_kms)}
    state |= numbers or {}
    by_tle = parallel.run("opportunities", small_study(window=window))
    by_state = parallel.run(
        "opportunities", {k: v for k, v in small_study(window=window, state=state).items() if k != "tle"}
    )
    return by_tle, by_state


def _assert_the_same_opportunities(by_tle, by_state):
    """The same sites and revolutions, burns within 5 s (the peak of a flat margin curve) and margins within 0.2 nmi
    (measured 0.035 s and 0.01 nmi over two hours: SGP4's theory and drag in WGS-72 against our propagation in WGS-84;
    1.4 nmi in the report's gravity, when the burns were compared to a minute and the margins to 20 nmi)."""
    key = lambda o: (o["site"], o["revolution"])  # noqa: E731
    a, b = {key(o): o for o in by_tle["opportunities"]}, {key(o): o for o in by_state["opportunities"]}
    assert a.keys() == b.keys() and a
    for k in a:
        assert abs((_utc(a[k]["burn_utc"]) - _utc(b[k]["burn_utc"])).total_seconds()) <= 5.0
        assert b[k]["margin_nmi"] == pytest.approx(a[k]["margin_nmi"], abs=0.2)


def test_a_state_vector_gives_the_opportunities_its_tle_gives():
    """The TLE's own TEME state at the window's start (sgp4), given as a state vector and propagated by our integrator
    (no drag, WGS-84's gravity), finds the same opportunities over two hours."""
    by_tle, by_state = _by_tle_and_by_state(2)
    assert by_state["elements"]["inclination_deg"] == pytest.approx(51.64, abs=0.05)
    _assert_the_same_opportunities(by_tle, by_state)


def test_a_state_vector_plans_a_window_shorter_than_an_orbit():
    """Issue 49 item 4: a state vector and a half-hour window (the orbit takes 92 min) failed in the worker, "outside
    the propagated span of the state" (accepted, 202, over HTTP). Now the opportunities of the TLE's in that window,
    each burn inside it, and its ascending node where the TLE's is."""
    by_tle, by_state = _by_tle_and_by_state(0.5)
    _assert_the_same_opportunities(by_tle, by_state)
    start, end = _utc("2008-09-21T00:00:00Z"), _utc("2008-09-21T00:30:00Z")
    assert all(start <= _utc(o["burn_utc"]) <= end for o in by_state["opportunities"])
    nodes = [_utc(t) for t in by_state["ascending_nodes_utc"]]
    assert len(nodes) == len(by_tle["ascending_nodes_utc"])
    for ours, theirs in zip(nodes, by_tle["ascending_nodes_utc"]):
        assert abs((ours - _utc(theirs)).total_seconds()) <= 0.1  # measured 0.004 s (SGP4's theory and drag, ours)


def test_a_state_vector_round_trips_and_keeps_its_jacobi_constant():
    """A TEME state at its epoch comes back as given (TEME in, TEME out), and the same state given earth-fixed does
    too; between the integrator's steps the interpolated states keep the Jacobi constant of the rotating frame
    (v^2/2 - omega^2 (x^2 + y^2)/2 - mu/r, a point-mass earth) to 1e-9 of its size."""
    from footprint.core import deorbit as dorb
    from footprint.core.aero import builtin_vehicle
    from footprint.core.constants import Earth
    from footprint.core.trajectory import Planet

    epoch = _utc("2008-09-21T00:00:00Z")
    r_km, v_kms = np.array([6778.0, 0.0, 0.0]), np.array([0.0, 4.766, 6.010])  # 400 km, 51.6 deg, circular
    mu_km3_s2, omega_rad_s = 398_600.4418, 7.292115e-5  # WGS-84's (NIMA TR8350.2 table 3.1), as a point mass
    point_mass = Earth("a point mass", mu_km3_s2, 6_378.137, 0.0, 0.0, 0.0, omega_rad_s)
    coast = dorb.Coast.of(builtin_vehicle("lod-1.89"), Planet(oblate=False), earth=point_mass)
    r, v = dorb.state_earth_fixed(epoch, "teme", r_km, v_kms, coast.omega_rad_s)
    for frame, position, velocity in (("teme", r_km, v_kms), ("earth_fixed", r / dorb.FT_PER_KM, v / dorb.FT_PER_KM)):
        r0, v0 = dorb.state_earth_fixed(epoch, frame, position, velocity, coast.omega_rad_s)
        orbit = dorb.PropagatedState(epoch, r0, v0, coast, 6_000.0)
        back_r, back_v = orbit.teme_km([epoch])
        assert np.allclose(back_r[0], r_km, rtol=0, atol=1e-9) and np.allclose(back_v[0], v_kms, rtol=0, atol=1e-12)
    times = [epoch + timedelta(seconds=s) for s in np.arange(0.0, 6_000.0, 37.3)]  # mostly between steps
    rr, vv = orbit.earth_fixed(times)
    w, mu = omega_rad_s, mu_km3_s2 * (1000.0 / 0.3048) ** 3
    jacobi = (
        0.5 * np.sum(vv**2, axis=1) - 0.5 * w**2 * (rr[:, 0] ** 2 + rr[:, 1] ** 2) - mu / np.linalg.norm(rr, axis=1)
    )
    assert np.ptp(jacobi) <= 1e-9 * abs(jacobi[0])


def test_the_python_door_gives_the_runners_answer(answer):
    from footprint import api

    again = api.opportunities(small_study())
    assert [o["burn_utc"] for o in again["opportunities"]] == [o["burn_utc"] for o in answer["opportunities"]]


def test_one_opportunity_a_pass_even_across_the_node(answer):
    """A run of burns that reaches a site across an ascending node is one pass, one opportunity (Diego Garcia had two,
    8 minutes apart, one in each revolution)."""
    for s in range(len(SITES)):
        burns = sorted(_utc(o["burn_utc"]) for o in answer["opportunities"] if o["site"] == s)
        assert all((b - a).total_seconds() > 60 * 60 for a, b in zip(burns, burns[1:])), (SITES[s]["name"], burns)


def test_the_drawn_footprint_lies_about_the_opportunitys_entry(answer):
    """Each point of an opportunity's footprint is placed at its down-range and cross-range about that entry (cos of
    the arc from the entry = cos(d / R) cos(c / R), by haversine here); the vertex nearest the site, flown again,
    lands where the whole footprint flown again puts it, the others within what the scan's table of footprints (one
    per 30 deg of the orbit here) allows (they were left at the scan's places, up to 1,494 nmi off)."""
    from footprint.core.sphere import MEAN_RADIUS_NMI as R

    full = {
        (o["site"], o["burn_utc"]): o for o in parallel.run("opportunities", small_study(refly="full"))["opportunities"]
    }
    for o in answer["opportunities"]:
        ring, e = o["footprint_ring"], o["entry"]
        for d, cr, lat, lon in zip(
            ring["downrange_nmi"], ring["crossrange_nmi"], ring["latitude_deg"], ring["longitude_deg"]
        ):
            arc = math.acos(math.cos(d / R) * math.cos(cr / R)) * R
            assert distance_nmi(e["latitude_deg"], e["longitude_deg"], lat, lon) == pytest.approx(arc, abs=0.01)
        other = full[(o["site"], o["burn_utc"])]["footprint_ring"]
        site = SITES[o["site"]]
        gaps = sorted(
            (distance_nmi(site["latitude_deg"], site["longitude_deg"], a, b), distance_nmi(a, b, x, y))
            for a, b, x, y in zip(
                ring["latitude_deg"], ring["longitude_deg"], other["latitude_deg"], other["longitude_deg"]
            )
        )
        assert gaps[0][1] <= 1.0, (o["site_name"], gaps[:4])  # the vertex nearest the site is one flown again
        # the rest: the scan's, from the ring up to 15 deg of orbit away: measured <= 171 nmi but one far vertex of
        # Moron's 02:49 footprint, 1,444 nmi (14.3 deg from its ring; 250 nmi held with the burns at the peaks)
        assert all(gap <= 1_500.0 for _, gap in gaps)


OFFSETS = st.integers(-1439, 1439).map(lambda m: timezone(timedelta(minutes=m)))  # as ISO 8601 writes them
ANY_TIME = st.datetimes(timezones=OFFSETS)  # year 1 to 9999, any offset a time zone can have
NEAR_TIME = st.datetimes(datetime(2008, 9, 10), datetime(2008, 10, 10), timezones=OFFSETS)  # about the TLE's epoch
EDGE_TIME = st.datetimes(datetime(9999, 12, 30), timezones=OFFSETS) | st.datetimes(
    max_value=datetime(1, 1, 2), timezones=OFFSETS
)  # where a time zone's offset or an hour more leaves datetime's years
TIMES = ANY_TIME | NEAR_TIME | EDGE_TIME


@settings(max_examples=100, deadline=None)
@given(start=TIMES, end=st.none() | TIMES, epoch=st.none() | TIMES)
def test_any_aware_time_is_a_study_or_one_line_naming_its_field(start, end, epoch):
    """Issue 49 item 2: a window's start or end, or a state's epoch, at any aware time is read or refused in one line
    naming the field; never another exception (an OverflowError near year 9999 or 1 before)."""
    window = {"start": start.isoformat()} | ({"end": end.isoformat()} if end else {"hours": 1})
    study = small_study(window=window)
    if epoch is not None:
        study = {k: v for k, v in study.items() if k != "tle"} | {"state": STATE | {"epoch": epoch.isoformat()}}
    try:
        contracts.parse("opportunities", study)
    except (ValidationError, InputError) as exc:
        line = error_line(exc)
        assert "\n" not in line and line.split(":")[0] in FIELDS, line


STATE = {"epoch": "2008-09-21T00:00:00Z", "position_km": [6778.0, 0.0, 0.0], "velocity_km_s": [0.0, 4.766, 6.01]}
FIELDS = ("window", "window.start", "window.end", "window.hours", "state", "state.epoch", "deorbit", "tle")


def test_each_opportunity_is_flown_guided_and_names_its_interface_and_touchdown(answer):
    """Issue 52 items 3 and 5: every opportunity is flown guided from its own entry to its site; one that reaches the
    terminal-area interface names it (its UTC from the entry and the guided flight's time) and the touchdown estimated
    after it (the guidance's stated allowance), and the daylight rule is taken at that touchdown, not at the arrival
    over the site at 50,000 ft (landing_utc). The interface's distance to the site is a haversine here."""
    from footprint.core import sun

    reached_within_limits = 0
    for o in answer["opportunities"]:
        g = o["guided"]
        gd, site = g["guidance"], answer["sites"][o["site"]]
        if not gd["reached"]:
            assert o["interface_utc"] is None and o["touchdown_utc"] is None and o["sun_at"] == "arrival"
            continue
        to_site = distance_nmi(g["final_latitude_deg"], g["final_longitude_deg"], site["latitude_deg"],
                               site["longitude_deg"])  # fmt: skip
        assert abs(to_site - gd["interface_range_nmi"]) <= 5.0  # on the interface circle, 50 nmi out
        entry, interface, touchdown = (_utc(o[k]) for k in ("entry_utc", "interface_utc", "touchdown_utc"))
        assert (interface - entry).total_seconds() == pytest.approx(g["flight_time_s"], abs=0.001)
        allowance_s = gd["touchdown_estimate"]["terminal_area_s"]
        assert (touchdown - interface).total_seconds() == pytest.approx(allowance_s, abs=0.001)
        assert o["sun_at"] == "touchdown"
        at_touchdown = sun.elevation_deg([touchdown], *_site(site))[0]  # the time as written, to the millisecond
        assert o["sun_elevation_deg"] == pytest.approx(at_touchdown, abs=1e-4)  # the sun moves 4e-6 deg in 1 ms
        reached_within_limits += g["limits_held"]
    assert reached_within_limits >= 1  # a guided opportunity that holds every limit of the vehicle


def _site(site):
    return site["latitude_deg"], site["longitude_deg"]
