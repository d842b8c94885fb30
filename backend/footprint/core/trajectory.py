"""fly(): one entry trajectory from plain, already validated inputs, and its Trajectory record.

`simulate(spec)` gives the time histories and the summary; `simulate_summary(spec)` the same summary, equal to the
bit, without the histories (a Monte Carlo sample needs only its landing point and maxima): it converts to latitude,
longitude and down-range only the few rows the summary reads (`_track_rows`), not every row.
"""

import csv
import functools
import math
import os
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Any, NamedTuple

import numpy as np
from numpy.typing import NDArray

from footprint.core import constants as c
from footprint.core._jit import njit
from footprint.core.aero import Vehicle
from footprint.core.atmosphere import (
    DENSITY_NODE_COUNT,
    MODEL_IDS,
    density_factor_table,
    density_profile,
    isothermal_temperature_R,
)
from footprint.core.controls import C_START, C_START_ALT, START_ALTITUDE, START_ENTRY, steering_angle_deg
from footprint.core.dynamics import (
    INTEGRATOR_IDS,
    M_BANK_ACTIVE,
    M_BANK_DONE,
    M_HOLD_ALT,
    M_PULLED_OUT,
    M_PULLOUT_ALT,
    M_PULLOUT_T,
    M_REF_ANGLE,
    M_SIZE,
    M_TURN_DONE_DEG,
    P_ATM,
    P_ATM_T,
    P_CD_MULTIPLIER,
    P_CL_MULTIPLIER,
    P_DENSITY_DISPERSED,
    P_DENSITY_PROFILE,
    P_G0,
    P_H,
    P_INTEGRATOR,
    P_J,
    P_K,
    P_MAX_STEP,
    P_MU,
    P_OBLATE,
    P_OMEGA,
    P_POLE_X,
    P_RE,
    P_RHO0,
    P_RP,
    P_RTOL,
    P_SCALE_H,
    P_SIZE,
    P_SKIP_ALT,
    P_STOP_ALT,
    P_STOP_ENERGY,
    P_STOP_TIME,
    P_STOP_VEL,
    P_WS,
    energy_height_ft,
    steering_angles,
)
from footprint.core.errors import InputError, Stopped
from footprint.core.frames import (
    ecef_from_geodetic,
    flight_angles,
    geodetic_latitude_terms,
    heading_terms,
    horizon_basis,
    velocity_from_angles,
)
from footprint.core.guidance import Guidance, GuidedRecord, fly_guided
from footprint.core.heating import CorrelationHeating, ReferenceHeating, trajectory_heating
from footprint.core.integrate import (
    R_ALPHA,
    R_ALT,
    R_BANK,
    R_CD,
    R_CL,
    R_INTERIOR,
    R_MACH,
    R_Q,
    R_SIN_GAMMA,
    R_T,
    R_V,
    R_VX,
    R_VY,
    R_VZ,
    R_X,
    R_Y,
    R_Z,
    STOP_ASKED,
    STOP_REASONS,
    integrate,
)
from footprint.core.limits import flight_limits
from footprint.core.sampled import peak, step_integral
from footprint.core.sphere import MEAN_RADIUS_NMI, frame_axes, great_circle_frame, range_terms, unwrapped_correction


@dataclass(frozen=True)
class Planet:
    """Planet constants (App. A defaults) and atmosphere; every value can be overridden."""

    rotating: bool = True
    oblate: bool = True
    radius_ft: float = c.RADIUS_EQUATORIAL_FT
    polar_radius_ft: float = c.RADIUS_POLAR_FT
    mu_ft3_s2: float = c.MU_EARTH_FT3_S2
    rotation_rate_deg_s: float = c.OMEGA_EARTH_DEG_S
    j: float = c.J_ZONAL
    h: float = c.H_ZONAL
    k: float = c.K_ZONAL
    atmosphere: str = "ardc1959"
    rho0_slug_ft3: float = 0.0027
    scale_height_ft: float = 23_800.0
    temperature_R: float | None = None  # exponential model: defaults to g0 H / R


