"""`fly` against an independent reference integration in a different formulation.

The core (footprint.core) integrates the report's eqs. (1)-(3): EARTH-FIXED position and EARTH-RELATIVE
velocity with explicit Coriolis and centrifugal terms, gravity from eq. (A10) in local-horizon components,
Bowring's geodetic latitude, its own numba Dormand-Prince 5(4) with Illinois event location.

The reference below shares none of that. It integrates
* the INERTIAL cartesian state (position, inertial velocity; z toward the north pole, x toward longitude 0
  at t = 0), so there are no fictitious forces at all;
* gravity as the analytic gradient of the zonal potential
  U = mu/r [1 - sum_{n=2..4} J_n (Re/r)^n P_n(sin phi_c)], J2 = J/1.5, J3 = H/2.5, J4 = -K/3.75
  (spherical planet: mu/r^2); the potential is axisymmetric, so it is evaluated on inertial coordinates;
* the air velocity v_rel = v_I - omega x r (the atmosphere turns with the earth); the earth-fixed position
  is the inertial one rotated by -omega t about z;
* geodetic latitude and altitude by Newton's method on f(phi) = p sin(phi) - z cos(phi) - e^2 N sin(phi) cos(phi);
* lift along the component of the geocentric r_hat normal to v_rel (Gram-Schmidt), turned by the bank toward
  r_hat x v_rel (left); drag along -v_rel; L/m = CL q g0 / (W/S), q = rho |v_rel|^2 / 2, Mach = |v_rel|/a;
* scipy's DOP853 (8th order) at rtol 1e-11, in two phases split at pull-out (first zero of r . v_rel) by
  scipy's event location; the bank law is zero before pull-out.
Shared with the core, and validated elsewhere: the atmosphere and aerodynamic-coefficient kernels and the
constants. A sign, frame or factor error in the core's dynamics, gravity, frames, controls or integrator
therefore shows up as a disagreement here, with two limits: the J3 term moves a trajectory by < 5 ft and
< 0.001 deg, so its sign is left to the gravity unit tests; and the reference is itself checked below
(gravity against its potential, the geodetic inversion, the Table 2 entry state).
"""

import functools
import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

import footprint
from footprint.core import aero
from footprint.core import constants as c
from footprint.core.atmosphere import MODEL_IDS, atmosphere
from tests.authorities.report import REPORT, table2_entry, table2_stop

MU = c.MU_EARTH_FT3_S2
RE = c.RADIUS_EQUATORIAL_FT
RP = c.RADIUS_POLAR_FT  # the case contract's default polar radius
E2 = 1.0 - (RP / RE) ** 2
J2, J3, J4 = c.J_ZONAL / 1.5, c.H_ZONAL / 2.5, -c.K_ZONAL / 3.75
G0 = c.G0_FT_S2
Z_HAT = np.array([0.0, 0.0, 1.0])
ARDC = MODEL_IDS["ardc1959"]

RTOL = 1e-11
ATOL = np.array([1e-4, 1e-4, 1e-4, 1e-7, 1e-7, 1e-7])  # ft, ft/s (positions ~2e7 ft, speeds ~3e4 ft/s)
T_MAX_S = 20_000.0

# agreement required of fly()
TOL_LATLON_DEG = 0.02
TOL_TIME_S = 1.0
TOL_PULLOUT_FT = 500.0
# along the whole recorded history (observed: <= 1.2 ft and 3e-4 deg). Tighter than the end-point checks on
# purpose: flipping the sign of J4 moves the altitude history by 45-185 ft, but the end point by < 0.013 deg.
TOL_HISTORY_ALT_FT = 25.0
TOL_HISTORY_LATLON_DEG = 0.005


# ------------------------------------------------------------------------------------------ reference
def _legendre(s):
    """(P2, P3, P4) and their derivatives in s (standard normalization)."""
    s2 = s * s
    p = ((3 * s2 - 1) / 2, (5 * s2 * s - 3 * s) / 2, (35 * s2 * s2 - 30 * s2 + 3) / 8)
    dp = (3 * s, (15 * s2 - 3) / 2, (140 * s2 * s - 60 * s) / 8)
    return p, dp


