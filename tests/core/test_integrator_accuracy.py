"""Both integrators (core.integrate: DOPRI5, the default, and DOP853) land where an independent tight solve of the
same right-hand side lands: scipy's DOP853 at rtol 1e-12 (solve_ivp, its own step control and event location) on
dynamics.rhs, in two legs split at the pull-out, as in bench/bench_trajectory.py."""

import math

import pytest

from footprint.core.dynamics import INTEGRATOR_DOP853, INTEGRATOR_DOPRI5, M_PULLOUT_ALT, P_OBLATE, P_RE, P_RP
from footprint.core.frames import geodetic_from_ecef
from footprint.core.integrate import R_X, R_Z, STOP_REASONS, integrate
from tests.authorities.report import example
from tests.authorities.tight import inputs, tight
from tests.core.test_guidance import distance_nmi

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


def _landing_deg(p, state):
    lat, lon, _ = geodetic_from_ecef(state[0], state[1], state[2], p[P_RE], p[P_RP], p[P_OBLATE] != 0.0)
    return math.degrees(lat), math.degrees(lon)


@pytest.mark.parametrize("method", [INTEGRATOR_DOPRI5, INTEGRATOR_DOP853], ids=["dopri5", "dop853"])
@pytest.mark.parametrize("name", CASES)
def test_the_landing_is_the_tight_reference_s(name, method):
    spec, p, s0, mode = inputs(CASES[name], method)
    rows, stop, _ = integrate(s0, p, spec.vehicle.blob, spec.ctrl, mode, spec.max_steps)
    assert STOP_REASONS[stop] == "altitude"
    reference = tight(inputs(CASES[name], method))
    miss = distance_nmi(*_landing_deg(p, rows[-1, R_X : R_Z + 1]), *_landing_deg(p, reference.landing()))
    pullout_alt = reference.pullout_altitude_ft
    # issue 29's bar on its case. Elsewhere at rtol 1e-9 (observed, 2025): DOP853 0.0002-0.0011 nmi, DOPRI5 up to
    # 0.013 nmi; the steps across the kinks of the tables and layers hold both back
    if name == "table2":
        assert miss < LANDING_TOL_NMI, miss
    else:
        assert miss < (2.0 * LANDING_TOL_NMI if method == INTEGRATOR_DOP853 else 20.0 * LANDING_TOL_NMI), miss
    assert abs(mode[M_PULLOUT_ALT] - pullout_alt) < PULLOUT_TOL_FT
