"""An opportunity's path as states (issue 52, the files a planner hands on): the coast from the deorbit burn to the
entry interface and the entry flight after it, each an earth-fixed state per integrator step (ft, ft/s relative to
the earth, in the frame the integrator flies: TEME turned by GMST about the pole, polar motion neglected, i.e.
CCSDS's GRC) on whole milliseconds of UTC from the burn, as every time of the opportunities is written.

The coast is flown again from the orbit's state at the burn with the opportunity's Δv (core.deorbit: the same
integrator, the same Δv, so the same coast); the entry is a flight spec (the caller's: the case guided to the site,
or the case's own controls) flown from the coast's entry state, by the trajectory module as every flight is.
"""

from __future__ import annotations

from dataclasses import dataclass
from datetime import datetime

import numpy as np
from numpy.typing import NDArray

from footprint.core import deorbit as dorb
from footprint.core.dynamics import M_SIZE
from footprint.core.elements import Orbit
from footprint.core.integrate import R_T, R_VX, R_VZ, R_X, R_Z, integrate
from footprint.core.opportunities import states_at
from footprint.core.trajectory import FlightSpec, flown_rows

TIME_STEP_S = 1e-3  # each state is moved to the whole millisecond its epoch is written with (isos)


@dataclass(frozen=True)
class Phase:
    """One phase of the path: SI seconds from the burn (whole milliseconds), earth-fixed position (ft, n x 3) and
    earth-relative velocity (ft/s, n x 3)."""

    name: str
    seconds: NDArray[np.float64]
    r_ft: NDArray[np.float64]
    v_rel_fps: NDArray[np.float64]


def on_milliseconds(name: str, start_s: float, rows: NDArray[np.float64]) -> Phase:
    """Integrator rows (R_* columns, times from `start_s` after the burn) moved to the nearest whole millisecond from
    the burn by a second-order Taylor step (a shift of at most 0.5 ms: 4e-6 ft at a 3 g deceleration), the
    acceleration a difference of the rows' velocities; a row that rounds onto its predecessor's millisecond is
    dropped."""
    t = start_s + rows[:, R_T]
    keep = np.concatenate([[True], np.diff(np.round(t / TIME_STEP_S)) > 0])
    t, r, v = t[keep], rows[keep, R_X : R_Z + 1], rows[keep, R_VX : R_VZ + 1]
    on = np.round(t / TIME_STEP_S) * TIME_STEP_S
    a = np.gradient(v, t, axis=0) if len(t) > 1 else np.zeros_like(v)
    shift = (on - t)[:, None]
    return Phase(name, on, r + v * shift + 0.5 * a * shift**2, v + a * shift)


def coast_phase(
    orbit: Orbit, coast: dorb.Coast, burn_utc: datetime, delta_v_fps: float
) -> tuple[Phase, NDArray[np.float64]]:
    """The coast from the burn (its Δv along the inertial velocity) to the interface, and its entry row (E_*)."""
    r, v = states_at(orbit, [burn_utc], coast.omega_rad_s)
    after = dorb.burn(r, v, delta_v_fps, coast.omega_rad_s)
    rows, _, _ = integrate(
        np.concatenate([r[0], after[0]]), coast.p, coast.aero, coast.ctrl, np.zeros(M_SIZE), dorb.MAX_STEPS
    )
    entry = dorb.entry_states(coast, r, after)[0]
    return on_milliseconds("coast", 0.0, rows), entry


def entry_phase(spec: FlightSpec, coast_s: float) -> Phase:
    """The flight `spec` (its entry the coast's; guided or not) from the interface, `coast_s` after the burn, to
    where it ends (a guided flight: its guidance's hand-over at the terminal energy)."""
    return on_milliseconds("entry", coast_s, flown_rows(spec))