def gravity(r_vec, oblate):
    """grad U at r_vec; U is axisymmetric about z so any frame sharing the z axis will do."""
    r = math.sqrt(r_vec @ r_vec)
    rhat = r_vec / r
    if not oblate:
        return -MU / (r * r) * rhat
    s = rhat[2]
    q = RE / r
    p, dp = _legendre(s)
    # U = mu/r - sum_n mu J_n Re^n r^-(n+1) P_n(s);  grad U = dU/dr r_hat + dU/ds (z_hat - s r_hat)/r
    du_dr = -MU / (r * r)
    du_ds = 0.0
    for n, jn, pn, dpn in ((2, J2, p[0], dp[0]), (3, J3, p[1], dp[1]), (4, J4, p[2], dp[2])):
        coeff = MU * jn * q**n / r
        du_dr += (n + 1) * coeff * pn / r
        du_ds -= coeff * dpn
    return du_dr * rhat + du_ds / r * (Z_HAT - s * rhat)


def zonal_potential(r_vec):
    r = math.sqrt(r_vec @ r_vec)
    p, _ = _legendre(r_vec[2] / r)
    q = RE / r
    return MU / r * (1 - J2 * q**2 * p[0] - J3 * q**3 * p[1] - J4 * q**4 * p[2])


def geodetic(p, z, oblate):
    """(latitude rad, altitude ft) of a point at distance p from the axis and height z over the equator."""
    if not oblate:
        return math.atan2(z, p), math.hypot(p, z) - RE
    phi = math.atan2(z, p * (1.0 - E2))  # the latitude of the surface point below: a close start
    for _ in range(10):
        sin_phi, cos_phi = math.sin(phi), math.cos(phi)
        w2 = 1.0 - E2 * sin_phi * sin_phi
        n = RE / math.sqrt(w2)
        f = p * sin_phi - z * cos_phi - E2 * n * sin_phi * cos_phi
        dn = n * E2 * sin_phi * cos_phi / w2
        df = p * cos_phi + z * sin_phi - E2 * (dn * sin_phi * cos_phi + n * (cos_phi * cos_phi - sin_phi * sin_phi))
        step = f / df
        phi -= step
        if abs(step) < 1e-15:
            break
    sin_phi, cos_phi = math.sin(phi), math.cos(phi)
    return phi, p * cos_phi + z * sin_phi - RE * math.sqrt(1.0 - E2 * sin_phi * sin_phi)


def position_from_geodetic(lat, lon, alt, oblate):
    sin_lat, cos_lat = math.sin(lat), math.cos(lat)
    if not oblate:
        r = RE + alt
        return np.array([r * cos_lat * math.cos(lon), r * cos_lat * math.sin(lon), r * sin_lat])
    n = RE / math.sqrt(1.0 - E2 * sin_lat * sin_lat)
    return np.array(
        [(n + alt) * cos_lat * math.cos(lon), (n + alt) * cos_lat * math.sin(lon), (n * (1.0 - E2) + alt) * sin_lat]
    )


def rot_z(angle):
    cos_a, sin_a = math.cos(angle), math.sin(angle)
    return np.array([[cos_a, -sin_a, 0.0], [sin_a, cos_a, 0.0], [0.0, 0.0, 1.0]])


