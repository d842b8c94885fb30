"""Path limits held in flight across a step of the alpha law (issue 50 item 1): the L/D 1.89 vehicle at (L/D)max,
whose alpha steps from 12.5 to 17.4 deg between Mach 6.45 and 6.14 (C_L +56 %), flown guided to 4,300 nmi down-range.
The flown peak is recomputed from the history's own columns (n = q sqrt(C_L^2 + C_D^2) / (W/S), the lift and drag
over the weight), not read from the summary."""

import copy

import numpy as np
import pytest

from footprint.api import fly
from footprint.contracts import parse, stored_form
from footprint.core import guided_dispersion as gdisp
from tests.authorities.report import example, guided_spreads
from tests.core.test_guidance import LOD189, guided

SPREADS = guided_spreads()  # the example's dispersions

MARGIN = 1.01  # the flown peak within 1 % of the limit


def _flight(downrange_nmi=4300.0, **settings):
    case = guided(downrange_nmi, 0.0, copy.deepcopy(LOD189), **settings)
    return fly(case), parse("case", case).to_spec().vehicle.wing_loading_psf


def _crosses_the_alpha_step(history):
    return np.min(history["alpha_deg"]) < 13.0 and np.max(history["alpha_deg"]) > 17.0


@pytest.mark.parametrize("limit_g", [2.5, 2.0])
def test_a_load_factor_limit_holds_across_the_alpha_step(limit_g):
    """Before issue 50 the bound used today's alpha: 2.89 g flown under a 2.5 g limit, 2.93 g under 2.0 g."""
    flight, wing_loading_psf = _flight(max_load_factor=limit_g)
    h, guidance = flight.history, flight.summary["guidance"]
    load = h["dynamic_pressure_psf"] * np.hypot(h["cl"], h["cd"]) / wing_loading_psf
    assert _crosses_the_alpha_step(h)
    assert np.max(load) <= limit_g * MARGIN
    assert guidance["status"] == ("reached" if guidance["miss_nmi"] <= 5.0 else "not reachable")


def test_a_heat_rate_limit_holds_across_the_alpha_step():
    """The reference heating model (eqs. 5-7), 28 Btu/(ft^2 s) against the 31.8 flown free."""
    base = copy.deepcopy(LOD189) | {"heating": {"model": "reference"}}
    case = guided(4300.0, 0.0, base, max_heat_rate_btu_ft2_s=28.0)
    h = fly(case).history
    assert _crosses_the_alpha_step(h)
    assert np.max(h["heat_rate_btu_ft2_s"]) <= 28.0 * MARGIN


def test_a_dynamic_pressure_limit_holds_across_the_alpha_step():
    flight, _ = _flight(max_dynamic_pressure_psf=600.0)
    h = flight.history
    assert _crosses_the_alpha_step(h)
    assert np.max(h["dynamic_pressure_psf"]) <= 600.0 * MARGIN


# --- the vehicle's limits held by default (issue 50 item 2) ---
# A crewed glider's limits, the Shuttle orbiter's (Harpold & Graves 1979: 2.5 g; the commonly quoted 375 psf)
VEHICLE_G, VEHICLE_PSF = 2.5, 375.0


def _peaks(flight, wing_loading_psf):
    h = flight.history
    load = h["dynamic_pressure_psf"] * np.hypot(h["cl"], h["cd"]) / wing_loading_psf
    return float(np.max(load)), float(np.max(h["dynamic_pressure_psf"]))


@pytest.mark.parametrize("downrange_nmi", [4300.0, 3000.0])
def test_an_unset_guidance_holds_the_vehicles_limits(downrange_nmi):
    """Before, an unset limit was no limit: the 4,300 nmi target was flown by diving to 4.73 g and 1,583 psf, the
    unreachable 3,000 nmi one to 6.63 g and 2,181 psf. Within 2.5 g and 375 psf neither is reachable from Table 2's
    entry (wings level the glider at (L/D)max glides at q = (W/S)/C_L ~ 390 psf at low speed): each ends "not
    reachable", at the best miss that holds them, and says the limit that bound it."""
    flight, wing_loading_psf = _flight(downrange_nmi, lifted={})
    load_g, qbar_psf = _peaks(flight, wing_loading_psf)
    guidance = flight.summary["guidance"]
    assert load_g <= VEHICLE_G * MARGIN and qbar_psf <= VEHICLE_PSF * MARGIN
    assert guidance["status"] == "not reachable" and guidance["miss_nmi"] > 5.0
    assert "dynamic_pressure_psf" in guidance["binding_limits"]
    assert guidance["status_reason"] == "within the limits: " + ", ".join(guidance["binding_limits"])


def test_a_reachable_target_within_the_limits_is_reached_holding_them():
    """6,000 nmi straight ahead is within the glider's limits: reached, and no peak past them."""
    flight, wing_loading_psf = _flight(6000.0, lifted={})
    load_g, qbar_psf = _peaks(flight, wing_loading_psf)
    assert flight.summary["guidance"]["status"] == "reached" and flight.summary["guidance"]["status_reason"] is None
    assert load_g <= VEHICLE_G * MARGIN and qbar_psf <= VEHICLE_PSF * MARGIN


