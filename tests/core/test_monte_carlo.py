"""Dispersed footprints (issue 16): a footprint's control settings flown in Monte Carlo samples of the entry, the
air and the aerodynamics (footprint.contracts.dispersion, footprint.core.monte_carlo). Checked against routes that
do not go through the Monte Carlo: the undispersed footprint flown by footprint() (full histories), the linear
covariance J Sigma J^T from finite differences of fly(), closed forms (the exact binomial interval, an ellipse's
enclosed fraction) and the geometry of sites placed inside, outside and on the nominal boundary."""

import copy
import math

import numpy as np
import pytest
from pydantic import ValidationError
from scipy import stats

from footprint import contracts, parallel
from footprint.api import disperse as run
from footprint.contracts.dispersion import Plan, parse_request
from footprint.contracts.messages import error_line
from footprint.core import monte_carlo as mc
from footprint.core.errors import InputError
from footprint.core.footprint_methods import footprint
from footprint.core.method_settings import SingleParameter
from footprint.core.plane import inside_polygon
from footprint.core.sphere import downrange_crossrange_nmi, latlon_from_ranges
from tests.authorities.report import example

FOOTPRINT = example("footprint_lod189")  # the L/D 1.89 Table 2 entry, 11 bank settings, both halves
SMALL = FOOTPRINT | {"bank0_deg": [0, 60, 120]}  # 3 settings: 6 flights a sample (axis, 2 x 2, zero lift)


def study(footprint_study=SMALL, **fields) -> dict:
    return {"footprint": copy.deepcopy(footprint_study), **fields}


def test_without_dispersion_every_sample_lands_on_the_nominal_point_to_the_bit():
    result, _ = run(study(samples=6, seed=3))
    nominal = footprint(
        parse_request(study()).footprint.case.to_spec(),
        SingleParameter(bank0_deg=tuple(SMALL["bank0_deg"]), min_range="zero_lift", mirror=True),
    )  # simulate's histories
    flown = {
        (p.side, p.parameter.bank0_deg if p.parameter.min_range is None else p.parameter.min_range): p
        for p in nominal.points + nominal.interior
    }
    clouds = result.clouds
    for j, f in enumerate(result.flights):
        p = flown[(f["side"], f["parameter"].get("bank0_deg", f["parameter"].get("min_range")))]
        assert f["landed"] == 6 and f["outcomes"] == {}
        assert set(clouds["latitude_deg"][:, j]) == {p.latitude_deg}  # the same bits, all six samples
        assert set(clouds["longitude_deg"][:, j]) == {p.longitude_deg}
        assert len(set(clouds["downrange_nmi"][:, j])) == len(set(clouds["crossrange_nmi"][:, j])) == 1
        assert np.abs(f["covariance_nmi2"]).max() < 1e-20  # nmi^2: numpy's mean of six equal numbers, rounded
    assert result.outcomes == {"flights": 36, "landed": 36}


def _flight(result, side, bank0_deg):
    return next(
        j for j, f in enumerate(result.flights) if f["side"] == side and f["parameter"].get("bank0_deg") == bank0_deg
    )


SPREAD = {"altitude_ft": 300.0, "velocity_fps": 4.0, "gamma_deg": 0.004}  # small: the response is linear
ONE_SETTING = FOOTPRINT | {"bank0_deg": [60], "min_range": None, "mirror": False}  # one flight a sample