class Reference:
    """One reference flight: zero bank to pull-out, then the bank law, until the stop altitude."""

    def __init__(self, *, oblate, rotating, entry, bank, vehicle, stop_alt_ft=50_000.0):
        self.oblate = oblate
        self.omega = c.OMEGA_EARTH_RAD_S if rotating else 0.0
        self.bank = bank  # ("constant", deg) or ("single_parameter", K, limit_deg or None)
        self.vehicle = vehicle  # ("blob", blob, W/S) or ("constant", CL, CD, W/S)
        self.stop_alt = stop_alt_ft
        lat, lon = math.radians(entry["latitude_deg"]), math.radians(entry["longitude_deg"])
        r0 = position_from_geodetic(lat, lon, entry["altitude_ft"], oblate)
        up = r0 / np.linalg.norm(r0)
        east = np.cross(Z_HAT, up)
        east /= np.linalg.norm(east)
        north = np.cross(up, east)
        g, h, v = math.radians(entry["gamma_deg"]), math.radians(entry["heading_deg"]), entry["velocity_fps"]
        d0 = math.cos(h) * north + math.sin(h) * east
        self.pole_e = np.cross(up, d0)  # left pole of the initial great circle, earth-fixed
        v_rel = v * (math.sin(g) * up + math.cos(g) * d0)
        self.y0 = np.concatenate([r0, v_rel + self.omega * np.cross(Z_HAT, r0)])  # x_I = x_E at t = 0

    # --- pieces of the right-hand side
    def v_rel(self, y):
        r = y[:3]
        return y[3:] - self.omega * np.array([-r[1], r[0], 0.0])

    def altitude(self, y):
        return geodetic(math.hypot(y[0], y[1]), y[2], self.oblate)[1]

    def zeta_deg(self, t, r, v_rel):
        """Angle, clockwise from above, from the horizontal projection of the pole to that of v_rel."""
        rhat = r / np.linalg.norm(r)
        pole = rot_z(self.omega * t) @ self.pole_e  # the pole turns with the earth
        pole_h = pole - (pole @ rhat) * rhat
        vh = v_rel - (v_rel @ rhat) * rhat
        return math.degrees(math.atan2(rhat @ np.cross(vh, pole_h), pole_h @ vh))

    def bank_deg(self, t, r, v_rel, active):
        if not active:
            return 0.0
        if self.bank[0] == "constant":
            return self.bank[1]
        _, k, limit = self.bank
        b = k * self.zeta_deg(t, r, v_rel)
        return b if limit is None else min(max(b, -limit), limit)

    def coefficients(self, mach, alt):
        if self.vehicle[0] == "constant":
            return self.vehicle[1], self.vehicle[2]
        blob = self.vehicle[1]
        alpha = aero.alpha_max_ld_deg(blob, mach, alt)
        return aero.coefficients(blob, mach, alpha, alt)

    def rhs(self, t, y, active):
        r = y[:3]
        vr = self.v_rel(y)
        alt = self.altitude(y)
        rho, _, _, sound = atmosphere(ARDC, alt, 0.0027, 23_800.0, 500.0)
        speed = math.sqrt(vr @ vr)
        vhat = vr / speed
        cl, cd = self.coefficients(speed / sound, alt)
        force_per_coeff = 0.5 * rho * speed * speed * G0 / self.vehicle[-1]
        rhat = r / math.sqrt(r @ r)
        lift_up = rhat - (rhat @ vhat) * vhat
        lift_up /= math.sqrt(lift_up @ lift_up)
        left = np.cross(rhat, vhat)
        left /= math.sqrt(left @ left)
        b = math.radians(self.bank_deg(t, r, vr, active))
        a = gravity(r, self.oblate) + force_per_coeff * (cl * (math.cos(b) * lift_up + math.sin(b) * left) - cd * vhat)
        return np.concatenate([y[3:], a])

    # --- the flight
    def fly(self):
        def stop_event(t, y, *_):
            return self.altitude(y) - self.stop_alt

        def pullout_event(t, y, *_):
            return y[:3] @ self.v_rel(y)  # |r||v_rel| sin(gamma)

        stop_event.terminal, stop_event.direction = True, -1
        pullout_event.terminal, pullout_event.direction = True, 1
        kw = dict(method="DOP853", rtol=RTOL, atol=ATOL, dense_output=True)
        s1 = solve_ivp(self.rhs, (0.0, T_MAX_S), self.y0, events=(stop_event, pullout_event), args=(False,), **kw)
        assert s1.status == 1, s1.message
        segments = [s1]
        pullout = None
        if s1.t_events[1].size:
            t_po, y_po = s1.t_events[1][0], s1.y_events[1][0]
            pullout = {"time_s": t_po, "altitude_ft": self.altitude(y_po)}
            s2 = solve_ivp(self.rhs, (t_po, T_MAX_S), y_po, events=(stop_event,), args=(True,), **kw)
            assert s2.status == 1, s2.message
            segments.append(s2)
        last = segments[-1]
        t_f, y_f = last.t_events[0][0], last.y_events[0][0]
        r_e = rot_z(-self.omega * t_f) @ y_f[:3]
        lat, alt = geodetic(math.hypot(r_e[0], r_e[1]), r_e[2], self.oblate)
        return {
            "flight_time_s": t_f,
            "final_latitude_deg": math.degrees(lat),
            "final_longitude_deg": math.degrees(math.atan2(r_e[1], r_e[0])),
            "final_altitude_ft": alt,
            "pullout": pullout,
            "segments": segments,
        }

    def earth_fixed_at(self, result, t):
        """(geodetic latitude deg, longitude deg, altitude ft) at time t, from the dense output."""
        for seg in result["segments"]:
            if seg.t[0] <= t <= seg.t[-1]:
                r_e = rot_z(-self.omega * t) @ seg.sol(t)[:3]
                lat, alt = geodetic(math.hypot(r_e[0], r_e[1]), r_e[2], self.oblate)
                return math.degrees(lat), math.degrees(math.atan2(r_e[1], r_e[0])), alt
        raise ValueError(f"t = {t} s is outside the reference flight")


