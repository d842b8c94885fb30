"""Dispersions of one Monte Carlo sample (trajectory.Dispersion): CL and CD multipliers on the aero tables and a
density factor 1 + delta(h) on the atmosphere, flown inside the compiled right-hand side; and the sampler that
draws them (core/dispersion.py)."""

from dataclasses import replace

import numpy as np
import pytest
from scipy.interpolate import CubicSpline

from footprint.contracts import parse
from footprint.core import dispersion as mc
from footprint.core.atmosphere import (
    DENSITY_NODE_COUNT,
    DENSITY_NODES_FT,
    density_factor_table,
    density_kink_between_ft,
    density_profile,
)
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


def test_level_flight_holds_its_altitude_with_a_dispersed_lift_curve():
    """The hold asks the dispersed vehicle for the lift it needs (alpha_for_cl_deg on CL / multiplier), so the flight
    stays level below (L/D)max whatever the multiplier (as test_control_laws' nominal level flight)."""
    for multiplier in (0.9, 1.1):
        t = simulate(dispersed(table2(alpha={"law": "level_flight"}, bank={"law": "zero"}), cl_multiplier=multiplier))
        s, h = t.summary, t.history
        level = (h["time_s"] > s["pullout_time_s"] + 1e-9) & (h["alpha_deg"] < 11.999)
        assert level.sum() > 20
        assert np.max(np.abs(h["gamma_deg"][level])) < 0.05  # deg
        assert np.ptp(h["altitude_ft"][level]) < 300.0  # ft


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


def factor(delta, altitudes_ft):
    return density_factor_table(density_profile(delta), altitudes_ft)


def test_the_density_factor_is_the_natural_cubic_spline_through_the_nodes_held_beyond():
    rng = np.random.default_rng(7)
    delta = rng.normal(0.0, 0.1, DENSITY_NODE_COUNT)
    altitudes_ft = np.concatenate([rng.uniform(-5_000.0, 450_000.0, 500), DENSITY_NODES_FT])
    spline = CubicSpline(DENSITY_NODES_FT, delta, bc_type="natural")  # scipy's, an independent construction
    held = np.clip(altitudes_ft, DENSITY_NODES_FT[0], DENSITY_NODES_FT[-1])
    np.testing.assert_allclose(factor(delta, altitudes_ft), 1.0 + spline(held), rtol=0.0, atol=1e-14)
    assert np.array_equal(factor(delta, DENSITY_NODES_FT), 1.0 + delta)  # the drawn nodes, exactly
    assert factor(delta, np.nan) == 1.0 + delta[0]  # a NaN altitude reads no node out of range
    # no kink at an inner node: the slopes on either side agree to the differencing error (a polyline's jump by ~0.1)
    h = 1.0  # ft
    inner = DENSITY_NODES_FT[1:-1]
    left = (factor(delta, inner) - factor(delta, inner - h)) / h
    right = (factor(delta, inner + h) - factor(delta, inner)) / h
    assert np.max(np.abs(right - left)) * 10_000.0 < 1e-4  # per node spacing


def test_a_profile_with_extreme_nodes_keeps_the_density_positive_between_them():
    """The spline through one node at +0.9 among nodes at -0.9 dips below -1 beside it (a negative density: scipy's
    own spline reaches a factor of -0.15); the factor is held above half the lower node's there; the nodes are kept."""
    delta = np.where(np.arange(DENSITY_NODE_COUNT) == 20, 0.9, -0.9)
    altitudes_ft = np.linspace(0.0, 400_000.0, 40_001)
    assert np.min(1.0 + CubicSpline(DENSITY_NODES_FT, delta, bc_type="natural")(altitudes_ft)) < 0.0
    assert np.min(factor(delta, altitudes_ft)) >= 0.05
    assert np.array_equal(factor(delta, DENSITY_NODES_FT), 1.0 + delta)


def test_the_profile_has_kinks_only_where_the_spline_meets_its_held_ends():
    """DOP853 steps onto a kink (integrate._kink_fraction): none at the inner nodes; at an end node, where the spline
    meets the held value, only if its slope there is not zero (scipy's spline's derivative is the reference)."""
    delta = np.random.default_rng(3).normal(0.0, 0.05, DENSITY_NODE_COUNT)
    profile = density_profile(delta)
    slope = CubicSpline(DENSITY_NODES_FT, delta, bc_type="natural").derivative()
    assert slope(DENSITY_NODES_FT[0]) != 0.0 and slope(DENSITY_NODES_FT[-1]) != 0.0
    assert np.isnan(density_kink_between_ft(profile, 0, 15_000.0, 385_000.0))  # 37 inner nodes, no kink
    assert density_kink_between_ft(profile, 0, 395_000.0, 405_000.0) == 400_000.0
    assert density_kink_between_ft(profile, 0, 5_000.0, -5_000.0) == 0.0
    assert np.isnan(density_kink_between_ft(density_profile(np.full(DENSITY_NODE_COUNT, 0.1)), 0, 395e3, 405e3))


