"""True optimal trajectories: the flight model as a nonlinear program, solved by IPOPT through CasADi.

Transcription: direct collocation on Legendre-Gauss-Radau points (Radau IIA, `degree` points per mesh
interval, order 2 degree - 1; Betts, Practical Methods for Optimal Control, 2nd ed., sec. 4.5; Garg et al.,
Automatica 46, 2010). States (core.model_casadi: r, longitude, geocentric latitude, V, gamma, psi, and the
heat load when asked for) at every collocation point, the angles those of the entry's frame (entry_frame: its
equator is the entry's great circle, so that a flight over a geographic pole is regular; the answer's latitudes,
longitudes and headings are geographic); alpha and bank at the mesh nodes, LINEAR in time
between them, so the optimum is exactly the time tables that `fly` takes (bank and alpha tables against
time): the re-flight by core.trajectory.simulate checks the transcription, not an interpolation of ours.
Free final time; the stop altitude is the terminal condition (and a floor along the way, so that the
re-flight does not stop early); terminal constraints on summary quantities; path constraints on the
radiation-equilibrium temperature, heat rate, dynamic pressure and load factor at every collocation point.

Every optimum is flown again (`simulate`, the compiled integrator, the tables' own linear interpolation and
the integrator's linear tables and atmosphere) and the mesh is doubled until the flown end state agrees:
final latitude and longitude within AGREE_DEG, down-range within AGREE_DOWNRANGE_REL.
Failure is an answer: a result says "optimal", "infeasible" or "not_converged" with the largest constraint
violation and keeps the last iterate.
"""

from __future__ import annotations

import math
import os
import shlex
import shutil
import sys
import time
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any

import casadi as ca
import numpy as np
from numpy.typing import ArrayLike, NDArray

from footprint.core import constants as c
from footprint.core.controls import BANK_ZERO, C_BANK_LAW, pack_controls, replace_bank_law
from footprint.core.errors import NoOptimum  # noqa: F401 (the collocation's failure, raised by its callers)
from footprint.core.frames import ecef_from_geodetic, velocity_from_angles
from footprint.core.model_casadi import Expr, FlightModel, geodetic
from footprint.core.optimize import Constraint
from footprint.core.sphere import MEAN_RADIUS_NMI, great_circle_frame, wrap_longitude
from footprint.core.trajectory import (
    Dispersion,
    Entry,
    FlightSpec,
    Trajectory,
    initial_state,
    pack_parameters,
    simulate,
)

TERMINAL = (
    "crossrange_nmi",
    "downrange_nmi",
    "final_latitude_deg",
    "final_longitude_deg",
    "final_velocity_fps",
    "final_gamma_deg",
    "final_heading_deg",
    "flight_time_s",
    "final_energy_ft",
    "heat_load_btu_ft2",
)
PATH = ("max_temperature_R", "max_heat_rate_btu_ft2_s", "max_dynamic_pressure_psf", "max_load_factor")
PATH_UNITS = {
    "max_temperature_R": "degR",
    "max_heat_rate_btu_ft2_s": "Btu/ft^2/s",
    "max_dynamic_pressure_psf": "lb/ft^2",
    "max_load_factor": "g",
}
QUANTITIES = TERMINAL + PATH
# a typical size of each quantity: objective and constraints enter the NLP divided by it
SCALE = {
    "crossrange_nmi": 1e3,
    "downrange_nmi": 1e3,
    "final_latitude_deg": 10.0,
    "final_longitude_deg": 10.0,
    "final_velocity_fps": 1e3,
    "final_gamma_deg": 1.0,
    "final_heading_deg": 10.0,
    "flight_time_s": 1e3,
    "final_energy_ft": 1e5,
    "heat_load_btu_ft2": 1e5,
    "max_temperature_R": 1e3,
    "max_heat_rate_btu_ft2_s": 100.0,
    "max_dynamic_pressure_psf": 100.0,
    "max_load_factor": 1.0,
}
AGREE_DEG = 0.01  # issue 12: flown final latitude and longitude within 0.01 deg of the NLP's
AGREE_DOWNRANGE_REL = 1e-3  # and down-range within 0.1 %
# state scales: r = R_e + H_SCALE x0, V = V_SCALE x3 (angles in rad); time T_SCALE; alpha, bank in these degrees
H_SCALE_FT, V_SCALE_FPS, T_SCALE_S = 1e5, 1e4, 1e3
# the floor along the way, above the stop altitude, tapering to it over the flight's last FLOOR_TAPER_FRACTION: the
# integrator ends the re-flight at the first touch, and an optimum that touched the stop altitude at a collocation
# point and climbed again (Betts' shuttle flying inverted) dipped below it between the points (0.4 deg off)
FLOOR_MARGIN_FT, FLOOR_TAPER_FRACTION = 1000.0, 0.02
ALPHA_SCALE_DEG, BANK_SCALE_DEG = 10.0, 45.0
# the tables' corners are rounded over this fraction of their shortest interval, stage by stage, each stage
# started from the last: wide corners converge from a rough guess, narrow ones are the integrator's tables.
# Measured on the L/D 1.89 maximum cross-range: 0.2 re-flies within 0.01 deg, 0.05 within 0.0025 deg. Halving
# matters: from 0.2 straight to 0.05 IPOPT ran out of 3,000 iterations (with the compiled point function),
# through 0.1 it needs 49 + 90; 0.02 needs thousands and 0.01 fails (the corners' curvature grows as 1/width).
SMOOTHING_STAGES = (0.2, 0.1, 0.05)
# the rates' penalty (Problem.smoothing_weight) of every stage but a last polish with a hundredth of it: it removes the
# singular directions of the controls where the air is too thin to act (the plunge from 364,800 ft: the
# L/D 1.89 maximum cross-range takes 1,928 iterations without it, 186 with it), and the polish takes its bias
# out (it moved Betts' heat-limited final time by 8 s); without any the L/D 1.89 polish does not converge
POLISH_WEIGHT = 1e-2  # the polish's share of smoothing_weight
# the polish's iterations: a refinement of an optimum that does not end within these keeps the stage before it
# (on the L/D 1.89 tables it ran out of 3,000 iterations, 230 s, for 1.2 nmi of cross-range)
POLISH_MAX_ITERATIONS = 300
# a path limit's peak on the flight that least exceeds the limits counts as past it beyond this share of the limit
EXCESS_RTOL = 1e-4
ITERATIONS_HALF_WAY = 50  # a progress estimate: typical iterations of a stage (Betts 20-50, the L/D 1.89 50-120)
STATUS_OF_IPOPT = {
    "Solve_Succeeded": "optimal",
    "Solved_To_Acceptable_Level": "optimal",
    "Infeasible_Problem_Detected": "infeasible",
    "User_Requested_Stop": "stopped",
}
# on_iteration(iteration, stage, stages) after every IPOPT iteration, and on_progress(fraction, note): True stops
OnIteration = Callable[[int, int, int], bool | None]
OnProgress = Callable[[float, str], bool | None]


