"""Issue 24 item 8: the CLI's JSON is strict JSON (RFC 8259) everywhere. `footprint optimize --json` printed NaN in
the optimum's temperature_R history for examples/optimize_fly_there.json without its stop altitude (301 of them; the
service writes null), and a C_D of 1e308 was accepted and printed Infinity with a numpy overflow warning."""

import json
import math

import pytest

from footprint.contracts.records import strict_json
from tests.test_cli import ROOT, run


def _strict(text: str):
    def refuse(constant):
        raise ValueError(f"not JSON: {constant}")

    return json.loads(text, parse_constant=refuse)


def test_an_optimum_flown_past_its_heating_data_prints_null_not_nan(tmp_path):
    study = json.loads((ROOT / "examples" / "optimize_fly_there.json").read_text())
    study["case"]["stop"].pop("altitude_ft")
    path = tmp_path / "nostop.json"
    path.write_text(json.dumps(study))
    proc = run("optimize", path, "--json")
    assert proc.returncode == 0, proc.stderr
    temperature_R = _strict(proc.stdout)["history"]["temperature_R"]
    assert temperature_R and set(temperature_R) == {None}  # a correlation gives no temperature: null, as the service


def test_strict_json_maps_non_finite_numbers_to_null_and_refuses_what_escapes():
    import numpy as np

    assert _strict(strict_json({"a": math.nan, "b": [np.float64(np.inf), 1.5], "c": np.float32(-np.inf)})) == {
        "a": None,
        "b": [None, 1.5],
        "c": None,
    }


@pytest.mark.parametrize(
    "aero, field",
    [
        ({"constant": {"cl": 0.5, "cd": 1e308}}, "vehicle.aero.constant.cd"),
        ({"polynomial": {"cl": [0, 1e200], "cd": [0.1]}}, "vehicle.aero.polynomial.cl"),
    ],
)
def test_a_coefficient_that_overflows_the_forces_is_refused_with_its_field(tmp_path, aero, field):
    case = json.loads((ROOT / "examples" / "table2_lod22.json").read_text())
    case["vehicle"] = {"aero": aero, "wing_loading_psf": 50}
    path = tmp_path / "case.json"
    path.write_text(json.dumps(case))
    proc = run("fly", path)
    assert proc.returncode == 2 and "Traceback" not in proc.stderr, proc.stderr
    line = proc.stderr.strip()
    assert "\n" not in line and field.removeprefix("vehicle.") in line and "100" in line, line
    assert "Infinity" not in proc.stdout and "overflow" not in proc.stderr


def _json_values():
    """Nested values as results hold them: Python and numpy numbers (NaN and infinities too), text, None, lists,
    tuples, dicts with text or integer keys, and numpy arrays, C-contiguous, strided or of text."""
    import numpy as np
    from hypothesis import strategies as st

    floats = st.floats(allow_nan=True, allow_infinity=True)
    arrays = st.lists(floats, max_size=6).map(lambda v: np.array(v, dtype=np.float64))
    leaves = st.one_of(
        floats,
        floats.map(np.float64),
        st.integers(-(2**63), 2**63 - 1),
        st.integers(-(2**63), 2**63 - 1).map(np.int64),
        st.booleans(),
        st.booleans().map(np.bool_),
        st.none(),
        st.text(max_size=8),
        arrays,
        arrays.map(lambda a: a[::2]),
        st.lists(st.text(max_size=3), max_size=3).map(lambda v: np.array(v, dtype=str)),
    )
    return st.recursive(
        leaves,
        lambda inner: st.one_of(
            st.lists(inner, max_size=4),
            st.lists(inner, max_size=4).map(tuple),
            st.dictionaries(st.one_of(st.text(max_size=6), st.integers(-5, 5)), inner, max_size=4),
        ),
        max_leaves=20,
    )


def test_the_one_writer_writes_what_plain_makes_to_the_bit():
    """Issue 29 (the doors): json_bytes hands orjson the value itself, not plain()'s copy of it; the text must read
    back as plain(value) does through json.dumps, every float to the bit (NaN and infinities null), and stay strict."""
    from hypothesis import given, settings

    from footprint.contracts.records import json_bytes, plain
    from tests.test_doors import bits

    @settings(max_examples=300, deadline=None)
    @given(_json_values())
    def check(value):
        expected = bits(json.loads(json.dumps(plain(value))))
        for indent in (None, 2):
            assert bits(_strict(json_bytes(value, indent).decode())) == expected

    check()


def test_the_services_job_events_are_strict_json_too():
    """The job event stream wrote its data with json.dumps, which writes a NaN as the bare word NaN that a browser's
    JSON.parse refuses; it goes through the same writer as the CLI now (a progress note's text kept as it is)."""
    from footprint.service.routers.jobs import _event

    text = _event("progress", {"fraction": math.nan, "note": 'mesh 2: "113 intervals" — ü'})
    name, data = text.removesuffix("\n\n").split("\n")
    assert name == "event: progress" and data.startswith("data: ")
    assert _strict(data.removeprefix("data: ")) == {"fraction": None, "note": 'mesh 2: "113 intervals" — ü'}
