"""The reference heating model of AFWAL-TR-82-3036 Section III (eqs. 5-7, Table 1) and the generic correlation."""

import json
import subprocess
import sys
from dataclasses import replace

import numpy as np
import pytest

from footprint.api import fly
from footprint.contracts import parse
from footprint.core.atmosphere import FT_PER_M, KG_PER_SLUG, atmosphere_table
from footprint.core.dynamics import P_ATM, P_ATM_T, P_RHO0, P_SCALE_H
from footprint.core.heating import (
    CALIBRATION_BANK_DEG,
    REFERENCE_RADIUS_FT,
    CorrelationHeating,
    ReferenceHeating,
    calibrate_reference_radius_ft,
    fay_riddell_coefficient_lbm_ft2_s,
    fay_riddell_cold_wall_btu_ft2_s,
    radiation_equilibrium_R,
    table1_ratio,
    thin_skin_R,
    total_enthalpy_btu_lbm,
    wall_equilibrium_R,
)
from footprint.core.trajectory import pack_parameters, simulate
from tests.authorities.report import REPORT, table2_entry, table2_stop

W_M2_PER_BTU_FT2_S = 11_356.53  # 1 Btu_IT/(ft^2 s)
TABLE2_ENTRY = table2_entry()
# Section III.1's calibration flight: the unconstrained optimum, an 8-point bank table vs zeta, 2,044.5 nmi
MAX_CROSS_RANGE_BANK = {"law": "table", "heading_deg": list(range(-15, 91, 15)), "bank_deg": list(CALIBRATION_BANK_DEG)}


def lod189(alpha=None, bank=None, heating=None):
    case = {
        "vehicle": {"builtin": "lod-1.89"},
        "entry": dict(TABLE2_ENTRY),
        "alpha": alpha or {"law": "max_ld"},
        "bank": bank or dict(MAX_CROSS_RANGE_BANK),
        "stop": table2_stop(),
    }
    if heating is not None:
        case["heating"] = heating
    return case


# --- Table 1 and eq. (7) ---------------------------------------------------------------------------------------
@pytest.mark.parametrize(
    "alpha_deg, ratio",
    [
        *(tuple(row) for row in REPORT["table1.h_ratio_vs_alpha"].value),  # Table 1 as printed
        (10, 0.1725),
        (22.5, 0.1875),
        (35, 0.23),
        (47.5, 0.28),  # linear between rows
        (-5, 0.17),
        (70, 0.30),  # held at the ends
    ],
)
def test_table1_ratio(alpha_deg, ratio):
    assert table1_ratio(alpha_deg) == pytest.approx(ratio, abs=1e-12)


def test_eq7_against_a_hand_calculation():
    # 19.3 / (4.75e-13 * 0.8) = 5.07895e13 Btu... ; sqrt = 7.12667e6 ; sqrt = 2669.58 degR (heating.md §3: 2,670)
    assert radiation_equilibrium_R(19.3, 0.8) == pytest.approx(2669.58, abs=0.05)  # degR
    assert radiation_equilibrium_R(0.0, 0.8) == 0.0


def test_wall_equilibrium_solves_eqs_6_and_7_together():
    h = np.array([0.0, 1e-4, 2.6e-3, 4.6e-3, 0.05])  # lbm/(ft^2 s)
    h_aw = np.array([8_000.0, 8_000.0, 8_096.0, 8_096.0, 3_000.0])  # Btu/lbm
    t = wall_equilibrium_R(h, h_aw, 0.8)
    q = h * (h_aw - 0.24 * t)  # eq. (6)
    assert np.allclose(4.75e-13 * 0.8 * t**4, q, rtol=1e-10, atol=1e-12)  # eq. (7)
    assert t[0] == 0.0 and np.all(np.diff(t[:4]) > 0)


