"""Creep + pattern parameter optimization and the penalty of eq. (4) (AFWAL-TR-82-3036 Section II.4-II.6)."""

import numpy as np
import pytest

from footprint.contracts import parse
from footprint.core import footprints as F
from footprint.core import method_settings as S
from footprint.core import optimize as O
from tests.authorities.report import REPORT, table2_entry, table2_stop

TABLE2_ENTRY = table2_entry()
REPORT_MAX_CROSSRANGE_NMI = REPORT["sec3.max_crossrange_nmi"].value  # the L/D 1.89 optimum


@pytest.fixture(scope="module")
def lod189():
    return parse("case", {"vehicle": {"builtin": "lod-1.89"}, "entry": TABLE2_ENTRY, "stop": table2_stop()}).to_spec()


def rosenbrock(x):
    return {"f": float(100.0 * (x[1] - x[0] ** 2) ** 2 + (1.0 - x[0]) ** 2)}


def quadratic(x):
    return {"f": float(x @ x), "sum": float(x.sum()), "x0": float(x[0])}


# ------------------------------------------------------------------------------------------ analytic
def test_creep_pattern_finds_the_rosenbrock_minimum():
    pr = O.Problem(lower=[-2, -1], upper=[2, 3], initial=[-1.2, 1.0], payoff="f", goal="min", evaluate=rosenbrock)
    r = O.creep_pattern(pr, step=0.5, min_step=1e-7, max_evaluations=20_000)
    assert r.converged
    assert r.params == pytest.approx([1.0, 1.0], abs=1e-3)
    assert r.payoff < 1e-6


def test_bounds_are_never_left():
    seen = []

    def f(x):
        seen.append(np.array(x))
        return rosenbrock(x)

    lower, upper = np.array([-2.0, -1.0]), np.array([0.5, 3.0])  # the free optimum (1, 1) lies outside
    r = O.creep_pattern(
        O.Problem(lower=lower, upper=upper, initial=[-1.2, 1.0], payoff="f", goal="min", evaluate=f),
        step=1.0,
        min_step=1e-6,
        max_evaluations=5_000,
    )
    pts = np.array(seen)
    assert np.all(pts >= lower) and np.all(pts <= upper)
    assert r.params[0] == pytest.approx(0.5, abs=1e-4)  # on the bound: x0 = 0.5, x1 = 0.25
    assert r.params[1] == pytest.approx(0.25, abs=1e-3)


def constrained_quadratic(weight=1e4):
    # min x.x  with  x0 + x1 + x2 = 3 and x0 >= 1.5 (active): x = (1.5, 0.75, 0.75)
    return O.Problem(
        lower=[-5] * 3,
        upper=[5] * 3,
        initial=[0, 0, 0],
        payoff="f",
        goal="min",
        evaluate=quadratic,
        constraints=(
            O.Constraint("sum", "equals", 3.0, 1e-3, weight),
            O.Constraint("x0", "at_least", 1.5, 1e-3, weight),
        ),
    )


def test_constrained_quadratic_by_two_routes():
    r = O.optimize(constrained_quadratic(), step=0.5, min_step=1e-7, max_evaluations=20_000)
    assert r.feasible and r.max_violation == 0.0
    assert r.params == pytest.approx([1.5, 0.75, 0.75], abs=2e-3)  # within the 1e-3 bands
    s = O.optimize_scipy(constrained_quadratic(), "SLSQP")
    assert s.params == pytest.approx([1.5, 0.75, 0.75], abs=1e-6)
    assert r.payoff == pytest.approx(s.payoff, abs=5e-3)


def test_the_search_reports_every_flight_and_stops_when_asked():
    """Issue 15 item 2: a creep + pattern job sat at 0 % until it ended, and could not be stopped. Its listener hears
    each flight (the fraction of the budget flown, never backwards) and may stop it; the result is then the best
    point so far, from no more flights than were reported."""
    heard = []
    full = O.optimize(constrained_quadratic(), max_evaluations=400, on_progress=lambda f, note: heard.append(f))
    assert len(heard) == full.trajectories and heard == sorted(heard) and heard[-1] <= 1.0
    assert heard[:3] == pytest.approx([1 / 400, 2 / 400, 3 / 400])
    stops = []
    cut = O.optimize(
        constrained_quadratic(), max_evaluations=400, on_progress=lambda f, note: stops.append(f) or len(stops) >= 25
    )
    assert len(stops) == 25 and cut.trajectories == 25 and cut.augmented_payoff >= full.augmented_payoff
    scipy_heard = []
    O.optimize_scipy(
        constrained_quadratic(), "Nelder-Mead", max_evaluations=50, on_progress=lambda f, note: scipy_heard.append(note)
    )
    assert scipy_heard[0] == "trajectory 1 of at most 50"


def test_penalty_is_zero_inside_the_band_and_quadratic_outside():
    eq = O.Constraint("downrange_nmi", "equals", 4000.0, O.TTOL_DOWNRANGE_NMI)
    for d in (3975.0, 4000.0, 4010.0, 4025.0):
        assert O.penalty((eq,), {"downrange_nmi": d}) == 0.0
    assert O.penalty((eq,), {"downrange_nmi": 4035.0}) == pytest.approx(100.0)  # (35 - 25)^2
    assert O.penalty((eq,), {"downrange_nmi": 3955.0}) == pytest.approx(400.0)  # (45 - 25)^2
    hot = O.Constraint("max_temperature_R", "at_most", 2550.0, O.TTOL_TEMPERATURE_R, weight=2.0)
    assert O.penalty((hot,), {"max_temperature_R": 2000.0}) == 0.0  # the safe side is never penalized
    assert O.penalty((hot,), {"max_temperature_R": 2556.5}) == pytest.approx(2.0 * 4.0**2)
    pr = O.Problem(
        lower=[0], upper=[1], initial=[0], payoff="downrange_nmi", goal="max", constraints=(eq,), evaluate=lambda x: {}
    )
    assert O.augmented(pr, {"downrange_nmi": 4035.0}) == pytest.approx(-4035.0 + 100.0)  # always worse


