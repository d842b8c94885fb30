"""One trajectory through every door gives the same numbers to the bit (issue 29 item 3: the doors made cheaper must
stay the same flight): footprint.api.fly(dict), simulate(spec) of a spec written by hand in the core's own types,
the CLI's `footprint fly` (a new process), and POST /api/trajectories, whose JSON holds to the bit the numbers its
response model wrote when FastAPI validated and serialized the answer (and validates against that model)."""

import copy
import json
import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from pydantic import TypeAdapter

from footprint import api
from footprint.contracts.records import decimated, plain, strict_json
from footprint.core.aero import builtin_vehicle
from footprint.core.controls import pack_controls
from footprint.core.trajectory import Entry, FlightSpec, Planet, Stop, simulate
from tests.authorities.report import example

ROOT = Path(__file__).resolve().parents[1]
TABLE2 = example("table2_lod22")


def by_hand() -> FlightSpec:
    """examples/table2_lod22.json in the core's types, without the case contract."""
    return FlightSpec(
        vehicle=builtin_vehicle("lod-2.2"),
        planet=Planet(),
        entry=Entry(altitude_ft=364_800.0, velocity_fps=24_480.0, gamma_deg=-2.0, heading_deg=90.0),
        ctrl=pack_controls(bank_law="single_parameter", bank_gain=0.8, bank_limit_deg=85.0),
        stop=Stop(altitude_ft=50_000.0),
    )


def bits(value):
    """Every float by its bits (float.hex: -0.0 is not 0.0; NaN equals NaN), recursively."""
    if isinstance(value, dict):
        return {k: bits(v) for k, v in value.items()}
    if isinstance(value, (list, tuple, np.ndarray)):
        return [bits(v) for v in value]
    if isinstance(value, (float, np.floating)):
        return float(value).hex()
    return value


def test_the_python_door_flies_the_spec_written_by_hand_to_the_bit():
    reference = simulate(by_hand())
    for _ in range(2):  # the second parse of the same case finds what the first one cached
        traj = api.fly(copy.deepcopy(TABLE2))
        assert bits(traj.summary) == bits(reference.summary)
        assert list(traj.history) == list(reference.history)
        assert bits(traj.history) == bits(reference.history)


def test_the_cli_prints_the_python_doors_summary(tmp_path):
    r = subprocess.run(
        [sys.executable, "-m", "footprint.cli", "fly", ROOT / "examples" / "table2_lod22.json"],
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert r.returncode == 0, r.stderr
    assert r.stdout == strict_json(simulate(by_hand()).summary, indent=2) + "\n"
    assert bits(json.loads(r.stdout)) == bits(plain(api.fly(TABLE2).summary))  # repr round-trips every float


def the_models_answer(summary, history, max_rows: int):
    """What FastAPI wrote from the route's dict through its response model (TrajectoryRead), read back: every number
    made plain (NaN and infinities None), validated against the model, serialized by it."""
    from footprint.service.schemas import TrajectoryRead

    adapter = TypeAdapter(TrajectoryRead)
    keep = decimated(len(history["time_s"]), max_rows)
    body = {"summary": plain(summary), "history": {k: plain(v[keep]) for k, v in history.items()}}
    return json.loads(adapter.dump_json(adapter.validate_python(body)))


def the_routes_answer(body: bytes):
    """The route's JSON read back, after checking that it validates against its response model."""
    from footprint.service.schemas import TrajectoryRead

    TrajectoryRead.model_validate_json(body)
    return json.loads(body)


@pytest.fixture(scope="module")
def service(tmp_path_factory):
    from fastapi.testclient import TestClient

    from footprint.service.app import create_app
    from footprint.service.settings import load_settings

    folder = tmp_path_factory.mktemp("doors")
    app = create_app(load_settings(database_url=f"sqlite:///{folder}/doors.db"), runs_jobs=False)
    with TestClient(app) as client:
        yield client


CASES = {
    "table2": TABLE2,
    "heated": TABLE2 | {"heating": {"model": "reference"}},
    "zero lift to the ground": TABLE2 | {"bank": {"law": "zero_lift"}, "stop": {"altitude_ft": 0}},
    "over 2,000 rows, decimated": TABLE2 | {"integrator": {"max_step_s": 0.5}},
}


@pytest.mark.parametrize("name", CASES)
def test_the_http_door_answers_the_python_doors_flight(service, name):
    from footprint.service.routers.trajectories import MAX_HISTORY_ROWS

    case = CASES[name]
    r = service.post("/api/trajectories", json=case)
    assert r.status_code == 200 and r.headers["content-type"] == "application/json"
    traj = api.fly(case)
    assert bits(the_routes_answer(r.content)) == bits(the_models_answer(traj.summary, traj.history, MAX_HISTORY_ROWS))
    answer = r.json()
    assert bits(answer["summary"]) == bits(plain(traj.summary))
    keep = decimated(len(traj.history["time_s"]), MAX_HISTORY_ROWS)
    for key, values in traj.history.items():
        expected = [v if math.isfinite(v) else None for v in values[keep].tolist()]
        assert bits(answer["history"][key]) == bits(expected), key


def test_the_routes_json_writes_what_the_model_wrote_for_any_number():
    """NaN and infinities as null, signed zeros, the extremes of float64, a summary's None, text and nested dict."""
    from footprint.service.routers.trajectories import MAX_HISTORY_ROWS, trajectory_json

    odd = np.array([np.nan, np.inf, -np.inf, 0.0, -0.0, 5e-324, 1.7976931348623157e308, 1e16, 1e-7, 1 / 3])
    history = {"time_s": np.arange(odd.size, dtype=float), "odd": odd, "strided": np.vstack([odd, odd]).T[:, 1]}
    summary = {
        "downrange_nmi": np.float64(1.5),
        "pullout_time_s": None,
        "stop_reason": "altitude",
        "steps": 9,
        "max_temperature_R": float("nan"),
        "guidance": {"reached": True, "miss_nmi": 0.25},
    }
    assert bits(the_routes_answer(trajectory_json(summary, history))) == bits(
        the_models_answer(summary, history, MAX_HISTORY_ROWS)
    )
    long = {"time_s": np.linspace(0.0, 1.0, 5_001), "odd": np.resize(odd, 5_001)}
    assert bits(the_routes_answer(trajectory_json(summary, long))) == bits(
        the_models_answer(summary, long, MAX_HISTORY_ROWS)
    )


def test_the_long_case_passes_the_routes_row_limit():
    assert len(api.fly(CASES["over 2,000 rows, decimated"]).history["time_s"]) > 2_000