@dataclass(frozen=True)
class Entry:
    altitude_ft: float
    velocity_fps: float
    gamma_deg: float
    heading_deg: float = 90.0
    latitude_deg: float = 0.0  # geodetic
    longitude_deg: float = 0.0
    velocity_frame: str = "relative"  # "inertial": speed, gamma and heading are inertial


@dataclass(frozen=True)
class Stop:
    altitude_ft: float | None = 50_000.0
    velocity_fps: float | None = None
    time_s: float | None = None
    # guard: a flight that climbs this high has left. Lower skips fall back and are flown on: Appendix C's
    # 25,800 ft/s entries at (L/D)max skip to 1.6 million ft and come back.
    skip_altitude_ft: float = 10_000_000.0
    energy_ft: float | None = None  # energy height h + V^2/(2 g0): a guided flight's terminal energy (its guidance's)


@dataclass(frozen=True)
class Dispersion:
    """A perturbed vehicle and atmosphere (one Monte Carlo sample); the defaults fly the tables and the atmosphere
    model as given, to the bit. Wing loading is the vehicle's own (Vehicle.wing_loading_psf)."""

    cl_multiplier: float = 1.0  # times the aero table's CL (dynamics.flown_coefficients)
    cd_multiplier: float = 1.0  # times the aero table's CD
    # density times 1 + delta(h): delta at atmosphere.DENSITY_NODES_FT (0 to 400,000 ft every 10,000 ft), the natural
    # cubic spline between them; None: the model's density. It acts on the motion and on the heating alike.
    # Given as any sequence of numbers, kept as a tuple of floats (a Dispersion compares and hashes by value).
    density_delta: Sequence[float] | NDArray[np.float64] | None = None

    def __post_init__(self) -> None:
        for name in ("cl_multiplier", "cd_multiplier"):
            value = getattr(self, name)
            if not (math.isfinite(value) and value > 0.0):
                raise InputError(f"dispersion.{name}", f"{value!r} must be a finite number > 0")
        if self.density_delta is not None:
            delta = np.asarray(self.density_delta, dtype=float)
            if delta.shape != (DENSITY_NODE_COUNT,):
                raise InputError(
                    "dispersion.density_delta",
                    f"{delta.shape} values; need {DENSITY_NODE_COUNT}, one per node of atmosphere.DENSITY_NODES_FT",
                )
            if not np.all(np.isfinite(delta) & (delta > -1.0)):
                raise InputError(
                    "dispersion.density_delta",
                    f"min {np.min(delta)!r}: every delta must be finite and > -1 (a positive density)",
                )
            object.__setattr__(self, "density_delta", tuple(delta.tolist()))


@dataclass(frozen=True)
class FlightSpec:
    vehicle: Vehicle
    planet: Planet
    entry: Entry
    ctrl: NDArray[np.float64]  # from controls.pack_controls
    stop: Stop = field(default_factory=Stop)
    rtol: float = 1e-9
    max_step_s: float = 50.0
    integrator_method: str = "dopri5"  # a key of dynamics.INTEGRATOR_IDS
    max_steps: int = 200_000
    heating: ReferenceHeating | CorrelationHeating | None = None  # core.heating; None: no heating histories
    dispersion: Dispersion = field(default_factory=Dispersion)
    guidance: Guidance | None = None  # core.guidance: the bank flown by the predictor-corrector, to its terminal energy
    # asked before the flight and each guidance prediction: True stops it (errors.Stopped; a time limit, a cancel)
    stop_asked: Callable[[], bool] | None = None