def test_an_unreachable_constraint_is_reported_infeasible():
    pr = O.Problem(
        lower=[-5] * 3,
        upper=[5] * 3,
        initial=[0, 0, 0],
        payoff="f",
        goal="min",
        evaluate=quadratic,
        constraints=(O.Constraint("x0", "at_least", 7.0, 0.1),),
    )
    r = O.optimize(pr, step=0.5, min_step=1e-6, max_evaluations=5_000)
    assert not r.feasible
    assert r.max_violation == pytest.approx(7.0 - 5.0 - 0.05, abs=1e-6)  # the best it could do: x0 on its bound
    assert r.params[0] == pytest.approx(5.0)


# ------------------------------------------------------------------------------ Section II.5, L/D 1.89
def test_unconstrained_cross_range_beats_the_single_parameter_control(lod189):
    sp = F.single_parameter(
        lod189, S.SingleParameter(bank0_deg=tuple(np.arange(60.0, 90.1, 1.0)), mirror=False, min_range=None)
    )
    best_sp = sp.max_crossrange_nmi  # 2,024 nmi near 75 deg
    r = O.optimize(O.cross_range_problem(lod189), max_evaluations=300, **O.CROSS_RANGE_SEARCH)
    assert r.feasible and r.converged
    assert r.payoff >= best_sp
    assert abs(r.payoff - REPORT_MAX_CROSSRANGE_NMI) < 0.10 * REPORT_MAX_CROSSRANGE_NMI
    assert r.trajectories <= 200  # report: about 110
    history = [h["payoff"] for h in r.history]
    assert history[29] > 0.95 * r.payoff  # Fig. 3: over 95 % within 30 trajectories
    assert np.all(np.diff(history) >= 0.0)  # best so far never falls
    assert np.all(r.params >= 0.0) and np.all(r.params <= 180.0)


def test_slsqp_reaches_the_same_unconstrained_optimum(lod189):
    r = O.optimize_scipy(O.cross_range_problem(lod189), "SLSQP", max_evaluations=600, eps=1.0)
    c = O.optimize(O.cross_range_problem(lod189), max_evaluations=300, **O.CROSS_RANGE_SEARCH)
    assert r.payoff == pytest.approx(c.payoff, abs=5.0)  # nmi: a flat optimum, both 2,044-2,045 nmi


def test_downrange_constrained_optimum_lands_in_the_band(lod189):
    r = O.optimize(
        O.cross_range_problem(lod189, downrange_nmi=4000.0),
        max_evaluations=400,
        **(O.CROSS_RANGE_SEARCH | {"ftol": 0.0}),
    )
    assert r.feasible
    assert abs(r.summary["downrange_nmi"] - 4000.0) <= O.TTOL_DOWNRANGE_NMI / 2
    assert r.payoff > 1_900.0  # single-parameter control at 4,000 nmi: 1,929 nmi


def test_soft_start_beats_the_single_parameter_control_at_3000_nmi(lod189):
    # unit weights from the start stall at 1,658 nmi here, below the single-parameter control
    sp = F.single_parameter(
        lod189, S.SingleParameter(bank0_deg=tuple(np.arange(95.0, 105.1, 0.5)), mirror=False, min_range=None)
    )
    r = O.optimize(
        O.cross_range_problem(lod189, downrange_nmi=3000.0), max_evaluations=1_200, **O.CONSTRAINED_CROSS_RANGE_SEARCH
    )
    assert r.feasible
    d = r.summary["downrange_nmi"]
    pts = sorted((p.downrange_nmi, p.crossrange_nmi) for p in sp.points if p.side == "left")
    single = np.interp(d, [p[0] for p in pts], [p[1] for p in pts])  # about 1,750 nmi
    assert r.payoff >= single


def test_a_downrange_beyond_reach_is_infeasible(lod189):
    r = O.optimize(O.cross_range_problem(lod189, downrange_nmi=16_000.0), max_evaluations=150, **O.CROSS_RANGE_SEARCH)
    assert not r.feasible
    assert r.max_violation > 1_000.0  # zero bank reaches 14,869 nmi


def test_a_scale_makes_each_penalty_term_dimensionless():
    """Beyond eq. (4): the excess divided by the scale, so one band's excess costs the weight whatever the unit."""
    speed = O.Constraint("final_velocity_fps", "equals", 2_500.0, 10.0, scale=10.0)
    angle = O.Constraint("final_gamma_deg", "equals", -5.0, 0.1, scale=0.1)
    flown = {"final_velocity_fps": 2_515.0, "final_gamma_deg": -5.15}  # each one band beyond its half band
    assert O.penalty((speed,), flown) == pytest.approx(1.0)
    assert O.penalty((angle,), flown) == pytest.approx(1.0)
    assert O.penalty((O.Constraint("final_gamma_deg", "equals", -5.0, 0.1),), flown) == pytest.approx(0.01)  # eq. (4)
