"""The guided footprint (core/guided_footprint.py, contracts/guided_footprint.py): with no dispersion it is the
undispersed guided one to the bisection's resolution; each traced boundary point is, flown again sample by sample
and measured by haversine, reached within R in at least p of the samples; it lies inside the report's footprint of
the same vehicle at every ray, whose boundary the guided vehicle does not reach; a ray meets a circle where the closed
form says."""

import copy
import math

import numpy as np
import pytest

from footprint import parallel
from footprint.contracts import parse
from footprint.core import dispersion as disp
from footprint.core import guided_footprint as gfp
from footprint.core.sphere import latlon_from_ranges
from footprint.core.trajectory import simulate_summary
from tests.core.test_guidance import INTERFACE_NMI, distance_nmi, guided
from tests.core.test_guided_dispersion import SPREADS

RADIUS_NMI = 5.0
STUDY = {
    "case": guided(5000.0, 600.0),
    "rays": 4,
    "samples": 8,
    # two misses of eight allowed: the one-sided 95 % Clopper-Pearson bound of 6 of 8 is 0.39, of 5 of 8 0.27
    "probability": 0.35,
    "radius_nmi": RADIUS_NMI,
    "optimal": False,  # the collocation footprint: the slow test below
    "seed": 5,
    **SPREADS,
}


@pytest.fixture(scope="module")
def spec():
    return parse("case", guided(5000.0, 600.0)).to_spec()


@pytest.fixture(scope="module")
def frame(spec):
    return gfp.frame(spec, RADIUS_NMI)


@pytest.fixture(scope="module")
def study():
    s = parse("guided_footprint", copy.deepcopy(STUDY))
    return s, parallel.run("guided_footprint", s)


def binomial_lower_bound(reached, samples, alpha=0.05):
    """The one-sided Clopper-Pearson lower bound by its definition, not scipy's beta: the P at which reaching
    `reached` or more of `samples` has probability alpha, P(X >= k) = sum C(n, j) P^j (1 - P)^(n - j), by bisection."""

    def tail(p):
        return sum(math.comb(samples, j) * p**j * (1 - p) ** (samples - j) for j in range(reached, samples + 1))

    lo, hi = 0.0, 1.0
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if tail(mid) < alpha else (lo, mid)
    return lo


def allowed_misses(samples, probability):
    """The most misses whose bound (binomial_lower_bound) is still >= probability (it falls with each miss)."""
    misses = 0
    while misses <= samples and binomial_lower_bound(samples - misses, samples) >= probability:
        misses += 1
    return misses - 1


def test_reachable_with_p_means_the_clopper_pearson_lower_bound_is_at_least_p():
    """Issue 50 item 6: 198 of 200 is a point estimate of 0.99, not P >= 0.99 with 95 % confidence. The one-sided
    95 % bound is 0.9689 (the issue's 0.964 is the two-sided 95 % interval's lower end, alpha 0.025)."""
    assert gfp.lower_bound(198, 200) == pytest.approx(binomial_lower_bound(198, 200), abs=1e-9)
    assert binomial_lower_bound(198, 200) == pytest.approx(0.96886, abs=1e-5)
    assert binomial_lower_bound(198, 200, alpha=0.025) == pytest.approx(0.96435, abs=1e-5)
    assert gfp.allowed_misses(200, 0.99) == allowed_misses(200, 0.99) == -1  # even 200 of 200 cannot show it
    assert gfp.fewest_samples(0.99) == 299 and allowed_misses(299, 0.99) == 0 and allowed_misses(298, 0.99) == -1
    for n, p in ((8, 0.35), (50, 0.9), (300, 0.95), (1000, 0.99)):
        assert gfp.allowed_misses(n, p) == allowed_misses(n, p), (n, p)


def test_a_study_whose_samples_cannot_show_p_is_refused_in_one_line():
    from pydantic import ValidationError

    from footprint.contracts.messages import error_line

    for change, words in (
        ({"samples": 200, "probability": 0.99}, "samples: 200 cannot show P >= 0.99 with 95 % confidence; give 299"),
        ({"samples": 8, "probability": 1.0}, "probability: 1 cannot be shown with 95 % confidence"),
    ):
        with pytest.raises(ValidationError) as info:
            parse("guided_footprint", {**copy.deepcopy(STUDY), **change})
        assert error_line(info.value).startswith(words), error_line(info.value)
    ok = parse("guided_footprint", {**copy.deepcopy(STUDY), "samples": 300, "probability": 0.99})
    assert ok.criterion().startswith("reached within 5 nmi: P >= 0.99 with 95 % confidence")
    assert ok.criterion().endswith("at most 0 of 300 samples missing")