class Trajectory:
    """Time histories (numpy arrays, units in the keys) and a summary of one flight. `history` is a dict, or a function
    that makes it on its first read: a door that needs only the summary never converts every row."""

    def __init__(
        self,
        summary: dict[str, Any],
        history: dict[str, NDArray[np.float64]] | Callable[[], dict[str, NDArray[np.float64]]],
        bank_table: dict[str, NDArray[np.float64]] | None = None,
    ) -> None:
        self.summary = summary
        self._history = history
        # a guided flight's bank as flown, a time table (time_s, bank_deg) that a bank table law flies again; else None
        self.bank_table = bank_table

    @property
    def history(self) -> dict[str, NDArray[np.float64]]:
        if callable(self._history):
            self._history = self._history()
        return self._history

    def __getstate__(self) -> dict[str, Any]:  # pickled (to and from Dask workers) with its histories made
        return {"summary": self.summary, "_history": self.history, "bank_table": self.bank_table}

    def write_csv(self, path: str | os.PathLike[str]) -> None:
        keys = list(self.history)
        with open(path, "w", newline="") as f:
            w = csv.writer(f)
            w.writerow(keys)
            for row in zip(*(self.history[k] for k in keys)):
                w.writerow([f"{v:.10g}" for v in row])


def pack_parameters(spec: FlightSpec) -> NDArray[np.float64]:
    pl, st = spec.planet, spec.stop
    p = np.zeros(P_SIZE)
    p[P_MU], p[P_RE], p[P_RP] = pl.mu_ft3_s2, pl.radius_ft, pl.polar_radius_ft
    p[P_J], p[P_H], p[P_K] = pl.j, pl.h, pl.k
    p[P_OMEGA] = math.radians(pl.rotation_rate_deg_s) if pl.rotating else 0.0
    p[P_OBLATE] = 1.0 if pl.oblate else 0.0
    p[P_ATM] = MODEL_IDS[pl.atmosphere]
    p[P_RHO0], p[P_SCALE_H] = pl.rho0_slug_ft3, pl.scale_height_ft
    p[P_ATM_T] = pl.temperature_R if pl.temperature_R is not None else isothermal_temperature_R(pl.scale_height_ft)
    p[P_WS] = spec.vehicle.wing_loading_psf
    p[P_G0] = c.G0_FT_S2
    p[P_STOP_ALT] = np.nan if st.altitude_ft is None else st.altitude_ft
    p[P_STOP_VEL] = np.nan if st.velocity_fps is None else st.velocity_fps
    p[P_STOP_TIME] = 50_000.0 if st.time_s is None else st.time_s
    p[P_SKIP_ALT] = st.skip_altitude_ft
    p[P_RTOL], p[P_MAX_STEP] = spec.rtol, spec.max_step_s
    p[P_INTEGRATOR] = INTEGRATOR_IDS[spec.integrator_method]
    energy = st.energy_ft if spec.guidance is None else spec.guidance.terminal_energy_ft
    p[P_STOP_ENERGY] = np.nan if energy is None else energy
    d = spec.dispersion
    p[P_CL_MULTIPLIER], p[P_CD_MULTIPLIER] = d.cl_multiplier, d.cd_multiplier
    if d.density_delta is not None:
        p[P_DENSITY_DISPERSED] = 1.0
        p[P_DENSITY_PROFILE:P_INTEGRATOR] = density_profile(d.density_delta)
    return p


def initial_state(spec: FlightSpec, p: NDArray[np.float64]) -> NDArray[np.float64]:
    """Earth-fixed state at entry; an inertial entry velocity loses the earth's rotation omega x r."""
    e, oblate = spec.entry, p[P_OBLATE] != 0.0
    x, y, z = ecef_from_geodetic(
        math.radians(e.latitude_deg), math.radians(e.longitude_deg), e.altitude_ft, p[P_RE], p[P_RP], oblate
    )
    vx, vy, vz = velocity_from_angles(x, y, z, e.velocity_fps, math.radians(e.gamma_deg), math.radians(e.heading_deg))
    if e.velocity_frame == "inertial":
        w = p[P_OMEGA]
        vx, vy = vx + w * y, vy - w * x  # v_rel = v_inertial - omega x r, omega along +z
    return np.array([x, y, z, vx, vy, vz])


