"""Dispersions of one Monte Carlo sample (trajectory.Dispersion): CL and CD multipliers on the aero tables and a
density factor 1 + delta(h) on the atmosphere, flown inside the compiled right-hand side."""

from dataclasses import replace

import numpy as np
import pytest

from footprint.contracts import parse
from footprint.core.atmosphere import DENSITY_NODE_COUNT, DENSITY_NODES_FT, density_factor_table
from footprint.core.errors import InputError
from footprint.core.trajectory import Dispersion, simulate
from tests.authorities.report import example

EXPONENTIAL = {"atmosphere": {"model": "exponential", "rho0_slug_ft3": 0.0027, "scale_height_ft": 23_800}}


def table2(**changes):
    """The Table 2 case of examples/table2_lod22.json (lod-2.2, single-parameter bank from pull-out)."""
    return parse("case", {**example("table2_lod22"), **changes}).to_spec()


def dispersed(spec, **knobs):
    return replace(spec, dispersion=Dispersion(**knobs))


def test_the_default_dispersion_and_a_zero_density_profile_fly_the_nominal_vehicle_to_the_bit():
    spec = table2(heating={"model": "reference"})
    nominal = simulate(spec)
    for knobs in ({"cl_multiplier": 1.0, "cd_multiplier": 1.0}, {"density_delta": np.zeros(DENSITY_NODE_COUNT)}):
        t = simulate(dispersed(spec, **knobs))
        assert t.summary == nominal.summary, knobs
        for key, values in nominal.history.items():
            np.testing.assert_array_equal(t.history[key], values, err_msg=key)


def test_more_drag_shortens_and_more_lift_lengthens_the_table2_flight():
    spec = table2()
    nominal = simulate(spec).summary["downrange_nmi"]
    draggy = simulate(dispersed(spec, cd_multiplier=1.05)).summary["downrange_nmi"]
    lifty = simulate(dispersed(spec, cl_multiplier=1.05)).summary["downrange_nmi"]
    # a 5 % change of L/D changes a glide of ~8,000 nmi by some hundreds of nmi (range ~ L/D)
    assert draggy < nominal - 100.0  # nmi
    assert lifty > nominal + 100.0  # nmi


def test_the_multipliers_scale_the_recorded_coefficients():
    spec = table2()
    nominal = simulate(spec).history
    t = simulate(dispersed(spec, cl_multiplier=1.1, cd_multiplier=0.9)).history
    # alpha is that of (L/D)max of the tables (scaling both curves leaves it), so at the entry row CL and CD are the
    # tables' times the multipliers
    assert t["alpha_deg"][0] == nominal["alpha_deg"][0]
    assert t["cl"][0] == pytest.approx(1.1 * nominal["cl"][0], rel=1e-15)
    assert t["cd"][0] == pytest.approx(0.9 * nominal["cd"][0], rel=1e-15)


@pytest.mark.parametrize("delta", [-0.2, 0.15])
def test_a_constant_density_profile_is_the_exponential_atmosphere_with_rho0_scaled(delta):
    """Two formulations of the same air: rho0 exp(-h/H) times (1 + delta) in the right-hand side, and an
    exponential atmosphere of density rho0 (1 + delta). They differ by the rounding of one product per
    evaluation, grown over the 3,400 s flight to ~1e-8 of the final velocity; the heating sees the dispersed
    density too."""
    heating = {"model": "reference"}
    base = table2(planet=EXPONENTIAL, heating=heating)
    by_profile = simulate(dispersed(base, density_delta=np.full(DENSITY_NODE_COUNT, delta))).summary
    rho0 = replace(base.planet, rho0_slug_ft3=base.planet.rho0_slug_ft3 * (1.0 + delta))
    by_rho0 = simulate(replace(base, planet=rho0)).summary
    nominal = simulate(base).summary
    assert abs(by_profile["downrange_nmi"] - nominal["downrange_nmi"]) > 1.0  # nmi: the factor does act
    assert by_profile["downrange_nmi"] == pytest.approx(by_rho0["downrange_nmi"], abs=1e-5)  # nmi (0.06 ft)
    assert by_profile["crossrange_nmi"] == pytest.approx(by_rho0["crossrange_nmi"], abs=1e-5)  # nmi
    assert by_profile["flight_time_s"] == pytest.approx(by_rho0["flight_time_s"], abs=1e-4)  # s
    assert by_profile["final_velocity_fps"] == pytest.approx(by_rho0["final_velocity_fps"], abs=1e-3)  # ft/s
    assert by_profile["max_temperature_R"] == pytest.approx(by_rho0["max_temperature_R"], abs=1e-6)  # degR
    assert by_profile["max_heat_rate_btu_ft2_s"] == pytest.approx(by_rho0["max_heat_rate_btu_ft2_s"], rel=1e-9)
    # the heat load is a trapezoidal sum over the steps, which the round-off moves a little
    assert by_profile["heat_load_btu_ft2"] == pytest.approx(by_rho0["heat_load_btu_ft2"], rel=1e-6)


def test_the_density_factor_is_linear_between_the_nodes_and_held_beyond():
    rng = np.random.default_rng(7)
    delta = rng.normal(0.0, 0.1, DENSITY_NODE_COUNT)
    altitudes_ft = np.concatenate([rng.uniform(-5_000.0, 450_000.0, 500), DENSITY_NODES_FT])
    expected = 1.0 + np.interp(altitudes_ft, DENSITY_NODES_FT, delta)  # np.interp holds the end values
    np.testing.assert_allclose(density_factor_table(delta, altitudes_ft), expected, rtol=1e-15, atol=0.0)
    assert density_factor_table(delta, np.nan) == 1.0 + delta[0]  # a NaN altitude reads no node out of range


@pytest.mark.parametrize("knobs, field", [
    ({"cl_multiplier": 0.0}, "dispersion.cl_multiplier"),
    ({"cd_multiplier": float("nan")}, "dispersion.cd_multiplier"),
    ({"density_delta": np.zeros(DENSITY_NODE_COUNT - 1)}, "dispersion.density_delta"),
    ({"density_delta": np.full(DENSITY_NODE_COUNT, -1.0)}, "dispersion.density_delta"),
])
def test_a_bad_dispersion_names_its_field(knobs, field):
    with pytest.raises(InputError) as err:
        Dispersion(**knobs)
    assert err.value.field == field
