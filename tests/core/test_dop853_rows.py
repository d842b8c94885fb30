"""DOP853 (p[P_INTEGRATOR] = INTEGRATOR_DOP853) records each step at integrate.DOP853_ROWS_PER_STEP points: its end
and interior rows from the step's quintic Hermite interpolant (or, cut at an event, its continuous extension). Checked
against independent values: the interior rows lie on scipy's DOP853 solution at rtol 1e-12 (its own dense output),
and the summary's maxima and heat load read off the rows (core.sampled) are within 3e-5 of those of the same
solution read every 0.02 s."""

import numpy as np
import pytest

from footprint.contracts import parse
from footprint.core import trajectory
from footprint.core.dynamics import (
    EV_ALPHA_DEG,
    EV_ALTITUDE_FT,
    EV_CD,
    EV_CL,
    EV_Q_PSF,
    EV_SPEED_FPS,
    INTEGRATOR_DOP853,
    INTEGRATOR_DOPRI5,
    P_ATM,
    P_ATM_T,
    P_RHO0,
    P_SCALE_H,
    evaluate,
)
from footprint.core.heating import trajectory_heating
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
    """The heated Table 2 case's summary flown by each method at the case's rtol, and the reference: scipy's DOP853 at
    rtol 1e-12 (tests/authorities/tight.py) read every 0.02 s on its own dense output, the model's q, C_L, C_D, alpha
    and heating evaluated there, maxima and the trapezoidal heat load taken over those ~170,000 points (their
    sampling error below 1e-8 of each)."""
    out = {
        m: trajectory.simulate(parse("case", dict(HEATED, integrator={"method": m})).to_spec()).summary
        for m in ("dopri5", "dop853")
    }
    case = inputs(HEATED, INTEGRATOR_DOP853)
    spec, p = case.spec, case.p
    ref = tight(case)
    cols, times = [], []
    for leg, mode, t0, t1 in (
        (ref.before, ref.mode_before, 0.0, ref.pullout_time_s),
        (ref.after, ref.mode_after, ref.pullout_time_s, float(ref.after.t[-1])),
    ):
        t = np.linspace(t0, t1, 1 + int((t1 - t0) / 0.02))
        for ti, state in zip(t, leg.sol(t).T):
            r = evaluate(ti, state, p, spec.vehicle.blob, spec.ctrl, mode)
            cols.append((r[EV_ALTITUDE_FT], r[EV_SPEED_FPS], r[EV_ALPHA_DEG], r[EV_Q_PSF], r[EV_CL], r[EV_CD]))
        times.append(t)
    t = np.concatenate(times)
    alt, v, alpha, q, cl, cd = np.array(cols).T
    heat_rate, temperature = trajectory_heating(
        spec.heating, alt, v, alpha, (p[P_ATM], p[P_RHO0], p[P_SCALE_H], p[P_ATM_T]), t
    )
    out["reference"] = {
        "max_dynamic_pressure_psf": float(q.max()),
        "max_load_factor": float(np.max(q * np.hypot(cl, cd))) / spec.vehicle.wing_loading_psf,
        "heat_load_btu_ft2": float(np.trapezoid(heat_rate, t)),
        "max_heat_rate_btu_ft2_s": float(heat_rate.max()),
        "max_temperature_R": float(temperature.max()),
    }
    return out


# relative; sampled on the rows the maxima were short by up to 9.5e-4 (DOP853's max q) and 1.8e-4 (DOPRI5's load)
MAXIMA_TOL = 3e-5


@pytest.mark.parametrize("key", SUMMARY_KEYS)
def test_the_summary_is_within_its_tolerance_of_scipys_tight_solution(summaries, key):
    """core.sampled: each maximum at the parabola's vertex about the largest row, the heat load by Simpson's 3/8 rule
    over DOP853's steps (the trapezoidal rule over DOPRI5's rows: 2.3e-4 here)."""
    reference = summaries["reference"][key]
    error = {name: abs(summaries[name][key] / reference - 1.0) for name in ("dopri5", "dop853")}
    if key == "heat_load_btu_ft2":
        assert error["dop853"] < MAXIMA_TOL and error["dopri5"] < 5e-4, error
    else:
        assert max(error.values()) < MAXIMA_TOL, error