def lands_within(spec, down_nmi, cross_nmi, radius_nmi):
    """Whether the flight aimed at (down, cross) ends within R of its interface circle about that point, by haversine
    on the sphere of R'."""
    s = simulate_summary(gfp.targeted(spec, down_nmi, cross_nmi))
    lat, lon = latlon_from_ranges(down_nmi, cross_nmi, 0.0, 0.0, 90.0)
    miss = abs(distance_nmi(s["final_latitude_deg"], s["final_longitude_deg"], float(lat), float(lon)) - INTERFACE_NMI)
    return s["stop_reason"] == "energy" and miss <= radius_nmi


def test_the_frame_is_the_undispersed_reach_on_the_axis(spec, frame):
    near = frame.center_nmi - frame.half_length_nmi
    far = frame.center_nmi + frame.half_length_nmi
    step = 0.01 * frame.half_length_nmi  # well over the bisection's resolution
    assert lands_within(spec, near + step, 0.0, RADIUS_NMI) and not lands_within(spec, near - step, 0.0, RADIUS_NMI)
    assert lands_within(spec, far - step, 0.0, RADIUS_NMI) and not lands_within(spec, far + step, 0.0, RADIUS_NMI)


def test_with_no_dispersion_the_guided_boundary_is_the_undispersed_one(spec, frame):
    # no miss allowed: the bound of 3 of 3 is 0.37, of 2 of 3 0.14
    settings = gfp.GuidedFootprintSettings(rays=4, samples=3, radius_nmi=RADIUS_NMI, probability=0.3)
    for angle_deg in (0.0, 90.0):
        ray = gfp.trace_ray(spec, frame, math.radians(angle_deg), disp.draw({}, 3, 0), settings)
        resolution = (1.0 - gfp.LOWER_FRACTION) * ray["s_nominal"] / 2**gfp.GUIDED_BISECTIONS
        assert ray["s_nominal"] - resolution <= ray["s_guided"] <= ray["s_nominal"]


def test_each_boundary_point_is_reached_in_p_of_the_samples_flown_again(study):
    s, answer = study
    spec = s.case.to_spec()
    samples = s.draw(spec)
    allowed = allowed_misses(s.samples, s.probability)
    assert allowed == 2
    for r in answer["rays"]:
        point = gfp.targeted(spec, r["guided"]["downrange_nmi"], r["guided"]["crossrange_nmi"])
        t = point.guidance
        reached = 0
        for i in range(s.samples):
            f = simulate_summary(disp.sample_spec(point, samples, i))
            to_site = distance_nmi(f["final_latitude_deg"], f["final_longitude_deg"], t.target_latitude_deg,
                                   t.target_longitude_deg)  # fmt: skip
            miss = abs(to_site - INTERFACE_NMI)
            reached += f["stop_reason"] == "energy" and miss <= RADIUS_NMI
        assert reached >= s.samples - allowed, r


def test_the_guided_footprint_lies_inside_the_nominal_and_the_reports(study):
    _, answer = study
    f = answer["frame"]
    for r in answer["rays"]:
        # nmi along the ray per unit s; the guided rings are of targets, whose interface (where the flight ends) lies
        # 50 nmi before them, the report's of ends: the ends' reach, the targets' less the interface range, is inside
        a = math.radians(r["angle_deg"])
        per_s = math.hypot(f["half_length_nmi"] * math.cos(a), f["half_width_nmi"] * math.sin(a))
        assert 0.0 < r["s_guided"] <= r["s_nominal"], r
        assert r["s_nominal"] * per_s - INTERFACE_NMI < r["s_report"] * per_s, r
    assert answer["margin_to_report"]["inside_at_every_ray"]
    assert answer["guided"]["area_nmi2"] < answer["nominal_guided"]["area_nmi2"] < answer["report"]["area_nmi2"]
    m = answer["margin_to_report"]
    assert m["area_nmi2"] == pytest.approx(answer["report"]["area_nmi2"] - answer["guided"]["area_nmi2"])
    assert m["percent"] == pytest.approx(100 * m["area_nmi2"] / answer["report"]["area_nmi2"])
    assert answer["optimal"] is None and "margin_to_optimal" not in answer