def _set_left_pole(p: NDArray[np.float64], s0: NDArray[np.float64], heading_deg: float) -> None:
    """Left pole of the initial great circle (through the entry point along the named heading)."""
    ux, uy, uz, nx, ny, nz, ex, ey, ez = horizon_basis(s0[0], s0[1], s0[2])
    ch, sh = math.cos(math.radians(heading_deg)), math.sin(math.radians(heading_deg))
    dx, dy, dz = nx * ch + ex * sh, ny * ch + ey * sh, nz * ch + ez * sh
    p[P_POLE_X : P_POLE_X + 3] = (uy * dz - uz * dy, uz * dx - ux * dz, ux * dy - uy * dx)  # up x direction


def initial_mode(spec: FlightSpec, p: NDArray[np.float64], s0: NDArray[np.float64]) -> NDArray[np.float64]:
    mode = np.zeros(M_SIZE)
    ctrl = spec.ctrl
    zeta, heading = steering_angles(s0[0], s0[1], s0[2], s0[3], s0[4], s0[5], p)  # mypy cannot count a *s0 before p
    _, gamma0, _ = flight_angles(*s0)
    if gamma0 >= 0.0:  # entering level or climbing: pulled out from the start
        mode[M_PULLED_OUT], mode[M_PULLOUT_T], mode[M_PULLOUT_ALT] = 1.0, 0.0, spec.entry.altitude_ft
        mode[M_HOLD_ALT] = spec.entry.altitude_ft
    start = int(ctrl[C_START])
    if (
        start == START_ENTRY
        or (start == START_ALTITUDE and spec.entry.altitude_ft <= ctrl[C_START_ALT])
        or (mode[M_PULLED_OUT] and start != START_ALTITUDE)
    ):
        mode[M_BANK_ACTIVE] = 1.0
        mode[M_REF_ANGLE] = steering_angle_deg(ctrl, zeta, heading)
    return mode


class _Flight(NamedTuple):
    """What the integrator returns for one spec, with the parameters it flew."""

    p: NDArray[np.float64]
    rows: NDArray[np.float64]  # integrate.R_* columns, one row per step and event
    stop_code: int
    n_rhs: int
    mode: NDArray[np.float64]  # the mode at the stop (pull-out time and altitude, turn done)
    guided: GuidedRecord | None = None  # a guided flight's commands and cycles


def flight_inputs(spec: FlightSpec) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    """What integrate.integrate takes besides the vehicle and controls: (parameters, entry state, initial mode)."""
    p = pack_parameters(spec)
    s0 = initial_state(spec, p)
    _set_left_pole(p, s0, spec.entry.heading_deg)
    return p, s0, initial_mode(spec, p, s0)


def _fly(spec: FlightSpec) -> _Flight:
    if spec.stop_asked is not None and spec.stop_asked():
        raise Stopped("stopped before a flight")
    p, s0, mode = flight_inputs(spec)
    if spec.guidance is not None:
        guided = fly_guided(
            s0, p, spec.vehicle.blob, spec.ctrl, mode, spec.guidance, spec.heating, spec.max_steps, spec.stop_asked
        )
        if guided.stop_code == STOP_ASKED:
            raise Stopped(f"stopped at guidance cycle {len(guided.cycles) + 1:,}")
        return _Flight(p, guided.rows, guided.stop_code, guided.n_rhs, mode, guided)
    rows, stop_code, n_rhs = integrate(s0, p, spec.vehicle.blob, spec.ctrl, mode, spec.max_steps)
    return _Flight(p, rows, int(stop_code), int(n_rhs), mode)


def flown_rows(spec: FlightSpec) -> NDArray[np.float64]:
    """One flight's integrator rows (integrate.R_* columns), guided or not, as simulate flies it."""
    return _fly(spec).rows


