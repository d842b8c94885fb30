"""`footprint optimize`, as a user runs it (DESIGN.md's optimization study contract)."""

import csv
import json
import subprocess
import sys
from pathlib import Path

import pytest

from footprint.contracts import parse
from tests.authorities.report import REPORT

ROOT = Path(__file__).resolve().parents[1]
STUDY = json.loads((ROOT / "examples" / "optimize_lod189_4000nmi.json").read_text())
BETTS = json.loads((ROOT / "examples" / "optimize_betts_shuttle.json").read_text())


def betts_optimum():
    """Betts' published maximum cross-range of the Space Shuttle entry (tests/authorities)."""
    with open(ROOT / "tests" / "authorities" / "betts_shuttle_reentry.csv") as f:
        rows = list(csv.DictReader(line for line in f if not line.startswith("#")))
    return {k: float(v) for k, v in rows[0].items() if k != "case"}


BETTS_SHARE = 0.995  # issue 12: the search reaches 99.5 % of the published final latitude


def run(tmp_path, study, *args):
    path = tmp_path / "study.json"
    path.write_text(json.dumps(study))
    return subprocess.run(
        [sys.executable, "-m", "footprint.cli", "optimize", str(path), *args],
        capture_output=True,
        text=True,
        timeout=900,
    )


def test_unconstrained_optimum_beats_the_single_parameter_control_and_draws_fig_3(tmp_path):
    r = run(tmp_path, {**STUDY, "constraints": [], "max_trajectories": 200}, "--plot", str(tmp_path / "c.png"))
    assert r.returncode == 0, r.stderr
    out = json.loads(r.stdout)
    assert set(out) >= {"summary", "parameters", "history", "feasible", "trajectories"}
    assert out["feasible"] and out["trajectories"] <= 200
    # the best single-parameter point of the L/D 1.89 footprint is 2,024 nmi (docs/validation.md)
    assert out["summary"]["crossrange_nmi"] >= 2_024.0
    assert out["summary"]["crossrange_nmi"] == pytest.approx(REPORT["sec3.max_crossrange_nmi"].value, rel=0.10)
    assert len(out["parameters"]) == 8 and all(0 <= v <= 180 for v in out["parameters"].values())
    payoffs = [h["payoff"] for h in out["history"]]
    assert payoffs == sorted(payoffs)  # best so far, one stage: never down
    assert (tmp_path / "c.png").read_bytes()[:4] == b"\x89PNG"


def test_a_down_range_beyond_reach_is_reported_infeasible_with_its_violation(tmp_path):
    study = {**STUDY, "constraints": [{"quantity": "downrange_nmi", "equals": 16_000}], "max_trajectories": 150}
    r = run(tmp_path, study)
    assert r.returncode == 1
    out = json.loads(r.stdout)
    assert out["feasible"] is False
    # the zero-bank flight, 14,869 nmi, is as far as the vehicle goes: at least 1,100 nmi short beyond the band
    assert out["max_violation"] == pytest.approx(16_000 - 25 - 14_869, abs=5.0)


def test_bank_and_alpha_tables_hold_a_temperature_limit(tmp_path):
    """Section III: the bank table plus an alpha table vs velocity, maximum cross-range at RET <= 2,550 degR."""
    case = {**STUDY["case"], "heating": {"model": "reference"}}
    limit = REPORT["sec3.limit_R"].value
    study = {
        **STUDY,
        "case": case,
        "controls": ["bank", "alpha"],
        "max_trajectories": 2_500,
        "constraints": [{"quantity": "max_temperature_R", "at_most": limit}],
    }
    r = run(tmp_path, study)
    assert r.returncode == 0, r.stderr
    out = json.loads(r.stdout)
    assert out["feasible"] and out["summary"]["max_temperature_R"] <= limit + 2.5  # degR: half the TTOL band
    alphas = {k: v for k, v in out["parameters"].items() if k.startswith("alpha_deg")}
    assert len(out["parameters"]) == 13 and len(alphas) == 5
    assert all(12.5 <= v <= 40.0 for v in alphas.values())  # deg: (L/D)max to C_L max of lod-1.89
    assert max(alphas.values()) > 12.5  # the unconstrained optimum peaks at 2,670 degR: alpha must rise


