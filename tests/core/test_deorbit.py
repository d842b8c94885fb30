"""The deorbit burn and vacuum coast to the entry interface (core/deorbit.py) against independent routes: on a
spherical, non-rotating, J-free earth the two-body closed forms (energy and angular momentum for the entry speed and
flight-path angle, Kepler's equation for the coast time, the perigee of the message, the Δv for a target angle) and
energy conservation; on the rotating earth with J2 (J2 = J / 1.5, the report's J of eq. A10) and in WGS-84's
gravity (an orbit's earth: its point mass and J2-J4) a scipy DOP853 propagation in inertial axes with the acceleration
written out (tests.core.orbit_routes). The constants are typed from the report, not imported from the package."""

import math
import re

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

from footprint.core import deorbit as d
from footprint.core.aero import builtin_vehicle
from footprint.core.constants import WGS84 as WGS84_RECORD
from footprint.core.errors import InputError
from footprint.core.trajectory import Planet
from tests.authorities.report import REPORT
from tests.core.orbit_routes import WGS84, zonal_acceleration

FT_PER_M, FT_PER_NMI = 1.0 / 0.3048, 1852.0 / 0.3048  # the international foot
MU, RE = 1.407698e16, 20_925_631.0  # ft^3/s^2, ft: AFWAL-TR-82-3036 App. A, the planet's defaults
J_REPORT = 1623.41e-6  # App. A's J = 1.5 J2
OMEGA_REPORT_RAD_S = math.radians(REPORT["sec4.omega_deg_s"].value)  # Section IV.3's omega_p
OMEGA_WGS84_RAD_S = 7.292115e-5  # NIMA TR8350.2 table 3.1
R1 = RE + 420_000.0 * FT_PER_M  # an ISS-like circular orbit, 420 km up
R_ENTRY = RE + d.INTERFACE_ALTITUDE_FT
V_CIRCULAR = math.sqrt(MU / R1)
INCLINATION = math.radians(51.6)
R_BURN = np.array([[R1, 0.0, 0.0]])
V_INERTIAL = V_CIRCULAR * np.array([[0.0, math.cos(INCLINATION), math.sin(INCLINATION)]])
VEHICLE = builtin_vehicle("lod-1.89")
SPHERE = d.Coast.of(VEHICLE, Planet(rotating=False, oblate=False, j=0.0, h=0.0, k=0.0))
J2_PLANET = Planet(rotating=True, oblate=True, h=0.0, k=0.0)  # the report's J = 1.5 J2 (gravity.py, A10)


def two_body_entry(v1: float) -> tuple[float, float]:
    """Speed (ft/s) and flight-path angle (deg) at R_ENTRY of the orbit leaving R1 horizontally at v1."""
    v_entry = math.sqrt(v1**2 + 2.0 * MU * (1.0 / R_ENTRY - 1.0 / R1))
    return v_entry, -math.degrees(math.acos(R1 * v1 / (R_ENTRY * v_entry)))


def kepler_time_from_apoapsis_s(v1: float) -> float:
    """Time from apoapsis R1 (speed v1) down to R_ENTRY: Kepler's equation on the descending half."""
    a = 1.0 / (2.0 / R1 - v1**2 / MU)
    e = R1 / a - 1.0
    ecc_anomaly = 2.0 * math.pi - math.acos((1.0 - R_ENTRY / a) / e)
    return (ecc_anomaly - e * math.sin(ecc_anomaly) - math.pi) / math.sqrt(MU / a**3)


@pytest.mark.parametrize("delta_v", [300.0, 450.0, 600.0, 900.0])
def test_entry_against_the_two_body_closed_form_on_a_spherical_earth(delta_v):
    row = d.entry_states(SPHERE, R_BURN, d.burn(R_BURN, V_INERTIAL, delta_v, 0.0))[0]
    v1 = V_CIRCULAR - delta_v
    v_entry, gamma = two_body_entry(v1)
    assert row[d.E_GAMMA] == pytest.approx(gamma, abs=0.01)  # deg; measured 1e-8
    assert row[d.E_V] == pytest.approx(v_entry, abs=0.5)  # ft/s; measured 2e-6
    assert row[d.E_ALT] == pytest.approx(d.INTERFACE_ALTITUDE_FT, abs=1.0)  # ft
    assert row[d.E_COAST_S] == pytest.approx(kepler_time_from_apoapsis_s(v1), abs=1.0)  # s; measured 7e-6


@pytest.mark.parametrize("delta_v", [300.0, 900.0])
def test_the_coast_conserves_energy_on_a_spherical_earth(delta_v):
    v_after = d.burn(R_BURN, V_INERTIAL, delta_v, 0.0)
    row = d.entry_states(SPHERE, R_BURN, v_after)[0]
    energy_burn = 0.5 * float(v_after[0] @ v_after[0]) - MU / R1
    energy_entry = 0.5 * row[d.E_V] ** 2 - MU / float(np.linalg.norm(row[d.E_X : d.E_Z + 1]))
    assert energy_entry == pytest.approx(energy_burn, rel=1e-6)  # measured 2e-10


