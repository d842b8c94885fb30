"""The deorbit burn and vacuum coast to the entry interface (core/deorbit.py) against independent routes: on a
spherical, non-rotating, J-free earth the two-body closed forms (energy and angular momentum for the entry speed and
flight-path angle, Kepler's equation for the coast time, the perigee of the message, the Δv for a target angle) and
energy conservation; on the rotating earth with J2 a scipy DOP853 propagation in inertial axes with the point-mass
and J2 acceleration written out here (J2 = J / 1.5, the report's J of eq. A10)."""

import math
import re

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

from footprint.core import deorbit as d
from footprint.core.aero import builtin_vehicle
from footprint.core.constants import FT_PER_M, FT_PER_NMI, MU_EARTH_FT3_S2, OMEGA_EARTH_RAD_S, RADIUS_EQUATORIAL_FT
from footprint.core.errors import InputError
from footprint.core.trajectory import Planet

MU, RE = MU_EARTH_FT3_S2, RADIUS_EQUATORIAL_FT
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


def j2_inertial(j2: float):
    def rhs(_t: float, s: np.ndarray) -> list[float]:
        x, y, z = s[:3]
        r2 = x * x + y * y + z * z
        k, q, zz = -MU / r2**1.5, 1.5 * j2 * RE**2 / r2, 5.0 * z * z / r2
        return [s[3], s[4], s[5], k * x * (1 + q * (1 - zz)), k * y * (1 + q * (1 - zz)), k * z * (1 + q * (3 - zz))]

    return rhs


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


def test_the_coast_on_the_rotating_j2_earth_against_an_inertial_propagation():
    coast = d.Coast.of(VEHICLE, J2_PLANET)
    omega = np.array([0.0, 0.0, OMEGA_EARTH_RAD_S])
    v_relative = V_INERTIAL - np.cross(omega, R_BURN)  # earth-fixed = inertial axes at the burn
    v_after = d.burn(R_BURN, v_relative, 450.0, OMEGA_EARTH_RAD_S)
    row = d.entry_states(coast, R_BURN, v_after)[0]
    t = row[d.E_COAST_S]
    start = np.concatenate([R_BURN[0], v_after[0] + np.cross(omega, R_BURN[0])])

    def earth_fixed_miss_ft(j2: float) -> float:
        sol = solve_ivp(j2_inertial(j2), (0.0, t), start, method="DOP853", rtol=1e-12, atol=1e-6)
        x, y, z = sol.y[:3, -1]
        c, s = math.cos(OMEGA_EARTH_RAD_S * t), math.sin(OMEGA_EARTH_RAD_S * t)  # rotate by -omega t about z
        return float(np.linalg.norm(np.array([c * x + s * y, -s * x + c * y, z]) - row[d.E_X : d.E_Z + 1]))

    assert earth_fixed_miss_ft(J2_PLANET.j / 1.5) < 0.5 * FT_PER_NMI  # measured 0.01 ft
    assert earth_fixed_miss_ft(0.0) > 3.0 * FT_PER_NMI  # the check sees J2: 45,700 ft without it


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
