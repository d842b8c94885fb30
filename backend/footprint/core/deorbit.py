"""The deorbit (issue 28 item 2): an impulsive retrograde burn on an orbit's state and the vacuum coast from the burn
to the entry interface, flown by our own integrator (eqs. (1)-(3) on the rotating oblate earth, gravity A10) with
the drag off: the entry state (altitude, earth-relative speed, flight-path angle, heading, latitude, longitude) and
the time the coast took. The coast of an orbit is flown in the gravity and rotation of the orbit's earth (SGP4's
WGS-72 for a TLE, WGS-84 for a state vector: core.constants.Earth), the interface's altitude measured on the flight's
ellipsoid (the report's, App. A), as the flight after it measures it.

The burn is along the inertial velocity (retrograde: it slows the vehicle in inertial space, the only direction a
deorbit thruster aims); a target flight-path angle at the interface sets the Δv by a secant search on flown coasts,
started from the two-body closed form (Vallado, Fundamentals of Astrodynamics, 4th ed., sec. 2.2: energy and angular
momentum conserved, cos γ = h / (r V)). The coast's air is the exponential model with zero density: the same
integrator, its aerodynamic forces zero above the interface.

States are earth-fixed, ft and ft/s, the velocity relative to the earth (as the integrator flies them).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, replace
from datetime import datetime

import numpy as np
from numpy.typing import NDArray

from footprint.core._jit import njit
from footprint.core.aero import Vehicle
from footprint.core.constants import Earth
from footprint.core.controls import pack_controls
from footprint.core.dynamics import M_SIZE, P_MAX_STEP, P_MU, P_OBLATE, P_OMEGA, P_RE, P_RP, P_STOP_ALT, P_STOP_TIME
from footprint.core.elements import FT_PER_KM, earth_fixed_to_teme, teme_to_earth_fixed
from footprint.core.errors import InputError
from footprint.core.frames import flight_angles, geodetic_from_ecef
from footprint.core.integrate import R_T, R_VX, R_VZ, R_X, R_Z, STOP_ALTITUDE, STOP_REASONS, STOP_TIME, integrate
from footprint.core.trajectory import Entry, FlightSpec, Planet, Stop, pack_parameters
from footprint.core.utc import elapsed_s, iso

INTERFACE_ALTITUDE_FT = 400_000.0  # the entry interface of the report's cases (Table 2 enters at 364,800 ft)
COAST_RTOL = 1e-10  # 0.002 ft a step on the planet's radius: the coast is smooth and cheap
COAST_MAX_STEP_S = 120.0
MAX_COAST_S = 20_000.0  # more than three low orbits: a coast that has not come down by then will not
MAX_STEPS = 20_000
GAMMA_TOLERANCE_DEG = 1e-6  # the secant's stop on a target flight-path angle
N_ENTRY = 10  # entry_states' columns, below
E_COAST_S, E_ALT, E_V, E_GAMMA, E_HEADING, E_LAT, E_LON, E_X, E_Y, E_Z = range(N_ENTRY)
ENTRY_INPUT_COLUMNS = {  # a dispersion's entry inputs (core.dispersion.ENTRY_INPUTS) and their columns
    "altitude_ft": E_ALT, "velocity_fps": E_V, "gamma_deg": E_GAMMA, "heading_deg": E_HEADING, "latitude_deg": E_LAT,
    "longitude_deg": E_LON,
}  # fmt: skip


def earth_planet(planet: Planet, earth: Earth) -> Planet:
    """The planet with an orbit's earth's gravity and rotation, its ellipsoid kept (a spherical planet's sphere): the
    interface's altitude measured as the flight after it measures it. Eq. (A10)'s J, H, K are 1.5 J2, 2.5 J3 and
    -3.75 J4 on the planet's radius (core.gravity: the gradient of the zonal potential), so each J_n of the earth's
    radius is scaled by (R_earth / R_planet)^n: the same field."""
    ratio = earth.radius_ft / planet.radius_ft
    return replace(
        planet,
        mu_ft3_s2=earth.mu_ft3_s2,
        rotating=True,
        rotation_rate_deg_s=math.degrees(earth.rotation_rad_s),
        oblate=True,
        polar_radius_ft=planet.polar_radius_ft if planet.oblate else planet.radius_ft,
        j=1.5 * earth.j2 * ratio**2,
        h=2.5 * earth.j3 * ratio**3,
        k=-3.75 * earth.j4 * ratio**4,
    )


@dataclass(frozen=True)
class Coast:
    """What every coast of one study flies with, packed once: the integrator's parameters (the planet with its air
    removed, stopping at the interface; an orbit's earth's gravity and rotation when given: earth_planet), a
    vehicle's tables (their forces are zero in vacuum) and zero-lift controls."""

    p: NDArray[np.float64]
    aero: NDArray[np.float64]
    ctrl: NDArray[np.float64]
    interface_altitude_ft: float
    earth: Earth | None = None  # None: the planet's own gravity (the flight's)

    @classmethod
    def of(
        cls,
        vehicle: Vehicle,
        planet: Planet,
        interface_altitude_ft: float = INTERFACE_ALTITUDE_FT,
        earth: Earth | None = None,
    ) -> Coast:
        gravity = planet if earth is None else earth_planet(planet, earth)
        vacuum = replace(gravity, atmosphere="exponential", rho0_slug_ft3=0.0)
        spec = FlightSpec(
            vehicle=vehicle,
            planet=vacuum,
            entry=Entry(altitude_ft=interface_altitude_ft, velocity_fps=1.0, gamma_deg=0.0),
            ctrl=pack_controls(bank_law="zero"),
            stop=Stop(altitude_ft=interface_altitude_ft, time_s=MAX_COAST_S, skip_altitude_ft=1e9),
            rtol=COAST_RTOL,
            max_step_s=COAST_MAX_STEP_S,
        )
        return cls(pack_parameters(spec), vehicle.blob, spec.ctrl, interface_altitude_ft, earth)

    @property
    def omega_rad_s(self) -> float:
        return float(self.p[P_OMEGA])

    @property
    def mu_ft3_s2(self) -> float:
        return float(self.p[P_MU])


