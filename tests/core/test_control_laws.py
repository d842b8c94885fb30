"""Each bank and angle-of-attack law, checked against its definition along a flown history."""

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

import footprint
from footprint.core.aero import builtin_vehicle, coefficients
from footprint.core.controls import (
    ALPHA_LAWS,
    ALPHA_TABLE_BY_ABSCISSA,
    BANK_LAWS,
    BANK_STARTS,
    BANK_VARIABLES,
    LEFT,
    RIGHT,
    pack_controls,
    replace_controls,
    unpack_controls,
)
from tests.authorities.report import table2_entry, table2_stop

ENTRY = table2_entry()


def fly(bank=None, alpha=None, vehicle="lod-2.2", **kw):
    case = {
        "vehicle": {"builtin": vehicle},
        "entry": dict(ENTRY),
        "alpha": alpha or {"law": "max_ld"},
        "bank": bank or {"law": "zero"},
        "stop": table2_stop(),
    }
    case.update(kw)
    t = footprint.fly(case)
    return t.summary, t.history


def after_pullout(s, h):
    return h["time_s"] > s["pullout_time_s"] + 1e-9


def signed_heading(h):
    """Heading wrapped to (-180, 180], as the laws see it (a turn past north goes negative)."""
    return (h["heading_deg"] + 180.0) % 360.0 - 180.0


def test_staged_bank_holds_until_the_heading_has_turned_then_rolls_out():
    s, h = fly({"law": "staged", "bank_deg": 40, "turn_deg": 45})
    turned = 90.0 - h["heading_deg"]
    i = np.flatnonzero(after_pullout(s, h) & (h["bank_deg"] == 0.0))[0]  # the roll-out
    assert turned[i] == pytest.approx(45.0, abs=0.01)  # located on the heading, not on a step
    assert np.all(h["bank_deg"][after_pullout(s, h) & (h["time_s"] < h["time_s"][i])] == 40.0)
    assert np.all(h["bank_deg"][i:] == 0.0)


@pytest.mark.parametrize("method", ["dop853", "dopri5"])
def test_a_turn_of_179_deg_rolls_out_at_179_deg_whatever_the_steps(method):
    """The turn is counted step by step, so a step from under 179 to past 181 deg does not carry it round: the wrapped
    difference from the turn's start exceeds 179 deg only between the two, and DOP853's 5 deg steps of heading
    flew on to 351 deg (App. C data set 2's widest turn at gamma -20 deg: 72 against 473 nmi of cross-range)."""
    s, h = fly({"law": "staged", "bank_deg": 70, "turn_deg": 179}, integrator={"method": method, "max_step_s": 50})
    assert s["turn_deg"] == pytest.approx(179.0, abs=1e-6)
    turned = (90.0 - h["heading_deg"]) % 360.0
    i = np.flatnonzero(after_pullout(s, h) & (h["bank_deg"] == 0.0))[0]  # the roll-out
    assert turned[i] == pytest.approx(179.0, abs=0.01) and np.all(turned[:i] < 179.0 + 1e-6)


def test_two_parameter_bank_is_linear_in_heading_and_limited():
    s, h = fly({"law": "two_parameter", "bank_gain": 1.0, "sigma_f_deg": 30, "limit_deg": 75})
    m = after_pullout(s, h)
    expected = np.clip(1.0 * (signed_heading(h)[m] - 30.0), -75.0, 75.0)  # Fig. 5-6: K (sigma - sigma_f)
    np.testing.assert_allclose(h["bank_deg"][m], expected, atol=1e-9)
    s2, h2 = fly({"law": "two_parameter", "bank_gain": 1.0, "sigma_f_deg": 0, "limit_deg": 75})
    assert h2["bank_deg"].max() == 75.0  # K sigma_0 = 90 deg is cut at the 75 deg limit
    assert s["final_heading_deg"] == pytest.approx(30.0, abs=3.0)  # the law steers onto sigma_f


def test_single_parameter_without_limit_banks_past_85_degrees():
    s, h = fly({"law": "single_parameter", "bank_gain": 1.5})
    m = after_pullout(s, h)
    np.testing.assert_allclose(h["bank_deg"][m], 1.5 * signed_heading(h)[m], atol=1e-9)  # Fig. 8: K sigma
    assert h["bank_deg"][m].max() > 100.0


def test_bank_table_interpolates_linearly_in_heading():
    headings = [-15, 0, 15, 30, 45, 60, 75, 90]  # Section II.5: eight parameters, -15 to 90 deg
    banks = [0, 10, 30, 45, 55, 60, 50, 40]
    s, h = fly({"law": "table", "heading_deg": headings, "bank_deg": banks})
    m = after_pullout(s, h)
    np.testing.assert_allclose(h["bank_deg"][m], np.interp(signed_heading(h)[m], headings, banks), atol=1e-9)