# ---------------------------------------------------------------------------------------------- cases
TABLE2_ENTRY = table2_entry()
INCLINED_ENTRY = table2_entry(heading_deg=50.0, latitude_deg=28.5, longitude_deg=-80.0)
CONSTANT_VEHICLE = {"name": "c", "wing_loading_psf": 40.0, "aero": {"constant": {"cl": 0.35, "cd": 0.16}}}
BANKS = {
    "bank30": ({"law": "constant", "bank_deg": 30.0}, ("constant", 30.0)),
    "K0.8": ({"law": "single_parameter", "bank_gain": 0.8, "limit_deg": 85.0}, ("single_parameter", 0.8, 85.0)),
    "K0.6": ({"law": "single_parameter", "bank_gain": 0.6}, ("single_parameter", 0.6, None)),
}
PLANETS = {
    "sphere-fixed": (False, False),
    "sphere-rot": (False, True),
    "oblate-fixed": (True, False),
    "oblate-rot": (True, True),
}

CASES = {
    f"{planet}-{bank}": (planet, bank, "lod-2.2", TABLE2_ENTRY) for planet in PLANETS for bank in ("bank30", "K0.8")
}
CASES["inclined-oblate-rot-K0.6"] = ("oblate-rot", "K0.6", "constant", INCLINED_ENTRY)


def case_dict(name):
    planet, bank, vehicle, entry = CASES[name]
    oblate, rotating = PLANETS[planet]
    return {
        "vehicle": CONSTANT_VEHICLE if vehicle == "constant" else {"builtin": vehicle},
        "planet": {"rotating": rotating, "oblate": oblate},
        "entry": dict(entry),
        "alpha": {"law": "max_ld"},
        "bank": BANKS[bank][0],
        "bank_start": "pullout",
        "stop": table2_stop(),
    }


def reference_for(name):
    planet, bank, vehicle, entry = CASES[name]
    oblate, rotating = PLANETS[planet]
    if vehicle == "constant":
        const = CONSTANT_VEHICLE
        veh = ("constant", const["aero"]["constant"]["cl"], const["aero"]["constant"]["cd"], const["wing_loading_psf"])
    else:
        v = aero.builtin_vehicle(vehicle)
        veh = ("blob", v.blob, v.wing_loading_psf)
    return Reference(oblate=oblate, rotating=rotating, entry=entry, bank=BANKS[bank][1], vehicle=veh)


@functools.cache
def flown(name):
    """(fly() trajectory, reference, reference result) of one case, computed once."""
    ref = reference_for(name)
    return footprint.fly(case_dict(name)), ref, ref.fly()


def wrap180(a):
    return (a + 180.0) % 360.0 - 180.0


def comparison(name):
    """Rows (quantity, ours, reference, difference, tolerance)."""
    traj, _, res = flown(name)
    s = traj.summary
    rows = [
        (
            "final_latitude_deg",
            s["final_latitude_deg"],
            res["final_latitude_deg"],
            s["final_latitude_deg"] - res["final_latitude_deg"],
            TOL_LATLON_DEG,
        ),
        (
            "final_longitude_deg",
            s["final_longitude_deg"],
            res["final_longitude_deg"],
            wrap180(s["final_longitude_deg"] - res["final_longitude_deg"]),
            TOL_LATLON_DEG,
        ),
        (
            "flight_time_s",
            s["flight_time_s"],
            res["flight_time_s"],
            s["flight_time_s"] - res["flight_time_s"],
            TOL_TIME_S,
        ),
    ]
    po = res["pullout"]
    ours_po = s["pullout_altitude_ft"]
    if po is None or ours_po is None:
        rows.append(
            (
                "pullout_altitude_ft",
                ours_po,
                None if po is None else po["altitude_ft"],
                0.0 if po is None and ours_po is None else math.inf,
                TOL_PULLOUT_FT,
            )
        )
    else:
        rows.append(("pullout_altitude_ft", ours_po, po["altitude_ft"], ours_po - po["altitude_ft"], TOL_PULLOUT_FT))
    return rows