def test_the_sample_covariance_is_the_linear_covariance_of_finite_differences():
    """N = 2,000 samples of a banked flight: its (down-range, cross-range) covariance against J Sigma J^T, J by
    central differences of fly() in the same ranges (about the nominal entry)."""
    n = 2_000
    result, _ = run(
        study(
            ONE_SETTING,
            samples=n,
            design="random",
            seed=11,
            entry={k: {"normal": {"std": s}} for k, s in SPREAD.items()},
        )
    )
    sample = np.array(result.flights[0]["covariance_nmi2"])
    case = ONE_SETTING["case"]
    e = case["entry"]

    def landing(**entry):
        fly_case = copy.deepcopy(case) | {"bank": {"law": "single_parameter", "bank_gain": 60 / 90}}
        fly_case["entry"] |= entry
        s = parallel.run("case", fly_case).summary
        return np.array(
            downrange_crossrange_nmi(
                s["final_latitude_deg"],
                s["final_longitude_deg"],
                e["latitude_deg"],
                e["longitude_deg"],
                e["heading_deg"],
            )
        )

    jacobian = np.stack(
        [(landing(**{k: e[k] + s}) - landing(**{k: e[k] - s})) / (2 * s) for k, s in SPREAD.items()], axis=1
    )
    linear = jacobian @ np.diag([s * s for s in SPREAD.values()]) @ jacobian.T
    # each entry within 4 of its sampling standard errors, sqrt((S_ii S_jj + S_ij^2) / (n - 1)) for a normal cloud
    # (for a variance sqrt(2 / (n - 1)) = 3.2 % of it)
    for i in range(2):
        for j in range(2):
            error = math.sqrt((linear[i, i] * linear[j, j] + linear[i, j] ** 2) / (n - 1))
            assert abs(sample[i, j] - linear[i, j]) < 4 * error, (i, j, sample, linear)
    assert linear[0, 0] > 1_000.0 and linear[1, 1] > 0.01  # nmi^2: a cloud (47 nmi along the track, 0.25 across)


def test_site_probabilities_inside_outside_and_on_the_nominal_boundary():
    spec = parse_request(study()).footprint.case.to_spec()
    e = spec.entry
    plan = Plan(parse_request(study()))
    nominal = plan.nominal()
    down, _ = mc.nominal_ranges(spec, nominal)
    front = down[0, 0]  # the zero-bank flight: the nominal footprint's farthest point, a vertex of its boundary
    sites = [
        ("deep inside", *latlon_from_ranges(0.6 * front, 0.0, e.latitude_deg, e.longitude_deg, e.heading_deg)),
        ("far outside", 45.0, -100.0),
        ("on the boundary", nominal.values[0, 0, mc.LAT], nominal.values[0, 0, mc.LON]),
    ]
    result, _ = run(
        study(
            samples=256,
            seed=5,
            entry={"gamma_deg": {"normal": {"std": 0.02}}},
            sites=[{"name": n, "latitude_deg": float(a), "longitude_deg": float(o)} for n, a, o in sites],
        )
    )
    by_name = {s["name"]: s for s in result.sites}
    assert by_name["deep inside"]["probability"] == 1.0 and by_name["deep inside"]["inside_nominal"]
    assert by_name["far outside"]["probability"] == 0.0 and not by_name["far outside"]["inside_nominal"]
    edge = by_name["on the boundary"]
    assert 0.4 < edge["probability"] < 0.6, edge  # symmetric in gamma, linear: half the samples reach farther
    assert edge["interval"][0] < 0.5 < edge["interval"][1]
    assert by_name["deep inside"]["interval"] == [pytest.approx(0.025 ** (1 / 256)), 1.0]  # Clopper-Pearson, n of n


def test_the_confidence_footprint_lies_inside_the_nominal_one_and_grows_as_the_level_falls():
    result, _ = run(study(samples=128, seed=2, entry={"gamma_deg": {"normal": {"std": 0.05}}}, confidence=[0.5, 0.99]))
    half, most = (max(c["rings"], key=lambda r: r["area_nmi2"]) for c in result.confidence)
    assert most["area_nmi2"] < half["area_nmi2"]
    front = result.nominal[0]["downrange_nmi"]
    assert max(most["downrange_nmi"]) < front < max(half["downrange_nmi"]) + 100.0  # nmi: a grid cell or two
    assert most["latitude_deg"][0] == most["latitude_deg"][-1]  # a closed ring


