"""Optimal and heating-constrained footprints (AFWAL-TR-82-3036 Section III, Figs. 20-29); reduced budgets."""

import numpy as np
import pytest

from footprint.contracts import parse
from footprint.core import constrained as C
from footprint.core import method_settings as S
from footprint.core.constants import G0_FT_S2
from footprint.core.heating import CALIBRATION_BANK_DEG, ReferenceHeating
from footprint.core.optimize import Problem, creep_pattern_feasible
from footprint.core.trajectory import simulate
from footprint.parallel import client_map, dask_client
from tests.authorities.report import REPORT, table2_entry, table2_stop

TABLE2_ENTRY = table2_entry()
SINGLE_PARAMETER_BANK = {"law": "single_parameter", "bank_gain": 75 / 90}  # the best single-parameter point, 2,024 nmi
OPTIMAL_BANK = {"law": "table", "heading_deg": list(range(-15, 91, 15)), "bank_deg": list(CALIBRATION_BANK_DEG)}
LIMIT_R = REPORT["sec3.limit_R"].value  # the most stringent limit
BAND_R = 0.5 * C.TTOL_TEMPERATURE_R  # degR, half the tolerance band of the temperature constraint


def lod189(bank=None):
    case = {
        "vehicle": {"builtin": "lod-1.89"},
        "entry": TABLE2_ENTRY,
        "stop": table2_stop(),
        "heating": {"model": "reference"},
    }
    if bank is not None:
        case["bank"] = bank
    return parse("case", case).to_spec()


@pytest.fixture(scope="module")
def single_parameter_spec():
    return lod189(SINGLE_PARAMETER_BANK)


def alpha_only_problem(spec, limit_R):
    """Five alpha-table parameters under the single-parameter bank: the Section III problem made small."""
    na = len(C.ALPHA_TABLE_VELOCITIES_FPS)
    return Problem(
        lower=np.full(na, C.ALPHA_BOUNDS_DEG[0]),
        upper=np.full(na, C.ALPHA_BOUNDS_DEG[1]),
        initial=np.full(na, C.ALPHA_MAX_LD_HYPERSONIC_DEG),
        payoff="crossrange_nmi",
        goal="max",
        constraints=(C.temperature_limit(limit_R),),
        base=spec,
        controls=lambda s, x: C.with_alpha_table(s, x),
    )


def test_spec_carries_the_heating_model(single_parameter_spec):
    assert isinstance(single_parameter_spec.heating, ReferenceHeating)
    spec = parse("case", {"vehicle": {"builtin": "lod-1.89"}, "entry": TABLE2_ENTRY}).to_spec()
    with pytest.raises(ValueError, match="heating model"):
        C.control_problem(spec, constraints=(C.temperature_limit(LIMIT_R),), controls="bank_alpha")


def test_alpha_table_moves_alpha_along_the_flight_within_bounds(single_parameter_spec):
    table = [40.0, 30.0, 20.0, 15.0, 12.5]  # deg at 2,000 ... 26,000 ft/s
    h = simulate(C.with_alpha_table(single_parameter_spec, table)).history
    a, v = h["alpha_deg"], h["velocity_fps"]
    assert a.min() >= C.ALPHA_BOUNDS_DEG[0] - 1e-9 and a.max() <= C.ALPHA_BOUNDS_DEG[1] + 1e-9
    assert a.max() - a.min() > 15.0  # deg: the table really steers alpha
    expected = np.interp(v, C.ALPHA_TABLE_VELOCITIES_FPS, table)
    assert np.max(np.abs(a - expected)) < 1e-9  # deg: alpha is the table at the flown velocity


def test_alpha_table_against_time(single_parameter_spec):
    times_s, table = (0.0, 300.0, 1_000.0), [40.0, 20.0, 12.5]
    pr = C.control_problem(single_parameter_spec, controls="bank_alpha", alpha_times_s=times_s)
    assert pr.names[-3:] == ("alpha_deg_at_time_s_0", "alpha_deg_at_time_s_300", "alpha_deg_at_time_s_1000")
    h = simulate(pr.controls(pr.base, np.concatenate((C.nominal_bank_deg(1.0), table)))).history
    assert np.max(np.abs(h["alpha_deg"] - np.interp(h["time_s"], times_s, table))) < 1e-9  # deg


def test_bank_alpha_controls_keep_both_tables():
    spec = lod189()
    x = np.concatenate((C.nominal_bank_deg(1.0), [35.0, 30.0, 25.0, 20.0, 15.0]))
    h = simulate(C.bank_alpha_controls(spec, x)).history
    assert h["alpha_deg"].max() > 20.0  # deg: the alpha table is flown
    pull = np.argmax(h["gamma_deg"] >= 0.0)  # first flare: the bank is zero in the plunge (Fig. 20)
    assert np.all(h["bank_deg"][:pull] == 0.0)
    assert h["bank_deg"].max() > 30.0  # deg: the bank table flies after pull-out