REPORT_J2 = {"mu_km3_s2": MU / (1000.0 * FT_PER_M) ** 3, "radius_km": RE / (1000.0 * FT_PER_M), "j2": J_REPORT / 1.5}


@pytest.mark.parametrize(
    ("coast", "earth", "omega_rad_s"),
    [(d.Coast.of(VEHICLE, J2_PLANET), REPORT_J2, OMEGA_REPORT_RAD_S),
     (d.Coast.of(VEHICLE, Planet(), earth=WGS84_RECORD), WGS84, OMEGA_WGS84_RAD_S)],
    ids=["the report's planet, J2", "an orbit's earth, WGS-84"],
)  # fmt: skip
def test_the_coast_on_the_rotating_oblate_earth_against_an_inertial_propagation(coast, earth, omega_rad_s):
    omega = np.array([0.0, 0.0, omega_rad_s])
    v_relative = V_INERTIAL - np.cross(omega, R_BURN)  # earth-fixed = inertial axes at the burn
    v_after = d.burn(R_BURN, v_relative, 450.0, coast.omega_rad_s)
    row = d.entry_states(coast, R_BURN, v_after)[0]
    t = row[d.E_COAST_S]
    start = np.concatenate([R_BURN[0], v_after[0] + np.cross(omega, R_BURN[0])])

    def earth_fixed_miss_ft(constants: dict) -> float:
        sol = solve_ivp(zonal_acceleration(**constants), (0.0, t), start, method="DOP853", rtol=1e-12, atol=1e-6)
        x, y, z = sol.y[:3, -1]
        c, s = math.cos(omega_rad_s * t), math.sin(omega_rad_s * t)  # rotate by -omega t about z
        return float(np.linalg.norm(np.array([c * x + s * y, -s * x + c * y, z]) - row[d.E_X : d.E_Z + 1]))

    assert earth_fixed_miss_ft(earth) < 0.5 * FT_PER_NMI  # measured 0.01 ft
    assert earth_fixed_miss_ft(earth | {"j2": 0.0, "j3": 0.0, "j4": 0.0}) > 3.0 * FT_PER_NMI  # it sees J2: 45,700 ft


@pytest.mark.parametrize("coast", [SPHERE, d.Coast.of(VEHICLE, J2_PLANET)], ids=["sphere", "rotating J2"])
def test_a_burn_too_small_to_come_down_names_the_perigee(coast):
    v_relative = V_INERTIAL - np.cross([0.0, 0.0, coast.omega_rad_s], R_BURN)
    with pytest.raises(InputError) as caught:
        d.entry_states(coast, R_BURN, d.burn(R_BURN, v_relative, 50.0, coast.omega_rad_s))
    assert caught.value.field == "deorbit" and "perigee" in caught.value.message
    v1 = V_CIRCULAR - 50.0  # two-body perigee: r_p = 2 a - r_apoapsis
    perigee = 2.0 / (2.0 / R1 - v1**2 / MU) - R1 - RE
    shown = float(re.search(r"perigee[^0-9]*([\d,]+) ft", caught.value.message).group(1).replace(",", ""))
    assert shown == pytest.approx(perigee, abs=1.0)  # ft, printed to the foot
    d.entry_states(coast, R_BURN, d.burn(R_BURN, v_relative, 300.0, coast.omega_rad_s))  # comes down: no error


def test_delta_v_for_a_target_angle_against_the_closed_form():
    delta_v, row = d.delta_v_for_gamma(SPHERE, R_BURN[0], V_INERTIAL[0], -2.0)
    v1 = brentq(lambda v: two_body_entry(v)[1] + 2.0, 0.9 * V_CIRCULAR, V_CIRCULAR - 290.0, xtol=1e-9)
    assert delta_v == pytest.approx(V_CIRCULAR - v1, abs=0.05)  # ft/s; measured 3e-7
    assert row[d.E_GAMMA] == pytest.approx(-2.0, abs=1e-5)  # measured 1e-9


def test_a_shallow_reachable_target_angle_is_found():
    # -0.3 deg needs 287.1 ft/s (grazing: 283.2); the secant's first coast, at 0.9 x 287.1 = 258.4, stays up
    v1 = brentq(lambda v: two_body_entry(v)[1] + 0.3, 0.9 * V_CIRCULAR, V_CIRCULAR - 284.0, xtol=1e-9)
    delta_v, row = d.delta_v_for_gamma(SPHERE, R_BURN[0], V_INERTIAL[0], -0.3)
    assert delta_v == pytest.approx(V_CIRCULAR - v1, abs=0.05)
    assert row[d.E_GAMMA] == pytest.approx(-0.3, abs=1e-5)