def test_the_one_and_three_sigma_ellipses_hold_their_share_of_a_normal_cloud():
    rng = np.random.default_rng(0)
    cov = np.array([[400.0, 150.0], [150.0, 100.0]])
    pts = rng.multivariate_normal([1000.0, 50.0], cov, size=20_000)
    for sigmas, share in ((1.0, 1 - math.exp(-0.5)), (3.0, 1 - math.exp(-4.5))):  # chi-square, 2 degrees of freedom
        x, y = mc.ellipse(np.array([1000.0, 50.0]), cov, sigmas, points=721)
        inside = np.mean([inside_polygon(x[:-1], y[:-1], 720, px, py) for px, py in pts])
        assert inside == pytest.approx(share, abs=4 * math.sqrt(share * (1 - share) / len(pts)))


def test_the_clopper_pearson_interval_is_the_beta_quantiles():
    assert mc.clopper_pearson(0, 10) == (0.0, pytest.approx(1 - 0.025 ** (1 / 10)))
    low, high = mc.clopper_pearson(3, 10)
    assert stats.binom.sf(2, 10, low) == pytest.approx(0.025) and stats.binom.cdf(3, 10, high) == pytest.approx(0.025)


def test_a_chunked_run_is_the_same_whatever_the_chunks():
    s = study(
        samples=20,
        seed=9,
        entry={"velocity_fps": {"uniform": {"half_width": 30}}},
        vehicle={"cd_multiplier": {"truncated_normal": {"std": 0.02}}},
        density={"std": 0.03},
    )
    whole, _ = run(s | {"chunk_samples": 20})
    cut, info = run(s | {"chunk_samples": 3})
    assert info["tasks"] == 7
    for key in whole.clouds:
        np.testing.assert_array_equal(whole.clouds[key], cut.clouds[key])


def test_flights_that_end_otherwise_are_counted_not_dropped():
    """A stop by time just past the nominal zero-bank flight's: the faster samples' longest flights run out of time
    before the stop altitude; each is counted with its reason, beside the landed ones."""
    nominal = Plan(parse_request(study())).nominal()
    timed = copy.deepcopy(SMALL)
    timed["case"]["stop"] = {"altitude_ft": 50_000, "time_s": float(nominal.values[0, 0, mc.TIME]) + 1.0}
    result, _ = run(study(timed, samples=32, seed=1, entry={"velocity_fps": {"normal": {"std": 30}}}))
    front = result.flights[0]
    assert front["side"] == "axis" and 0 < front["outcomes"]["ran out of time"] < 32, front
    assert front["landed"] + front["outcomes"]["ran out of time"] == 32
    assert result.outcomes["flights"] == 32 * 6 == result.outcomes["landed"] + result.outcomes["ran out of time"]
    assert all(f["landed"] + sum(f["outcomes"].values()) == 32 for f in result.flights)


@pytest.mark.parametrize(
    "fields, field, words",
    [
        ({"entry": {"altitude_ft": {"normal": {"std": -100}}}}, "entry.altitude_ft.normal.std", "must be > 0"),
        ({"entry": {"altitude_ft": {"gamma": {"k": 2}}}}, "entry.altitude_ft.gamma", "not permitted"),
        ({"entry": {"altitude_ft": {}}}, "entry.altitude_ft", "exactly one of"),
        ({"vehicle": {"lift": {"normal": {"std": 0.1}}}}, "vehicle.lift", "not permitted"),
        ({"samples": 2_000_000}, "samples", "1000000"),
        ({"footprint": FOOTPRINT, "samples": 1_000_000}, "samples", "22000000 trajectories"),
        ({"density": {"std": 0.5}}, "density.std", "0 to 0.2"),
        (
            {
                "footprint": {
                    "case": FOOTPRINT["case"],
                    "method": "two_parameter",
                    "bank_gain": [0.5],
                    "sigma_f_deg": [0],
                }
            },
            "footprint.method",
            "fixed control laws",
        ),
        (
            {"footprint": FOOTPRINT | {"case": FOOTPRINT["case"] | {"stop": {"altitude_ft": -5}}}},
            "footprint.case.stop.altitude_ft",
            "outside the allowed range",
        ),  # not footprint.single_parameter.case...
    ],
)
def test_bad_dispersions_get_one_line_naming_the_field(fields, field, words):
    with pytest.raises(ValidationError) as info:
        parse_request(study(**fields))
    line = error_line(info.value)
    assert line.startswith(field) and words.replace(",", "") in line.replace(",", ""), line
    assert "\n" not in line