@pytest.mark.parametrize(
    "change, words",
    [
        ({"constraints": [{"quantity": "max_temperature_R", "at_most": 2550}]}, "case.heating"),
        ({"constraints": [{"quantity": "downrange_nmi", "equals": 4000, "at_most": 5000}]}, "exactly one of"),
        ({"payoff": {"quantity": "happiness", "goal": "max"}}, "payoff.quantity"),
        ({"method": "genetic"}, "method"),
        ({"max_trajectories": 5}, "max_trajectories"),
        ({"controls": ["alpha"]}, "controls"),
        ({"controls": ["bank", "bank"]}, "controls"),
    ],
)
def test_a_bad_study_gets_one_line_and_exit_2(tmp_path, change, words):
    r = run(tmp_path, {**STUDY, **change})
    assert r.returncode == 2 and r.stdout == "" and "Traceback" not in r.stderr
    assert r.stderr.count("\n") == 1 and words in r.stderr, r.stderr


# ------------------------------------------------------------- the search's knobs: Betts' Space Shuttle entry
ENERGY_FT = [177_000, 10_445_000]  # the terminal (80,000 ft, 2,500 ft/s) to the entry energy height


@pytest.mark.parametrize(
    "knobs",
    [
        {},  # the example: bank (16 nodes) and alpha (8 nodes) against energy height
        {
            "bank_table": {"time_s": [0, 2_100], "count": 12, "bounds_deg": [-1, 89]},
            "alpha_table": {"velocity_fps": [2_500, 25_600], "count": 6},
        },
    ],
    ids=["energy_energy", "time_velocity"],
)
def test_betts_shuttle_maximum_cross_range_within_half_a_percent_of_the_published_optimum(tmp_path, knobs):
    """Betts (2010) section 6.1 posed as a study: creep + pattern, default weights, tolerance-scaled constraints."""
    published = betts_optimum()
    r = run(tmp_path, {**BETTS, **knobs})
    assert r.returncode == 0, r.stderr
    out = json.loads(r.stdout)
    s = out["summary"]
    assert out["feasible"] and s["stop_reason"] == "altitude"
    assert s["final_latitude_deg"] >= BETTS_SHARE * published["final_latitude_deg"]
    assert abs(s["final_velocity_fps"] - 2_500) <= 10 / 2  # ft/s: half the tolerance band
    assert abs(s["final_gamma_deg"] + 5) <= 0.1 / 2  # deg: half the tolerance band
    assert out["trajectories"] <= BETTS["max_trajectories"]
    # deg: Betts' bank beta in [-89, 1] deg is ours negated (a positive bank turns left, north here)
    banks = [v for k, v in out["parameters"].items() if k.startswith("bank_deg")]
    assert all(-1 <= v <= 89 for v in banks)
    assert s["flight_time_s"] == pytest.approx(published["flight_time_s"], rel=0.02)  # s: the same optimum's length


def test_a_scipy_method_searches_the_same_tables(tmp_path):
    r = run(tmp_path, {**BETTS, "method": "Nelder-Mead", "max_trajectories": 60})
    assert r.returncode in (0, 1), r.stderr  # 1: no feasible point in so small a budget
    out = json.loads(r.stdout)
    assert out["trajectories"] <= 60 and out["method"] == "Nelder-Mead"
    names = list(out["parameters"])
    assert names[0] == "bank_deg_at_energy_ft_177000" and names[15] == "bank_deg_at_energy_ft_10445000"
    assert names[16] == "alpha_deg_at_energy_ft_177000" and len(names) == 16 + 8


def test_constraints_are_scaled_by_their_tolerance_by_default_only_with_a_table_block():
    assert [c.scale for c in parse("optimize", BETTS).core_constraints()] == [10.0, 0.1]  # ft/s, deg
    assert [c.scale for c in parse("optimize", {**BETTS, "constraint_scaling": "none"}).core_constraints()] == [1, 1]
    plain = {k: v for k, v in BETTS.items() if k not in ("bank_table", "alpha_table")}
    assert [c.scale for c in parse("optimize", plain).core_constraints()] == [1.0, 1.0]  # eq. (4) as before
    given = dict(BETTS["constraints"][0], scale=2.0)
    assert (
        parse("optimize", {**plain, "constraints": [given], "constraint_scaling": "tolerance"})
        .core_constraints()[0]
        .scale
        == 2.0
    )


NARROW_ALPHA = {
    **BETTS["case"],
    "vehicle": {
        **BETTS["case"]["vehicle"],
        "aero": {"polynomial": {**BETTS["case"]["vehicle"]["aero"]["polynomial"], "alpha_range_deg": [0, 45]}},
    },
}