def test_temperature_constrained_optimum_is_in_the_band():
    spec = lod189(OPTIMAL_BANK)
    free = simulate(spec).summary  # the unconstrained optimum at (L/D)max: 2,670 degR by calibration
    r = creep_pattern_feasible(
        alpha_only_problem(spec, LIMIT_R), max_evaluations=200, step=5.0, min_step=0.2, soft_start=1e-2
    )
    assert free["max_temperature_R"] == pytest.approx(REPORT["sec3.max_temperature_R"].value, abs=5.0)
    assert r.feasible
    assert r.summary["max_temperature_R"] <= LIMIT_R + BAND_R + 1e-9
    assert r.summary["crossrange_nmi"] < free["crossrange_nmi"]  # the limit costs cross-range
    assert r.params.max() > C.ALPHA_MAX_LD_HYPERSONIC_DEG + 1.0  # deg: alpha raised off (L/D)max somewhere


def test_an_impossible_temperature_is_reported_infeasible(single_parameter_spec):
    r = creep_pattern_feasible(
        alpha_only_problem(single_parameter_spec, 2_000.0), max_evaluations=120, step=5.0, min_step=0.2
    )
    assert not r.feasible
    excess = r.summary["max_temperature_R"] - 2_000.0 - BAND_R
    assert r.max_violation == pytest.approx(excess, abs=1e-9)  # degR, the best flight's own excess
    assert r.violations["max_temperature_R"] == r.max_violation > 100.0  # degR: far from reach
    assert r.max_violation < simulate(single_parameter_spec).summary["max_temperature_R"] - 2_000.0  # it tried


def test_parallel_and_serial_optimal_footprints_agree(same_numbers):
    """Same search, same steps; the summaries may differ in the last bit (NumPy's SIMD paths vary by process)."""
    spec = lod189()
    kw = {"downranges_nmi": (3_000.0, 6_000.0), "controls": "bank", "max_evaluations": 40}
    with dask_client(workers=2) as client:  # the core runs its points through the map it is given
        par = C.optimal_footprint(spec, map_tasks=client_map(client), **kw)
    ser = C.optimal_footprint(spec, **kw)
    assert [p.label for p in par.points] == ["max_crossrange", "downrange_3000", "downrange_6000", "max_downrange"]
    assert par.trajectories == ser.trajectories
    for a, b in zip(par.points, ser.points):
        assert a.label == b.label
        assert np.array_equal(a.result.params, b.result.params)
        same_numbers(a.result.summary, b.result.summary)
    assert par.point("max_downrange").downrange_nmi > par.point("max_crossrange").downrange_nmi


def test_tables_on_other_abscissae_fly_at_their_nodes():
    """Bank against energy height, alpha against time: each angle is its table read at the flown abscissa."""
    bank = C.ControlTable("energy", (1e6, 5e6, 1e7), (0.0, 90.0), (10.0, 40.0, 70.0))
    alpha = C.ControlTable("time", (0.0, 600.0, 1_500.0), (12.5, 40.0), (30.0, 20.0, 15.0))
    pr = C.control_problem(lod189(), controls="bank_alpha", bank_table=bank, alpha_table=alpha)
    assert pr.names == (
        "bank_deg_at_energy_ft_1000000",
        "bank_deg_at_energy_ft_5000000",
        "bank_deg_at_energy_ft_10000000",
        "alpha_deg_at_time_s_0",
        "alpha_deg_at_time_s_600",
        "alpha_deg_at_time_s_1500",
    )
    assert list(pr.initial) == [10.0, 40.0, 70.0, 30.0, 20.0, 15.0] and list(pr.upper) == [90.0] * 3 + [40.0] * 3
    h = simulate(pr.controls(pr.base, pr.initial)).history
    energy_ft = h["altitude_ft"] + h["velocity_fps"] ** 2 / (2.0 * G0_FT_S2)
    banked = h["bank_deg"] != 0.0  # zero in the plunge, before the bank start
    assert banked.any()
    assert np.max(np.abs(h["bank_deg"][banked] - np.interp(energy_ft[banked], bank.nodes, bank.initial_deg))) < 1e-6
    assert np.max(np.abs(h["alpha_deg"] - np.interp(h["time_s"], alpha.nodes, alpha.initial_deg))) < 1e-9  # deg
    with pytest.raises(ValueError, match="bank_alpha"):
        C.control_problem(lod189(), controls="bank", alpha_table=alpha)


def test_unknown_controls_are_refused():
    with pytest.raises(ValueError, match="controls"):
        C.control_problem(lod189(), controls="alpha")


def test_a_flight_that_does_not_reach_the_stop_altitude_has_no_payoff():
    """Bank 150 deg at alpha 40 deg chatters to the step limit: the search must not take it for a short flight."""
    pr = C.control_problem(lod189(), payoff="downrange_nmi", goal="min", controls="bank_alpha")
    s = pr.summary(np.concatenate((np.full(8, 150.0), np.full(5, 40.0))))
    assert s["stop_reason"] == "max_steps" and s["downrange_nmi"] is None
    ok = pr.summary(np.concatenate((np.full(8, 150.0), np.full(5, 12.5))))
    assert ok["stop_reason"] == "altitude" and ok["downrange_nmi"] > 1_000.0  # nmi


