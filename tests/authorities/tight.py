"""An independent tight solve of a case: scipy's DOP853 at rtol 1e-12 (solve_ivp, its own step control, event
location and dense output) on core.dynamics.rhs, in two legs split at the pull-out, as bench/bench_trajectory.py
flies it. The integrator's tests compare our DOPRI5 and DOP853 against it."""

import math
from typing import Any, NamedTuple

import numpy as np

from footprint.contracts import parse
from footprint.core.dynamics import (
    EV_ALTITUDE_FT,
    EV_SIN_GAMMA,
    EV_STEER_DEG,
    M_BANK_ACTIVE,
    M_PULLED_OUT,
    M_REF_ANGLE,
    P_INTEGRATOR,
    P_RE,
    P_STOP_ALT,
    evaluate,
    rhs,
)
from footprint.core.trajectory import flight_inputs


class Inputs(NamedTuple):
    spec: Any  # trajectory.FlightSpec
    p: np.ndarray
    s0: np.ndarray
    mode: np.ndarray


class Tight(NamedTuple):
    before: Any  # solve_ivp's answer from the entry to the pull-out (or the ground)
    after: Any  # from the pull-out to the stop altitude
    pullout_time_s: float
    pullout_altitude_ft: float
    mode_before: np.ndarray  # the mode vector each leg flies with
    mode_after: np.ndarray

    def state(self, time_s: float) -> np.ndarray:
        """The dense solution at a time of either leg."""
        return (self.before if time_s < self.pullout_time_s else self.after).sol(time_s)

    def landing(self) -> np.ndarray:
        """The earth-fixed state where the second leg reaches the stop altitude."""
        return self.after.y_events[0][0]


def inputs(case: dict, method: float) -> Inputs:
    """A case's packed inputs as trajectory.simulate makes them, flown by `method` (dynamics.INTEGRATOR_*)."""
    spec = parse("case", case).to_spec()
    p, s0, mode = flight_inputs(spec)
    p[P_INTEGRATOR] = method
    return Inputs(spec, p, s0, mode)


def tight(i: Inputs) -> Tight:
    from scipy.integrate import solve_ivp

    aero, ctrl, out = i.spec.vehicle.blob, i.spec.ctrl, np.empty(6)
    v0 = math.sqrt(i.s0[3] ** 2 + i.s0[4] ** 2 + i.s0[5] ** 2)
    atol = np.array([i.p[P_RE]] * 3 + [v0] * 3) * 1e-12
    mode = i.mode.copy()

    def f(t, s):
        rhs(t, s, i.p, aero, ctrl, mode, out)
        return out.copy()

    def pullout(t, s):
        return evaluate(t, s, i.p, aero, ctrl, mode)[EV_SIN_GAMMA]

    def ground(t, s):
        return evaluate(t, s, i.p, aero, ctrl, mode)[EV_ALTITUDE_FT] - i.p[P_STOP_ALT]

    pullout.terminal, pullout.direction = True, 1.0
    ground.terminal, ground.direction = True, -1.0
    kw = dict(method="DOP853", rtol=1e-12, atol=atol, max_step=i.spec.max_step_s, dense_output=True)
    before = solve_ivp(f, (0.0, 5.0e4), i.s0, events=[pullout, ground], **kw)
    t1, s1 = before.t_events[0][0], before.y_events[0][0]
    mode_before = mode.copy()
    pullout_alt = evaluate(t1, s1, i.p, aero, ctrl, mode)[EV_ALTITUDE_FT]
    mode[M_PULLED_OUT] = mode[M_BANK_ACTIVE] = 1.0
    mode[M_REF_ANGLE] = evaluate(t1, s1, i.p, aero, ctrl, mode)[EV_STEER_DEG]
    after = solve_ivp(f, (t1, 5.0e4), s1, events=[ground], **kw)
    return Tight(before, after, float(t1), float(pullout_alt), mode_before, mode)
