"""A guided dispersion from an executed deorbit burn (issue 52 item 5): the nominal flight enters where the planned
burn's coast reaches the interface (checked against the independent route: sgp4's state, the coast in WGS-72 written
apart), every sample where its executed burn's does; the guidance absorbs the burn's errors that the open loop
carries to the ground."""

import copy
import json
import math
from datetime import UTC, datetime

import numpy as np
import pytest
from pydantic import ValidationError

from footprint import parallel
from footprint.contracts import module, parse
from footprint.contracts.messages import error_line
from footprint.core.sphere import MEAN_RADIUS_NMI
from tests.core.orbit_routes import WGS72, independent_entry, sgp4_teme_km
from tests.core.test_guidance import distance_nmi

EXAMPLE = json.loads(open("examples/opportunities_iss_20_sites.json").read())
BURN_UTC = datetime(2008, 9, 21, 0, 0, 0, tzinfo=UTC)
DELTA_V_FPS = 400.0
DOWNRANGE_NMI = 6_000.0  # within the vehicle's limits (its 375 psf: shorter targets are not reachable)
BURN = {"tle": EXAMPLE["tle"], "burn_utc": "2008-09-21T00:00:00Z", "delta_v_fps": DELTA_V_FPS}


def _ahead(lat_deg, lon_deg, heading_deg, range_nmi):
    """The point range_nmi along the great circle from a place and heading (the spherical direct problem)."""
    p, lam, az, d = map(math.radians, (lat_deg, lon_deg, heading_deg, math.degrees(range_nmi / MEAN_RADIUS_NMI)))
    p2 = math.asin(math.sin(p) * math.cos(d) + math.cos(p) * math.sin(d) * math.cos(az))
    lam2 = lam + math.atan2(math.sin(az) * math.sin(d) * math.cos(p), math.cos(d) - math.sin(p) * math.sin(p2))
    return math.degrees(p2), (math.degrees(lam2) + 180.0) % 360.0 - 180.0


def _study(samples=24, **change):
    case = copy.deepcopy(EXAMPLE["footprint"]["case"])
    planned = parse("guided_dispersion", {"case": case | {"bank": _bank(0.0, 0.0)}, "samples": 1, "burn": BURN})
    e = module("guided_dispersion").Plan(planned).spec.entry  # where the planned burn enters: the target ahead of it
    target = _ahead(e.latitude_deg, e.longitude_deg, e.heading_deg, DOWNRANGE_NMI)
    errors = {"delta_v_fps": 2.0, "pitch_deg": 1.0, "yaw_deg": 1.0, "time_s": 1.0}
    study = {"case": case | {"bank": _bank(*target)}, "samples": samples, "seed": 5, "radius_nmi": [5.0, 50.0],
             "burn": BURN | {"errors": errors}}  # fmt: skip
    return study | change


def _bank(lat, lon):
    return {"law": "guided", "target": {"latitude_deg": lat, "longitude_deg": lon}}


@pytest.fixture(scope="module")
def run():
    study = parse("guided_dispersion", _study())
    stats, info = parallel.run("guided_dispersion", study)
    return module("guided_dispersion").to_dict(study, stats, None, info), study


def test_the_nominal_enters_where_the_planned_burn_does(run):
    answer, _ = run
    r, v = sgp4_teme_km(EXAMPLE["tle"].splitlines()[1:], BURN_UTC)
    _, lat, lon = independent_entry(r, v, DELTA_V_FPS, WGS72, BURN_UTC)
    assert distance_nmi(lat, lon, answer["entry"]["latitude_deg"], answer["entry"]["longitude_deg"]) < 0.005


def test_the_executed_burns_spread_the_entries_and_the_guidance_absorbs_them(run):
    answer, study = run
    samples = module("guided_dispersion").Plan(study).samples
    entry_lon, gamma = samples.values["longitude_deg"], samples.values["gamma_deg"]
    assert np.std(entry_lon) > 0.01 and np.std(gamma) > 0.005  # the burn's errors reach the interface
    guided, open_loop = answer["guided"], answer["open_loop"]
    assert guided["miss_nmi"]["max"] < 50.0 < open_loop["miss_nmi"]["max"]
    within = guided["within"][1]
    assert within["radius_nmi"] == 50.0 and within["interval"][0] <= within["probability"] <= within["interval"][1]


@pytest.mark.parametrize(
    "change, field",
    [
        ({"entry": {"gamma_deg": {"normal": {"std": 0.05}}}}, "entry"),
        ({"burn": BURN | {"errors": {"pitch_deg": -1.0}}}, "burn.errors.pitch_deg"),
        ({"burn": {k: v for k, v in BURN.items() if k != "tle"}}, "burn"),
        ({"burn": BURN | {"burn_utc": "2009-09-21T00:00:00Z"}}, "burn.burn_utc"),
        ({"burn": BURN | {"tle": "ISS\n1 25544U\n2 25544"}}, "burn.tle"),
    ],
)
def test_a_bad_burn_names_its_field(change, field):
    with pytest.raises(ValidationError) as exc:
        parse("guided_dispersion", _study(**change))
    assert error_line(exc.value).startswith(field), error_line(exc.value)