@pytest.mark.parametrize(
    "change, words",
    [
        ({"bank_table": {"altitude_ft": [0, 1]}}, "bank_table.altitude_ft: Extra inputs"),
        ({"bank_table": {"time_s": [0, 100], "energy_ft": [1e5, 1e7]}}, "bank_table: give at most one of"),
        ({"bank_table": {"time_s": [0, 500, 400]}}, "time_s must be strictly increasing"),
        (
            {"bank_table": {"zeta_deg": [-200, 0]}},
            "bank_table.zeta_deg.0: -200 is outside the allowed range -180 to 180",
        ),
        ({"bank_table": {"heading_deg": [0, 270]}}, "bank_table.heading_deg.1: 270 is outside the allowed range"),
        ({"bank_table": {"time_s": [-5, 100]}}, "bank_table.time_s.0: -5 is outside the allowed range 0 to 100,000 s"),
        (
            {"bank_table": {"velocity_fps": [0, 50_000]}},
            "bank_table.velocity_fps.1: 50,000 is outside the allowed range",
        ),
        (
            {"bank_table": {"energy_ft": [0, 2e8]}},
            "bank_table.energy_ft.1: 200,000,000 is outside the allowed range 0 to 100,000,000",
        ),
        (
            {"bank_table": {"energy_ft": ENERGY_FT, "count": 1}},
            "bank_table.count: 1 is outside the allowed range 2 to 64",
        ),
        ({"bank_table": {"energy_ft": [1e5, 1e6, 1e7], "count": 8}}, "needs the first and last node"),
        ({"bank_table": {"bounds_deg": [-200, 89]}}, "bank_table.bounds_deg.0: -200 is outside the allowed range"),
        ({"bank_table": {"bounds_deg": [89, -1]}}, "bounds_deg: lower bound 89 is not below the upper bound -1"),
        ({"bank_table": {"initial_deg": [10, 20, 30]}}, "initial_deg has 3 values for 8 nodes"),
        ({"bank_table": {"bounds_deg": [-1, 89], "initial_deg": 95}}, "initial_deg 95 is outside bounds_deg -1 to 89"),
        ({"alpha_table": {"heading_deg": [0, 10]}}, "alpha_table.heading_deg: Extra inputs"),
        ({"alpha_table": {"time_s": [0, 1e6]}}, "alpha_table.time_s.1: 1,000,000 is outside the allowed range"),
        ({"alpha_table": {"velocity_fps": [3_000, 2_000]}}, "alpha_table: velocity_fps must be strictly increasing"),
        ({"alpha_table": {"energy_ft": ENERGY_FT, "count": 65}}, "alpha_table.count: 65 is outside the allowed range"),
        (
            {"alpha_table": {"bounds_deg": [-100, 40]}},
            "alpha_table.bounds_deg.0: -100 is outside the allowed range -90",
        ),
        (
            {"case": NARROW_ALPHA, "alpha_table": {"bounds_deg": [-5, 40]}},
            "alpha_table: bounds_deg -5 to 40 must lie within the vehicle's alpha range 0 to 45 deg",
        ),
        (
            {"case": NARROW_ALPHA, "alpha_table": {"initial_deg": 60}},
            "alpha_table: initial_deg 60 is outside the vehicle's alpha range 0 to 45 deg",
        ),
        ({"alpha_table": {"initial_deg": [15, 17]}}, "alpha_table: initial_deg has 2 values for 5 nodes"),
        ({"controls": ["bank"]}, "alpha_table: the alpha table is searched with controls ['bank', 'alpha']"),
        ({"constraint_scaling": "unit"}, "constraint_scaling: Input should be 'tolerance' or 'none'"),
        (
            {"constraints": [{"quantity": "final_gamma_deg", "equals": -5}]},
            "constraints.0.tolerance: constraint_scaling",
        ),
        (
            {"constraints": [{"quantity": "final_gamma_deg", "equals": -5, "tolerance": 0.1, "scale": 0}]},
            "constraints.0.scale: 0 is outside the allowed range",
        ),
    ],
)
def test_a_bad_search_knob_gets_one_line_and_exit_2(tmp_path, change, words):
    r = run(tmp_path, {**BETTS, **change})
    assert r.returncode == 2 and r.stdout == "" and "Traceback" not in r.stderr
    assert r.stderr.count("\n") == 1 and words in r.stderr, r.stderr


COLLOCATION = json.loads((ROOT / "examples" / "optimize_betts_collocation.json").read_text())


def test_collocation_study_reaches_betts_published_optimum_and_draws_its_histories(tmp_path):
    r = run(tmp_path, COLLOCATION, "--plot", str(tmp_path / "h.png"))
    assert r.returncode == 0, r.stderr
    out = json.loads(r.stdout)
    assert out["method"] == "collocation" and out["status"] == "optimal" and out["feasible"]
    assert abs(out["summary"]["final_latitude_deg"] - betts_optimum()["final_latitude_deg"]) < 0.01  # deg
    assert out["agreement"]["latitude_deg"] < 0.01 and out["refly"]["stop_reason"] == "altitude"
    # the mesh refined from the study's intervals until the optimum settled (issue 29)
    assert len(out["controls"]["time_s"]) == out["intervals"] + 1 > COLLOCATION["collocation"]["intervals"] + 1
    assert abs(out["mesh_change"]) <= 1e-3
    assert (tmp_path / "h.png").stat().st_size > 10_000


