"""The deorbit burn as it is executed (issue 52 item 5): the entry states of burns dispersed in their magnitude, their
pointing and their time, each coasted to the interface by the orbit's own coast (core.deorbit), so that a guided
dispersion of an opportunity starts from the entries its burn can give, with their correlations (a late burn enters
later and farther on; a short one shallower and farther), not from independent spreads of each entry variable.

The thrust is retrograde against the inertial velocity (core.deorbit.burn); pitch tilts it in the orbit's plane
towards the local vertical (up), yaw out of the plane towards the orbit's angular momentum. The errors are normal,
independent, each with its standard deviation; the draw is its own random stream (the seed's second child), apart
from the study's other inputs.
"""

from __future__ import annotations

from dataclasses import dataclass
from datetime import datetime

import numpy as np
from numpy.typing import NDArray

from footprint.core import deorbit as dorb
from footprint.core.elements import Orbit, teme_to_earth_fixed
from footprint.core.utc import after_s


@dataclass(frozen=True)
class BurnErrors:
    """One standard deviation of each execution error. Chosen values for a burn trimmed by its guidance to about a
    foot per second, a strapdown attitude of a few tenths of a degree and a half-second ignition: the scale of the
    Shuttle's OMS deorbit residuals (a few tenths of a ft/s after the RCS trim), kept larger here to be safe."""

    delta_v_fps: float = 1.0
    pitch_deg: float = 0.5
    yaw_deg: float = 0.5
    time_s: float = 0.5

    def problem(self) -> str | None:
        for name in ("delta_v_fps", "pitch_deg", "yaw_deg", "time_s"):
            value = getattr(self, name)
            if not (np.isfinite(value) and value >= 0.0):
                return f"{name}: {value!r} must be a finite number >= 0"
        return None


def normals(n: int, seed: int) -> NDArray[np.float64]:
    """n x 4 standard normals (Δv, pitch, yaw, time): the seed's second child stream, apart from the other draws."""
    child = np.random.SeedSequence(seed).spawn(2)[1]
    return np.random.default_rng(child).standard_normal((n, 4))


def thrust_directions(
    r_ft: NDArray[np.float64],
    v_in_fps: NDArray[np.float64],
    pitch_deg: NDArray[np.float64],
    yaw_deg: NDArray[np.float64],
) -> NDArray[np.float64]:
    """Unit vectors of the Δv (n x 3): against the inertial velocity, tilted by pitch towards the local vertical in
    the orbit's plane and by yaw towards the angular momentum."""
    along = v_in_fps / np.linalg.norm(v_in_fps, axis=1)[:, None]
    normal = np.cross(r_ft, v_in_fps)
    normal /= np.linalg.norm(normal, axis=1)[:, None]
    up = np.cross(along, normal)  # in the plane, 90 deg from the velocity, on the side of r
    up *= np.sign(np.einsum("ij,ij->i", up, r_ft))[:, None]
    p, y = np.radians(pitch_deg)[:, None], np.radians(yaw_deg)[:, None]
    direction: NDArray[np.float64] = -np.cos(p) * np.cos(y) * along + np.sin(p) * up + np.cos(p) * np.sin(y) * normal
    return direction


def executed_entries(
    coast: dorb.Coast,
    orbit: Orbit,
    burn_utc: datetime,
    delta_v_fps: float,
    errors: BurnErrors,
    z: NDArray[np.float64],
) -> NDArray[np.float64]:
    """The entry (rows of core.deorbit's E_* columns; E_COAST_S from the planned burn time) of each executed burn:
    the planned burn (its time, Δv) with the errors errors x z (z: normals())."""
    dt = errors.time_s * z[:, 3]
    utc = after_s(burn_utc, dt)
    r, v = teme_to_earth_fixed(*orbit.teme_km(utc), utc, coast.omega_rad_s)
    v_in = dorb.inertial_velocity(r, v, coast.omega_rad_s)
    dv = delta_v_fps + errors.delta_v_fps * z[:, 0]
    direction = thrust_directions(r, v_in, errors.pitch_deg * z[:, 1], errors.yaw_deg * z[:, 2])
    rows = dorb.entry_states(coast, r, v + dv[:, None] * direction)
    rows[:, dorb.E_COAST_S] += dt
    return rows
