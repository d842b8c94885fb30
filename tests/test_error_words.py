"""Issue 49 item 2: no mistake in a request reaches the user in Python's words. An opportunities study from a state
vector past escape speed was answered `study: math domain error` (a ValueError of math.sqrt inside the study's
validator), and a density spread out of range named pydantic's union member
(`density.std.function-after[check(), function-before[_not_bool(), float]]: ...`). Each is said in the house's words
now, and a ValueError that Python raised inside a validator is said as such, never as if it were the reason."""

import copy
import json
import math
import subprocess
import sys

import pytest
from pydantic import ValidationError

from footprint import contracts
from footprint.contracts.messages import error_line
from tests.authorities.report import example

MU_WGS84_KM3_S2 = 398_600.4418  # the earth's gravitational parameter (WGS 84), independent of the report's


def opportunities_from_state(position_km, velocity_km_s) -> dict:
    study = copy.deepcopy(example("opportunities_iss_20_sites"))
    study.pop("tle")
    study["state"] = {
        "epoch": "2024-01-01T00:00:00Z",
        "frame": "teme",
        "position_km": position_km,
        "velocity_km_s": velocity_km_s,
    }
    study["window"] = {"start": "2024-01-01T00:00:00Z", "hours": 6}
    return study


def test_a_state_past_escape_speed_names_its_velocity_and_the_escape_speed(tmp_path):
    r_km = 7_000.0
    escape_km_s = math.sqrt(2.0 * MU_WGS84_KM3_S2 / r_km)  # 10.67: 11.2 km/s leaves the earth
    study = opportunities_from_state([r_km, 0, 0], [0, 11.2, 0])
    with pytest.raises(ValidationError) as err:
        contracts.parse("opportunities", study)
    line = error_line(err.value)
    assert line.startswith("state.velocity_km_s: 11.2 km/s "), line
    assert f"escape speed {escape_km_s:.3g} km/s" in line and "math domain" not in line
    path = tmp_path / "escaping.json"
    path.write_text(json.dumps(study))
    cli = subprocess.run(
        [sys.executable, "-m", "footprint.cli", "opportunities", str(path)], capture_output=True, text=True, timeout=300
    )
    assert (cli.returncode, cli.stderr) == (2, f"error: {line}\n")


def test_a_union_names_its_field_not_pydantics_members():
    dispersion = copy.deepcopy(example("disperse_lod189"))
    dispersion["density"]["std"] = 0.5
    with pytest.raises(ValidationError) as err:
        contracts.parse("dispersion", dispersion)
    assert error_line(err.value) == "density.std: 0.5 is outside the allowed range 0 to 0.2"
    dispersion["density"]["std"] = [0.01] * 40 + [0.5]
    with pytest.raises(ValidationError) as err:
        contracts.parse("dispersion", dispersion)
    assert error_line(err.value) == "density.std.40: 0.5 is outside the allowed range 0 to 0.2"
    case = example("table2_lod22")
    with pytest.raises(ValidationError) as err:
        contracts.parse("case", case | {"bank_start": 5})
    assert error_line(err.value).startswith("bank_start: ")
    with pytest.raises(ValidationError) as err:
        contracts.parse("case", case | {"bank_start": {"altitude_ft": 5}})
    assert error_line(err.value) == "bank_start.altitude_ft: 5 is outside the allowed range 1000 to 3e+06 ft"