# --- the Fay-Riddell coefficient --------------------------------------------------------------------------------
def test_detra_kemp_riddell_worked_example():
    """heating.md §5: 20,000 ft/s at 200,000 ft (ARDC 1959), 1-ft sphere: 123.6 Btu/(ft^2 s), h_F&R 0.01551."""
    rho, t_inf = 6.118e-7, 449.0  # slug/ft^3, degR
    assert fay_riddell_cold_wall_btu_ft2_s(rho, 20_000.0, 1.0) == pytest.approx(123.6, abs=0.1)  # printed to 0.1
    assert total_enthalpy_btu_lbm(20_000.0, t_inf) == pytest.approx(8_096.0, abs=1.0)
    assert fay_riddell_coefficient_lbm_ft2_s(rho, 20_000.0, t_inf, 1.0) == pytest.approx(0.01551, abs=1e-5)


@pytest.mark.parametrize(
    "alpha_deg, heat_rate, temperature_R",
    [
        (0, 19.7, 2_682),
        (20, 20.2, 2_701),
        (25, 23.0, 2_790),
        (30, 26.4, 2_887),
        (45, 29.8, 2_975),
        (50, 34.2, 3_081),
    ],
)
def test_body_point_table_of_heating_md(alpha_deg, heat_rate, temperature_R):
    """heating.md §5 table (R = 1 ft, eps = 0.8, H_AW = H_0, H_W = 0.24 T_W iterated), printed to 0.1 and 1 degR."""
    q, t = ReferenceHeating(reference_radius_ft=1.0, emissivity=0.8).evaluate(6.118e-7, 20_000.0, alpha_deg, 449.0)
    assert q == pytest.approx(heat_rate, abs=0.15)  # Btu/(ft^2 s)
    assert t == pytest.approx(temperature_R, abs=2.0)  # degR


@pytest.mark.parametrize(
    "altitude_ft, velocity_fps",
    [
        (280_000, 25_500),
        (250_000, 24_000),
        (230_000, 22_000),
        (200_000, 20_000),
        (180_000, 16_000),
        (150_000, 12_000),
    ],
)
def test_fay_riddell_against_sutton_graves(altitude_ft, velocity_fps):
    """Sutton & Graves (1971), an independent correlation: q = 1.7415e-4 sqrt(rho/R_n) V^3, SI, Earth air.
    DKR goes as V^3.15 and Sutton-Graves as V^3, so they part by up to ~15 % near orbital speed."""
    rho = float(atmosphere_table("ardc1959", altitude_ft)["density_slug_ft3"])
    rho_kg_m3, v_m_s, radius_m = rho * KG_PER_SLUG * FT_PER_M**3, velocity_fps * 0.3048, 0.3048
    sutton_graves = 1.7415e-4 * np.sqrt(rho_kg_m3 / radius_m) * v_m_s**3 / W_M2_PER_BTU_FT2_S
    ours = fay_riddell_cold_wall_btu_ft2_s(rho, velocity_fps, 1.0)
    assert abs(ours / sutton_graves - 1.0) < 0.15  # two correlations of the same theory, ~15 % apart at most


# --- the calibration and the report's trajectories --------------------------------------------------------------
@pytest.fixture(scope="module")
def max_crossrange():
    return fly(lod189(heating={"model": "reference"}))


def test_calibration_max_crossrange_peaks_at_2670R(max_crossrange):
    s = max_crossrange.summary
    assert s["crossrange_nmi"] == pytest.approx(2_044.5, abs=0.5)  # nmi: the optimum (bench/results/optimize.json)
    assert s["max_temperature_R"] == pytest.approx(REPORT["sec3.max_temperature_R"].value, abs=5)  # degR
    # the peak between the rows (core.sampled: the parabola's vertex about the largest row) lies above that row, by
    # less than the rows' spacing allows (1.9e-3 Btu/ft^2/s here)
    rows_max = max_crossrange.history["heat_rate_btu_ft2_s"].max()
    assert rows_max <= s["max_heat_rate_btu_ft2_s"] <= rows_max * (1.0 + 1e-3)


def test_calibration_recomputes_the_reference_radius(max_crossrange):
    spec = parse("case", lod189()).to_spec()
    p = pack_parameters(spec)
    h = max_crossrange.history
    radius_ft = calibrate_reference_radius_ft(
        h["altitude_ft"], h["velocity_fps"], h["alpha_deg"], (p[P_ATM], p[P_RHO0], p[P_SCALE_H], p[P_ATM_T])
    )
    assert radius_ft == pytest.approx(REFERENCE_RADIUS_FT, rel=1e-3)  # the constant is rounded to 4 figures


