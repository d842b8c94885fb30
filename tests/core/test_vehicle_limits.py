"""Issue 50 item 2: the vehicle carries its limits and every flight's summary says whether they held. The issue's
4,300 nmi guided target dives to 4.73 g and 1,584 psf with nothing in the summary to say so; with a crewed glider's
limits (2.5 g, 375 psf) it must be flagged broken, its margins negative. The load factor is recomputed from the
flown history's columns, n = q sqrt(C_L^2 + C_D^2) / (W/S) with the report's W/S = 70 psf (Fig. 1a), not read from
the code's peak."""

import copy

import numpy as np
import pytest
from pydantic import ValidationError

from footprint.api import fly
from footprint.contracts.vehicle import VehicleCase
from footprint.core.limits import tally
from tests.authorities.report import example
from tests.core.test_guidance import guided

LOD189 = example("footprint_lod189")["case"]
WING_LOADING_PSF = 70.0  # AFWAL-TR-82-3036 Sec. II, Fig. 1a: the L/D 1.89 vehicle


def with_limits(case, limits):
    out = copy.deepcopy(case)
    out["vehicle"]["limits"] = limits
    return out


@pytest.fixture(scope="module")
def dive():
    """The issue's short target: 4,300 nmi down-range, no cross-range, the built-in vehicle's own limits."""
    return fly(guided(4300.0, 0.0))


def history_load_factor_g(traj):
    h = traj.history
    return float(np.max(h["dynamic_pressure_psf"] * np.hypot(h["cl"], h["cd"]))) / WING_LOADING_PSF


def test_a_flight_past_the_gliders_load_and_q_limits_is_flagged_broken(dive):
    s, n_flown = dive.summary, history_load_factor_g(dive)
    q_flown = float(np.max(dive.history["dynamic_pressure_psf"]))
    assert n_flown > 2.5 and q_flown > 375.0  # the dive the issue saw: past both
    assert s["load_factor_limit_g"] == 2.5 and s["dynamic_pressure_limit_psf"] == 375.0
    assert s["load_factor_margin_g"] == pytest.approx(2.5 - n_flown, rel=0.02, abs=0.02)
    assert s["dynamic_pressure_margin_psf"] == pytest.approx(375.0 - q_flown, rel=0.02)
    assert s["limits_held"] is False
    assert s["limits_broken"] == ["load_factor_g", "dynamic_pressure_psf"]
    # no heating model in the case: the heat rate and temperature limits are not evaluated, and say so
    assert s["limits_unchecked"] == ["heat_rate_btu_ft2_s", "temperature_R"]
    assert s["heat_rate_margin_btu_ft2_s"] is None


def test_a_case_changes_or_lifts_its_vehicles_limits(dive):
    n_flown = history_load_factor_g(dive)
    roomy = fly(with_limits(guided(4300.0, 0.0), {"load_factor_g": n_flown + 1.0, "dynamic_pressure_psf": None}))
    s = roomy.summary
    assert s["load_factor_margin_g"] == pytest.approx(1.0, rel=0.02)
    assert s["dynamic_pressure_limit_psf"] is None and s["dynamic_pressure_margin_psf"] is None
    assert s["limits_held"] is True and s["limits_broken"] == []
    lifted = fly(with_limits(LOD189, None)).summary
    assert lifted["limits_held"] is True and lifted["limits_unchecked"] == []
    assert all(lifted[k] is None for k in ("load_factor_limit_g", "temperature_limit_R"))


def test_a_limit_out_of_range_is_refused_naming_the_field_and_range():
    with pytest.raises(ValidationError) as err:
        VehicleCase.model_validate({"builtin": "lod-1.89", "limits": {"load_factor_g": 0.0}})
    text = str(err.value)
    assert "load_factor_g" in text and "0.1 to 100 g" in text


def test_the_tally_counts_the_flights_that_broke_a_limit():
    flights = [[], ["load_factor_g"], ["load_factor_g", "dynamic_pressure_psf"], []]
    assert tally(flights) == {
        "flights": 4,
        "broke_a_limit": 2,
        "by_limit": {"load_factor_g": 2, "dynamic_pressure_psf": 1},
    }


SMALL_STUDY = example("footprint_lod189") | {"bank0_deg": [0, 60]}  # 2 settings: axis, left and right, zero lift


def study_with(limits):
    return copy.deepcopy(SMALL_STUDY) | {"case": with_limits(SMALL_STUDY["case"], limits)}


def test_a_footprint_and_a_dispersion_count_the_flights_that_broke_a_limit():
    """Any gliding entry decelerates past 0.1 g: with that limit every flight breaks it; lifted, none does."""
    from footprint.api import disperse, footprint

    tight = {"load_factor_g": 0.1, "dynamic_pressure_psf": None, "heat_rate_btu_ft2_s": None, "temperature_R": None}
    free = None
    fp = footprint(study_with(tight))
    flown = [p for p in fp.points + fp.interior if not p.mirrored]
    assert fp.limits() == {
        "flights": len(flown),
        "broke_a_limit": len(flown),
        "by_limit": {"load_factor_g": len(flown)},
    }
    assert footprint(study_with(free)).to_dict()["limits"] == {
        "flights": len(flown),
        "broke_a_limit": 0,
        "by_limit": {},
    }
    result, _ = disperse({"footprint": study_with(tight), "samples": 3, "seed": 1})
    flights = 3 * len(result.flights)
    assert result.to_dict()["limits"] == {
        "flights": flights,
        "broke_a_limit": flights,
        "by_limit": {"load_factor_g": flights},
    }
    assert all(f["limits"]["broke_a_limit"] == 3 for f in result.flights)


def test_an_opportunitys_ring_keeps_each_vertexs_broken_limits_when_flown_again():
    from footprint.core.opportunities import Ring

    ring = Ring(np.zeros(3), np.zeros(3), np.zeros(3), limits_broken=((), ("load_factor_g",), ()))
    again = Ring(np.ones(1), np.ones(1), np.ones(1), limits_broken=(("dynamic_pressure_psf",),))
    moved = ring.replaced([1], [again])
    assert moved.limits_broken == ((), ("dynamic_pressure_psf",), ())
    assert tally(moved.limits_broken) == {"flights": 3, "broke_a_limit": 1, "by_limit": {"dynamic_pressure_psf": 1}}


def test_a_vehicles_definition_keeps_a_lifted_limit_lifted():
    """A stored vehicle or a sweep's case is the definition dumped and read again: a null dropped from it would come
    back as the default."""
    given = {"builtin": "lod-1.89", "limits": {"temperature_R": None, "load_factor_g": 3.0}}
    again = VehicleCase.model_validate(VehicleCase.model_validate(given).definition()).to_vehicle().limits
    assert (again.temperature_R, again.load_factor_g, again.dynamic_pressure_psf) == (None, 3.0, 375.0)
    lifted = VehicleCase.model_validate({"builtin": "lod-1.89", "limits": None}).definition()
    assert VehicleCase.model_validate(lifted).to_vehicle().limits.load_factor_g is None
