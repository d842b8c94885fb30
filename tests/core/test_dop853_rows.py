"""DOP853 (p[P_INTEGRATOR] = INTEGRATOR_DOP853) records each step at integrate.DOP853_ROWS_PER_STEP points: its end
and interior rows from the step's quintic Hermite interpolant (or, cut at an event, its continuous extension). Checked
against independent values: the interior rows lie on scipy's DOP853 solution at rtol 1e-12 (its own dense output),
and the summary's maxima and trapezoidal heat load are as close to a converged flight's (rtol 1e-12, 0.2 s steps) as
DOPRI5's one row a step is."""

import numpy as np
import pytest

from footprint.contracts import parse
from footprint.core import trajectory
from footprint.core.dynamics import (
    EV_ALTITUDE_FT,
    EV_SPEED_FPS,
    INTEGRATOR_DOP853,
    INTEGRATOR_DOPRI5,
    P_INTEGRATOR,
    evaluate,
)
from footprint.core.integrate import DOP853_ROWS_PER_STEP, R_ALT, R_INTERIOR, R_T, R_V, integrate
from tests.authorities.report import example
from tests.authorities.tight import inputs, tight

TABLE2 = example("table2_lod22")
HEATED = dict(TABLE2, heating={"model": "reference"})
SUMMARY_KEYS = (
    "max_dynamic_pressure_psf",
    "max_load_factor",
    "heat_load_btu_ft2",
    "max_heat_rate_btu_ft2_s",
    "max_temperature_R",
)


def _fly(case, method):
    spec, p, s0, mode = inputs(case, method)
    start = mode.copy()
    rows, _, _ = integrate(s0, p, spec.vehicle.blob, spec.ctrl, mode, spec.max_steps)
    return spec, p, s0, start, mode, rows


def test_each_dop853_step_is_recorded_at_its_points_and_dopri5_at_its_ends():
    *_, rows = _fly(TABLE2, INTEGRATOR_DOP853)
    ends = rows[:, R_INTERIOR] == 0.0
    assert ends[0] and ends[-1]
    steps = int(ends.sum()) - 1
    # every step but the capped ones (DOPRI5 above the atmosphere) has DOP853_ROWS_PER_STEP - 1 rows inside
    assert (DOP853_ROWS_PER_STEP - 1) * (steps - 5) <= rows.shape[0] - 1 - steps <= (DOP853_ROWS_PER_STEP - 1) * steps
    assert np.all(np.diff(rows[:, R_T]) > 0.0)
    *_, rows5 = _fly(TABLE2, INTEGRATOR_DOPRI5)
    assert np.all(rows5[:, R_INTERIOR] == 0.0)


def test_the_interior_rows_lie_on_a_tight_solution():
    """scipy's DOP853 at rtol 1e-12 on dynamics.rhs, in two legs split at the pull-out, its dense output read at the
    interior rows' times: altitude and speed."""
    spec, p, _, _, _, rows = _fly(TABLE2, INTEGRATOR_DOP853)
    reference = tight(inputs(TABLE2, INTEGRATOR_DOP853))
    worst_alt = worst_speed = 0.0
    for row in rows[rows[:, R_INTERIOR] == 1.0]:
        t = row[R_T]
        mode = reference.mode_before if t < reference.pullout_time_s else reference.mode_after
        res = evaluate(t, reference.state(t), p, spec.vehicle.blob, spec.ctrl, mode)
        worst_alt = max(worst_alt, abs(row[R_ALT] - res[EV_ALTITUDE_FT]))
        worst_speed = max(worst_speed, abs(row[R_V] - res[EV_SPEED_FPS]))
    assert worst_alt < 1.0  # ft
    assert worst_speed < 0.01  # ft/s


@pytest.fixture(scope="module")
def summaries():
    """The heated Table 2 case's summary flown by DOPRI5 and by DOP853 at the case's rtol, and converged (DOP853 at
    rtol 1e-12 with 0.2 s steps: ~50,000 rows)."""
    out = {}
    with pytest.MonkeyPatch.context() as mp:
        for name, method, tight in (
            ("dopri5", INTEGRATOR_DOPRI5, False),
            ("dop853", INTEGRATOR_DOP853, False),
            ("converged", INTEGRATOR_DOP853, True),
        ):
            packed = trajectory.pack_parameters

            def pack(spec, method=method, packed=packed):
                p = packed(spec)
                p[P_INTEGRATOR] = method
                return p

            mp.setattr(trajectory, "pack_parameters", pack)
            spec = parse("case", HEATED).to_spec()
            if tight:
                spec = trajectory.FlightSpec(**{**spec.__dict__, "rtol": 1e-12, "max_step_s": 0.2})
            out[name] = trajectory.simulate(spec).summary
            mp.undo()
    return out


@pytest.mark.parametrize("key", SUMMARY_KEYS)
def test_dop853_summary_is_as_close_to_the_converged_one_as_dopri5s(summaries, key):
    converged = summaries["converged"][key]
    error = {name: abs(summaries[name][key] / converged - 1.0) for name in ("dopri5", "dop853")}
    assert error["dop853"] < max(2.0 * error["dopri5"], 1e-3)
