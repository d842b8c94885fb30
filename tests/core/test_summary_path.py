"""simulate_summary(spec), which simulate(spec) also gives, is the summary of the track of every row to the bit,
though it converts only a handful of rows."""

import copy
import pickle
from dataclasses import replace

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from footprint.contracts import parse
from footprint.core.atmosphere import DENSITY_NODES_FT
from footprint.core.sphere import great_circle_frame
from footprint.core.trajectory import (
    Dispersion,
    _fly,
    _heating,
    _pullout_row,
    _summary,
    _track,
    _track_rows,
    simulate,
    simulate_summary,
)
from tests.authorities.report import example

TABLE2 = example("table2_lod22")
LOD189 = example("footprint_lod189")["case"]  # zero bank: 14,869 nmi, past half a circumference


def variant(base, **changes):
    case = copy.deepcopy(base)
    case.update(changes)
    return case


CASES = {
    "table2": TABLE2,
    "lod189 past half a circumference": LOD189,
    "reference heating, banked": variant(
        LOD189, heating={"model": "reference"}, bank={"law": "constant", "bank_deg": 40}
    ),
    "thin skin": variant(LOD189, heating={"model": "reference", "skin_heat_capacity_btu_ft2_R": 0.01}),
    # about Betts' shuttle correlation: 17,700 (1e-4)^3.07 rho^0.5 V^3.07
    "correlation heating": variant(
        TABLE2, heating={"model": "correlation", "coefficient": 9.3e-9, "velocity_exponent": 3.07, "emissivity": 0.8}
    ),
    "skip-out": variant(
        TABLE2,
        entry=dict(TABLE2["entry"], velocity_fps=26_500, gamma_deg=-1.0),
        stop={"altitude_ft": 50_000, "max_altitude_ft": 600_000},
    ),
    "orbiting, stopped by time": variant(
        TABLE2,
        entry=dict(TABLE2["entry"], velocity_fps=25_800, gamma_deg=-1.0),
        stop={"altitude_ft": 50_000, "time_s": 20_000},
    ),
    "stopped by velocity": variant(TABLE2, stop={"altitude_ft": None, "velocity_fps": 8_000}),
    "zero lift, ground hit": variant(TABLE2, bank={"law": "zero_lift"}, stop={"altitude_ft": 0}),
    "constant-altitude turn": variant(TABLE2, bank={"law": "constant_altitude", "turn_deg": 60}),
    "high-lod, far off the initial great circle": variant(TABLE2, vehicle={"builtin": "high-lod"}),
    "inertial entry near the date line": variant(
        TABLE2,
        entry=dict(TABLE2["entry"], velocity_frame="inertial", heading_deg=10, latitude_deg=30, longitude_deg=170),
    ),
}


def every_row(spec) -> dict:
    """The summary read off the track of every row (as simulate made it before its histories were made on demand)."""
    f = _fly(spec)
    return _summary(spec, f, _track(spec, f.p, f.rows), _pullout_row(f), _heating(spec, f.p, f.rows))


def bits(summary: dict) -> dict:
    """Every float by its bits (float.hex tells -0.0 from 0.0), everything else as it is."""
    return {k: v.hex() if isinstance(v, float) else v for k, v in summary.items()}


@pytest.mark.parametrize("name", CASES)
def test_summary_path_equals_the_full_path_to_the_bit(name):
    spec = parse("case", CASES[name]).to_spec()
    assert bits(simulate_summary(spec)) == bits(every_row(spec))


def test_a_dispersed_heated_flight_gives_the_same_summary_both_ways():
    spec = parse("case", variant(LOD189, heating={"model": "reference"})).to_spec()
    delta = 0.1 * np.sin(DENSITY_NODES_FT / 60_000.0)
    spec = replace(spec, dispersion=Dispersion(cl_multiplier=1.03, cd_multiplier=0.97, density_delta=delta))
    assert bits(simulate_summary(spec)) == bits(every_row(spec))


@settings(max_examples=60, deadline=None)
@given(
    latitude_deg=st.floats(-80, 80),
    longitude_deg=st.floats(-180, 180),
    heading_deg=st.floats(-180, 360),
    velocity_fps=st.floats(20_000, 27_500),
    gamma_deg=st.floats(-5, -0.5),
    bank_deg=st.floats(-100, 100),
    vehicle=st.sampled_from(["lod-1.89", "lod-2.2", "lod-2.6"]),
)
def test_summary_path_equals_the_full_path_anywhere(
    latitude_deg, longitude_deg, heading_deg, velocity_fps, gamma_deg, bank_deg, vehicle
):
    entry = dict(
        TABLE2["entry"],
        latitude_deg=latitude_deg,
        longitude_deg=longitude_deg,
        heading_deg=heading_deg,
        velocity_fps=velocity_fps,
        gamma_deg=gamma_deg,
    )
    spec = parse(
        "case",
        variant(
            TABLE2,
            vehicle={"builtin": vehicle},
            entry=entry,
            bank={"law": "constant", "bank_deg": bank_deg},
            stop={"altitude_ft": 50_000, "time_s": 15_000},
        ),
    ).to_spec()
    assert bits(simulate_summary(spec)) == bits(every_row(spec))


def test_simulate_gives_the_summary_path_and_the_histories_on_demand():
    spec = parse("case", CASES["lod189 past half a circumference"]).to_spec()
    trajectory = simulate(spec)
    assert bits(trajectory.summary) == bits(simulate_summary(spec))
    h = trajectory.history  # made now, from every row
    assert h["downrange_nmi"][-1] == trajectory.summary["downrange_nmi"] > 10_800  # past half a circumference
    assert h["crossrange_nmi"][-1] == trajectory.summary["crossrange_nmi"]
    assert h is trajectory.history  # made once
    again = pickle.loads(pickle.dumps(trajectory))  # as Dask ships it
    assert np.array_equal(again.history["latitude_deg"], h["latitude_deg"]) and again.summary == trajectory.summary


def test_the_summary_path_converts_a_handful_of_rows():
    spec = parse("case", TABLE2).to_spec()
    f = _fly(spec)
    e = spec.entry
    kept = _track_rows(f.rows, _pullout_row(f), *great_circle_frame(e.latitude_deg, e.longitude_deg, e.heading_deg))
    assert len(kept) < 10 < 400 < len(f.rows)  # entry, pull-out, final and the changes of quadrant
    assert kept[0] == 0 and kept[-1] == len(f.rows) - 1