def _guidance_of(bank=None, vehicle_limits=None, heating=None):
    case = guided(5000.0, 600.0, copy.deepcopy(LOD189), lifted={}, **(bank or {}))
    if vehicle_limits is not None:
        case["vehicle"]["limits"] = vehicle_limits
    if heating is not None:
        case["heating"] = heating
    return parse("case", case).to_spec().guidance


def test_a_guidance_limit_unset_is_the_vehicles_a_number_changes_it_and_null_lifts_it():
    unset = _guidance_of(vehicle_limits={"load_factor_g": 3.0, "dynamic_pressure_psf": 500.0})
    assert (unset.max_load_factor, unset.max_dynamic_pressure_psf) == (3.0, 500.0)
    given = _guidance_of({"max_load_factor": 2.0, "max_dynamic_pressure_psf": None})
    assert (given.max_load_factor, given.max_dynamic_pressure_psf) == (2.0, None)
    lifted_vehicle = _guidance_of(vehicle_limits={"load_factor_g": None})
    assert lifted_vehicle.max_load_factor is None and lifted_vehicle.max_dynamic_pressure_psf == VEHICLE_PSF


def test_heat_rate_and_temperature_are_held_only_where_the_case_evaluates_them():
    """No heating model: neither (the summary lists them unchecked); the reference model: both, the vehicle's 70
    Btu/(ft^2 s) and 3,460 degR; a correlation without emissivity: the heat rate, not the temperature (eq. 7)."""
    none = _guidance_of()
    assert none.max_heat_rate_btu_ft2_s is None and none.max_temperature_R is None
    reference = _guidance_of(heating={"model": "reference"})
    assert (reference.max_heat_rate_btu_ft2_s, reference.max_temperature_R) == (70.0, 3460.0)
    correlation = _guidance_of(heating={"model": "correlation", "coefficient": 9.3e-9, "velocity_exponent": 3.07})
    assert correlation.max_heat_rate_btu_ft2_s == 70.0 and correlation.max_temperature_R is None


# --- the vehicle's limits held under dispersion (issue 50: the dispersed example peaked at 4.66 g, p99 4.15 g) ---
def _dispersed_peaks(case, samples):
    """Each sample's peak load factor and q-bar (the summary's, checked against the history in test_vehicle_limits),
    flown guided under the example's dispersions (tests/authorities/report.guided_spreads)."""
    study = parse("guided_dispersion", {"case": case, "samples": samples, "seed": 1, "open_loop": False, **SPREADS})
    spec = study.case.to_spec()
    values = gdisp.fly_samples(spec, None, study.draw(spec)).values[:, 0]
    return {k: values[:, gdisp.COLUMNS.index(k)] for k in ("max_load_factor", "max_dynamic_pressure_psf")}


def _fraction_past(peaks, limit):
    return float(np.mean(peaks > limit * MARGIN))


DISPERSED = [pytest.param(60, id="60"), pytest.param(300, id="300", marks=pytest.mark.slow)]
# (the case, the limits it holds): measured with 300 samples, seed 1, 2026-12-08 (before: no limit held, the
# example peaked at 4.66 g, p99 4.15 g, and past 375 psf in every sample)
HELD = {
    # the example as examples/ gives it, 2.5 g held and 375 psf lifted: max 2.33 g, every landing within 0.60 nmi
    "example": (lambda: example("disperse_guided_lod189")["case"], ["max_load_factor"]),
    # the example's target with every vehicle limit: max 1.99 g, 377.4 psf (385.2 psf p99 before the bound took the
    # scale height of the air flown, not the model's), not reachable (miss p50 283 nmi)
    "example, vehicle's limits": (
        lambda: guided(5000.0, 600.0, copy.deepcopy(LOD189), lifted={}),
        ["max_load_factor", "max_dynamic_pressure_psf"],
    ),
    # 6,000 nmi straight ahead, reached within every vehicle limit: max 1.94 g, 372.6 psf, miss p99 0.61 nmi
    "6000/0, vehicle's limits": (
        lambda: guided(6000.0, 0.0, copy.deepcopy(LOD189), lifted={}),
        ["max_load_factor", "max_dynamic_pressure_psf"],
    ),
}
LIMIT_OF = {"max_load_factor": VEHICLE_G, "max_dynamic_pressure_psf": VEHICLE_PSF}


@pytest.mark.parametrize("samples", DISPERSED)
@pytest.mark.parametrize("name", list(HELD))
def test_the_dispersed_peaks_hold_the_limits_in_99_percent_of_samples(name, samples):
    case, held = HELD[name]
    peaks = _dispersed_peaks(case(), samples)
    for key in held:
        assert _fraction_past(peaks[key], LIMIT_OF[key]) <= 0.01, (key, np.max(peaks[key]))


def test_a_job_stores_unset_limits_unset_and_lifted_ones_lifted():
    """A job's workers parse the study's stored form (contracts.stored_form): an unset limit must stay the vehicle's
    there and a null one lifted, not come back as the null default."""
    case = guided(5000.0, 600.0, copy.deepcopy(LOD189), lifted={}, max_dynamic_pressure_psf=None)
    again = parse("case", stored_form(parse("case", case))).to_spec().guidance
    assert again.max_load_factor == VEHICLE_G and again.max_dynamic_pressure_psf is None