def inertial_velocity(
    r_ft: NDArray[np.float64], v_rel_fps: NDArray[np.float64], omega_rad_s: float
) -> NDArray[np.float64]:
    """v_inertial = v_relative + omega x r (omega along +z), rows of n x 3, in the earth-fixed axes of the instant."""
    spin = np.zeros_like(r_ft)
    spin[:, 0], spin[:, 1] = -omega_rad_s * r_ft[:, 1], omega_rad_s * r_ft[:, 0]
    v_in: NDArray[np.float64] = v_rel_fps + spin
    return v_in


def burn(
    r_ft: NDArray[np.float64],
    v_rel_fps: NDArray[np.float64],
    delta_v_fps: NDArray[np.float64] | float,
    omega_rad_s: float,
) -> NDArray[np.float64]:
    """The earth-relative velocity after an impulsive Δv (ft/s, n or scalar) against the inertial velocity."""
    v_in = inertial_velocity(r_ft, v_rel_fps, omega_rad_s)
    speed = np.linalg.norm(v_in, axis=1)
    scale = 1.0 - np.broadcast_to(np.asarray(delta_v_fps, float), speed.shape) / speed
    after: NDArray[np.float64] = v_rel_fps + v_in * (scale - 1.0)[:, None]
    return after


@njit
def _coasts(
    states: NDArray[np.float64],
    p: NDArray[np.float64],
    aero: NDArray[np.float64],
    ctrl: NDArray[np.float64],
    max_steps: int,
) -> tuple[NDArray[np.float64], NDArray[np.int64]]:
    """Each row's coast to the stop: its last row (t, x, y, z, vx, vy, vz) and its stop code."""
    n = states.shape[0]
    out = np.empty((n, 7))
    codes = np.empty(n, np.int64)
    mode = np.zeros(M_SIZE)
    for i in range(n):
        mode[:] = 0.0
        rows, code, _ = integrate(states[i].copy(), p, aero, ctrl, mode, max_steps)
        last = rows[rows.shape[0] - 1]
        out[i, 0] = last[R_T]
        out[i, 1:4] = last[R_X : R_Z + 1]
        out[i, 4:7] = last[R_VX : R_VZ + 1]
        codes[i] = code
    return out, codes