def test_zero_lift_flies_ballistic_at_zero_lift_alpha():
    s, h = fly({"law": "zero_lift"})
    assert np.all(h["cl"] == 0.0)
    lift = fly()[0]
    assert s["downrange_nmi"] < 0.5 * lift["downrange_nmi"]  # Section II.6 d: the minimum down-range point
    assert abs(s["crossrange_nmi"]) < 1.0


def test_bank_starts_at_an_altitude():
    s, h = fly({"law": "constant", "bank_deg": 30}, bank_start={"altitude_ft": 295_000})  # Fig. 13
    start = np.flatnonzero(h["bank_deg"] != 0.0)[0]
    assert h["altitude_ft"][start] == pytest.approx(295_000.0, abs=1.0)  # located on the altitude
    assert np.all(h["bank_deg"][:start] == 0.0) and np.all(h["bank_deg"][start:] == 30.0)
    assert s["pullout_time_s"] > h["time_s"][start]  # banked before pull-out


def test_cl_max_and_constant_alpha_laws():
    blob = builtin_vehicle("lod-2.2").blob
    s, h = fly(alpha={"law": "cl_max"})
    np.testing.assert_allclose(h["alpha_deg"], 40.0, atol=1e-9)  # CL is largest at the last alpha (Table B-3)
    s, h = fly(alpha={"law": "constant", "alpha_deg": 17.5})
    assert np.all(h["alpha_deg"] == 17.5)
    cl = [coefficients(blob, m, 17.5, a)[0] for m, a in zip(h["mach"], h["altitude_ft"])]
    np.testing.assert_allclose(h["cl"], cl, rtol=1e-12)


def test_alpha_table_versus_velocity_and_time():
    v, a = [0, 10_000, 20_000, 30_000], [30, 20, 15, 10]
    s, h = fly(alpha={"law": "table", "velocity_fps": v, "alpha_deg": a})
    np.testing.assert_allclose(h["alpha_deg"], np.interp(h["velocity_fps"], v, a), atol=1e-9)
    t, a = [0, 500, 1500], [25, 15, 12]
    s, h = fly(alpha={"law": "table", "time_s": t, "alpha_deg": a})
    np.testing.assert_allclose(h["alpha_deg"], np.interp(h["time_s"], t, a), atol=1e-9)


def test_level_flight_after_pullout_until_max_ld_then_max_ld():
    s, h = fly(alpha={"law": "level_flight"})  # Section II.7 / App. C data set 2, straight down-range
    m = after_pullout(s, h)
    level = m & (h["alpha_deg"] < 11.999)
    assert level.sum() > 20
    # while alpha is below (L/D)max the flight-path angle is held at zero (altitude within ~100 ft)
    assert np.max(np.abs(h["gamma_deg"][level])) < 0.05
    assert np.ptp(h["altitude_ft"][level]) < 300.0
    # once (L/D)max is reached the law latches onto it for the rest of the flight
    first_max = np.flatnonzero(m & (h["alpha_deg"] >= 11.999))[0]
    assert np.all(h["alpha_deg"][first_max:] == pytest.approx(12.0, abs=1e-6))


def test_gamma_hold_flies_the_commanded_flight_path_angle():
    s, h = fly(alpha={"law": "gamma_hold", "gamma_deg": -0.5})  # Fig. 18: small commanded gamma_c
    held = after_pullout(s, h) & (h["time_s"] > s["pullout_time_s"] + 100.0) & (h["alpha_deg"] < 11.999)
    assert held.sum() > 10
    assert np.max(np.abs(h["gamma_deg"][held] + 0.5)) < 0.05


def test_constant_altitude_turn_holds_pullout_altitude_while_turning():
    s, h = fly({"law": "constant_altitude", "turn_deg": 8})  # App. C data set 2
    m = after_pullout(s, h) & (h["bank_deg"] > 0.0)
    assert m.sum() > 10
    assert np.max(np.abs(h["altitude_ft"][m] - s["pullout_altitude_ft"])) < 300.0
    turned = 90.0 - h["heading_deg"]
    end = np.flatnonzero(m)[-1] + 1  # the roll-out, located on the heading change
    assert turned[end] == pytest.approx(8.0, abs=0.01)
    assert np.all(h["bank_deg"][end:] == 0.0)


def test_constant_altitude_turn_ends_when_the_wings_come_level():
    # "The maximum amount of turn available is to maintain the turn using bank control until the wings
    # are level" (Section II.7, Fig. 19 dashed line): lift runs out long before 90 deg
    s, h = fly({"law": "constant_altitude", "turn_deg": 90})
    m = after_pullout(s, h) & (h["bank_deg"] > 0.0)
    end = np.flatnonzero(m)[-1] + 1
    assert 2.0 < 90.0 - h["heading_deg"][end] < 60.0
    assert h["bank_deg"][end - 1] < 5.0  # the bank had come down to level
    assert np.all(h["bank_deg"][end:] == 0.0)
    assert (
        s["crossrange_nmi"] < fly({"law": "single_parameter", "bank_gain": 0.8, "limit_deg": 85})[0]["crossrange_nmi"]
    )