# ---------------------------------------------------------------------------------- the reference itself
@pytest.mark.parametrize("lat_deg", [-70.0, -10.0, 0.0, 33.0, 89.0])
def test_reference_gravity_is_the_gradient_of_its_potential(lat_deg):
    # central differences at 50 ft: truncation ~1e-10 ft/s^2, rounding ~1e-9; the J3, J4 terms are ~1e-4
    r = position_from_geodetic(math.radians(lat_deg), 0.7, 250_000.0, True)
    fd = np.array([(zonal_potential(r + d) - zonal_potential(r - d)) / 100.0 for d in np.eye(3) * 50.0])
    assert np.max(np.abs(gravity(r, True) - fd)) < 1e-7
    # and the J2 term is there, of the right size: 1.5 J2 (Re/r)^2 mu/r^2 ~ 0.05 ft/s^2 at the equator
    assert np.linalg.norm(gravity(r, True) - gravity(r, False)) > 1e-3


@pytest.mark.parametrize("lat_deg", [-89.0, -45.0, 0.0, 28.5, 60.0, 90.0])
@pytest.mark.parametrize("alt_ft", [0.0, 50_000.0, 400_000.0])
def test_reference_geodetic_inverts_the_ellipsoid(lat_deg, alt_ft):
    r = position_from_geodetic(math.radians(lat_deg), 1.0, alt_ft, True)
    lat, alt = geodetic(math.hypot(r[0], r[1]), r[2], True)
    assert math.degrees(lat) == pytest.approx(lat_deg, abs=1e-11)
    assert alt == pytest.approx(alt_ft, abs=1e-5)


def test_reference_initial_state_is_table_2():
    ref = reference_for("oblate-rot-K0.8")
    r, v_i = ref.y0[:3], ref.y0[3:]
    v_rel = REPORT["table2.velocity_fps"].value
    assert np.linalg.norm(ref.v_rel(ref.y0)) == pytest.approx(v_rel, rel=1e-14)
    # Section II.2: 24,480 ft/s relative "corresponds to an inertial velocity of 26,032 feet/second"
    assert np.linalg.norm(v_i) == pytest.approx(REPORT["entry.inertial_velocity_text_fps"].value, abs=3.0)
    assert math.degrees(math.asin(r @ ref.v_rel(ref.y0) / np.linalg.norm(r) / v_rel)) == pytest.approx(
        REPORT["table2.gamma_deg"].value
    )
    assert ref.zeta_deg(0.0, r, ref.v_rel(ref.y0)) == pytest.approx(REPORT["table2.heading_deg"].value, abs=1e-12)


# ----------------------------------------------------------------------------------------- fly vs reference
MAIN = [n for n in CASES if not n.startswith("inclined")]
EXTRA = [pytest.param(n, marks=pytest.mark.slow) for n in CASES if n.startswith("inclined")]


@pytest.mark.parametrize("name", MAIN + EXTRA)
def test_fly_agrees_with_the_reference(name):
    traj, _, res = flown(name)
    assert traj.summary["stop_reason"] == "altitude"
    assert res["final_altitude_ft"] == pytest.approx(50_000.0, abs=1e-3)
    rows = comparison(name)
    table = "\n".join(f"  {q:22s} ours {o!s:>22} ref {r!s:>22} diff {d:+.3g} (tol {tol:g})" for q, o, r, d, tol in rows)
    bad = [q for q, _, _, d, tol in rows if not abs(d) <= tol]
    assert not bad, f"{name}: {bad} disagree with the reference\n{table}"


@pytest.mark.parametrize("name", MAIN + EXTRA)
def test_fly_follows_the_reference_along_the_trajectory(name):
    traj, ref, res = flown(name)
    h = traj.history
    worst = {"altitude_ft": 0.0, "latitude_deg": 0.0, "longitude_deg": 0.0}
    for i in np.flatnonzero(h["time_s"] <= res["flight_time_s"]):
        lat, lon, alt = ref.earth_fixed_at(res, h["time_s"][i])
        for key, d in (
            ("altitude_ft", h["altitude_ft"][i] - alt),
            ("latitude_deg", h["latitude_deg"][i] - lat),
            ("longitude_deg", wrap180(h["longitude_deg"][i] - lon)),
        ):
            worst[key] = max(worst[key], abs(d))
    assert worst["altitude_ft"] <= TOL_HISTORY_ALT_FT, worst
    assert worst["latitude_deg"] <= TOL_HISTORY_LATLON_DEG, worst
    assert worst["longitude_deg"] <= TOL_HISTORY_LATLON_DEG, worst