def test_an_unreachable_collocation_target_exits_1_with_one_line(tmp_path):
    study = {
        **COLLOCATION,
        "constraints": COLLOCATION["constraints"] + [{"quantity": "downrange_nmi", "equals": 20000}],
        "collocation": {**COLLOCATION["collocation"], "max_iterations": 300},
    }
    r = run(tmp_path, study)
    assert r.returncode == 1
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith(("error: infeasible:", "error: not converged:"))
    assert "largest violation" in lines[0]
    assert json.loads(r.stdout)["feasible"] is False  # the last iterate is printed


@pytest.mark.parametrize(
    "change, field",
    [
        ({"collocation": {"intervals": 2}}, "collocation.intervals"),
        ({"collocation": {"bank_bounds_deg": [10, -10]}}, "bank_bounds_deg"),
        ({"collocation": {"starts": 9}}, "collocation.starts"),
        (
            {
                "constraints": [
                    {"quantity": "final_latitude_deg", "equals": 90},
                    {"quantity": "final_longitude_deg", "equals": 0},
                ]
            },
            "constraints.final_longitude_deg: a final latitude of +-90 deg is the pole",
        ),
        ({"method": "creep_pattern"}, "collocation: options for method 'collocation'"),
        ({"payoff": {"quantity": "pullout_altitude_ft"}}, "pullout_altitude_ft: not available to the collocation"),
    ],
)
def test_a_bad_collocation_study_is_one_line_and_exit_2(tmp_path, change, field):
    r = run(tmp_path, {**COLLOCATION, **change})
    assert r.returncode == 2
    assert field in r.stderr and len(r.stderr.strip().splitlines()) == 1


# a collocation answer as to_dict gives it, with what the lines below read
OPTIMUM = {"method": "collocation", "feasible": True, "iterations": 120, "seconds": 2.0}


def test_an_optimum_flying_upside_down_says_so_in_its_lines():
    """The collocation re-flight's time upside down at negative lift (collocation.inverted_s), in the CLI's words."""
    from footprint.cli import _optimum_lines

    optimum = OPTIMUM | {
        "summary": {"crossrange_nmi": 0.4, "downrange_nmi": 17_955.5, "flight_time_s": 5_786.0},
        "agreement": {"latitude_deg": 0.0007, "longitude_deg": 0.0001, "east_west_deg": 0.0001, "end_deg": 0.0007},
        "refly": {"inverted_s": 5_786.0},
    }
    lines = _optimum_lines(optimum)
    assert "flies upside down at negative lift for 5,786 s (alpha_bounds_deg can rule it out)" in lines
    assert not any("upside down" in line for line in _optimum_lines(optimum | {"refly": {"inverted_s": 0.0}}))


def test_an_optimum_says_its_payoff_unless_it_is_the_cross_range_of_the_first_line():
    """The fly-there's least heat load was not in the lines at all (they gave the cross-range, 900.6 nmi)."""
    from footprint.cli import _optimum_lines

    optimum = OPTIMUM | {
        "objective": 24_022.61,
        "summary": {"crossrange_nmi": 900.6, "downrange_nmi": 3_002.0, "heat_load_btu_ft2": 24_022.61},
    }
    heat = _optimum_lines(optimum, (("heat_load_btu_ft2", 1.0),), "min")
    assert "minimized heat_load_btu_ft2: 24,022.61" in heat
    weighted = _optimum_lines(optimum, (("heat_load_btu_ft2", 1.0), ("crossrange_nmi", -2.0)), "min")
    assert "minimized heat_load_btu_ft2 + -2 x crossrange_nmi: 24,022.61" in weighted
    assert len(_optimum_lines(optimum, (("crossrange_nmi", 1.0),))) == len(_optimum_lines(optimum))


def test_an_optimum_of_several_starts_lists_their_objectives():
    from footprint.cli import _optimum_lines

    optimum = OPTIMUM | {
        "summary": {"crossrange_nmi": 901.0, "downrange_nmi": 3_002.0, "flight_time_s": 930.0},
        "start_objectives": [5_439_674.27, None, 5_889_284.35],
    }
    assert "the best of 3 starts, whose first meshes ended at: 5,439,674.3, none, 5,889,284.3" in _optimum_lines(
        optimum
    )
    assert not any("starts" in line for line in _optimum_lines(optimum | {"start_objectives": None}))