def simulate(spec: FlightSpec) -> Trajectory:
    """Fly one trajectory (AFWAL-TR-82-3036 Sections II.2-II.3): its summary, and its time histories made when first
    read (the same summary, to the bit, either way: simulate_summary)."""
    f = _fly(spec)
    heating = _heating(spec, f.p, f.rows)
    table = None if f.guided is None else f.guided.bank_table()
    return Trajectory(_summary_of(spec, f, heating), functools.partial(_history, spec, f, heating), table)


def simulate_summary(spec: FlightSpec) -> dict[str, Any]:
    """simulate(spec).summary, equal to the bit, without the histories: the landing point, the pull-out and the
    maxima (heating from the altitude, velocity, alpha and time columns), for Monte Carlo samples and searches."""
    f = _fly(spec)
    return _summary_of(spec, f, _heating(spec, f.p, f.rows))


def _summary_of(
    spec: FlightSpec, f: _Flight, heating: tuple[NDArray[np.float64], NDArray[np.float64]] | None
) -> dict[str, Any]:
    """The summary from the track at the few rows it reads (_track_rows), equal to the bit to the full track's."""
    i_pullout = _pullout_row(f)
    e = spec.entry
    frame = _entry_frame(e.latitude_deg, e.longitude_deg, e.heading_deg)
    kept = _track_rows(f.rows, i_pullout, *frame)
    track = _track(spec, f.p, f.rows[kept], frame)
    return _summary(spec, f, track, int(np.searchsorted(kept, i_pullout)), heating)


def _history(
    spec: FlightSpec, f: _Flight, heating: tuple[NDArray[np.float64], NDArray[np.float64]] | None
) -> dict[str, NDArray[np.float64]]:
    """Every row's time histories (Trajectory.history)."""
    track = _track(spec, f.p, f.rows)
    rows = f.rows
    with np.errstate(divide="ignore", invalid="ignore"):
        ld = np.where(rows[:, R_CD] > 0, rows[:, R_CL] / rows[:, R_CD], np.nan)
    history = {
        "time_s": rows[:, R_T],
        "altitude_ft": rows[:, R_ALT],
        "velocity_fps": rows[:, R_V],
        "gamma_deg": track.gamma_deg,
        "heading_deg": track.heading_deg,
        "latitude_deg": track.latitude_deg,
        "longitude_deg": track.longitude_deg,
        "alpha_deg": rows[:, R_ALPHA],
        "bank_deg": rows[:, R_BANK],
        "mach": rows[:, R_MACH],
        "dynamic_pressure_psf": rows[:, R_Q],
        "cl": rows[:, R_CL],
        "cd": rows[:, R_CD],
        "lift_to_drag": ld,
        "downrange_nmi": track.downrange_nmi,
        "crossrange_nmi": track.crossrange_nmi,
    }
    if f.guided is not None:
        history |= f.guided.history()
    if heating is not None:
        history["heat_rate_btu_ft2_s"], history["temperature_R"] = heating
    return history


class _Track(NamedTuple):
    """Where a flight went, at some of its rows (every row for the histories): geodetic latitude, longitude,
    heading, flight-path angle, and down- and cross-range about the initial great circle (eqs. 8-11)."""

    latitude_deg: NDArray[np.float64]
    longitude_deg: NDArray[np.float64]
    heading_deg: NDArray[np.float64]
    gamma_deg: NDArray[np.float64]
    # unwrapped along the rows given: past half a circumference if they see every turn
    downrange_nmi: NDArray[np.float64]
    crossrange_nmi: NDArray[np.float64]


Frame = tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]


def _entry_frame(latitude_deg: float, longitude_deg: float, heading_deg: float) -> Frame:
    """great_circle_frame of an entry (read-only arrays), made once per entry point and heading: a door's repeated
    case, a footprint's flights and a dispersion's samples share it."""
    signs = tuple(math.copysign(1.0, v) for v in (latitude_deg, longitude_deg, heading_deg))  # -0.0 is not 0.0 here
    return _frame_of(float(latitude_deg), float(longitude_deg), float(heading_deg), signs)


