"""Both integrators (core.integrate: DOPRI5, the default, and DOP853) land where an independent tight solve of the
same right-hand side lands: scipy's DOP853 at rtol 1e-12 (solve_ivp, its own step control and event location) on
dynamics.rhs, in two legs split at the pull-out, as in bench/bench_trajectory.py."""

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from footprint.contracts import parse
from footprint.core.dynamics import (
    EV_ALTITUDE_FT,
    EV_SIN_GAMMA,
    EV_STEER_DEG,
    INTEGRATOR_DOP853,
    INTEGRATOR_DOPRI5,
    M_BANK_ACTIVE,
    M_PULLED_OUT,
    M_PULLOUT_ALT,
    M_REF_ANGLE,
    P_INTEGRATOR,
    P_OBLATE,
    P_RE,
    P_RP,
    P_STOP_ALT,
    evaluate,
    rhs,
)
from footprint.core.frames import geodetic_from_ecef
from footprint.core.integrate import R_X, R_Z, STOP_REASONS, integrate
from footprint.core.sphere import MEAN_RADIUS_NMI
from footprint.core.trajectory import _set_left_pole, initial_mode, initial_state, pack_parameters
from tests.authorities.report import example

TABLE2 = example("table2_lod22")
CASES = {
    "table2": TABLE2,
    "table2, bank 40 deg": dict(TABLE2, bank={"law": "constant", "bank_deg": 40}),
    "table2, lod-1.89, K 0.6": dict(
        TABLE2, vehicle={"builtin": "lod-1.89"}, bank={"law": "single_parameter", "bank_gain": 0.6}
    ),
}
LANDING_TOL_NMI = 0.001  # issue 29: the landing unchanged within 0.001 nmi of the converged answer
PULLOUT_TOL_FT = 1.0  # the pull-out located on the continuous extension (order 4 or 7)


def _inputs(case):
    spec = parse("case", case).to_spec()
    p = pack_parameters(spec)
    s0 = initial_state(spec, p)
    _set_left_pole(p, s0, spec.entry.heading_deg)
    return spec, p, s0, initial_mode(spec, p, s0)


def _landing(p, state):
    lat, lon, _ = geodetic_from_ecef(state[0], state[1], state[2], p[P_RE], p[P_RP], p[P_OBLATE] != 0.0)
    return lat, lon


def _distance_nmi(a, b):
    (lat1, lon1), (lat2, lon2) = a, b
    c = math.sin(lat1) * math.sin(lat2) + math.cos(lat1) * math.cos(lat2) * math.cos(lon1 - lon2)
    return MEAN_RADIUS_NMI * math.atan2(math.sqrt(max(0.0, 1.0 - c * c)), c)


def _scipy_reference(case):
    """(landing (lat, lon) rad, pull-out altitude ft) by solve_ivp DOP853, rtol 1e-12, on dynamics.rhs."""
    spec, p, s0, mode = _inputs(case)
    aero, ctrl, out = spec.vehicle.blob, spec.ctrl, np.empty(6)
    v0 = math.sqrt(s0[3] ** 2 + s0[4] ** 2 + s0[5] ** 2)
    atol = np.array([p[P_RE]] * 3 + [v0] * 3) * 1e-12

    def f(t, s):
        rhs(t, s, p, aero, ctrl, mode, out)
        return out.copy()

    def pullout(t, s):
        return evaluate(t, s, p, aero, ctrl, mode)[EV_SIN_GAMMA]

    def ground(t, s):
        return evaluate(t, s, p, aero, ctrl, mode)[EV_ALTITUDE_FT] - p[P_STOP_ALT]

    pullout.terminal, pullout.direction = True, 1.0
    ground.terminal, ground.direction = True, -1.0
    kw = dict(method="DOP853", rtol=1e-12, atol=atol, max_step=spec.max_step_s)
    leg1 = solve_ivp(f, (0.0, 5.0e4), s0, events=[pullout, ground], **kw)
    t1, s1 = leg1.t_events[0][0], leg1.y_events[0][0]
    pullout_alt = evaluate(t1, s1, p, aero, ctrl, mode)[EV_ALTITUDE_FT]
    mode[M_PULLED_OUT] = mode[M_BANK_ACTIVE] = 1.0
    mode[M_REF_ANGLE] = evaluate(t1, s1, p, aero, ctrl, mode)[EV_STEER_DEG]
    leg2 = solve_ivp(f, (t1, 5.0e4), s1, events=[ground], **kw)
    return _landing(p, leg2.y_events[0][0]), pullout_alt


@pytest.mark.parametrize("method", [INTEGRATOR_DOPRI5, INTEGRATOR_DOP853], ids=["dopri5", "dop853"])
@pytest.mark.parametrize("name", CASES)
def test_the_landing_is_the_tight_reference_s(name, method):
    spec, p, s0, mode = _inputs(CASES[name])
    p[P_INTEGRATOR] = method
    rows, stop, _ = integrate(s0, p, spec.vehicle.blob, spec.ctrl, mode, spec.max_steps)
    assert STOP_REASONS[stop] == "altitude"
    landing, pullout_alt = _scipy_reference(CASES[name])
    miss = _distance_nmi(_landing(p, rows[-1, R_X : R_Z + 1]), landing)
    # issue 29's bar on its case. Elsewhere at rtol 1e-9 (observed, 2025): DOP853 0.0002-0.0011 nmi, DOPRI5 up to
    # 0.013 nmi; the steps across the kinks of the tables and layers hold both back
    if name == "table2":
        assert miss < LANDING_TOL_NMI, miss
    else:
        assert miss < (2.0 * LANDING_TOL_NMI if method == INTEGRATOR_DOP853 else 20.0 * LANDING_TOL_NMI), miss
    assert abs(mode[M_PULLOUT_ALT] - pullout_alt) < PULLOUT_TOL_FT