def entry_states(coast: Coast, r_ft: NDArray[np.float64], v_rel_fps: NDArray[np.float64]) -> NDArray[np.float64]:
    """Each state (after its burn) coasted to the interface: rows of E_* (coast s, altitude ft, earth-relative speed
    ft/s, flight-path angle deg, heading deg, geodetic latitude deg, longitude deg, earth-fixed x, y, z ft); a coast
    that does not come down to the interface raises InputError on "deorbit" with its stop reason."""
    states = np.ascontiguousarray(np.column_stack([r_ft, v_rel_fps]), dtype=np.float64)
    last, codes = _coasts(states, coast.p, coast.aero, coast.ctrl, MAX_STEPS)
    bad = np.flatnonzero(codes != STOP_ALTITUDE)
    if bad.size:
        perigee = perigee_altitude_ft(coast, states[bad[0], :3], states[bad[0], 3:])
        raise InputError(
            "deorbit",
            f"the coast does not reach the interface at {coast.interface_altitude_ft:,.0f} ft (it ended by "
            f"{STOP_REASONS[int(codes[bad[0]])]}; the orbit's perigee after the burn is {perigee:,.0f} ft): "
            "a larger Δv or a steeper target angle",
        )
    p = coast.p
    out = np.empty((len(last), N_ENTRY))
    for i, (t, x, y, z, vx, vy, vz) in enumerate(last):
        lat, lon, alt = geodetic_from_ecef(x, y, z, p[P_RE], p[P_RP], p[P_OBLATE] != 0.0, 3)
        v, gamma, heading = flight_angles(x, y, z, vx, vy, vz)
        out[i] = (t, alt, v, math.degrees(gamma), math.degrees(heading), math.degrees(lat), math.degrees(lon), x, y, z)
    return out


def entered(spec: FlightSpec, row: NDArray[np.float64]) -> FlightSpec:
    """The spec entering at an entry row (entry_states): its altitude, earth-relative speed, angles and place."""
    values = {name: float(row[col]) for name, col in ENTRY_INPUT_COLUMNS.items()}
    return replace(spec, entry=replace(spec.entry, velocity_frame="relative", **values))