def test_peak_does_not_depend_on_the_output_step(max_crossrange):
    """The peak is read from the integrator's rows: a 10x finer output must not move it."""
    spec = replace(parse("case", lod189(heating={"model": "reference"})).to_spec(), max_step_s=5.0)
    fine = simulate(spec).summary["max_temperature_R"]
    assert fine == pytest.approx(max_crossrange.summary["max_temperature_R"], abs=1.0)  # degR


def test_cl_max_plunge_is_cooler_than_max_ld_plunge():
    """Report III.2: a tighter RET limit forces entry towards C_L max. In this model Table 1 raises h/h_F&R
    from .17 (12.5 deg, (L/D)max) to .23 (40 deg, C_L max), x1.35, but the C_L max vehicle pulls out ~30,000 ft
    higher, where rho is ~1/4 and h ~ sqrt(rho) ~1/2: the plunge's peak RET must drop."""
    ld = fly(lod189(bank={"law": "zero"}, heating={"model": "reference"})).summary
    cl = fly(lod189(alpha={"law": "cl_max"}, bank={"law": "zero"}, heating={"model": "reference"})).summary
    assert cl["pullout_altitude_ft"] > ld["pullout_altitude_ft"] + 20_000  # ft
    assert cl["max_temperature_R"] < ld["max_temperature_R"] - 100  # degR (2,393 vs 2,632 when written)


# --- the thin skin (the report's "one-dimensional conduction analysis", in its simplest form) -------------------
ES = 4.75e-13 * 0.8  # Btu/(ft^2 s degR^4), eq. (7) with eps = 0.8


def test_thin_skin_against_an_independent_integration():
    """C dT/dt = h (H - c_p T) - eps sigma T^4 for a heat pulse, against scipy's Radau at tight tolerances."""
    from scipy.integrate import solve_ivp

    cap = 0.5  # Btu/(ft^2 degR)

    def h(t):
        return 0.004 * np.exp(-(((t - 200.0) / 60.0) ** 2))  # lbm/(ft^2 s)

    def rhs(t, y):
        return [(h(t) * (7_000.0 - 0.24 * y[0]) - ES * y[0] ** 4) / cap]

    times = np.linspace(0.0, 600.0, 601)  # rows 1 s apart
    ref = solve_ivp(rhs, (0.0, 600.0), [530.0], method="Radau", t_eval=times, rtol=1e-10, atol=1e-8).y[0]
    ours = thin_skin_R(times, h(times), np.full(601, 7_000.0), 0.8, cap, 530.0)
    assert ref.max() > 2_700.0  # degR: a pulse that matters
    assert np.max(np.abs(ours - ref)) < 0.2  # degR; h linear between rows is the main approximation


def test_thin_skin_settles_at_the_radiation_equilibrium():
    """Constant heating: the skin tends to eq. (7)'s RET, and near it the gap decays at the linearized rate."""
    times = np.linspace(0.0, 2_000.0, 201)
    h, haw = np.full(201, 0.003), np.full(201, 8_000.0)
    ret = wall_equilibrium_R(0.003, 8_000.0, 0.8)
    assert thin_skin_R(times, h, haw, 0.8, 1.0, 530.0)[-1] == pytest.approx(ret, abs=0.01)  # degR
    # from 10 degR below: the gap decays as exp(-t / tau), tau = C / (4 eps sigma T^3 + h c_p)
    tau = 1.0 / (4.0 * ES * ret**3 + 0.003 * 0.24)
    t3 = thin_skin_R(np.array([0.0, 3 * tau]), h[:2], haw[:2], 0.8, 1.0, ret - 10.0)[-1]
    assert ret - t3 == pytest.approx(10.0 * np.exp(-3.0), rel=0.05)


def test_thin_skin_lags_and_damps_a_flight_and_tends_to_ret():
    ret = fly(lod189(heating={"model": "reference"}))
    thin = fly(lod189(heating={"model": "reference", "skin_heat_capacity_btu_ft2_R": 0.01})).summary
    thick = fly(lod189(heating={"model": "reference", "skin_heat_capacity_btu_ft2_R": 4.0}))
    assert thin["max_temperature_R"] == pytest.approx(ret.summary["max_temperature_R"], abs=5.0)  # degR
    assert thick.summary["max_temperature_R"] < ret.summary["max_temperature_R"] - 100.0  # degR: damped (174)
    assert np.argmax(thick.history["temperature_R"]) > np.argmax(ret.history["temperature_R"])  # and late