def test_a_dispersion_that_draws_an_impossible_value_names_its_field():
    with pytest.raises(InputError, match=r"^entry\.altitude_ft: .* must be > 0"):
        run(study(samples=16, entry={"altitude_ft": {"uniform": {"half_width": 1_000_000}}}))


def test_a_footprint_round_a_pole_is_outlined_closed_along_it():
    """The map fills a ring from its outline (core.outline), whose area takes in the pole of a ring that holds one: an
    entry at 60 N heading north reaches 14,000 nmi, round the north pole and back; the Table 2 footprint about the
    equator holds no pole."""
    polar = copy.deepcopy(SMALL)
    polar["case"]["entry"] |= {"latitude_deg": 60.0, "heading_deg": 0.0}
    result = run(study(polar, samples=8, seed=2, entry={"gamma_deg": {"normal": {"std": 0.02}}}, confidence=[0.5]))[
        0
    ].to_dict()
    ring = max(result["confidence"][0]["rings"], key=lambda r: r["area_nmi2"])
    for shape in (result["nominal_boundary"], ring):
        o = shape["outline"]
        top = max(y for polygon in o["area"] for ring in polygon for _, y in ring)
        assert o["pole"] == "north" and top == 90.0, o["pole"]  # the area runs along the map's top edge
        assert max(o["longitude_deg"]) - min(o["longitude_deg"]) > 340.0  # the line goes once round
    equatorial = run(study(samples=4, seed=2, confidence=[0.5]))[0].to_dict()
    assert equatorial["nominal_boundary"]["outline"]["pole"] is None
    assert all(r["outline"]["pole"] is None for r in equatorial["confidence"][0]["rings"])


def test_a_study_that_ends_by_velocity_or_altitude_lands_every_flight_that_ends_either_way():
    """Stopped at 3,500 ft/s or 100,000 ft, whichever comes first: the undispersed zero-bank flights end by velocity
    and the banked ones by altitude, so both are the study's own endings (every flight of an undispersed run
    landed); with only a velocity stop above the default 50,000 ft floor, a flight reaching the floor first did not."""
    either = copy.deepcopy(SMALL)
    either["case"]["stop"] = {"altitude_ft": 100_000, "velocity_fps": 3_500}
    result, _ = run(study(either, samples=4, seed=1))
    assert {n["stop_reason"] for n in result.nominal} == {"velocity", "altitude"}
    assert result.outcomes == {"flights": 24, "landed": 24}
    assert all(f["landed"] == 4 for f in result.flights)
    fast = ONE_SETTING | {"case": FOOTPRINT["case"] | {"stop": {"altitude_ft": 120_000, "velocity_fps": 8_000}}}
    s = study(
        fast,
        samples=64,
        seed=1,
        entry={"gamma_deg": {"normal": {"std": 0.5}}},
        vehicle={"cl_multiplier": {"normal": {"std": 0.1}}},
    )
    result, _ = run(copy.deepcopy(s))
    assert result.nominal[0]["stop_reason"] == "velocity"
    early = result.flights[0]["outcome_samples"]["hit the stop altitude early"]
    assert early and result.outcomes["landed"] == 64 - len(early)
    plan = Plan(parse_request(s))
    for i in early:  # flown again with histories: at 120,000 ft still faster than 8,000 ft/s
        (traj,) = mc.sample_trajectories(plan.spec, plan.flights, plan.samples, i)
        assert traj.summary["final_altitude_ft"] == pytest.approx(120_000, abs=1.0)
        assert traj.summary["final_velocity_fps"] > 8_000