@pytest.mark.parametrize(
    "knobs, field",
    [
        ({"cl_multiplier": 0.0}, "dispersion.cl_multiplier"),
        ({"cd_multiplier": float("nan")}, "dispersion.cd_multiplier"),
        ({"density_delta": np.zeros(DENSITY_NODE_COUNT - 1)}, "dispersion.density_delta"),
        ({"density_delta": np.full(DENSITY_NODE_COUNT, -1.0)}, "dispersion.density_delta"),
    ],
)
def test_a_bad_dispersion_names_its_field(knobs, field):
    with pytest.raises(InputError) as err:
        Dispersion(**knobs)
    assert err.value.field == field


# ------------------------------------------------------------------------------- the sampler (core/dispersion.py)

ENTRY_DISPERSIONS = {
    "altitude_ft": mc.Normal(364_800.0, 1_000.0),
    "velocity_fps": mc.Normal(24_480.0, 20.0),
    "gamma_deg": mc.TruncatedNormal(-2.0, 0.05, -2.1, -1.9),
    "heading_deg": mc.Uniform(89.9, 90.1),
    "cl_multiplier": mc.Normal(1.0, 0.03),
    "cd_multiplier": mc.Normal(1.0, 0.03),
    "wing_loading_psf": mc.TruncatedNormal(50.0, 1.0, 47.0, 53.0),
}


def test_the_density_profile_is_correlated_as_exp_minus_dh_over_l():
    """Sample correlation between nodes against exp(-Delta h / L), within 4 standard errors of a correlation
    coefficient estimated from n samples, (1 - rho^2) / sqrt(n)."""
    n, length_ft = 20_000, 30_000.0
    delta = mc.draw(
        {}, n, seed=3, method="random", density=mc.GaussMarkovDensity(std=0.08, correlation_length_ft=length_ft)
    ).density_delta
    assert delta.shape == (n, DENSITY_NODE_COUNT)
    sample = np.corrcoef(delta, rowvar=False)
    for i, j in [(0, 1), (0, 3), (5, 6), (10, 13), (20, 30), (37, 40), (2, 40)]:
        rho = np.exp(-abs(DENSITY_NODES_FT[j] - DENSITY_NODES_FT[i]) / length_ft)
        assert abs(sample[i, j] - rho) < 4.0 * (1.0 - rho**2) / np.sqrt(n) + 1e-3, (i, j, sample[i, j], rho)
    # stationary: every node has the std asked for (standard error of a std: std / sqrt(2 n))
    np.testing.assert_allclose(delta.std(axis=0), 0.08, atol=4.0 * 0.08 / np.sqrt(2 * n))
    np.testing.assert_allclose(delta.mean(axis=0), 0.0, atol=4.0 * 0.08 / np.sqrt(n))


def test_a_std_per_node_scales_each_node():
    std = np.linspace(0.01, 0.15, DENSITY_NODE_COUNT)
    delta = mc.draw({}, 8_192, seed=4, density=mc.GaussMarkovDensity(std=std)).density_delta
    np.testing.assert_allclose(delta.std(axis=0) / std, 1.0, atol=0.05)  # 4 standard errors of 8,192 samples


@pytest.mark.parametrize("method", mc.METHODS)
def test_the_draws_follow_their_distributions(method):
    n = 4_096
    s = mc.draw(ENTRY_DISPERSIONS, n, seed=11, method=method).values
    for name in ("altitude_ft", "velocity_fps", "cl_multiplier"):
        d = ENTRY_DISPERSIONS[name]
        assert abs(s[name].mean() - d.mean) < 4.0 * d.std / np.sqrt(n), name
        assert abs(s[name].std() / d.std - 1.0) < 4.0 / np.sqrt(2 * n), name
    assert np.all((s["gamma_deg"] >= -2.1) & (s["gamma_deg"] <= -1.9))
    assert np.all((s["heading_deg"] >= 89.9) & (s["heading_deg"] <= 90.1))
    assert np.all((s["wing_loading_psf"] >= 47.0) & (s["wing_loading_psf"] <= 53.0))
    # the truncated normal of +-2 std keeps its untruncated shape inside: std 0.880 of the parent's
    assert s["gamma_deg"].std() == pytest.approx(0.05 * 0.8796, rel=0.05)


