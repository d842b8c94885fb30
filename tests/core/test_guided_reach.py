"""The guided reach of landing sites (core/guided_reach.py, contracts/guided_reach.py): each site's count of landings
within R is an independent count (every sample flown again to the site, its miss of the interface circle by
haversine), its interval scipy's exact binomial one; with no dispersion a reachable site is reached by every sample
and an unreachable one by none."""

import copy

import pytest
from scipy.stats import binomtest

from footprint import parallel
from footprint.contracts import parse
from footprint.core import dispersion as disp
from footprint.core import guided_reach as greach
from footprint.core.trajectory import simulate_summary
from tests.authorities.report import guided_spreads
from tests.core.test_guidance import INTERFACE_NMI, distance_nmi, guided, target

RADIUS_NMI = 5.0
SITES = [
    {"name": "5,000 nmi down, 600 across", **target(5000.0, 600.0)},  # reached by the guided nominal
    {"name": "1,500 nmi down", **target(1500.0, 0.0)},  # short of the zero-lift range: not reachable
    {"name": "7,500 nmi down, 1,500 across", **target(7500.0, 1500.0)},  # near the guided footprint's edge
]
STUDY = {"case": guided(5000.0, 600.0), "sites": SITES, "samples": 6, "seed": 4, "radius_nmi": RADIUS_NMI,
         **guided_spreads()}  # fmt: skip


@pytest.fixture(scope="module")
def answer():
    return parallel.run("guided_reach", parse("guided_reach", copy.deepcopy(STUDY)))


def test_each_sites_count_is_an_independent_count_of_its_landings(answer):
    study = parse("guided_reach", copy.deepcopy(STUDY))
    spec = study.case.to_spec()
    samples = study.draw(spec)
    assert [s["name"] for s in answer["sites"]] == [s["name"] for s in SITES]
    for got, site in zip(answer["sites"], SITES):
        aimed = greach.aimed_at(spec, site["latitude_deg"], site["longitude_deg"])
        k = 0
        for i in range(study.samples):
            f = simulate_summary(disp.sample_spec(aimed, samples, i))
            to_site = distance_nmi(f["final_latitude_deg"], f["final_longitude_deg"], site["latitude_deg"],
                                   site["longitude_deg"])  # fmt: skip
            miss = abs(to_site - INTERFACE_NMI)  # the interface circle's miss
            k += f["stop_reason"] == "energy" and miss <= RADIUS_NMI
        assert got["samples_within"] == k and got["probability"] == k / study.samples
        ci = binomtest(k, study.samples).proportion_ci(confidence_level=0.95, method="exact")
        assert got["interval"] == pytest.approx([ci.low, ci.high], abs=1e-9)
    reached, short, _ = answer["sites"]
    assert reached["probability"] == 1.0 and reached["nominal_status"] == "reached"
    assert short["probability"] == 0.0 and short["nominal_status"] == "not reachable"


def test_with_no_dispersion_every_sample_is_the_nominal_verdict():
    spec = parse("case", guided(5000.0, 600.0)).to_spec()
    none = disp.draw({}, 3, 0)
    for site, expected in ((SITES[0], 1.0), (SITES[1], 0.0)):
        r = greach.site_reach(spec, site["name"], site["latitude_deg"], site["longitude_deg"], none, RADIUS_NMI)
        assert r["probability"] == expected and r["samples"] == 3
        assert (r["nominal_miss_nmi"] <= RADIUS_NMI) == (expected == 1.0)


@pytest.mark.parametrize(
    ("change", "field"),
    [
        ({"sites": []}, "sites"),
        ({"sites": [{"name": "x", "latitude_deg": 95, "longitude_deg": 0}]}, "sites.0.latitude_deg"),
        ({"case": {**guided(5000.0, 600.0), "bank": {"law": "zero"}}}, "case.bank.law"),
        ({"radius_nmi": 0}, "radius_nmi"),
    ],
)
def test_a_bad_guided_reach_names_its_field(change, field):
    from pydantic import ValidationError

    from footprint.contracts.messages import error_line

    with pytest.raises(ValidationError) as info:
        parse("guided_reach", {**copy.deepcopy(STUDY), **change})
    assert error_line(info.value).startswith(field), error_line(info.value)
