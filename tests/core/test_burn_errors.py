"""An executed deorbit burn (issue 52 item 5): its magnitude, pointing and time dispersed, each coasted to the
interface. Checked against the independent route of tests/core/orbit_routes.py: sgp4's own state at the executed
burn's time, the thrust direction built here by Gram-Schmidt in TEME (not the package's cross products), the coast by
scipy's DOP853 in WGS-72 typed from its source, the interface on the report's ellipsoid by the route's own altitude."""

import math
from datetime import timedelta

import numpy as np
import pytest

from footprint import contracts
from footprint.core import deorbit as dorb
from footprint.core.burn_errors import BurnErrors, executed_entries, normals
from tests.core.orbit_routes import FT_PER_KM, WGS72, coast_to_interface, geodetic_ft, gmst_rad, sgp4_teme_km
from tests.core.test_guidance import distance_nmi
from tests.core.test_opportunities import EXAMPLE, small_study

DELTA_V_FPS = 400.0
ERRORS = BurnErrors(delta_v_fps=3.0, pitch_deg=2.0, yaw_deg=2.0, time_s=1.5)


@pytest.fixture(scope="module")
def study():
    return contracts.parse("opportunities", small_study(window={"start": "2008-09-21T00:00:00Z", "hours": 1}))


def _independent(start, z):
    """The executed burn written apart: (coast s from the planned burn, latitude, longitude deg)."""
    dt = ERRORS.time_s * z[3]
    utc = start + timedelta(seconds=dt)  # no leap second near 2008-09-21
    r_km, v_km_s = sgp4_teme_km(EXAMPLE["tle"].splitlines()[1:], utc)
    r, v = np.array(r_km) * FT_PER_KM, np.array(v_km_s) * FT_PER_KM  # TEME: v is the inertial velocity
    along = v / np.linalg.norm(v)
    up = r - np.dot(r, along) * along  # the local vertical's part normal to the velocity
    up /= np.linalg.norm(up)
    across = np.cross(r, v)
    across /= np.linalg.norm(across)
    pitch, yaw = math.radians(ERRORS.pitch_deg * z[1]), math.radians(ERRORS.yaw_deg * z[2])
    thrust = -math.cos(pitch) * math.cos(yaw) * along + math.sin(pitch) * up + math.cos(pitch) * math.sin(yaw) * across
    t, (x, y, zz), _ = coast_to_interface(r, v + (DELTA_V_FPS + ERRORS.delta_v_fps * z[0]) * thrust, WGS72)
    theta = gmst_rad(utc, t)
    xe, ye = math.cos(theta) * x + math.sin(theta) * y, -math.sin(theta) * x + math.cos(theta) * y
    return t + dt, geodetic_ft(xe, ye, zz)[0], math.degrees(math.atan2(ye, xe))


Z = np.array([[0, 0, 0, 0], [1, 0, 0, 0], [-1, 0, 0, 0], [0, 1, 0, 0], [0, -1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1],
              [0, 0, 0, -1], [0.7, -1.2, 0.4, 0.9]], float)  # fmt: skip


def test_each_executed_burn_enters_where_the_independent_route_says(study):
    start = study.window.bounds[0]
    rows = executed_entries(study.coast, study.orbit, start, DELTA_V_FPS, ERRORS, Z)
    for z, row in zip(Z, rows):
        coast_s, lat, lon = _independent(start, z)
        assert distance_nmi(lat, lon, row[dorb.E_LAT], row[dorb.E_LON]) < 0.005, z
        assert abs(row[dorb.E_COAST_S] - coast_s) < 0.01, z


def test_the_errors_move_the_entry_as_a_burn_does(study):
    """Signs a flight engineer knows: a larger Δv enters steeper and sooner; a late burn enters later by about the
    delay; yaw turns the entry's heading and hardly its coast."""
    start = study.window.bounds[0]
    nominal, more, _, _, _, yawed, late, _, _ = executed_entries(
        study.coast, study.orbit, start, DELTA_V_FPS, ERRORS, Z
    )
    assert more[dorb.E_GAMMA] < nominal[dorb.E_GAMMA] and more[dorb.E_COAST_S] < nominal[dorb.E_COAST_S]
    assert late[dorb.E_COAST_S] - nominal[dorb.E_COAST_S] == pytest.approx(ERRORS.time_s, abs=0.2)
    assert abs(yawed[dorb.E_HEADING] - nominal[dorb.E_HEADING]) > 0.01
    # out of plane the retrograde part loses only 1 - cos(yaw) of the Δv (0.24 of 3 ft/s): the coast barely changes
    yaw_s, dv_s = (abs(row[dorb.E_COAST_S] - nominal[dorb.E_COAST_S]) for row in (yawed, more))
    assert yaw_s < 0.25 * dv_s


def test_the_errors_draw_their_own_stream():
    """Normal, independent, repeatable; apart from the study's other draws of the same seed."""
    z = normals(4_000, 7)
    assert np.allclose(z, normals(4_000, 7))
    assert np.all(np.abs(z.mean(axis=0)) < 0.06) and np.all(np.abs(z.std(axis=0) - 1.0) < 0.04)
    assert np.all(np.abs(np.corrcoef(z.T) - np.eye(4)) < 0.06)
    assert not np.allclose(z[:, 0], np.random.default_rng(7).standard_normal(4_000))


def test_a_negative_error_is_refused():
    assert "time_s" in BurnErrors(time_s=-1.0).problem()
    assert BurnErrors().problem() is None
