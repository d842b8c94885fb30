"""A footprint study reaches the core as its method's settings record (core.method_settings, issue 26): the
contract's defaults are the record's own, and every field the user gives arrives, None included."""

import pytest

from footprint import api
from footprint.contracts import parse
from footprint.core import method_settings as S

CASE = {
    "vehicle": {"builtin": "lod-1.89"},
    "entry": {"altitude_ft": 400_000, "velocity_fps": 22_000, "gamma_deg": -2, "heading_deg": 90},
    "stop": {"altitude_ft": 100_000},
    "heating": {"model": "reference"},
}
REQUIRED = {"temperature_limited": {"limit_R": 2_550.0}}
CORE = {
    "single_parameter": S.SingleParameter(),
    "constant_bank": S.ConstantBank(),
    "staged": S.Staged(),
    "two_parameter": S.TwoParameter(),
    "constant_altitude": S.ConstantAltitude(),
    "temperature_limited": S.TemperatureLimited(limit_R=2_550.0, mirror=True),  # a study mirrors unless told
    "collocation": S.Collocation(),
}


@pytest.mark.parametrize("method", CORE)
def test_a_study_with_nothing_but_its_method_gets_the_cores_defaults(method):
    study = parse("footprint", {"case": CASE, "method": method, **REQUIRED.get(method, {})})
    assert study.to_settings() == CORE[method]


def test_a_constant_bank_study_without_a_shortest_flight_flies_none():
    """It flew the zero-lift point all the same: its `min_range: null` was dropped on the way to the core, whose
    default then applied."""
    fp = api.footprint({"case": CASE, "method": "constant_bank", "bank_deg": [0, 45], "min_range": None})
    assert [p.parameter.min_range for p in fp.points + fp.interior] == [None] * len(fp.points + fp.interior)
    assert sorted({p.parameter.bank_deg for p in fp.points}) == [0.0, 45.0]