@functools.lru_cache(maxsize=1024)
def _frame_of(latitude_deg: float, longitude_deg: float, heading_deg: float, signs: tuple[float, ...]) -> Frame:
    frame = great_circle_frame(latitude_deg, longitude_deg, heading_deg)
    for v in frame:
        v.flags.writeable = False
    return frame


TRACK_ANGLES = 5  # _track_terms: geodetic latitude, longitude, heading, down-range, cross-range


@njit
def _track_terms(
    rows: NDArray[np.float64],
    re_ft: float,
    rp_ft: float,
    oblate: bool,
    p0: NDArray[np.float64],
    d0: NDArray[np.float64],
    pole: NDArray[np.float64],
) -> NDArray[np.float64]:
    """terms (2, TRACK_ANGLES, rows): the track's angles at each row are atan2(terms[0], terms[1]) (numpy's, over
    the whole array at once): the geodetic latitude (frames.geodetic_latitude_terms), the longitude, the heading
    (frames.heading_terms: then taken into [0, 2 pi)), and the down- and cross-range of the geodetic latitude and
    longitude on the sphere (sphere.range_terms: the down-range then unwrapped), their sines and cosines from those
    terms, without trigonometry."""
    n = rows.shape[0]
    t = np.empty((2, TRACK_ANGLES, n))
    axes = frame_axes(p0, d0, pole)
    for i in range(n):
        x, y, z = rows[i, R_X], rows[i, R_Y], rows[i, R_Z]
        s, c = geodetic_latitude_terms(x, y, z, re_ft, rp_ft, oblate)
        unit = 1.0 / math.sqrt(s * s + c * c)
        sin_lat, cos_lat = s * unit, c * unit
        p = math.sqrt(x * x + y * y)
        cos_lon, sin_lon = (x / p, y / p) if p > 0.0 else (1.0, 0.0)  # on the axis: longitude atan2(0, 0) = 0
        t[0, 0, i], t[1, 0, i] = s, c
        t[0, 1, i], t[1, 1, i] = y, x
        t[0, 2, i], t[1, 2, i] = heading_terms(x, y, z, rows[i, R_VX], rows[i, R_VY], rows[i, R_VZ])
        along_d0, along_p0, along_n = range_terms(cos_lat * cos_lon, cos_lat * sin_lon, sin_lat, axes)
        t[0, 3, i], t[1, 3, i] = along_d0, along_p0
        t[0, 4, i], t[1, 4, i] = along_n, math.sqrt(along_p0 * along_p0 + along_d0 * along_d0)  # hypot: a call
    return t


@njit
def _wrap_track(angles: NDArray[np.float64]) -> None:
    """In place on _track_terms' angles: the heading into [0, 2 pi), the down-range unwrapped along the rows (as
    numpy.unwrap: sphere.unwrapped_correction)."""
    heading, down = angles[2], angles[3]
    correction, previous = 0.0, 0.0
    for i in range(angles.shape[1]):
        if heading[i] < 0.0:
            heading[i] += 2.0 * math.pi
        raw = down[i]
        if i > 0:
            correction = unwrapped_correction(raw, previous, correction)
        previous = raw
        down[i] = raw + correction


def _track(
    spec: FlightSpec,
    p: NDArray[np.float64],
    rows: NDArray[np.float64],
    frame: Frame | None = None,
) -> _Track:
    """The track at `rows` (recorded rows, in order; frame: the initial great circle's, if at hand). Each value
    depends on its own row only, but the down-range's unwrapping on the rows before it: `_track_rows` says which
    rows keep it equal to the full history's."""
    e = spec.entry
    p0, d0, n = _entry_frame(e.latitude_deg, e.longitude_deg, e.heading_deg) if frame is None else frame
    terms = _track_terms(rows, p[P_RE], p[P_RP], p[P_OBLATE] != 0.0, p0, d0, n)
    angles = np.arctan2(terms[0], terms[1])  # vectorized: per element as in any other call
    _wrap_track(angles)
    lat, lon, heading = np.degrees(angles[:3])
    down, cross = MEAN_RADIUS_NMI * angles[3:]
    gamma = np.degrees(np.arcsin(np.clip(rows[:, R_SIN_GAMMA], -1, 1)))
    return _Track(lat, lon, heading, gamma, down, cross)


