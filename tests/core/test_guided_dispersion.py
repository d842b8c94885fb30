"""Guided dispersions (core/guided_dispersion.py): with no dispersion every sample is the guided nominal to the bit;
the statistics are what an independent count of the landings gives (haversine misses of the interface circle, the
exact binomial interval from scipy's binomtest); guidance closes the loop that the same samples flown open loop leave
wide open."""

import copy
import math
from dataclasses import replace

import numpy as np
import pytest
from scipy.stats import binomtest

from footprint import parallel
from footprint.contracts import module, parse
from footprint.core import dispersion as disp
from footprint.core import guided_dispersion as gdisp
from footprint.core.controls import replace_bank_table
from tests.authorities.report import guided_spreads
from tests.core.test_guidance import INTERFACE_NMI, distance_nmi, guided

SPREADS = guided_spreads()  # the example dispersions
STUDY = {"case": guided(5000.0, 600.0), "samples": 24, "seed": 3, "radius_nmi": [0.3, 1.0, 5.0], **SPREADS}


@pytest.fixture(scope="module")
def run():
    study = parse("guided_dispersion", copy.deepcopy(STUDY))
    stats, info = parallel.run("guided_dispersion", study)
    return module("guided_dispersion").to_dict(study, stats, None, info)


def test_with_no_dispersion_every_sample_is_the_guided_nominal_to_the_bit():
    spec = parse("case", guided(5000.0, 600.0)).to_spec()
    nominal = gdisp.nominal_flight(spec).summary
    landings = gdisp.fly_samples(spec, None, disp.draw({}, 3, 0))
    lat, lon = landings.values[:, 0, gdisp.LAT], landings.values[:, 0, gdisp.LON]
    assert np.all(lat == nominal["final_latitude_deg"]) and np.all(lon == nominal["final_longitude_deg"])


def test_the_statistics_are_an_independent_count_of_the_landings(run):
    t, n = run["target"], run["samples"]
    for mode in ("guided", "open_loop"):
        cloud = run["clouds"][mode]
        miss = np.array(
            [
                abs(distance_nmi(a, b, t["latitude_deg"], t["longitude_deg"]) - INTERFACE_NMI)
                if a is not None
                else math.inf
                for a, b in zip(cloud["latitude_deg"], cloud["longitude_deg"])
            ]
        )
        assert run[mode]["miss_nmi"]["cep"] == pytest.approx(np.median(miss[np.isfinite(miss)]), abs=1e-6)
        for w in run[mode]["within"]:
            k = int(np.sum(miss <= w["radius_nmi"]))
            assert w["samples_within"] == k and w["probability"] == k / n
            ci = binomtest(k, n).proportion_ci(confidence_level=w["level"], method="exact")
            assert w["interval"] == pytest.approx([ci.low, ci.high], abs=1e-9)


def test_guidance_closes_the_loop_the_open_loop_leaves_open(run):
    """The example dispersions move the open-loop landing by hundreds of miles; the guided vehicle lands within
    5 nmi every time, and 99 % within 5 nmi is inside its 95 % interval."""
    g, o = run["guided"], run["open_loop"]
    assert g["landed"] == run["samples"] and g["miss_nmi"]["max"] < 5.0
    assert g["within"][2]["interval"][1] >= 0.99
    assert o["miss_nmi"]["cep"] > 50.0 and o["within"][2]["probability"] < 0.2
    assert g["spreads"]["max_load_factor"]["max"] > 1.0 and g["final"]["final_energy_ft"]["std"] < 1.0


def _landings_miss_nmi(spec, samples, target):
    v = gdisp.fly_samples(spec, None, samples).values[:, 0]
    return np.array([distance_nmi(a, b, *target) for a, b in zip(v[:, gdisp.LAT], v[:, gdisp.LON])])


def test_the_open_loop_flies_the_nominal_bank_against_energy_not_time():
    """Issue 50 item 5: in a dispersed world time slides, so the nominal bank against time is the weakest baseline
    (the issue's re-flight on 300 samples: CEP 773 nmi against time, 293 against energy). The time table is built
    here from the nominal's bank nodes; on the same samples the module's open loop lands at most half as far, and
    undispersed it flies the guided landing again."""
    spec = parse("case", guided(5000.0, 600.0)).to_spec()
    nominal = gdisp.nominal_flight(spec)
    g, table = spec.guidance, nominal.bank_table
    by_time = replace(
        spec,
        guidance=None,
        ctrl=replace_bank_table(spec.ctrl, table["bank_deg"], table["time_s"], "time"),
        stop=replace(spec.stop, energy_ft=g.terminal_energy_ft),
    )
    by_energy = gdisp.open_loop(spec, nominal)
    samples = parse("guided_dispersion", copy.deepcopy(STUDY)).draw(spec)
    target = (g.target_latitude_deg, g.target_longitude_deg)
    cep = {
        name: np.median(_landings_miss_nmi(s, samples, target))
        for name, s in (("time", by_time), ("energy", by_energy))
    }
    assert cep["energy"] < 0.5 * cep["time"], cep
    landed = nominal.summary
    again = _landings_miss_nmi(
        by_energy, disp.draw({}, 1, 0), (landed["final_latitude_deg"], landed["final_longitude_deg"])
    )
    assert again[0] < 5.0


@pytest.mark.parametrize(
    "change, field",
    [
        ({"case": {**guided(5000.0, 600.0), "bank": {"law": "zero"}}}, "case.bank.law"),
        ({"radius_nmi": [0]}, "radius_nmi.0"),
        ({"samples": 0}, "samples"),
    ],
)
def test_a_bad_guided_study_names_its_field(change, field):
    from pydantic import ValidationError

    from footprint.contracts.messages import error_line

    with pytest.raises(ValidationError) as info:
        parse("guided_dispersion", STUDY | change)
    assert error_line(info.value).startswith(field)
