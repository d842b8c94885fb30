"""The report's numbers as data (afwal_tr_82_3036.json) agree with themselves and with examples/table2_lod22.json."""

import math

from tests.authorities.report import REPORT, table2_entry, table2_stop


def test_every_record_says_where_it_is_printed():
    assert len(REPORT) >= 50
    for key, n in REPORT.items():
        assert n.where and n.quote and isinstance(n.unit, str), key


def test_the_table2_example_is_table2():
    e = table2_entry()
    for field in ("altitude_ft", "velocity_fps", "gamma_deg", "heading_deg", "latitude_deg", "longitude_deg"):
        assert e[field] == REPORT[f"table2.{field}"].value, field
    assert e["velocity_frame"] == "relative" and table2_stop() == {
        "altitude_ft": REPORT["table2.stop_altitude_ft"].value
    }


def test_the_report_s_own_arithmetic():
    v = {k: n.value for k, n in REPORT.items()}
    assert v["sec3.max_crossrange_nmi"] - v["sec3.crossrange_loss_nmi"] == v["sec3.max_crossrange_2550_nmi"]
    assert (
        round(100 * v["sec3.crossrange_loss_nmi"] / v["sec3.max_crossrange_nmi"], 1)
        == v["sec3.crossrange_loss_percent"]
    )
    assert (
        round(100 * (1 - v["sec3.max_downrange_2550_nmi"] / v["sec3.max_downrange_nmi"]))
        == v["sec3.downrange_loss_percent"]
    )
    assert v["sec3.min_downrange_2550_nmi"] == 2 * v["sec3.min_downrange_nmi"]  # "doubled"
    assert round(3 * v["sec2.iterations_per_optimum"] / v["sec2.points_per_footprint"]) == v["sec2.cost_factor"]
    assert 3 * v["sec2.iterations_per_optimum"] * v["sec2.cyber175_s_per_trajectory"] == v["sec2.optimized_points_s"]
    assert v["sec2.points_per_footprint"] * v["sec2.cyber175_s_per_trajectory"] == v["sec2.linear_control_footprint_s"]
    for t, shift in (("min", "min"), ("max", "max")):
        w = v["sec4.omega_deg_s"] * v[f"sec4.flight_time_{t}_s"]
        assert round(w, 1) == v[f"sec4.longitude_shift_{shift}_deg"]
    assert math.isclose(v["table2.altitude_ft"], v["entry.altitude_text_ft"], abs_tol=250)  # 60 nmi vs Table 2
    assert abs(v["table2.inertial_velocity_fps"] - v["entry.inertial_velocity_text_fps"]) == 1