# _track_rows: bounds on the along-track angle of the geocentric direction against the down-range's (geodetic
# latitude taken as spherical). The two directions differ by at most 0.0034 rad (0.19 deg, at 45 deg latitude), so
# within TRACK_NEAR_AXIS_RAD of the initial great circle (cos 1.3 = 0.27) the angles differ by at most 0.0126 rad.
TRACK_NEAR_AXIS_RAD = 1.3  # rad (4,470 nmi of cross-range); farther off the initial great circle every row is kept
TRACK_CUT_MARGIN_RAD = 0.05  # rad; > 3 x 0.0126 rad: keeps both rows of every step across the +-pi cut
TRACK_MAX_STEP_RAD = math.pi / 4  # rad; a larger step between rows (none seen): every row is kept
QUADRANT_RAD = math.pi / 2


@njit
def _track_rows(
    rows: NDArray[np.float64],
    i_pullout: int,
    p0: NDArray[np.float64],
    d0: NDArray[np.float64],
    pole: NDArray[np.float64],
) -> NDArray[np.intp]:
    """Indices of the rows the summary's track needs: the entry, pull-out and final rows, and enough rows between
    them that numpy.unwrap over their down-range angles adds the same corrections, at the same pairs of rows, as
    over every row, so that the final down-range is the full history's to the bit.

    numpy.unwrap corrects where neighbours differ by pi or more: only across the +-pi cut (behind the initial point)
    when steps are small. So both rows of every step across the cut are kept (every row whose geocentric
    along-track angle lies within the largest step plus TRACK_CUT_MARGIN_RAD of it), and both rows of every change
    of quadrant, so that rows kept next to each other never differ by pi or more. Far from the initial great
    circle (near its poles) the angle is ill-conditioned and every row is kept."""
    n = rows.shape[0]
    theta = np.empty(n)
    largest_step = 0.0
    near_axis = math.sin(TRACK_NEAR_AXIS_RAD)
    for i in range(n):
        x, y, z = rows[i, R_X], rows[i, R_Y], rows[i, R_Z]
        r = math.sqrt(x * x + y * y + z * z)
        if abs(x * pole[0] + y * pole[1] + z * pole[2]) > near_axis * r:
            return np.arange(n)
        theta[i] = math.atan2(x * d0[0] + y * d0[1] + z * d0[2], x * p0[0] + y * p0[1] + z * p0[2])
        if not math.isfinite(theta[i]):
            return np.arange(n)
        if i > 0:
            step = abs(theta[i] - theta[i - 1])
            largest_step = max(largest_step, min(step, 2.0 * math.pi - step))
    if largest_step > TRACK_MAX_STEP_RAD:
        return np.arange(n)
    near_cut = math.pi - largest_step - TRACK_CUT_MARGIN_RAD
    keep = np.zeros(n, dtype=np.bool_)
    keep[0] = keep[i_pullout] = keep[n - 1] = True
    for i in range(n):
        if abs(theta[i]) > near_cut:
            keep[i] = True
        if i > 0 and math.floor(theta[i] / QUADRANT_RAD) != math.floor(theta[i - 1] / QUADRANT_RAD):
            keep[i - 1] = keep[i] = True
    return np.flatnonzero(keep)


def _pullout_row(f: _Flight) -> int:
    """The row of the pull-out event (0 when the flight never pulled out)."""
    return int(np.searchsorted(f.rows[:, R_T], f.mode[M_PULLOUT_T])) if f.mode[M_PULLED_OUT] != 0.0 else 0