def _jit_options() -> dict[str, Any] | None:
    """CasADi options that compile a point function and its derivatives with gcc -O1 (None without a compiler).

    The tables' point function is the NLP's cost: compiled, its Hessian takes 24 ms per L/D 1.89 iteration
    instead of 48 ms in CasADi's SX virtual machine (and the expanded NLP costs 17 s to build). Objects are
    kept by core/_cc_cache.py, so only the first process that meets a model compiles it (~45 s)."""
    compiler = os.environ.get("CC", "gcc")
    if os.environ.get("FOOTPRINT_NO_JIT", "") not in ("", "0") or shutil.which(compiler) is None:
        return None
    root = Path(os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache") / "footprint" / f"casadi-{ca.__version__}"  # type: ignore[attr-defined]  # CasADi's stubs omit __version__
    (root / "build").mkdir(parents=True, exist_ok=True)
    command = " ".join(
        shlex.quote(a) for a in (sys.executable, str(Path(__file__).with_name("_cc_cache.py")), f"--cache={root}")
    )
    return {
        "jit": True,
        "compiler": "shell",
        "jit_options": {
            "compiler": command,
            "linker": command,
            "flags": ["-O1"],
            "verbose": False,
            "directory": f"{root / 'build'}/",
        },
    }


def _map_threads(compiled: bool) -> tuple[str, int] | tuple[()]:
    """CasADi map arguments that evaluate a compiled point function (and so its derivatives) on every core:
    the L/D 1.89 true footprint 25-28 s instead of 27-33 on 2 cores; the SX virtual machine stays serial."""
    return ("thread", os.cpu_count() or 1) if compiled else ()


class _Iterations(ca.Callback):
    """IPOPT's iteration callback (its option iteration_callback): counts the iterations and passes each one to
    `report(iteration, stage, stages)`, set per solve; a report that returns True stops IPOPT
    (User_Requested_Stop)."""

    report: OnIteration | None

    def __init__(self, nx: int, ng: int, np_: int) -> None:
        ca.Callback.__init__(self)
        self.sizes = {"x": nx, "lam_x": nx, "g": ng, "lam_g": ng, "f": 1, "lam_p": np_}
        self.report, self.iteration, self.stage, self.stages = None, 0, 0, 1
        self.construct("iterations", {})

    def get_n_in(self) -> int:
        return ca.nlpsol_n_out()

    def get_n_out(self) -> int:
        return 1

    def get_name_in(self, i: int) -> str:
        return ca.nlpsol_out(i)

    def get_name_out(self, i: int) -> str:
        return "stop"

    def get_sparsity_in(self, i: int) -> ca.Sparsity:
        return ca.Sparsity.dense(self.sizes[ca.nlpsol_out(i)], 1)

    def eval(self, arg: Sequence[ca.DM]) -> list[int]:
        self.iteration += 1  # IPOPT calls at its iteration 0 of every stage too
        stop = self.report is not None and self.report(max(self.iteration, 0), self.stage, self.stages)
        return [1 if stop else 0]


def iteration_progress(on_progress: OnProgress, share: tuple[float, float] = (0.0, 1.0), what: str = "") -> OnIteration:
    """An on_iteration that reports on_progress(fraction, note) within share (from, to) of a larger piece of work:
    iterations have no known end, so each stage moves k / (k + ITERATIONS_HALF_WAY) of its part."""
    lo, hi = share

    def on_iteration(iteration: int, stage: int, stages: int) -> bool | None:
        fraction = (stage + iteration / (iteration + ITERATIONS_HALF_WAY)) / stages
        note = f"{what}IPOPT iteration {iteration}" + (f", stage {stage + 1} of {stages}" if stages > 1 else "")
        return on_progress(lo + (hi - lo) * fraction, note)

    return on_iteration


class CollocationError(ValueError):
    """A problem the transcription cannot pose (one line naming the field)."""


@dataclass(frozen=True)
class Problem:
    """An optimal-control problem on the flight model of `base` (its vehicle, planet, entry, stop altitude,
    heating model; its control laws only serve as the default initial guess).

    objective: ((quantity, weight), ...), maximized or minimized as `goal`; constraints: optimize.Constraint
    (equals: within +- tolerance/2, 0 by default; at_most / at_least: exactly); bounds and rate limits on
    the controls in deg and deg/s."""

    base: FlightSpec
    objective: tuple[tuple[str, float], ...] = (("crossrange_nmi", 1.0),)
    goal: str = "max"
    constraints: tuple[Constraint, ...] = ()
    alpha_bounds_deg: tuple[float, float] | None = None  # default: the vehicle's valid alpha range
    bank_bounds_deg: tuple[float, float] = (-180.0, 180.0)
    alpha_rate_deg_s: float | None = None
    bank_rate_deg_s: float | None = None
    intervals: int = 100
    degree: int = 3
    max_intervals: int = 400  # the mesh is refined up to this many intervals until the optimum settles (solve)
    mesh_tolerance: float | None = None  # the objective's change that counts as settled (objective_tolerance)
    max_iterations: int = 3000
    max_seconds: float = 600.0  # IPOPT's wall time per solve: far from any optimum an iteration can take seconds
    tolerance: float = 1e-8  # IPOPT's tol (scaled NLP)
    smoothing_weight: float = 1e-4  # penalty on the controls' scaled rates before the polish (SMOOTHING_STAGES)
    polish: bool = True  # a last stage at POLISH_WEIGHT (an optimal footprint's points skip it: 0.05 % of range)
    starts: int = 1  # first guesses solved on the first mesh, the best kept (first_guesses: a multi-modal payoff)


@dataclass
class Guess:
    """States (n x 6: r ft, lon rad, lat_c rad, V ft/s, gamma rad, psi rad; the angles in entry_frame's
    coordinates) and controls (n x 2: alpha, bank deg) at times tau * final_time_s, tau in [0, 1] increasing;
    optional heat load (n)."""

    tau: NDArray[np.float64]
    states: NDArray[np.float64]
    controls: NDArray[np.float64]
    final_time_s: float
    downrange_nmi: float
    heat_load: NDArray[np.float64] | None = None

    def at(
        self, tau: NDArray[np.float64]
    ) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64] | None]:
        s = np.column_stack([np.interp(tau, self.tau, self.states[:, i]) for i in range(6)])
        u = np.column_stack([np.interp(tau, self.tau, self.controls[:, i]) for i in range(2)])
        q = None if self.heat_load is None else np.interp(tau, self.tau, self.heat_load)
        return s, u, q


@dataclass
class Result:
    status: str  # "optimal" | "infeasible" | "not_converged" | "stopped" (on_iteration asked)
    message: str  # IPOPT's return status, or the largest violation
    objective: float  # in the quantities' own units (weighted sum), the NLP's value
    summary: dict[str, Any]  # the NLP's end state and path maxima, trajectory-summary keys
    history: dict[str, NDArray[np.float64]]  # at the collocation points: time_s, altitude_ft, ..., alpha_deg, bank_deg
    controls: dict[str, NDArray[np.float64]]  # the node tables: time_s, alpha_deg, bank_deg
    refly: dict[str, Any] | None  # summary of the re-flight by simulate()
    agreement: dict[str, float] | None  # NLP against re-flight
    max_violation: float  # largest constraint violation of the (scaled) NLP at the returned point
    iterations: int
    seconds: float
    intervals: int
    guess: Guess | None = field(repr=False, default=None)
    mesh_change: float | None = None  # the objective's change under the last mesh refinement (solve)
    mesh_remaining: float | None = None  # how far it may still move (remaining_move of the refinements' changes)
    advice: str = ""  # what to change, when there is no optimum (NO_OPTIMUM_ADVICE unless said)
    solver_state: dict[str, NDArray[np.float64]] | None = field(
        repr=False, default=None
    )  # x, lam_x, lam_g for a warm start
    start_objectives: list[float | None] | None = None  # each start's optimum on the first mesh (None: none found)
    # an infeasible end's diagnosis: each path limit's peak on the flight that least exceeds them (_path_limits_said)
    least_path_peaks: dict[str, float | None] | None = None

    @property
    def ok(self) -> bool:
        return self.status == "optimal"

    feasible = ok  # the name the parameter search's result uses

    def one_line(self) -> str:
        if self.ok:
            return "optimal"
        return f"{self.status.replace('_', ' ')}: {self.advice or NO_OPTIMUM_ADVICE}; {self.message}"

    def to_dict(self) -> dict[str, Any]:
        arrays = {k: v.tolist() for k, v in self.history.items()}
        return {
            "method": "collocation",
            "status": self.status,
            "message": self.message,
            "feasible": self.ok,
            "objective": self.objective,
            "summary": self.summary,
            "controls": {k: v.tolist() for k, v in self.controls.items()},
            "history": arrays,
            "refly": self.refly,
            "agreement": self.agreement,
            "max_violation": self.max_violation,
            "iterations": self.iterations,
            "seconds": self.seconds,
            "intervals": self.intervals,
            "mesh_change": self.mesh_change,
            "mesh_remaining": self.mesh_remaining,
            "start_objectives": self.start_objectives,
            "least_path_peaks": self.least_path_peaks,
        }


# ----------------------------------------------------------------------------------------------- guesses
def entry_frame(entry: Entry) -> NDArray[np.float64]:
    """The frame of the NLP's spherical coordinates (rows: its axes in earth-fixed components): x to the entry
    point, y along its heading, z to the left pole of its great circle (sphere.great_circle_frame). The
    coordinates' poles, where longitude and heading are singular, then lie 90 deg across the flight, and a flight
    over a geographic pole is as regular as one along the equator. Components under 1e-15 are round-off of the
    angles' sines and cosines, set to 0: an equatorial entry heading east is the geographic frame turned about its
    axis, whose equations keep their geographic form (model_casadi.FlightModel's axis)."""
    frame = np.array(great_circle_frame(entry.latitude_deg, entry.longitude_deg, entry.heading_deg))
    frame[np.abs(frame) < 1e-15] = 0.0
    return frame


def frame_states(
    frame: NDArray[np.float64], positions_ft: NDArray[np.float64], velocities_fps: NDArray[np.float64]
) -> NDArray[np.float64]:
    """(r, lon, lat_c, V, gamma, psi) in `frame`'s coordinates (n x 6) of earth-fixed positions and velocities
    (n x 3); psi in the geocentric horizon, as core.frames.flight_angles."""
    x, v = positions_ft @ frame.T, velocities_fps @ frame.T
    r = np.linalg.norm(x, axis=1)
    lon, lat = np.arctan2(x[:, 1], x[:, 0]), np.arctan2(x[:, 2], np.hypot(x[:, 0], x[:, 1]))
    so, co, sl, cl = np.sin(lon), np.cos(lon), np.sin(lat), np.cos(lat)
    v_up = (v * x).sum(axis=1) / r
    v_east = -v[:, 0] * so + v[:, 1] * co
    v_north = -v[:, 0] * sl * co - v[:, 1] * sl * so + v[:, 2] * cl
    speed = np.linalg.norm(v, axis=1)
    return np.column_stack(
        [r, lon, lat, speed, np.arctan2(v_up, np.hypot(v_east, v_north)), np.arctan2(v_east, v_north)]
    )


def geographic(
    frame: NDArray[np.float64], lon: Expr, lat: Expr, psi: Expr, lon_ref: Expr = 0.0, heading_ref: Expr = 0.0
) -> tuple[Expr, Expr, Expr]:
    """(geocentric latitude, longitude, heading) rad of points given by their longitude, latitude and heading in
    `frame`'s coordinates; the longitude within pi of lon_ref and the heading within pi of heading_ref (continuous
    for the NLP away from the opposite meridian and heading). CasADi expressions, or numbers (then DMs)."""
    # a frame turned about the axis (an equatorial entry heading east): the frame's own angles, the longitude offset,
    # so the NLP has the geographic form it had (through the general turn, the most-final-energy fly-there took 250
    # to 2,000 IPOPT iterations or none converged, by the round-off of its guess; so, 254 to 440, as before)
    if frame[2, 0] == frame[2, 1] == 0.0 and frame[2, 2] == 1.0:
        offset = math.atan2(frame[0, 1], frame[0, 0])
        return lat, lon_ref + _within_pi(lon + offset - lon_ref), heading_ref + _within_pi(psi - heading_ref)
    so, co, sl, cl, sp, cp = ca.sin(lon), ca.cos(lon), ca.sin(lat), ca.cos(lat), ca.sin(psi), ca.cos(psi)
    ux, uy, uz = earth_fixed_position(frame, lon, lat)
    h = (-sp * so - cp * sl * co, sp * co - cp * sl * so, cp * cl)  # sin(psi) east + cos(psi) north, in the frame
    hx, hy, hz = _earth_fixed(frame, h)
    rho2 = ux * ux + uy * uy
    # east = (-uy, ux, 0) / rho and north = (-uz ux, -uz uy, rho^2) / rho: the heading's atan2 without 1 / rho
    east, north = -hx * uy + hy * ux, -uz * (hx * ux + hy * uy) + hz * rho2
    c_lon, s_lon, c_hdg, s_hdg = ca.cos(lon_ref), ca.sin(lon_ref), ca.cos(heading_ref), ca.sin(heading_ref)
    return (
        ca.atan2(uz, ca.sqrt(rho2)),
        lon_ref + ca.atan2(uy * c_lon - ux * s_lon, ux * c_lon + uy * s_lon),
        heading_ref + ca.atan2(east * c_hdg - north * s_hdg, north * c_hdg + east * s_hdg),
    )