def test_the_reports_boundary_is_not_reached_under_dispersion_a_point_well_inside_is(study, spec, frame):
    s, answer = study
    samples = s.draw(spec)
    settings = s.settings()
    for r in answer["rays"]:
        on_edge = gfp.ray_point(frame, math.radians(r["angle_deg"]), r["s_report"])
        inside = gfp.ray_point(frame, math.radians(r["angle_deg"]), 0.5 * r["s_guided"])
        assert not gfp.dispersed_ok(gfp.targeted(spec, *on_edge), samples, settings, [0]), (r, on_edge)
        assert gfp.dispersed_ok(gfp.targeted(spec, *inside), samples, settings, [0]), (r, inside)
    # the verdict does not depend on which samples fly first; a failure found first among the hard ones is cheap
    r = answer["rays"][0]
    beyond = gfp.targeted(spec, *gfp.ray_point(frame, 0.0, 0.5 * (r["s_guided"] + r["s_nominal"])))
    in_order, hard = [0], []
    verdict = gfp.dispersed_ok(beyond, samples, settings, in_order, hard)
    again = [0]
    assert gfp.dispersed_ok(beyond, samples, settings, again, list(hard)) == verdict
    assert again[0] <= in_order[0]


def test_a_ray_meets_a_circle_where_the_closed_form_says():
    f = gfp.Frame(center_nmi=5000.0, half_length_nmi=2000.0, half_width_nmi=1000.0)
    radius = 1500.0
    a = np.linspace(0.0, 2.0 * np.pi, 721)[:-1]
    ring = [(f.center_nmi + radius * math.cos(t), radius * math.sin(t)) for t in a]
    for angle in np.radians([0.0, 30.0, 90.0, 200.0, 300.0]):
        # |s (a cos, b sin)| = radius on the circle about the centre
        s = radius / math.hypot(f.half_length_nmi * math.cos(angle), f.half_width_nmi * math.sin(angle))
        assert gfp.reach_on_ray(ring, f, angle) == pytest.approx(s, rel=1e-4)


@pytest.mark.parametrize(
    ("change", "field"),
    [
        ({"case": {**guided(5000.0, 600.0), "bank": {"law": "zero"}}}, "case.bank.law"),
        ({"rays": 2}, "rays"),
        ({"probability": 1.5}, "probability"),
        ({"radius_nmi": 0}, "radius_nmi"),
    ],
)
def test_a_bad_guided_footprint_study_names_its_field(change, field):
    from pydantic import ValidationError

    from footprint.contracts.messages import error_line

    with pytest.raises(ValidationError) as info:
        parse("guided_footprint", {**copy.deepcopy(STUDY), **change})
    assert error_line(info.value).startswith(field), error_line(info.value)


@pytest.mark.slow
def test_the_guided_footprint_lies_inside_the_true_optimal_one_at_every_ray():
    s = parse("guided_footprint", {**copy.deepcopy(STUDY), "rays": 8, "optimal": True})
    answer = parallel.run("guided_footprint", s)
    f = answer["frame"]
    for r in answer["rays"]:  # the targets' reach less the interface range against the optimal ends' (above)
        a = math.radians(r["angle_deg"])
        per_s = math.hypot(f["half_length_nmi"] * math.cos(a), f["half_width_nmi"] * math.sin(a))
        assert r["s_guided"] <= r["s_nominal"] and r["s_nominal"] * per_s - INTERFACE_NMI < r["s_optimal"] * per_s, r
    assert answer["margin_to_optimal"]["inside_at_every_ray"]
    assert answer["optimal"]["area_nmi2"] > answer["report"]["area_nmi2"] > answer["guided"]["area_nmi2"]


@pytest.mark.parametrize("threshold", [1.0, 0.95, 0.81, 0.79, 0.5, 0.2])
def test_the_guided_bisection_finds_a_threshold_to_its_resolution(threshold):
    """Against a predicate with a known edge (s <= threshold), the search returns a point that passed, below the edge
    by less than its bracket's resolution, whichever bracket the edge falls in."""
    asked = []

    def ok(s):
        asked.append(s)
        return s <= threshold

    s = gfp._bisect_guided(ok, 1.0)
    bracket = next(b for b in (gfp.LOWER_FRACTION**k for k in range(1, 20)) if b <= threshold)  # the edge's floor
    resolution = (bracket / gfp.LOWER_FRACTION - bracket) / 2**gfp.GUIDED_BISECTIONS
    assert s in asked and s <= threshold and threshold - s <= resolution + 1e-12, (s, threshold)