def _heating(
    spec: FlightSpec, p: NDArray[np.float64], rows: NDArray[np.float64]
) -> tuple[NDArray[np.float64], NDArray[np.float64]] | None:
    """(heat_rate, temperature) along every row, or None without a heating model (Section III: evaluated on the
    histories, no effect on the motion). A dispersed density heats as it decelerates: the same factor."""
    if spec.heating is None:
        return None
    factor = None
    if p[P_DENSITY_DISPERSED] != 0.0:
        factor = density_factor_table(p[P_DENSITY_PROFILE:P_INTEGRATOR], rows[:, R_ALT])
    return trajectory_heating(
        spec.heating,
        rows[:, R_ALT],
        rows[:, R_V],
        rows[:, R_ALPHA],
        (p[P_ATM], p[P_RHO0], p[P_SCALE_H], p[P_ATM_T]),
        rows[:, R_T],
        density_factor=factor,
    )


def _summary(
    spec: FlightSpec,
    f: _Flight,
    track: _Track,
    at_pullout: int,
    heating: tuple[NDArray[np.float64], NDArray[np.float64]] | None,
) -> dict[str, Any]:
    """The summary of a flight from its rows and its track (whose last entry is the final row and entry
    `at_pullout` the pull-out row)."""
    rows, mode = f.rows, f.mode
    t = rows[:, R_T]
    max_heat_rate = max_temperature = heat_load = None
    if heating is not None:
        heat_rate, temperature = heating
        max_heat_rate = peak(t, heat_rate)
        heat_load = step_integral(t, heat_rate, rows[:, R_INTERIOR] == 0.0)  # integrated heat load
        max_temperature = peak(t, temperature) if np.all(np.isfinite(temperature)) else None
    pulled_out = mode[M_PULLED_OUT] != 0.0
    i_po = _pullout_row(f)  # an event row
    summary: dict[str, Any] = {
        "downrange_nmi": float(track.downrange_nmi[-1]),
        "crossrange_nmi": float(track.crossrange_nmi[-1]),
        "flight_time_s": float(rows[-1, R_T]),
        "final_altitude_ft": float(rows[-1, R_ALT]),
        "final_velocity_fps": float(rows[-1, R_V]),
        "final_gamma_deg": float(track.gamma_deg[-1]),
        "final_latitude_deg": float(track.latitude_deg[-1]),
        "final_longitude_deg": float(track.longitude_deg[-1]),
        "final_heading_deg": float(track.heading_deg[-1]),
        "pullout_altitude_ft": float(mode[M_PULLOUT_ALT]) if pulled_out else None,
        "pullout_time_s": float(mode[M_PULLOUT_T]) if pulled_out else None,
        "pullout_downrange_nmi": float(track.downrange_nmi[at_pullout]) if pulled_out else None,
        "pullout_velocity_fps": float(rows[i_po, R_V]) if pulled_out else None,
        "turn_deg": float(mode[M_TURN_DONE_DEG]) if mode[M_BANK_DONE] != 0.0 else None,  # staged, constant altitude
        "max_dynamic_pressure_psf": peak(t, rows[:, R_Q]),
        # load factor sqrt(L^2 + D^2) / W = q sqrt(CL^2 + CD^2) / (W/S)
        "max_load_factor": peak(t, rows[:, R_Q] * np.hypot(rows[:, R_CL], rows[:, R_CD]))
        / spec.vehicle.wing_loading_psf,
        "final_energy_ft": float(energy_height_ft(rows[-1, R_ALT], rows[-1, R_V], c.G0_FT_S2)),
        "heat_load_btu_ft2": heat_load,
        "max_heat_rate_btu_ft2_s": max_heat_rate,
        "max_temperature_R": max_temperature,
        "stop_reason": STOP_REASONS[f.stop_code],
        "vehicle": spec.vehicle.id,
        "steps": int(rows.shape[0] - 1),
        "rhs_evaluations": f.n_rhs,
    }
    summary |= flight_limits(summary, spec.vehicle.limits)  # each limit, its margin, and whether it held
    if f.guided is not None:
        summary["guidance"] = f.guided.summary(summary)
    return summary