@pytest.mark.parametrize("method", mc.METHODS)
def test_a_seed_and_n_give_the_same_samples_to_the_bit_however_they_are_chunked(method):
    density = mc.GaussMarkovDensity(std=0.1)
    a = mc.draw(ENTRY_DISPERSIONS, 300, seed=5, method=method, density=density)
    b = mc.draw(ENTRY_DISPERSIONS, 300, seed=5, method=method, density=density)
    for name in a.values:
        assert a.values[name].tobytes() == b.values[name].tobytes()
    assert a.density_delta.tobytes() == b.density_delta.tobytes()
    chunks = [a[i : i + 64] for i in range(0, len(a), 64)]
    assert [len(c) for c in chunks] == [64, 64, 64, 64, 44]
    base = table2()
    for i in (0, 63, 64, 299):
        k, j = divmod(i, 64)
        whole, chunked = mc.sample_spec(base, a, i), mc.sample_spec(base, chunks[k], j)
        assert whole.entry == chunked.entry and whole.vehicle == chunked.vehicle
        assert whole.dispersion == chunked.dispersion
    other = mc.draw(ENTRY_DISPERSIONS, 300, seed=6, method=method, density=density)
    assert not np.array_equal(other.values["altitude_ft"], a.values["altitude_ft"])


def test_sample_spec_puts_each_input_in_its_place():
    s = mc.draw(ENTRY_DISPERSIONS, 8, seed=1, density=mc.GaussMarkovDensity(std=0.05))
    base = table2()
    spec = mc.sample_spec(base, s, 3)
    assert spec.entry.altitude_ft == s.values["altitude_ft"][3]
    assert spec.entry.heading_deg == s.values["heading_deg"][3]
    assert spec.entry.latitude_deg == base.entry.latitude_deg  # not dispersed: the base's
    assert spec.vehicle.wing_loading_psf == s.values["wing_loading_psf"][3]
    assert spec.vehicle.blob is base.vehicle.blob  # the tables are not rebuilt
    assert spec.dispersion.cl_multiplier == s.values["cl_multiplier"][3]
    assert np.array_equal(spec.dispersion.density_delta, s.density_delta[3])


def test_a_small_monte_carlo_run_flies_in_chunks_as_in_one_piece():
    s = mc.draw(ENTRY_DISPERSIONS, 16, seed=2, density=mc.GaussMarkovDensity(std=0.1))
    base = table2()
    whole = mc.summaries(base, s)
    assert whole == mc.summaries(base, s[:5]) + mc.summaries(base, s[5:])
    assert all(x["stop_reason"] == "altitude" for x in whole)
    # the glide's range goes with L/D: the multipliers' ratio explains most of the spread (the density, speed and
    # wing loading the rest)
    down = np.array([x["downrange_nmi"] for x in whole])
    ld_multiplier = s.values["cl_multiplier"] / s.values["cd_multiplier"]
    assert np.corrcoef(ld_multiplier, down)[0, 1] > 0.7


@pytest.mark.parametrize(
    "kwargs, field",
    [
        ({"distributions": {"mass_lb": mc.Normal(1.0, 1.0)}}, "distributions.mass_lb"),
        ({"distributions": {"gamma_deg": mc.Normal(-2.0, 0.0)}}, "distributions.gamma_deg"),
        ({"distributions": {"heading_deg": mc.Uniform(91.0, 90.0)}}, "distributions.heading_deg"),
        ({"distributions": {"cd_multiplier": mc.Normal(1.0, 1.0)}}, "distributions.cd_multiplier"),  # draws < 0
        ({"density": mc.GaussMarkovDensity(std=0.5)}, "density"),
        ({"density": mc.GaussMarkovDensity(std=0.1, correlation_length_ft=0.0)}, "density"),
        ({"method": "halton"}, "method"),
        ({"n": 0}, "n"),
    ],
)
def test_a_bad_draw_names_its_field(kwargs, field):
    args = {"distributions": {}, "n": 64, "seed": 0} | kwargs
    with pytest.raises(InputError) as err:
        mc.draw(**args)
    assert err.value.field == field