def test_a_sample_asked_for_is_flown_again_with_histories_that_end_where_its_summary_landed():
    """Two routes to a sample's flights: the summary path of the run (no histories) and trajectory.simulate with
    histories (contracts.dispersion's `histories`); the same landing to the bit. A flight that ran out of time names
    its samples, and its history ends at the study's time limit above the stop altitude."""
    nominal = Plan(parse_request(study())).nominal()
    timed = copy.deepcopy(SMALL)
    limit_s = float(nominal.values[0, 0, mc.TIME]) + 1.0
    timed["case"]["stop"] = {"altitude_ft": 50_000, "time_s": limit_s}
    s = study(timed, samples=32, seed=1, entry={"velocity_fps": {"normal": {"std": 30}}})
    first, _ = run(copy.deepcopy(s))
    late = first.flights[0]["outcome_samples"]["ran out of time"]
    assert len(late) == first.flights[0]["outcomes"]["ran out of time"]
    assert np.isnan(first.clouds["latitude_deg"][late, 0]).all()  # not landed: no point in the cloud
    asked = [late[0], next(i for i in range(32) if i not in late)]
    stats, info = run(s | {"histories": asked})
    kept = contracts.module("dispersion").to_dict(parse_request(s | {"histories": asked}), stats, None, info)
    histories = kept["histories"]
    assert [(h["sample"], h["side"]) for h in histories] == [(i, f["side"]) for i in asked for f in stats.flights]
    for h in histories:
        j = next(j for j, f in enumerate(stats.flights) if (f["side"], f["parameter"]) == (h["side"], h["parameter"]))
        summary = h["summary"]
        if h["sample"] == asked[0] and j == 0:
            assert summary["stop_reason"] == "time" and h["time_s"][-1] == pytest.approx(limit_s)
            assert h["altitude_ft"][-1] > 50_000
            continue
        assert summary["final_latitude_deg"] == stats.clouds["latitude_deg"][h["sample"], j]  # to the bit
        assert summary["final_longitude_deg"] == stats.clouds["longitude_deg"][h["sample"], j]
        assert h["latitude_deg"][-1] == summary["final_latitude_deg"] and len(h["time_s"]) <= 200
        assert h["altitude_ft"][-1] == pytest.approx(50_000, abs=1.0)


def test_histories_of_a_sample_that_is_not_there_are_refused():
    with pytest.raises(ValidationError) as info:
        parse_request(study(samples=10, histories=[3, 10]))
    assert error_line(info.value).startswith("histories.1: sample 10 is outside the allowed range 0 to 9")


def test_a_half_footprints_nominal_boundary_is_the_footprint_methods_own():
    """One boundary rule (core.footprints.boundary_order): a dispersed half footprint's nominal ring put the zero-lift
    point on its boundary although the footprint method, which closes a half footprint along the axis before it asks,
    keeps it inside (1,462 nmi against the 1,421 nmi of the 150-degree point, here)."""
    half = FOOTPRINT | {"bank0_deg": [0, 30, 60, 90, 120, 150], "mirror": False, "min_range": "zero_lift"}
    result, _ = run(study(half, samples=2, seed=1))
    fp = footprint(
        parse_request(study(half)).footprint.case.to_spec(), parse_request(study(half)).footprint.to_settings()
    )
    assert [p.parameter.min_range for p in fp.interior] == ["zero_lift"]
    ring = [p.downrange_nmi for p in fp.points]
    assert result.nominal_boundary["downrange_nmi"] == pytest.approx([ring[0], *ring, ring[-1]], abs=1e-9)  # + axis