# ------------------------------------------------------------------ the simple heating-constrained method
def test_a_zero_floor_is_the_max_ld_flight(single_parameter_spec):
    """alpha = max((L/D)max, 0) is (L/D)max: the same flight to the last bit."""
    plain = simulate(single_parameter_spec).summary
    floored = simulate(C.with_alpha_floor(single_parameter_spec, 0.0)).summary
    assert floored == plain


def test_the_floor_acts_only_above_its_knee(single_parameter_spec):
    h = simulate(C.with_alpha_floor(single_parameter_spec, 30.0)).history
    plain = simulate(single_parameter_spec)  # (L/D)max alpha is 12.5-20 deg on lod-1.89
    fast = h["velocity_fps"] >= C.FLOOR_VELOCITIES_FPS[1]
    slow = h["velocity_fps"] <= C.FLOOR_VELOCITIES_FPS[0]
    assert np.all(np.abs(h["alpha_deg"][fast] - 30.0) < 1e-9)  # deg: the floor binds where it is flown
    assert plain.history["alpha_deg"].max() < 30.0
    assert np.all(h["alpha_deg"][slow] < 21.0)  # deg: (L/D)max again below 12,000 ft/s
    assert slow.any() and fast.any()


def test_the_coolest_floor_meets_the_limit_and_a_lower_one_does_not(single_parameter_spec):
    p = C.coolest_floor(single_parameter_spec, LIMIT_R)
    assert p.floor_deg is not None and C.ALPHA_BOUNDS_DEG[0] < p.floor_deg < C.ALPHA_BOUNDS_DEG[1]
    assert p.summary["max_temperature_R"] <= LIMIT_R + C.TTOL_TEMPERATURE_R
    lower = C.FLOOR_SCAN_STEP_DEG / 2**C.FLOOR_BISECTIONS  # deg: the search's resolution
    below = simulate(C.with_alpha_floor(single_parameter_spec, p.floor_deg - lower)).summary
    assert below["max_temperature_R"] > LIMIT_R + C.TTOL_TEMPERATURE_R
    assert p.flights <= 1 + (C.ALPHA_BOUNDS_DEG[1] - C.ALPHA_BOUNDS_DEG[0]) / C.FLOOR_SCAN_STEP_DEG + C.FLOOR_BISECTIONS


@pytest.fixture(scope="module")
def limited_2550():
    return C.temperature_limited_footprint(lod189(), S.TemperatureLimited(limit_R=LIMIT_R))


def test_every_kept_point_meets_the_limit_and_every_dropped_one_cannot(limited_2550):
    kept = [p for p in limited_2550.points if p.floor_deg is not None]
    dropped = [p for p in limited_2550.points if p.floor_deg is None]
    assert kept and dropped  # the steep banks heat past 2,550 degR at any alpha up to C_L max
    assert all(p.summary["max_temperature_R"] <= LIMIT_R + C.TTOL_TEMPERATURE_R for p in kept)
    assert all(p.summary["max_temperature_R"] > LIMIT_R + C.TTOL_TEMPERATURE_R for p in dropped)
    assert max(p.bank0_deg for p in kept) < min(p.bank0_deg for p in dropped)  # steeper banks heat more
    assert len(limited_2550.footprint.points) == len(kept)  # left half (mirror off), one point per setting


def test_the_limit_doubles_the_minimum_downrange_as_the_report_says(limited_2550):
    """Section III: under 2,550 degR the minimum down-range about doubles (1,000 -> 2,000 nmi)."""
    free = C.temperature_limited_footprint(
        lod189(), S.TemperatureLimited(limit_R=1e9)
    ).footprint  # no limit: the plain footprint
    ratio = limited_2550.footprint.min_downrange_nmi / free.min_downrange_nmi
    report = REPORT["sec3.min_downrange_2550_nmi"].value / REPORT["sec3.min_downrange_nmi"].value  # 2
    assert abs(ratio - report) < 0.5


def test_the_simple_method_is_within_5_percent_of_the_optimizer_at_a_tenth_of_the_cost(limited_2550):
    """Issue 5: max cross-range and max down-range within 5 % of the optimized constrained footprint's,
    for at least 10x fewer trajectories (here against three of its points, its two ends and 8,000 nmi: a lower
    bound on its cost; bench/bench_limited_footprint.py measures the whole)."""
    opt = C.optimal_footprint(
        lod189(), (8_000.0,), constraints=(C.temperature_limit(LIMIT_R),), controls="bank_alpha", max_evaluations=3_000
    )
    simple = limited_2550.footprint
    assert all(p.result.feasible for p in opt.points)
    assert simple.max_crossrange_nmi == pytest.approx(opt.point("max_crossrange").crossrange_nmi, rel=0.05)
    assert simple.max_downrange_nmi == pytest.approx(opt.point("max_downrange").downrange_nmi, rel=0.05)
    assert opt.trajectories >= 10 * limited_2550.trajectories