def test_inertial_entry_velocity_is_converted():
    # Table 2 gives both: 24,480 ft/s relative = 26,031 ft/s inertial (east, equator, gamma -2 deg)
    rel = fly()[0]
    inertial = fly(entry=dict(ENTRY, velocity_fps=26_031.6, velocity_frame="inertial", gamma_deg=-1.8812))[0]
    assert inertial["downrange_nmi"] == pytest.approx(rel["downrange_nmi"], rel=2e-3)


@pytest.mark.parametrize(
    "kw",
    [
        {
            "bank_law": "two_parameter",
            "bank_gain": 0.8,
            "bank_limit_deg": 75.0,
            "sigma_f_deg": 30.0,
            "mirror": True,
            "bank_variable": "heading",
            "alpha_law": "gamma_hold",
            "gamma_deg": -1.5,
            "alpha_before": "cl_max",
            "hold_time_constant_s": 20.0,
        },
        {
            "bank_law": "table",
            "bank_variable": "energy",
            "bank_table": ([1e5, 5e6], [10.0, 60.0]),
            "bank_start": "altitude",
            "bank_start_altitude_ft": 250_000.0,
            "alpha_law": "table",
            "alpha_table": ([0.0, 900.0, 2_000.0], [40.0, 20.0, 15.0]),
            "alpha_table_abscissa": "time",
        },
        {
            "bank_law": "staged",
            "bank_deg": 40.0,
            "turn_deg": 45.0,
            "bank_start": "entry",
            "alpha_law": "max_ld_floor",
            "alpha_table": ([12_000.0, 16_000.0], [0.0, 20.0]),
        },
    ],
)
def test_unpack_controls_inverts_pack_controls(kw):
    ctrl = pack_controls(**kw)
    assert np.array_equal(pack_controls(**unpack_controls(ctrl)), ctrl)
    moved = unpack_controls(replace_controls(ctrl, bank_table=([0.0, 1_000.0], [5.0, 80.0]), bank_variable="time"))
    kept = unpack_controls(ctrl)
    assert moved.pop("bank_variable") == "time" and kept.pop("bank_variable") == kw.get("bank_variable", "zeta")
    assert np.array_equal(moved.pop("bank_table"), [[0.0, 1_000.0], [5.0, 80.0]])
    kept.pop("bank_table")
    assert pack_controls(**moved).tolist() == pack_controls(**kept).tolist()  # every other law and table kept


CHANGES = st.fixed_dictionaries(
    {},
    optional={
        "bank_law": st.sampled_from(sorted(BANK_LAWS)),
        "bank_deg": st.floats(-180, 180),
        "bank_gain": st.floats(0, 10),
        "side": st.sampled_from([LEFT, RIGHT]),
        "bank_limit_deg": st.none() | st.floats(0, 180),
        "sigma_f_deg": st.floats(-180, 180),
        "turn_deg": st.floats(0, 179),
        "bank_variable": st.sampled_from(sorted(BANK_VARIABLES)),
        "mirror": st.booleans(),
        "bank_start": st.sampled_from(sorted(BANK_STARTS)),
        "alpha_law": st.sampled_from(sorted(ALPHA_LAWS)),
        "alpha_table_abscissa": st.sampled_from(sorted(ALPHA_TABLE_BY_ABSCISSA)),
        "alpha_deg": st.floats(0, 60),
        "hold_time_constant_s": st.floats(0.1, 100),
    },
)


@given(
    base=st.sampled_from(
        [
            {"bank_law": "zero"},
            {
                "bank_law": "table",
                "bank_table": ([0.0, 90.0], [10.0, 60.0]),
                "alpha_law": "table",
                "alpha_table": ([1e3, 2e4], [30.0, 15.0]),
                "alpha_table_abscissa": "time",
            },
        ]
    ),
    changes=CHANGES,
)
def test_replacing_some_controls_writes_what_the_full_repack_writes(base, changes):
    """replace_controls writes the changed slots in place (issue 26: it decoded and re-encoded the whole array for
    every flight); the second route is the full round trip through unpack_controls and pack_controls."""
    ctrl = pack_controls(**base)
    assert replace_controls(ctrl, **changes).tolist() == pack_controls(**(unpack_controls(ctrl) | changes)).tolist()
    assert ctrl.tolist() == pack_controls(**base).tolist()  # the original is untouched


def test_replacing_a_control_that_does_not_exist_is_refused():
    with pytest.raises(TypeError):
        replace_controls(pack_controls(bank_law="zero"), bank_angle=10.0)