def earth_fixed_position(frame: NDArray[np.float64], lon: Expr, lat: Expr) -> tuple[Expr, Expr, Expr]:
    """The earth-fixed unit vector of the direction at `frame`'s longitude and latitude (rad)."""
    return _earth_fixed(frame, (ca.cos(lat) * ca.cos(lon), ca.cos(lat) * ca.sin(lon), ca.sin(lat)))


def _earth_fixed(frame: NDArray[np.float64], v: tuple[Expr, Expr, Expr]) -> tuple[Expr, Expr, Expr]:
    x, y, z = (sum(frame[i, j] * v[i] for i in range(3)) for j in range(3))  # frame^T v
    return x, y, z


def _within_pi(angle: Expr) -> Expr:
    """The angle moved by whole turns into (-pi, pi], smoothly away from the cut."""
    return ca.atan2(ca.sin(angle), ca.cos(angle))


def geographic_track(
    frame: NDArray[np.float64], states: NDArray[np.float64]
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    """geographic() of a flight's states (n x 6 as frame_states, from the entry) as arrays: (geocentric
    latitude, longitude, heading) rad, the longitude and heading continuous from the entry's (heading in [0, 2 pi)
    there, as core.frames.flight_angles)."""
    out = geographic(frame, states[:, 1], states[:, 2], states[:, 5])
    lat_c, lon, heading = (np.asarray(v, dtype=float).ravel() for v in out)
    heading[0] %= 2.0 * np.pi
    return lat_c, np.unwrap(lon), np.unwrap(heading)


def entry_state(spec: FlightSpec, frame: NDArray[np.float64]) -> NDArray[np.float64]:
    """The entry's (r, lon, lat_c, V, gamma, psi) in `frame`'s coordinates."""
    s0 = initial_state(spec, pack_parameters(spec))
    state: NDArray[np.float64] = frame_states(frame, s0[None, :3], s0[None, 3:])[0]
    return state


NO_OPTIMUM_ADVICE = (
    "to change: a bank law in the case that flies near the answer (the first guess), a wider "
    "tolerance on a constraint, more collocation.max_iterations or max_seconds, or a target within "
    "the vehicle's reach"
)
GUESS_BISECTIONS = 24  # constant-bank flights to land the first guess at a down-range target (to ~1e-6 of the range)


def first_guess(problem: Problem) -> Guess:
    """The base's own control laws flown; but when they fly wings level and a down-range is asked short of that
    flight (equals, or at_most), the constant bank whose flight lands there, bisected on the integrator. From the
    wings-level flight of the L/D 1.89 page defaults (14,869 nmi for a 4,000 nmi target) IPOPT ran 1,400 iterations
    without an optimum; from the banked one it converges (issue 25 item 3)."""
    spec = problem.base
    target = next(
        (k.target for k in problem.constraints if k.quantity == "downrange_nmi" and k.kind in ("equals", "at_most")),
        None,
    )
    flown = simulate(spec)
    if target is None or int(spec.ctrl[C_BANK_LAW]) != BANK_ZERO or flown.summary["downrange_nmi"] <= target:
        return guess_from_trajectory(spec, flown)
    low, high = 0.0, 90.0  # deg: wings level flies furthest; at 90 deg the lift holds no altitude
    for _ in range(GUESS_BISECTIONS):
        bank = 0.5 * (low + high)
        trial = simulate(replace(spec, ctrl=replace_bank_law(spec.ctrl, "constant", bank_deg=bank)))
        landed = trial.summary.get("downrange_nmi")
        if landed is not None and math.isfinite(landed) and landed > target:
            low, flown = bank, trial
        else:
            high = bank
    return guess_from_trajectory(spec, flown)


def first_guesses(problem: Problem) -> list[Guess]:
    """problem.starts first guesses: first_guess, then flights of the base's alpha law at constant banks spread
    over (0, 90) deg (90 k / starts), on the side the first one turns to, within the bank bounds. A payoff with
    several local optima (the most final energy at a site: one skip or several) ends in the one its guess leads
    to; from the fly-there example's guess, 15.5 N 50.5 E, 5.45 M ft where a 20 deg guess reaches 5.89 M."""
    first = first_guess(problem)
    side = 1.0 if first.states[-1, 2] >= 0.0 else -1.0  # the cross-range angle at its end (entry_frame's latitude)
    lo, hi = problem.bank_bounds_deg
    spec = problem.base
    guesses = [first]
    for k in range(1, problem.starts):
        bank = min(max(side * 90.0 * k / problem.starts, lo), hi)
        guesses.append(
            guess_from_trajectory(
                spec, simulate(replace(spec, ctrl=replace_bank_law(spec.ctrl, "constant", bank_deg=bank)))
            )
        )
    return guesses


def guess_from_trajectory(spec: FlightSpec, trajectory: Trajectory) -> Guess:
    """A guess from a flown trajectory: its histories' earth-fixed states in entry_frame's coordinates."""
    h = trajectory.history
    pl = spec.planet
    lat, lon, gamma, heading = (np.radians(h[k]) for k in ("latitude_deg", "longitude_deg", "gamma_deg", "heading_deg"))
    positions, velocities = [], []
    for i, (alt, v) in enumerate(zip(h["altitude_ft"], h["velocity_fps"])):
        x, y, z = ecef_from_geodetic(lat[i], lon[i], alt, pl.radius_ft, pl.polar_radius_ft, pl.oblate)
        positions.append((x, y, z))
        velocities.append(velocity_from_angles(x, y, z, v, gamma[i], heading[i]))
    t = np.asarray(h["time_s"], float)
    keep = np.concatenate(([True], np.diff(t) > 0))  # event rows repeat their time
    frame = entry_frame(spec.entry)
    states = frame_states(frame, np.array(positions), np.array(velocities))[keep]
    states[:, 1], states[:, 5] = np.unwrap(states[:, 1]), np.unwrap(states[:, 5])
    s0 = entry_state(spec, frame)
    states[:, 1] += s0[1] - states[0, 1]  # the unwrapped longitude and heading continue from the entry's
    states[:, 5] += s0[5] - states[0, 5]
    states[0] = s0  # exactly the entry state
    controls = np.column_stack([h["alpha_deg"], h["bank_deg"]])[keep]
    return Guess(
        tau=t[keep] / t[-1],
        states=states,
        controls=controls,
        final_time_s=float(t[-1]),
        downrange_nmi=float(trajectory.summary["downrange_nmi"]),
    )


# ------------------------------------------------------------------------------------------ transcription
def uniform_mesh(intervals: int) -> NDArray[np.float64]:
    return np.linspace(0.0, 1.0, intervals + 1)


def control_errors(controls: Mapping[str, NDArray[np.float64]]) -> NDArray[np.float64]:
    """Each interval's error of the linear controls (scaled alpha and bank), h^2 |u''| / 8 with u'' the second
    divided difference of the node values at either end (the interpolation error bound, e.g. Burden & Faires,
    thm. 3.3): large where a path limit or a turn bends the optimal control between nodes."""
    t = np.asarray(controls["time_s"], float)
    u = np.vstack([controls["alpha_deg"] / ALPHA_SCALE_DEG, controls["bank_deg"] / BANK_SCALE_DEG])
    tau = (t - t[0]) / (t[-1] - t[0])
    h = np.diff(tau)
    slope = np.diff(u, axis=1) / h
    second = np.zeros_like(u)
    second[:, 1:-1] = 2.0 * np.diff(slope, axis=1) / (h[:-1] + h[1:])
    second[:, 0], second[:, -1] = second[:, 1], second[:, -2]
    errors: NDArray[np.float64] = h**2 * np.maximum(np.abs(second[:, :-1]), np.abs(second[:, 1:])).max(axis=0) / 8.0
    return errors


def refine_mesh(mesh: NDArray[np.float64], errors: NDArray[np.float64], share: float = 0.1) -> NDArray[np.float64]:
    """The mesh with every interval whose error is at least `share` of the largest halved: each pass cuts
    the largest error about fourfold, as doubling the whole mesh would, for the intervals that carry it."""
    split = errors >= share * errors.max()
    middles = 0.5 * (mesh[:-1] + mesh[1:])[split]
    return np.sort(np.concatenate([mesh, middles]))


def _radau(degree: int) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Radau IIA points tau_1..tau_d (tau_d = 1) with tau_0 = 0, and D[j, r] = l_r'(tau_j), j = 1..d."""
    tau = np.concatenate(([0.0], np.asarray(ca.collocation_points(degree, "radau"))))
    d = np.zeros((degree, degree + 1))
    for r in range(degree + 1):
        others = np.delete(tau, r)
        poly = np.poly1d(others, r=True) / np.prod(tau[r] - others)
        d[:, r] = np.polyder(poly)(tau[1:])
    return tau, d


class Transcription:
    """The NLP of one Problem on a uniform mesh of `intervals`; solve() may be called many times with other
    objective weights, constraint targets and guesses (the continuation of an optimal footprint). With
    `least_excess`, the flight that least exceeds the path limits instead: the largest of their rows (each <= 0 where
    its limit holds) minimized by one more variable, the excess, every other constraint held (_path_limits_said)."""

    def __init__(
        self,
        problem: Problem,
        intervals: int | None = None,
        mesh: NDArray[np.float64] | None = None,
        least_excess: bool = False,
    ):
        self.problem = pr = problem
        self.least_excess = least_excess
        uniform = mesh is None  # its NLP is written as before meshes could be refined (the same IPOPT path)
        if mesh is None:
            mesh = uniform_mesh(intervals or pr.intervals)
        self.mesh = mesh  # the interval ends as fractions of the flight time, 0 to 1 (refine_mesh)
        self.n = n = len(mesh) - 1
        self.d = d = pr.degree
        spec = pr.base
        _check(pr)
        self.frame = entry_frame(spec.entry)
        self.model = FlightModel(spec, axis=self.frame[:, 2])
        self.x0 = entry_state(spec, self.frame)
        self.entry = spec.entry
        tau_c, dmat = _radau(d)
        h = np.full(n, 1.0 / n) if uniform else np.diff(mesh)  # each interval's share of the flight time
        inner = [(k + tau_c[1:]) / n if uniform else mesh[k] + h[k] * tau_c[1:] for k in range(n)]
        self.tau = np.concatenate([[0.0], *inner])  # all points, in [0, 1]
        m = n * d  # collocation points (point 0 is the entry)
        self.nq = 1 if self._needs_heat_load() else 0
        ns = 6 + self.nq
        self.ns = ns
        # decision variables, scaled: states (ns x (m+1)), controls at nodes (2 x (n+1)), final time
        xs = ca.MX.sym("x", ns, m + 1)
        us = ca.MX.sym("u", 2, n + 1)
        ts = ca.MX.sym("t")
        excess = ca.MX.sym("excess", 1 if least_excess else 0)  # the path rows' largest, in their own scaling
        w = ca.vertcat(ca.vec(xs), ca.vec(us), ts, excess)
        weights = ca.MX.sym("w", len(pr.objective))
        # the guess's final down-range angle, longitude and heading: keep the atan2s away from their cuts
        refs = ca.MX.sym("refs", 3)
        smoothing = ca.MX.sym("smoothing")  # SMOOTHING_STAGES
        regularization = ca.MX.sym("regularization")  # smoothing_weight, 0 in the polish
        par = ca.vertcat(weights, refs, smoothing, regularization)
        # linear controls: the values at the collocation points are weights of the node values
        lin = np.zeros((n + 1, m))
        for k in range(n):
            for j in range(d):
                lin[k, k * d + j] = 1.0 - tau_c[j + 1]
                lin[k + 1, k * d + j] = tau_c[j + 1]
        # collocation derivative: column (k, j) of xs @ dbig is sum_r D[j, r] x_{k, r}
        dbig = np.zeros((m + 1, m))
        for k in range(n):
            for j in range(d):
                dbig[k * d : k * d + d + 1, k * d + j] = dmat[j]
        self._point = point = self._point_function()
        u_all = ca.horzcat(us[:, 0], ca.mtimes(us, ca.sparsify(ca.DM(lin))))  # controls at every point, entry included
        rates, path = point.map(m + 1, *_map_threads(self.compiled))(xs, u_all, smoothing)
        rates = rates[:, 1:]
        t_f = ts * T_SCALE_S
        step: Expr = float(h[0]) * t_f if uniform else ca.repmat(ca.DM(np.repeat(h, d)).T, ns, 1) * t_f  # h t_f a point
        defects = ca.mtimes(xs, ca.sparsify(ca.DM(dbig))) - step * rates
        g: list[ca.MX] = []
        self._groups: list[tuple[str, int, NDArray[np.float64], NDArray[np.float64]]] = []

        def add(name: str, expr: ca.MX, lo: float | NDArray[np.float64], hi: float | NDArray[np.float64]) -> None:
            expr = ca.vec(expr)
            g.append(expr)
            self._groups.append(
                (
                    name,
                    expr.shape[0],
                    np.broadcast_to(lo, expr.shape[0]).astype(float),
                    np.broadcast_to(hi, expr.shape[0]).astype(float),
                )
            )

        add("collocation defects", defects, 0.0, 0.0)
        # altitude: a floor along the way, equal to the stop altitude at the end
        alt = path[0, :]
        stop_ft = spec.stop.altitude_ft
        assert stop_ft is not None  # _check refused a problem without a stop altitude
        floor_ft = stop_ft + FLOOR_MARGIN_FT * np.minimum(1.0, (1.0 - self.tau[1:-1]) / FLOOR_TAPER_FRACTION)
        add("altitude above the floor", (alt[1:-1] - floor_ft[None, :]) / H_SCALE_FT, 0.0, np.inf)
        add("final altitude", (alt[-1] - stop_ft) / H_SCALE_FT, 0.0, 0.0)
        self._path_rows: dict[str, object] = {}
        for con in pr.constraints:
            if con.quantity in PATH:
                expr = self._path_expression(con.quantity, con.target, path, smoothing)
                add(con.quantity, expr - excess if least_excess else expr, -np.inf, 0.0)
        final = self._terminal(xs[:, -1], t_f, refs)
        self._final = ca.Function("final", [w, par], [ca.vertcat(*[final[q] for q in TERMINAL if q in final])])
        self._final_names = [q for q in TERMINAL if q in final]
        for con in pr.constraints:
            if con.quantity in TERMINAL and _pole(con):
                add(con.quantity, *self._at_the_pole(xs[:, -1], con))
            elif con.quantity in TERMINAL:
                lo, hi = _band(con)
                sc = SCALE[con.quantity]
                add(con.quantity, final[con.quantity] / sc, lo / sc, hi / sc)
        for i, rate in ((0, pr.alpha_rate_deg_s), (1, pr.bank_rate_deg_s)):
            if rate is not None:
                scale = ALPHA_SCALE_DEG if i == 0 else BANK_SCALE_DEG
                du = (us[i, 1:] - us[i, :-1]) * scale
                most = rate * float(h[0]) * t_f if uniform else rate * ca.DM(h).T * t_f  # in each interval
                add(
                    ("alpha" if i == 0 else "bank") + " rate",
                    ca.horzcat(du - most, -du - most),
                    -np.inf,
                    0.0,
                )
        objective = sum(weights[i] * final[q] / SCALE[q] for i, (q, _) in enumerate(pr.objective))
        f = excess if least_excess else -objective if pr.goal == "max" else objective
        # the rates' integral of squares, sum (du/h)^2 h
        du = us[:, 1:] - us[:, :-1]
        f = f + (
            regularization * ca.sumsqr(du) * n if uniform else regularization * ca.sum2(ca.sum1(du**2) / ca.DM(h).T)
        )
        self._g = ca.vertcat(*g)
        self.lbg = np.concatenate([grp[2] for grp in self._groups])
        self.ubg = np.concatenate([grp[3] for grp in self._groups])
        self._bounds(ns, m, n)
        self._outputs = ca.Function("outputs", [w, par], [xs, us, t_f, path])
        self._iterations = _Iterations(w.shape[0], self._g.shape[0], par.shape[0])
        opts: dict[str, bool | int | float | str | ca.Function] = {
            "ipopt.print_level": 0,
            "print_time": False,
            "ipopt.sb": "yes",
            "ipopt.tol": pr.tolerance,
            "iteration_callback": self._iterations,
            "ipopt.max_iter": pr.max_iterations,
            "ipopt.max_wall_time": pr.max_seconds,
            "ipopt.mu_strategy": "adaptive",
            "ipopt.linear_solver": "mumps",
            "expand": not self.compiled,
        }
        self._nlp, self._opts = {"x": w, "f": f, "g": self._g, "p": par}, opts
        self.solver = ca.nlpsol("collocation", "ipopt", self._nlp, opts)
        self._warm_solvers: dict[int, ca.Function] = {}
        self._violation = ca.Function("g", [w, par], [self._g])

    # -- pieces ------------------------------------------------------------------------------------------
    def _needs_heat_load(self) -> bool:
        pr = self.problem
        return any(q == "heat_load_btu_ft2" for q, _ in pr.objective) or any(
            con.quantity == "heat_load_btu_ft2" for con in pr.constraints
        )

    def _point_function(self) -> ca.Function:
        """(scaled state, scaled controls) -> (scaled rates, path quantities [altitude, T margin, q, qbar, n])."""
        xs = ca.SX.sym("x", self.ns)
        us = ca.SX.sym("u", 2)
        smoothing = ca.SX.sym("smoothing")
        state = ca.vertcat(
            self.problem.base.planet.radius_ft + H_SCALE_FT * xs[0], xs[1], xs[2], V_SCALE_FPS * xs[3], xs[4], xs[5]
        )
        alpha, bank = ALPHA_SCALE_DEG * us[0], BANK_SCALE_DEG * us[1]
        pt = self.model.point(state, alpha, bank, smoothing)
        r = pt["rates"]
        rates = [r[0] / H_SCALE_FT, r[1], r[2], r[3] / V_SCALE_FPS, r[4], r[5]]
        heat = self.model.heating
        path = [pt["altitude_ft"], pt["q_psf"], pt["load_factor"], pt["rho"], pt["t_inf"], state[3], alpha]
        if self.nq:
            if heat is None:
                raise CollocationError("heating: heat_load_btu_ft2 needs a heating model in the case")
            rates.append(heat.heat_rate(pt["rho"], state[3], pt["t_inf"], alpha) / SCALE["heat_load_btu_ft2"])
        opts = _jit_options() if self.model.smoothed else None
        self.compiled = opts is not None
        return ca.Function("point", [xs, us, smoothing], [ca.vertcat(*rates), ca.vertcat(*path)], opts or {})

    def _path_expression(self, quantity: str, limit: float, path: ca.MX, smoothing: ca.MX) -> Expr:
        """<= 0 where the path constraint holds, at every collocation point (row vector)."""
        heat = self.model.heating
        qbar, load, rho, t_inf, v, alpha = (path[i, :] for i in range(1, 7))
        if quantity == "max_dynamic_pressure_psf":
            return (qbar - limit) / SCALE[quantity]
        if quantity == "max_load_factor":
            return load - limit
        if heat is None:
            raise CollocationError(f"constraints.{quantity}: needs a heating model in the case")
        if quantity == "max_temperature_R":
            return heat.temperature_margin(rho, v, t_inf, alpha, limit, smoothing)
        return heat.heat_rate(rho, v, t_inf, alpha) / limit - 1.0

    def _at_the_pole(self, xf: ca.MX, con: Constraint) -> tuple[ca.MX, NDArray[np.float64], NDArray[np.float64]]:
        """A final latitude of +-90 deg as (rows, lower, upper) in degrees of the latitude's scale: the end's
        earth-fixed x and y within the band's arc of the axis (a square inside that circle), and z on the pole's side.
        The latitude itself, atan2(z, sqrt(x^2 + y^2)), has no derivative there: IPOPT stopped in "Error_In_Step_
        Computation" 2e-13 deg from the north pole, at a heat load 2 % above that of a site 6 nmi beyond it."""
        ux, uy, uz = earth_fixed_position(self.frame, xf[1], xf[2])
        arc = 0.5 * con.tolerance / math.sqrt(2.0) if con.kind == "equals" else 0.0
        rows = ca.vertcat(ux, uy, _pole(con) * uz) * (180.0 / math.pi) / SCALE[con.quantity]
        bound = arc / SCALE[con.quantity]
        return rows, np.array([-bound, -bound, 0.0]), np.array([bound, bound, np.inf])

    def _terminal(self, xf: ca.MX, t_f: ca.MX, refs: ca.MX) -> dict[str, Expr]:
        """Summary quantities of the final point (CasADi expressions in their units); refs: _references."""
        pm = self.model.planet
        r = self.problem.base.planet.radius_ft + H_SCALE_FT * xf[0]
        v, gam = V_SCALE_FPS * xf[3], xf[4]
        theta_ref = refs[0]
        lat_c, lon, psi = geographic(self.frame, xf[1], xf[2], xf[5], refs[1], refs[2])
        lat, alt = geodetic(pm, r, lat_c)
        e = self.entry
        p0, d0, pole = great_circle_frame(e.latitude_deg, e.longitude_deg, e.heading_deg)
        pt = ca.vertcat(ca.cos(lat) * ca.cos(lon), ca.cos(lat) * ca.sin(lon), ca.sin(lat))
        # eqs. (8)-(11) as core.sphere, the down-range angle measured from the guess's (continuous past 180 deg)
        a_p, a_d = ca.dot(pt, ca.DM(p0)), ca.dot(pt, ca.DM(d0))
        along_ref = ca.cos(theta_ref) * a_p + ca.sin(theta_ref) * a_d
        across_ref = -ca.sin(theta_ref) * a_p + ca.cos(theta_ref) * a_d
        down = MEAN_RADIUS_NMI * (theta_ref + ca.atan2(across_ref, along_ref))
        cross = MEAN_RADIUS_NMI * ca.atan2(ca.dot(pt, ca.DM(pole)), ca.sqrt(a_p * a_p + a_d * a_d))
        out = {
            "crossrange_nmi": cross,
            "downrange_nmi": down,
            "final_latitude_deg": lat * (180 / np.pi),
            "final_longitude_deg": lon * (180 / np.pi),
            "final_velocity_fps": v,
            "final_gamma_deg": gam * (180 / np.pi),
            "final_heading_deg": psi * (180 / np.pi),
            "flight_time_s": t_f,
            "final_energy_ft": alt + 0.5 * v * v / c.G0_FT_S2,
        }
        if self.nq:
            out["heat_load_btu_ft2"] = xf[6] * SCALE["heat_load_btu_ft2"]
        return out

    def _bounds(self, ns: int, m: int, n: int) -> None:
        pr = self.problem
        lo_a, hi_a = self.alpha_bounds_deg()
        lo_b, hi_b = pr.bank_bounds_deg
        x_lo = np.tile(
            np.array([-0.5, -np.inf, -np.pi / 2 + 1e-3, 1e-3, -np.pi / 2 + 1e-3, -np.inf] + [-np.inf] * self.nq)[
                :, None
            ],
            (1, m + 1),
        )
        x_hi = np.tile(
            np.array([np.inf, np.inf, np.pi / 2 - 1e-3, np.inf, np.pi / 2 - 1e-3, np.inf] + [np.inf] * self.nq)[
                :, None
            ],
            (1, m + 1),
        )
        x_first = self._scaled_entry()
        x_lo[:, 0] = x_hi[:, 0] = x_first
        u_lo = np.tile(np.array([lo_a / ALPHA_SCALE_DEG, lo_b / BANK_SCALE_DEG])[:, None], (1, n + 1))
        u_hi = np.tile(np.array([hi_a / ALPHA_SCALE_DEG, hi_b / BANK_SCALE_DEG])[:, None], (1, n + 1))
        free = [np.inf] if self.least_excess else []  # the excess: unbounded
        self.lbx = np.concatenate([x_lo.ravel(order="F"), u_lo.ravel(order="F"), [1e-3], np.negative(free)])
        self.ubx = np.concatenate([x_hi.ravel(order="F"), u_hi.ravel(order="F"), [1e3], free])

    def alpha_bounds_deg(self) -> tuple[float, float]:
        """The problem's alpha bounds within the vehicle's valid alpha range (tables and polynomials alike)."""
        lo, hi = self.model.aero.alpha_range_deg
        if self.problem.alpha_bounds_deg is None:
            return lo, hi
        a, b = self.problem.alpha_bounds_deg
        if b <= lo or a >= hi:
            raise CollocationError(
                f"alpha_bounds_deg {a:g} to {b:g}: outside the vehicle's alpha range {lo:g} to {hi:g} deg"
            )
        return max(a, lo), min(b, hi)

    def _references(self, guess: Guess) -> list[float]:
        """The guess's final down-range angle (rad), geographic longitude and heading (rad, continued from the
        entry's): the NLP's down-range, longitude and heading are measured within pi of them; but a longitude or
        heading constraint's target is their reference, so that a target across 180 deg (or 360 deg) from the
        guess's end is met where it is, not a turn of the earth away."""
        _, lon, heading = geographic_track(self.frame, guess.states)
        refs = {"final_longitude_deg": float(lon[-1]), "final_heading_deg": float(heading[-1])}
        for con in self.problem.constraints:
            if con.quantity in refs:
                refs[con.quantity] = math.radians(con.target)
        return [guess.downrange_nmi / MEAN_RADIUS_NMI, refs["final_longitude_deg"], refs["final_heading_deg"]]

    def _scaled_entry(self) -> NDArray[np.float64]:
        s = self.x0
        return np.array(
            [(s[0] - self.problem.base.planet.radius_ft) / H_SCALE_FT, s[1], s[2], s[3] / V_SCALE_FPS, s[4], s[5]]
            + [0.0] * self.nq
        )

    def _scaled_guess(self, guess: Guess) -> NDArray[np.float64]:
        s, u, q = guess.at(self.tau)
        xs = np.column_stack(
            [
                (s[:, 0] - self.problem.base.planet.radius_ft) / H_SCALE_FT,
                s[:, 1],
                s[:, 2],
                s[:, 3] / V_SCALE_FPS,
                s[:, 4],
                s[:, 5],
            ]
        )
        if self.nq:
            xs = np.column_stack([xs, (q if q is not None else np.zeros(len(self.tau))) / SCALE["heat_load_btu_ft2"]])
        xs[0] = self._scaled_entry()
        nodes = self.tau[:: self.d]
        _, un, _ = guess.at(nodes)
        lo_a, hi_a = self.alpha_bounds_deg()
        lo_b, hi_b = self.problem.bank_bounds_deg
        us = np.column_stack(
            [np.clip(un[:, 0], lo_a, hi_a) / ALPHA_SCALE_DEG, np.clip(un[:, 1], lo_b, hi_b) / BANK_SCALE_DEG]
        )
        excess = [0.0] if self.least_excess else []
        return np.concatenate([xs.T.ravel(order="F"), us.T.ravel(order="F"), [guess.final_time_s / T_SCALE_S], excess])

    # -- solving -----------------------------------------------------------------------------------------
    def solve(
        self,
        guess: Guess,
        *,
        weights: Sequence[float] | None = None,
        constraint_targets: Mapping[str, tuple[float, float]] | None = None,
        warm: dict[str, NDArray[np.float64]] | None = None,
        stages: Sequence[float] | None = None,
        polish: bool | None = None,
        polish_only: bool = False,
        on_iteration: OnIteration | None = None,
        max_iterations: int | None = None,
    ) -> Result:
        """Solve from `guess` (or from `warm`, a previous solution's solver state of this transcription).

        weights: one per objective term (default: the problem's); constraint_targets: {quantity: (lo, hi)} to
        replace terminal constraint bands without rebuilding; stages: the smoothing of the tables, each stage
        started from the last (default SMOOTHING_STAGES, the last one alone from a warm start; one stage
        without tables); polish: a last stage at POLISH_WEIGHT (default: the problem's); polish_only: that stage
        alone, from `warm` (the optimum of this transcription's last stage, as solve() gives it);
        on_iteration(iteration, stage, stages) after every IPOPT iteration (True stops); max_iterations: IPOPT's
        limit for a warm start's stages, below the problem's (a start that one of several others may do better)."""
        pr = self.problem
        wts = np.array([wt for _, wt in pr.objective] if weights is None else weights, float)
        floor = self.entry_floor()
        if floor is not None:  # no iterate can meet it: said at once, in the limit's unit, without IPOPT
            par = np.concatenate([wts, self._references(guess), [SMOOTHING_STAGES[-1], 0.0]])
            x = self._scaled_guess(guess) if warm is None else warm["x"]
            result = self._result(x, par, "infeasible", floor, math.inf, 0, 0.0)
            result.advice = "to change: the limit (above the fixed entry state's least value) or the entry state"
            return result
        lbg, ubg = self.lbg.copy(), self.ubg.copy()
        offset = 0
        for name, size, _, _ in self._groups:
            if constraint_targets and name in constraint_targets:
                lo, hi = constraint_targets[name]
                lbg[offset : offset + size] = lo / SCALE[name]
                ubg[offset : offset + size] = hi / SCALE[name]
            offset += size
        if stages is None:
            stages = SMOOTHING_STAGES if warm is None else SMOOTHING_STAGES[-1:]
        if not self.model.smoothed:
            stages = stages[-1:]
        weight = pr.smoothing_weight
        plan = [(st, weight) for st in stages]
        if weight > 0 and (pr.polish if polish is None else polish):
            plan.append((stages[-1], weight * POLISH_WEIGHT))
        if polish_only:
            plan = [(stages[-1], weight * POLISH_WEIGHT)]
        seconds, iterations = 0.0, 0
        # a caller's warm start, and the stages after the first on smoothed tables, use the warm-start solver
        # (from the cold solver's start the L/D 1.89 stages do not converge); without tables the polish starts the
        # cold solver from the last point: building the warm-start solver costs as much as the first build (1 s)
        use_warm, x_start = warm is not None, None if warm is not None else self._scaled_guess(guess)
        if polish_only:  # as the polish after the stages: warm on the tables, from the last point without them
            use_warm = self.model.smoothed
        kept: tuple[dict[str, NDArray[np.float64]], NDArray[np.float64], dict[str, Any]] | None
        kept, note = None, ""  # the last stage that ended optimal: a narrower one that does not falls back to it
        listener = self._iterations
        listener.report, listener.stages = on_iteration, len(plan)
        for stage, (smoothing, reg) in enumerate(plan):
            listener.stage, listener.iteration = stage, iterations - 1
            par = np.concatenate([wts, self._references(guess), [smoothing, reg]])
            args = {"lbx": self.lbx, "ubx": self.ubx, "lbg": lbg, "ubg": ubg, "p": par}
            solver = self.solver
            if use_warm:
                # use_warm: a caller's warm start, or (smoothed tables) the stage before's solution
                assert warm is not None
                args.update(x0=warm["x"], lam_x0=warm["lam_x"], lam_g0=warm["lam_g"])
                polishing = reg < weight  # the entry after the stages
                cap = min(POLISH_MAX_ITERATIONS, pr.max_iterations) if polishing else pr.max_iterations
                cap = cap if max_iterations is None else min(cap, max_iterations)
                solver = self._warm(cap)
            else:
                x0 = x_start if warm is None else warm["x"]
                assert x0 is not None  # x_start is the guess whenever no warm start was given
                args["x0"] = x0
            t0 = time.perf_counter()
            sol = solver(**args)
            use_warm = use_warm or self.model.smoothed
            seconds += time.perf_counter() - t0
            stats = solver.stats()
            iterations += int(stats["iter_count"])
            warm = {
                "x": np.asarray(sol["x"]).ravel(),
                "lam_x": np.asarray(sol["lam_x"]).ravel(),
                "lam_g": np.asarray(sol["lam_g"]).ravel(),
            }
            if STATUS_OF_IPOPT.get(stats["return_status"]) != "optimal":
                # said in the message; the re-flight measures what the wider corners cost (not after a stop)
                if kept is not None and stats["return_status"] != "User_Requested_Stop":
                    note = (
                        f"; the stage at corners {smoothing:g} (rate weight {reg:g}) ended "
                        f"{stats['return_status']}: the optimum of the stage before is kept"
                    )
                    warm, par, stats = kept
                break  # a later stage cannot mend a stage that ended without an optimum
            kept = (warm, par, stats)
        listener.report = None
        assert warm is not None  # the plan has a stage at least, and every stage sets warm
        x = warm["x"]
        gval = np.asarray(self._violation(x, par)).ravel()
        viol = np.maximum(lbg - gval, 0.0) + np.maximum(gval - ubg, 0.0)
        status = STATUS_OF_IPOPT.get(stats["return_status"], "not_converged")
        result = self._result(x, par, status, stats["return_status"] + note, float(viol.max(initial=0.0)), iterations,
                              seconds)  # fmt: skip
        if status != "optimal":
            result.message = f"{stats['return_status']}; largest violation {self._worst(viol, result.summary)}"
        result.solver_state = warm
        return result

    def entry_floor(self) -> str | None:
        """The path limit the fixed entry state breaks at every allowed alpha, named with its excess in its unit (the
        least value over the alpha bounds on a 0.25 deg grid less the limit), or None. Heat rate, temperature, dynamic
        pressure and load factor do not depend on the bank (a coordinated turn without side force)."""
        limits = [con for con in self.problem.constraints if con.quantity in PATH]
        if not limits:
            return None
        lo, hi = self.alpha_bounds_deg()
        alpha = np.linspace(lo, hi, max(2, int((hi - lo) / 0.25) + 1))
        x = np.tile(self._scaled_entry()[:, None], (1, alpha.size))
        u = np.vstack([alpha / ALPHA_SCALE_DEG, np.zeros(alpha.size)])
        path = np.asarray(self._point.map(alpha.size)(x, u, SMOOTHING_STAGES[-1])[1])
        values: dict[str, NDArray[np.float64]] = {"max_dynamic_pressure_psf": path[1], "max_load_factor": path[2]}
        heating = self.problem.base.heating
        if heating is not None:  # the integrator's heating model, as the result's summary
            values["max_heat_rate_btu_ft2_s"], values["max_temperature_R"] = heating.evaluate(
                path[3], np.full(alpha.size, self.x0[3]), alpha, path[4], np.zeros(alpha.size)
            )
        for con in limits:
            least = int(np.argmin(values[con.quantity]))
            value = float(values[con.quantity][least])
            if value > con.target * (1.0 + 1e-6):
                return (
                    f"{con.quantity} by {value - con.target:.4g} {PATH_UNITS[con.quantity]} at the entry, which is "
                    f"fixed (its least {value:.4g} over alpha {lo:g} to {hi:g} deg, at {alpha[least]:g} deg; "
                    f"limit {con.target:g})"
                )
        return None

    def _warm(self, iterations: int) -> ca.Function:
        """The same NLP with IPOPT started at the given primal-dual point (small barrier, small bound push),
        one solver per iteration limit (0.2 s to build once the first is)."""
        if iterations not in self._warm_solvers:
            opts: dict[str, bool | int | float | str | ca.Function] = dict(
                self._opts,
                **{
                    "ipopt.warm_start_init_point": "yes",
                    "ipopt.mu_init": 1e-6,
                    "ipopt.warm_start_bound_push": 1e-9,
                    "ipopt.warm_start_mult_bound_push": 1e-9,
                    "ipopt.warm_start_slack_bound_push": 1e-9,
                    "ipopt.mu_strategy": "monotone",
                    "ipopt.max_iter": iterations,
                },
            )
            self._warm_solvers[iterations] = ca.nlpsol("collocation_warm", "ipopt", self._nlp, opts)
        return self._warm_solvers[iterations]

    def _worst(self, viol: NDArray[np.float64], summary: dict[str, float | None]) -> str:
        """The largest violation, named, in its own unit: a terminal constraint's by its scale, a path constraint's as
        the last iterate's peak less the limit (the NLP holds them relative to the limit, or as a flux margin); and the
        worst terminal constraint's where that is another."""
        offset, worst, name, terminal = 0, -1.0, "", (0.0, "")
        for gname, size, _, _ in self._groups:
            v = viol[offset : offset + size].max(initial=0.0)
            if v > worst:
                worst, name = v, gname
            if gname in TERMINAL and v * SCALE[gname] > terminal[0]:
                terminal = (v * SCALE[gname], gname)
            offset += size
        if name in TERMINAL:
            return f"{name} by {worst * SCALE[name]:.4g}"
        peak = summary.get(name) if name in PATH else None
        if peak is not None:
            limit = next(c.target for c in self.problem.constraints if c.quantity == name)
            line = f"{name} by {peak - limit:.4g} {PATH_UNITS[name]} (peak {peak:.4g}, limit {limit:g})"
        else:
            line = f"{name} by {worst:.3g} (scaled)"
        return line + (f"; {terminal[1]} by {terminal[0]:.4g}" if terminal[1] else "")

    def _result(
        self,
        x: NDArray[np.float64],
        par: NDArray[np.float64],
        status: str,
        message: str,
        max_violation: float,
        iterations: int,
        seconds: float,
    ) -> Result:
        xs, us, t_f_array, path = (np.asarray(v) for v in self._outputs(x, par))
        t_f = float(t_f_array.item())
        final = dict(zip(self._final_names, np.asarray(self._final(x, par)).ravel().tolist()))
        pr = self.problem
        r = pr.base.planet.radius_ft + H_SCALE_FT * xs[0]
        v, gam, psi = V_SCALE_FPS * xs[3], xs[4], xs[5]
        times = self.tau * t_f
        node_t = times[:: self.d]
        alpha_n, bank_n = us[0] * ALPHA_SCALE_DEG, us[1] * BANK_SCALE_DEG
        alpha_c = np.interp(times, node_t, alpha_n)
        bank_c = np.interp(times, node_t, bank_n)
        lat_c, lon, heading = geographic_track(self.frame, xs.T)
        lat_gd = np.array([float(geodetic(self.model.planet, r_i, lat_i)[0]) for r_i, lat_i in zip(r, lat_c)])
        history = {
            "time_s": times,
            "altitude_ft": path[0],
            "velocity_fps": v,
            "gamma_deg": np.degrees(gam),
            "heading_deg": np.degrees(heading),
            "latitude_deg": np.degrees(lat_gd),
            "longitude_deg": np.degrees(lon),
            "alpha_deg": alpha_c,
            "bank_deg": bank_c,
            "dynamic_pressure_psf": path[1],
            "load_factor": path[2],
        }
        summary: dict[str, float | None] = dict(final)
        # a trajectory summary's conventions (the NLP measures them about _references)
        summary["final_longitude_deg"] = float(wrap_longitude(final["final_longitude_deg"], closed_above=True))
        summary["final_heading_deg"] = final["final_heading_deg"] % 360.0
        summary["final_altitude_ft"] = float(path[0, -1])
        summary["max_dynamic_pressure_psf"] = float(path[1].max())
        summary["max_load_factor"] = float(path[2].max())
        heating = pr.base.heating
        if heating is not None:
            q, temp = heating.evaluate(path[3], v, alpha_c, path[4], times)
            history["heat_rate_btu_ft2_s"], history["temperature_R"] = q, temp
            summary["max_heat_rate_btu_ft2_s"] = float(np.max(q))
            summary["max_temperature_R"] = float(np.max(temp)) if np.all(np.isfinite(temp)) else None
        objective = sum(wt * final[q] for (q, _), wt in zip(pr.objective, par[: len(pr.objective)]))
        after = Guess(
            tau=self.tau.copy(),
            states=np.column_stack([r, xs[1], xs[2], v, gam, psi]),
            controls=np.column_stack([alpha_c, bank_c]),
            final_time_s=t_f,
            downrange_nmi=final["downrange_nmi"],
            heat_load=None if not self.nq else xs[6] * SCALE["heat_load_btu_ft2"],
        )
        res = Result(
            status=status,
            message=message,
            objective=float(objective),
            summary=summary,
            history=history,
            controls={"time_s": node_t, "alpha_deg": alpha_n, "bank_deg": bank_n},
            refly=None,
            agreement=None,
            max_violation=max_violation,
            iterations=iterations,
            seconds=seconds,
            intervals=self.n,
            guess=after,
        )
        return res


def _band(con: Constraint) -> tuple[float, float]:
    if con.kind == "equals":
        return con.target - 0.5 * con.tolerance, con.target + 0.5 * con.tolerance
    if con.kind == "at_most":
        return -np.inf, con.target
    return con.target, np.inf


def _pole(con: Constraint) -> int:
    """+1 (-1) when a constraint ends the flight at the north (south) pole: a final latitude equal to +-90 deg, at
    least 90 or at most -90; else 0."""
    if con.quantity != "final_latitude_deg" or abs(con.target) != 90.0:
        return 0
    north = con.target > 0.0
    return (1 if north else -1) if con.kind in ("equals", "at_least" if north else "at_most") else 0


def _check(pr: Problem) -> None:
    if pr.base.dispersion != Dispersion():
        raise CollocationError(
            "dispersion: the collocation's model (core.model_casadi) flies the nominal vehicle and "
            "atmosphere; fly a dispersed spec with trajectory.simulate"
        )
    if pr.base.stop.altitude_ft is None:
        raise CollocationError("stop.altitude_ft: the collocation ends at a stop altitude; give one")
    names = [q for q, _ in pr.objective] + [con.quantity for con in pr.constraints]
    for q in names:
        if q not in QUANTITIES:
            raise CollocationError(f"{q}: not a quantity the collocation knows; allowed: {', '.join(QUANTITIES)}")
    for con in pr.constraints:
        if con.quantity in PATH and con.kind != "at_most":
            raise CollocationError(f"constraints.{con.quantity}: a path maximum takes at_most only")
    for q, _ in pr.objective:
        if q in PATH:
            raise CollocationError(f"payoff: {q} is a path maximum; constrain it with at_most instead")
    refused = pole_and_longitude(pr.constraints)
    if refused:
        raise CollocationError(refused)


def pole_and_longitude(constraints: Sequence[Constraint]) -> str | None:
    """The one line refusing a longitude constraint beside a final latitude at a pole (_pole), else None."""
    if any(_pole(con) for con in constraints) and any(con.quantity == "final_longitude_deg" for con in constraints):
        return (
            "constraints.final_longitude_deg: a final latitude of +-90 deg is the pole, at every longitude; leave "
            "the longitude out"
        )
    return None


# --------------------------------------------------------------------------------------------- re-flight
def control_tables_spec(base: FlightSpec, controls: Mapping[str, ArrayLike]) -> FlightSpec:
    """The base flight with the optimum's alpha and bank as tables against time from entry (what `fly` takes)."""
    t = np.asarray(controls["time_s"], float)
    ctrl = pack_controls(
        bank_law="table",
        bank_table=(t, controls["bank_deg"]),
        bank_variable="time",
        bank_start="entry",
        alpha_law="table",
        alpha_table=(t, controls["alpha_deg"]),
        alpha_table_abscissa="time",
    )
    return replace(base, ctrl=ctrl)


def refly(problem: Problem, result: Result) -> Trajectory:
    """Fly the optimum's control tables with the compiled integrator and record the agreement."""
    trajectory = simulate(control_tables_spec(problem.base, result.controls))
    s, n = trajectory.summary, result.summary
    d_lon = float(wrap_longitude(s["final_longitude_deg"] - n["final_longitude_deg"]))
    down = n["downrange_nmi"]
    result.refly = {
        k: s[k]
        for k in (
            "downrange_nmi",
            "crossrange_nmi",
            "final_latitude_deg",
            "final_longitude_deg",
            "final_velocity_fps",
            "final_gamma_deg",
            "final_heading_deg",
            "flight_time_s",
            "final_altitude_ft",
            "final_energy_ft",
            "max_temperature_R",
            "max_heat_rate_btu_ft2_s",
            "heat_load_btu_ft2",
            "max_dynamic_pressure_psf",
            "stop_reason",
        )
    }
    result.refly["inverted_s"] = inverted_s(trajectory.history)
    d_lat = abs(s["final_latitude_deg"] - n["final_latitude_deg"])
    # the arc along the parallel (deg of a great circle): the longitude's difference means nothing at a pole
    east_west = abs(d_lon) * math.cos(math.radians(s["final_latitude_deg"]))
    result.agreement = {
        "latitude_deg": d_lat,
        "longitude_deg": abs(d_lon),
        "east_west_deg": east_west,
        "end_deg": max(d_lat, east_west),  # how far apart the two ends lie, in deg of arc (the larger of the two)
        "downrange_rel": abs(s["downrange_nmi"] - down) / max(abs(down), 1.0),
        "crossrange_nmi": abs(s["crossrange_nmi"] - n["crossrange_nmi"]),
        "flight_time_s": s["flight_time_s"] - n["flight_time_s"],
        "final_velocity_fps": s["final_velocity_fps"] - n["final_velocity_fps"],
        "final_gamma_deg": s["final_gamma_deg"] - n["final_gamma_deg"],
    }
    if n.get("max_temperature_R") is not None and s.get("max_temperature_R") is not None:
        result.agreement["max_temperature_R"] = s["max_temperature_R"] - n["max_temperature_R"]
    return trajectory


def inverted_s(history: dict[str, NDArray[np.float64]]) -> float:
    """Time flown upside down at negative lift (C_L < 0 and |bank| > 90 deg: the lift still points up), the
    trapezoidal rule over the rows. An optimum takes it where a polynomial's |L/D| is larger below its zero-lift
    alpha (Betts' shuttle: 2.87 at -3.23 deg against 1.89 upright), which a planner may want to bound out."""
    inverted = ((history["cl"] < 0.0) & (np.abs(history["bank_deg"]) > 90.0)).astype(float)
    return float(np.sum(np.diff(history["time_s"]) * (inverted[1:] + inverted[:-1]) / 2.0))


def agrees(result: Result) -> bool:
    a = result.agreement
    return a is not None and a["end_deg"] <= AGREE_DEG and a["downrange_rel"] <= AGREE_DOWNRANGE_REL


def objective_tolerance(problem: Problem, objective: float) -> float:
    """How little the objective must change under a mesh refinement for the optimum to count as settled (issue 29):
    Problem.mesh_tolerance, else 0.001 deg for an objective in degrees and 1e-4 of its value for any other."""
    if problem.mesh_tolerance is not None:
        return problem.mesh_tolerance
    if all(q.endswith("_deg") for q, _ in problem.objective):
        return 1e-3
    return 1e-4 * max(abs(objective), 1.0)


def remaining_move(moves: Sequence[float]) -> float | None:
    """How far the objective may still move after these successive changes under mesh refinement: the last change
    extrapolated by the geometric series that its ratio q to the one before sets, |m_k| q / (1 - q), when the two have
    one sign and shrink (Richardson's estimate for a rate of convergence that holds; exact for a geometric sequence);
    else the last change itself, with no rate to go by. None before any refinement."""
    if not moves:
        return None
    last = abs(moves[-1])
    if len(moves) >= 2 and moves[-1] * moves[-2] > 0.0 and last < abs(moves[-2]):
        q = last / abs(moves[-2])
        return last * q / (1.0 - q)
    return last


def solve(problem: Problem, guess: Guess | None = None, on_progress: OnProgress | None = None) -> Result:
    """Solve from `guess` (or from each of first_guesses, the best optimum kept), re-fly, and refine the mesh from
    the last solution until the optimum is settled: the re-flight agrees and, after two refinements at least, the
    objective may move by less than objective_tolerance under further refinement (remaining_move of its changes so
    far; or max_intervals is reached, or a refined mesh ends without an optimum: then the result is "not_converged"
    and says by how much the objective may still move). A refinement halves the intervals where the linear
    controls' error is largest (control_errors), or every interval while the re-flight disagrees, and starts from
    the last optimum at the narrowest corners. The meshes settle on the problem with the rates' penalty; the polish
    (Problem.polish) then follows once, on the last mesh. on_progress(fraction, note) after every IPOPT iteration
    (True stops)."""
    starts = [guess] if guess is not None else first_guesses(problem)
    mesh: NDArray[np.float64] | None = None  # the first: uniform, problem.intervals
    total_s, total_it, rounds = 0.0, 0, 0
    previous: tuple[Result, Transcription] | None = None  # the last mesh's optimum
    moves: list[float] = []  # the objective's change under each refinement
    while True:  # the k-th mesh reports within [1 - 2^-k, 1 - 2^-(k+1)] (how many there will be is not known)
        share, rounds = (1.0 - 0.5**rounds, 1.0 - 0.5 ** (rounds + 1)), rounds + 1
        transcription = Transcription(problem, mesh=mesh)
        n = transcription.n
        if previous is None:
            result = _best_start(transcription, starts, share, on_progress)
            result = _path_limits_said(problem, transcription, starts[0], result, share[1], on_progress)
            start_objectives = result.start_objectives
        else:
            # a refined mesh starts from the last optimum, at the narrowest corners: 5-40 iterations where a cold
            # start from the case's flight takes hundreds (the polish cannot start there: from the L/D 1.89 polished
            # optimum it ran out of 3,000 iterations, and from the finer mesh's own stage it did not always end
            # within 300)
            report = None if on_progress is None else iteration_progress(on_progress, share, f"{n} intervals: ")
            assert guess is not None  # the last mesh's optimum
            result = transcription.solve(guess, stages=SMOOTHING_STAGES[-1:], polish=False, on_iteration=report)
        total_s, total_it = total_s + result.seconds, total_it + result.iterations
        if previous is not None and not result.ok and result.status != "stopped":
            previous[0].message += f"; a refinement to {n} intervals ended {result.status}: {result.message}"
            result, transcription = previous
            break
        refly(problem, result)
        if not result.ok:
            break
        if previous is not None:
            moves.append(result.objective - previous[0].objective)
            result.mesh_change, result.mesh_remaining = moves[-1], remaining_move(moves)
        if agrees(result) and _settled(problem, result, moves):
            break
        errors = control_errors(result.controls) if agrees(result) else np.ones(n)
        finer = refine_mesh(transcription.mesh, errors)
        if len(finer) - 1 > problem.max_intervals:
            break
        assert result.guess is not None  # a solved result carries its solution (Transcription._result)
        guess, mesh, previous = result.guess, finer, (result, transcription)
    if result.ok and problem.polish and problem.smoothing_weight > 0:
        assert result.guess is not None and result.solver_state is not None
        change, remaining = result.mesh_change, result.mesh_remaining
        report = None if on_progress is None else iteration_progress(on_progress, (1.0 - 0.5**rounds, 1.0), "polish: ")
        stage = SMOOTHING_STAGES[-1:]
        polished = transcription.solve(
            result.guess, warm=result.solver_state, stages=stage, polish_only=True, on_iteration=report
        )
        total_s, total_it = total_s + polished.seconds, total_it + polished.iterations
        if polished.ok or polished.status == "stopped":
            result = polished
            result.mesh_change, result.mesh_remaining = change, remaining
            refly(problem, result)
        else:  # said, as a stage that does not end is: the optimum before it is kept
            result.message += f"; the polish ended {polished.message}: the optimum before it is kept"
    result.seconds, result.iterations, result.start_objectives = total_s, total_it, start_objectives
    if result.ok and problem.max_intervals > problem.intervals and not _settled(problem, result, moves):
        result.status = "not_converged"
        result.advice = "to change: a larger collocation.max_intervals"
        if result.mesh_change is None or result.mesh_remaining is None:
            result.message = (
                f"the mesh could not be refined within max_intervals ({problem.max_intervals}): how far the "
                "objective may still move is not measured; " + result.message
            )
        else:
            result.message = (
                f"the mesh stopped at {result.intervals} intervals with the objective still moving by "
                f"{abs(result.mesh_change):.3g} under the last refinement: it may move by about "
                f"{result.mesh_remaining:.3g} more (tolerance {objective_tolerance(problem, result.objective):.3g}"
                f"{'' if len(moves) > 1 else '; one refinement gives no rate to judge by'}); " + result.message
            )
    if result.ok and not agrees(result):  # said, not hidden: the mesh stopped at max_intervals
        a = result.agreement
        assert a is not None  # refly recorded it
        result.message += (
            f"; at {result.intervals} intervals the re-flight still differs by {a['latitude_deg']:.3g} deg "
            f"latitude, {a['east_west_deg']:.3g} deg east-west, {100 * a['downrange_rel']:.3g} % down-range"
        )
    return result


def _path_limits_said(
    problem: Problem,
    transcription: Transcription,
    guess: Guess,
    failed: Result,
    progress_at: float,
    on_progress: OnProgress | None,
) -> Result:
    """A first mesh that ended infeasible under path limits: the flight that least exceeds them (every other
    constraint held; least_excess on the same mesh from the same guess). Past a limit, the answer names that flight's
    peaks in their units (IPOPT's own words named the collocation defects); within every limit, the problem is solved
    again from that flight (IPOPT had ended infeasible from its start); with no such flight, the final conditions are
    out of reach whatever the limits. Progress is reported at the fraction `progress_at`."""
    limits = [con for con in problem.constraints if con.quantity in PATH]
    if failed.status != "infeasible" or failed.advice or not limits:  # advice: the fixed entry's limit, said at once
        return failed

    def report(what: str) -> OnIteration | None:
        return None if on_progress is None else iteration_progress(on_progress, (progress_at, progress_at), what)

    least = Transcription(problem, mesh=transcription.mesh, least_excess=True).solve(
        guess, polish=False, on_iteration=report("the least excess of the path limits: ")
    )
    failed.seconds, failed.iterations = failed.seconds + least.seconds, failed.iterations + least.iterations
    if least.status == "stopped":
        return failed
    if not least.ok:
        failed.advice = "to change: the final conditions (a target within the vehicle's reach)"
        failed.message += f"; with the path limits lifted no flight meets the final conditions either ({least.message})"
        return failed
    peaks = {con.quantity: least.summary.get(con.quantity) for con in limits}
    over = [(c, v) for c in limits if (v := peaks[c.quantity]) is not None and v > c.target * (1.0 + EXCESS_RTOL)]
    failed.least_path_peaks = peaks
    if over:
        failed.advice = "to change: " + ", ".join(f"{c.quantity} to {v:.5g} or more" for c, v in over)
        failed.advice += ", or the final conditions"
        failed.message = (
            "the path limits cannot be met with the final conditions: the flight that least exceeds them peaks at "
            + ", ".join(f"{c.quantity} {v:.5g} {PATH_UNITS[c.quantity]} (limit {c.target:g})" for c, v in over)
            + f"; {failed.message}"
        )
        return failed
    assert least.guess is not None  # a solved result carries its solution (Transcription._result)
    again = transcription.solve(least.guess, polish=False, on_iteration=report("from within the path limits: "))
    again.seconds, again.iterations = again.seconds + failed.seconds, again.iterations + failed.iterations
    again.least_path_peaks = peaks
    again.message += "; solved again from the flight that least exceeds the path limits, which meets them all"
    return again


def _best_start(
    transcription: Transcription, starts: list[Guess], share: tuple[float, float], on_progress: OnProgress | None
) -> Result:
    """The first mesh solved from each start, the best optimum kept (the first start's result if none is one),
    with every start's objective; a stopped solve ends the search."""
    results: list[Result] = []
    lo, hi = share
    for k, start in enumerate(starts):
        part = (lo + (hi - lo) * k / len(starts), lo + (hi - lo) * (k + 1) / len(starts))
        what = f"{transcription.n} intervals" + (f", start {k + 1} of {len(starts)}" if len(starts) > 1 else "") + ": "
        report = None if on_progress is None else iteration_progress(on_progress, part, what)
        results.append(transcription.solve(start, polish=False, on_iteration=report))
        if results[-1].status == "stopped":
            return results[-1]
    sign = 1.0 if transcription.problem.goal == "max" else -1.0
    found = [r for r in results if r.ok]
    best = max(found, key=lambda r: sign * r.objective) if found else results[0]
    if len(results) > 1:
        best.start_objectives = [r.objective if r.ok else None for r in results]
        best.seconds, best.iterations = sum(r.seconds for r in results), sum(r.iterations for r in results)
    return best


def _settled(problem: Problem, result: Result, moves: Sequence[float]) -> bool:
    """The objective may move by less than its tolerance, judged on two refinements at least: one change has no
    rate, and the first can be the smallest (the fly-there example turned to the north pole moved 22.9, then 36.5
    Btu/ft^2; settled on the first against a tolerance of 25, it stood 81 above the answer of 362 intervals)."""
    left = result.mesh_remaining
    return len(moves) >= 2 and left is not None and left <= objective_tolerance(problem, result.objective)