# --- the generic correlation ------------------------------------------------------------------------------------
BETTS_SHUTTLE = {
    "model": "correlation",
    "coefficient": 17_700 * 1e-4**3.07,
    "density_exponent": 0.5,
    "velocity_exponent": 3.07,
    "alpha_polynomial_deg": [1.0672181, -0.19213774e-1, 0.21286289e-3, -0.10117249e-5],
}


def test_correlation_by_hand():
    """Betts, Practical Methods for Optimal Control (2nd ed.), shuttle reentry: q = q_a q_r,
    q_r = 17,700 sqrt(rho) (1e-4 V)^3.07, q_a = c0 + c1 a + c2 a^2 + c3 a^3 (a in deg)."""
    rho, v, a = 2e-6, 20_000.0, 30.0
    c = BETTS_SHUTTLE["alpha_polynomial_deg"]
    by_hand = 17_700 * np.sqrt(rho) * (1e-4 * v) ** 3.07 * (c[0] + c[1] * a + c[2] * a**2 + c[3] * a**3)
    model = parse("case", lod189(heating=dict(BETTS_SHUTTLE, emissivity=0.85))).to_spec().heating
    assert isinstance(model, CorrelationHeating)
    q, t = model.evaluate(rho, v, a)
    assert q == pytest.approx(by_hand, rel=1e-12)
    assert t == pytest.approx((by_hand / (4.75e-13 * 0.85)) ** 0.25, rel=1e-12)  # eq. (7)


def test_correlation_along_a_flight():
    with_t = fly(lod189(heating=dict(BETTS_SHUTTLE, emissivity=0.8))).summary
    without_t = fly(lod189(heating=BETTS_SHUTTLE)).summary
    assert without_t["max_temperature_R"] is None
    assert with_t["max_heat_rate_btu_ft2_s"] == pytest.approx(without_t["max_heat_rate_btu_ft2_s"])
    # eq. (7) is monotone in the heat rate: the peaks coincide, each read between the rows to the parabola's O(h^3)
    assert with_t["max_temperature_R"] == pytest.approx(
        radiation_equilibrium_R(with_t["max_heat_rate_btu_ft2_s"], 0.8), rel=1e-6
    )


# --- the contract -----------------------------------------------------------------------------------------------
def test_no_model_no_heating():
    t = fly(lod189(bank={"law": "zero"}))
    assert t.summary["max_temperature_R"] is None and t.summary["max_heat_rate_btu_ft2_s"] is None
    assert "temperature_R" not in t.history and "heat_rate_btu_ft2_s" not in t.history


def test_reference_defaults_are_the_calibrated_ones():
    model = parse("case", lod189(heating={"model": "reference"})).to_spec().heating
    assert model == ReferenceHeating(reference_radius_ft=REFERENCE_RADIUS_FT, emissivity=0.8)


@pytest.mark.parametrize(
    "heating, field",
    [
        ({"model": "reference", "emissivity": 1.5}, "heating.emissivity"),
        ({"model": "reference", "reference_radius_ft": 0}, "heating.reference_radius_ft"),
        ({"model": "correlation", "coefficient": 1.0, "velocity_exponent": 12}, "heating.velocity_exponent"),
        ({"model": "reference", "nose_radius": 1}, "heating.nose_radius"),
        ({"model": "reference", "skin_heat_capacity_btu_ft2_R": -1}, "heating.skin_heat_capacity_btu_ft2_R"),
    ],
)
def test_bad_heating_section_is_one_line(tmp_path, heating, field):
    path = tmp_path / "case.json"
    path.write_text(json.dumps(lod189(heating=heating)))
    r = subprocess.run(
        [sys.executable, "-m", "footprint.cli", "fly", str(path)],
        check=False,
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert r.returncode == 2
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and field in lines[0] and "Traceback" not in r.stderr, r.stderr