def coast_track(
    coast: Coast, r_ft: NDArray[np.float64], v_rel_fps: NDArray[np.float64]
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    """One state's coast (after its burn) as the integrator's steps: time from the burn (s), geodetic latitude and
    longitude (deg), for the map."""
    rows, _, _ = integrate(
        np.concatenate([r_ft, v_rel_fps]), coast.p, coast.aero, coast.ctrl, np.zeros(M_SIZE), MAX_STEPS
    )
    p = coast.p
    places = np.array(
        [geodetic_from_ecef(x, y, z, p[P_RE], p[P_RP], p[P_OBLATE] != 0.0, 3) for x, y, z in rows[:, R_X : R_Z + 1]]
    )
    return rows[:, R_T], np.degrees(places[:, 0]), np.degrees(places[:, 1])


PROPAGATION_MAX_STEP_S = 10.0  # the states between steps are cubic (Hermite): 0.03 ft/s at this step in low orbit
DATETIME_RESOLUTION_S = 1e-6  # a UTC time is a datetime, to the microsecond: a time at the horizon may round past it


@dataclass(frozen=True)
class TwoBody:
    """The two-body orbit of a state about a point-mass earth (its inertial velocity): h = r x v, the energy
    v^2/2 - mu/r, e = sqrt(1 + 2 E h^2 / mu^2), a = -mu / (2 E) (Vallado, Fundamentals, sec. 2.2)."""

    inclination_deg: float
    eccentricity: float
    semi_major_axis_ft: float  # infinite for an orbit that is not bound
    mu_ft3_s2: float

    @property
    def mean_motion_rev_day(self) -> float:
        """Kepler's third law n^2 a^3 = mu (0 when not bound)."""
        return math.sqrt(self.mu_ft3_s2 / self.semi_major_axis_ft**3) * 86_400.0 / (2.0 * math.pi)

    @property
    def perigee_radius_ft(self) -> float:
        return self.semi_major_axis_ft * (1.0 - self.eccentricity)


def two_body(coast: Coast, r_ft: NDArray[np.float64], v_rel_fps: NDArray[np.float64]) -> TwoBody:
    """The two-body orbit of an earth-fixed state (ft, earth-relative ft/s) on the coast's planet."""
    v_in = inertial_velocity(r_ft[None, :], v_rel_fps[None, :], coast.omega_rad_s)[0]
    mu, r = coast.mu_ft3_s2, float(np.linalg.norm(r_ft))
    h = np.cross(r_ft, v_in)
    energy = 0.5 * float(v_in @ v_in) - mu / r
    e = math.sqrt(max(0.0, 1.0 + 2.0 * energy * float(h @ h) / mu**2))
    inclination = math.degrees(math.acos(max(-1.0, min(1.0, h[2] / max(float(np.linalg.norm(h)), 1e-300)))))
    return TwoBody(inclination, e, -mu / (2.0 * energy) if energy < 0.0 else math.inf, mu)


class PropagatedState:
    """An orbit given by one state at its UTC epoch, propagated by our integrator in the coast's earth (its point mass,
    J2-J4 and rotation; no drag: for the days of a window), forward to `horizon_s` after the epoch; the states in
    between by cubic Hermite interpolation of the steps' positions and velocities. Satisfies elements.Orbit."""

    name: str | None = None
    satellite_number: int | None = None
    revolution_number: int | None = None  # at the epoch, when the state's giver says (else counted from it)

    def __init__(self, epoch: datetime, r_ft: NDArray[np.float64], v_rel_fps: NDArray[np.float64], coast: Coast,
                 horizon_s: float, satellite_number: int | None = None,
                 revolution_number: int | None = None):  # fmt: skip
        self.satellite_number, self.revolution_number = satellite_number, revolution_number
        if coast.earth is None:
            raise ValueError("a state is propagated in an earth's gravity: Coast.of(..., earth=...)")
        self.epoch, self.coast, self.earth = epoch, coast, coast.earth
        p = coast.p.copy()
        p[P_STOP_ALT], p[P_STOP_TIME], p[P_MAX_STEP] = 0.0, horizon_s, PROPAGATION_MAX_STEP_S
        rows, code, _ = integrate(np.concatenate([r_ft, v_rel_fps]), p, coast.aero, coast.ctrl, np.zeros(M_SIZE),
                                  10 * MAX_STEPS)  # fmt: skip
        if code != STOP_TIME:
            raise InputError("state", f"the orbit does not last {horizon_s / 3600:.1f} h ({STOP_REASONS[int(code)]})")
        self.rows = rows
        orbit = two_body(coast, r_ft, v_rel_fps)
        self.inclination_deg, self.eccentricity = orbit.inclination_deg, orbit.eccentricity
        self.mean_motion_rev_day = orbit.mean_motion_rev_day

    def earth_fixed(self, utc: Sequence[datetime]) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """Earth-fixed position (ft) and earth-relative velocity (ft/s) at each UTC time, n x 3 each (the SI seconds
        from the epoch: a leap second between counts)."""
        t = elapsed_s(self.epoch, utc)
        rows = self.rows
        if t.min() < -DATETIME_RESOLUTION_S or t.max() > rows[-1, R_T] + DATETIME_RESOLUTION_S:
            raise InputError("window", f"outside the propagated span of the state (epoch {iso(self.epoch)} "
                                       f"to {rows[-1, R_T] / 3600:.1f} h after)")  # fmt: skip
        i = np.clip(np.searchsorted(rows[:, R_T], t, side="right") - 1, 0, len(rows) - 2)
        h = rows[i + 1, R_T] - rows[i, R_T]
        s = ((t - rows[i, R_T]) / h)[:, None]
        p0, p1 = rows[i, R_X : R_Z + 1], rows[i + 1, R_X : R_Z + 1]
        v0, v1 = rows[i, R_VX : R_VZ + 1] * h[:, None], rows[i + 1, R_VX : R_VZ + 1] * h[:, None]
        position = (
            (2 * s**3 - 3 * s**2 + 1) * p0
            + (s**3 - 2 * s**2 + s) * v0
            + (-2 * s**3 + 3 * s**2) * p1
            + (s**3 - s**2) * v1
        )
        velocity = ((6 * s**2 - 6 * s) * p0 + (3 * s**2 - 4 * s + 1) * v0 + (-6 * s**2 + 6 * s) * p1
                    + (3 * s**2 - 2 * s) * v1) / h[:, None]  # fmt: skip
        return position, velocity

    def teme_km(self, utc: Sequence[datetime]) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """TEME position (km) and velocity (km/s) at each UTC time."""
        return earth_fixed_to_teme(*self.earth_fixed(utc), utc, self.coast.omega_rad_s)


def state_earth_fixed(
    epoch: datetime, frame: str, position_km: Sequence[float], velocity_km_s: Sequence[float], omega_rad_s: float
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """A state vector as the integrator flies it (earth-fixed ft, earth-relative ft/s): "teme" (true equator, mean
    equinox of date, as SGP4 gives it) by elements.teme_to_earth_fixed; "earth_fixed" as given."""
    r, v = np.asarray(position_km, float)[None, :], np.asarray(velocity_km_s, float)[None, :]
    if frame == "earth_fixed":
        return r[0] * FT_PER_KM, v[0] * FT_PER_KM
    r_ft, v_fps = teme_to_earth_fixed(r, v, [epoch], omega_rad_s)
    return r_ft[0], v_fps[0]


def state_orbit(coast: Coast, r_ft: NDArray[np.float64], v_rel_fps: NDArray[np.float64]) -> TwoBody:
    """A state vector's two-body orbit, the state above the planet's polar radius and bound to it; else InputError
    naming its position or velocity."""
    radius_ft, polar_ft = float(np.linalg.norm(r_ft)), float(coast.p[P_RP])
    if radius_ft <= polar_ft:
        inside = f"{radius_ft / FT_PER_KM:,.0f} km from the earth's centre is inside the earth"
        raise InputError("state.position_km", f"{inside} (its polar radius is {polar_ft / FT_PER_KM:,.0f} km)")
    orbit = two_body(coast, r_ft, v_rel_fps)
    if not math.isfinite(orbit.semi_major_axis_ft):  # at or past the escape speed sqrt(2 mu / r): no a, no n
        v_in = float(np.linalg.norm(inertial_velocity(r_ft[None, :], v_rel_fps[None, :], coast.omega_rad_s)[0]))
        escape_fps = math.sqrt(2.0 * coast.mu_ft3_s2 / radius_ft)
        raise InputError(
            "state.velocity_km_s",
            f"{v_in / FT_PER_KM:.3g} km/s inertial at {radius_ft / FT_PER_KM:,.0f} km from the earth's centre is at or "
            f"past the escape speed {escape_fps / FT_PER_KM:.3g} km/s there: an orbit's state is slower",
        )
    return orbit


def perigee_altitude_ft(coast: Coast, r_ft: NDArray[np.float64], v_rel_fps: NDArray[np.float64]) -> float:
    """The two-body perigee of an earth-fixed state, above the equatorial radius (ft): r_p = a (1 - e)."""
    return two_body(coast, r_ft, v_rel_fps).perigee_radius_ft - float(coast.p[P_RE])


def two_body_entry_gamma_deg(mu_ft3_s2: float, r_burn_ft: float, v_burn_fps: float, r_entry_ft: float) -> float:
    """The flight-path angle (deg, negative: descending) at radius r_entry of a two-body orbit leaving r_burn
    horizontally at v_burn (energy and angular momentum conserved); NaN if the orbit does not come down that far."""
    v_entry = math.sqrt(max(0.0, v_burn_fps**2 + 2.0 * mu_ft3_s2 * (1.0 / r_entry_ft - 1.0 / r_burn_ft)))
    cos_gamma = r_burn_ft * v_burn_fps / (r_entry_ft * v_entry)
    return -math.degrees(math.acos(cos_gamma)) if cos_gamma <= 1.0 else math.nan


def delta_v_for_gamma(
    coast: Coast, r_ft: NDArray[np.float64], v_rel_fps: NDArray[np.float64], gamma_deg: float
) -> tuple[float, NDArray[np.float64]]:
    """The Δv (ft/s) whose coast from this one state enters at the earth-relative flight-path angle gamma_deg, and
    that entry (a row of E_*): a secant on flown coasts from the two-body estimates of 0.9 and 1.1 times it."""
    r, v_in = float(np.linalg.norm(r_ft)), inertial_velocity(r_ft[None, :], v_rel_fps[None, :], coast.omega_rad_s)[0]
    speed, r_entry = float(np.linalg.norm(v_in)), float(coast.p[P_RE]) + coast.interface_altitude_ft
    guess = _two_body_delta_v(coast.mu_ft3_s2, r, speed, r_entry, gamma_deg)
    grazing = _two_body_delta_v(coast.mu_ft3_s2, r, speed, r_entry, 0.0)  # the least that comes down to r_entry

    def entry(dv: float) -> NDArray[np.float64]:
        rows = entry_states(coast, r_ft[None, :], burn(r_ft[None, :], v_rel_fps[None, :], dv, coast.omega_rad_s))
        row: NDArray[np.float64] = rows[0]
        return row

    x0, x1 = max(0.99 * guess, grazing + 0.5 * (guess - grazing)), 1.01 * guess
    f0, e1 = entry(x0)[E_GAMMA] - gamma_deg, entry(x1)
    for _ in range(30):
        f1 = e1[E_GAMMA] - gamma_deg
        if abs(f1) < GAMMA_TOLERANCE_DEG:
            return x1, e1
        if f1 == f0:
            break
        x0, x1, f0 = x1, x1 - f1 * (x1 - x0) / (f1 - f0), f1
        e1 = entry(x1)
    raise InputError("deorbit.entry_gamma_deg", f"no Δv found that enters at {gamma_deg:g} deg (last {x1:.2f} ft/s)")


def _two_body_delta_v(mu: float, r_burn: float, speed: float, r_entry: float, gamma_deg: float) -> float:
    """The horizontal-burn Δv whose two-body orbit crosses r_entry at gamma_deg (cos γ = h / (r V), solved for V)."""
    cg = math.cos(math.radians(gamma_deg))
    # (r_b v)^2 = (r_e cg)^2 (v^2 + 2 mu (1/r_e - 1/r_b)), so v^2 (r_b^2 - (r_e cg)^2) = (r_e cg)^2 2 mu (1/r_e - 1/r_b)
    num = (r_entry * cg) ** 2 * 2.0 * mu * (1.0 / r_entry - 1.0 / r_burn)
    den = r_burn**2 - (r_entry * cg) ** 2
    if den <= 0.0 or num <= 0.0:
        raise InputError("deorbit.entry_gamma_deg", f"{gamma_deg:g} deg cannot be reached from this orbit")
    return speed - math.sqrt(num / den)
