"""The guided flight ends at a terminal-area interface (issue 50 item 3): on the circle of 50 nmi about the site,
headed at it, at the terminal energy; the summary says which point it means, each value against its tolerance, and
where and when the touchdown is expected. Ranges and headings here are geographiclib's geodesics on the WGS-84
ellipsoid, not the code's sphere."""

import copy
import json
from pathlib import Path

import pytest
from geographiclib.geodesic import Geodesic

from footprint.api import fly
from footprint.contracts import parse
from tests.core.test_guidance import INTERFACE_NMI, distance_nmi, guided

EXAMPLE = json.loads((Path(__file__).parents[2] / "examples" / "fly_guided_lod189.json").read_text())
M_PER_NMI = 1852.0
# the tolerances asked of the interface (chosen, core.guidance.Guidance: the Shuttle's ~80 kft, 2,500 ft/s, ~50 nmi)
RANGE_TOLERANCE_NMI, HEADING_TOLERANCE_DEG = 5.0, 5.0
ALTITUDE_TOLERANCE_FT, VELOCITY_TOLERANCE_FPS = 5_000.0, 100.0


def geodesic_to(summary, site):
    """(range nmi, heading error deg) of the flight's end to the site on the WGS-84 ellipsoid."""
    inv = Geodesic.WGS84.Inverse(
        summary["final_latitude_deg"], summary["final_longitude_deg"], site["latitude_deg"], site["longitude_deg"]
    )
    error = (summary["final_heading_deg"] - inv["azi1"] + 180.0) % 360.0 - 180.0
    return inv["s12"] / M_PER_NMI, error


@pytest.fixture(scope="module")
def example():
    return fly(copy.deepcopy(EXAMPLE)).summary


def test_the_example_ends_on_the_interface_circle_headed_at_the_site(example):
    """Before: it ended 0.21 nmi from the site with its heading 112 deg off the site's bearing (on top of it)."""
    s, site = example, EXAMPLE["bank"]["target"]
    range_nmi, heading_error = geodesic_to(s, site)
    assert s["stop_reason"] == "energy"
    assert abs(range_nmi - INTERFACE_NMI) <= RANGE_TOLERANCE_NMI
    assert abs(heading_error) <= HEADING_TOLERANCE_DEG
    i = s["guidance"]["interface"]
    assert i["range_to_site_nmi"] == pytest.approx(range_nmi, rel=4e-3)  # R' sphere against the ellipsoid
    assert i["heading_error_deg"] == pytest.approx(heading_error, abs=0.2)
    assert i["within"]["range"] and i["within"]["heading"] and s["guidance"]["status"] == "reached"


def test_the_interface_says_whether_its_altitude_and_velocity_are_within_tolerance(example):
    """The flags are the tolerances applied to the flight's end, here against the values asked (80,000 ft,
    2,500 ft/s); "met" is all four. (The example ends at ~91 kft and ~2,350 ft/s: above and slow, not met.)"""
    s = example
    i = s["guidance"]["interface"]
    assert i["altitude_ft"] == s["final_altitude_ft"] and i["velocity_fps"] == s["final_velocity_fps"]
    assert i["within"]["altitude"] == (abs(s["final_altitude_ft"] - 80_000.0) <= ALTITUDE_TOLERANCE_FT)
    assert i["within"]["velocity"] == (abs(s["final_velocity_fps"] - 2_500.0) <= VELOCITY_TOLERANCE_FPS)
    assert i["met"] == all(i["within"].values())
    assert (i["latitude_deg"], i["longitude_deg"], i["time_s"]) == (
        s["final_latitude_deg"],
        s["final_longitude_deg"],
        s["flight_time_s"],
    )


def test_the_touchdown_is_expected_at_the_site_after_the_terminal_area(example):
    g = example["guidance"]
    t = g["touchdown_estimate"]
    site = EXAMPLE["bank"]["target"]
    assert (t["latitude_deg"], t["longitude_deg"]) == (site["latitude_deg"], site["longitude_deg"])
    assert 300.0 <= t["terminal_area_s"] <= 360.0  # the Shuttle's ~5-6 min from 2,500 ft/s to wheels stop
    assert t["time_s"] == pytest.approx(example["flight_time_s"] + t["terminal_area_s"], abs=1e-9)
    assert g["point"] == "interface"


@pytest.mark.parametrize("range_nmi", [30.0, 80.0])
def test_the_interface_range_is_the_cases(range_nmi):
    s = fly(guided(5000.0, 600.0, terminal={"range_nmi": range_nmi})).summary
    site = guided(5000.0, 600.0)["bank"]["target"]
    range_to_site, _ = geodesic_to(s, site)
    assert abs(range_to_site - range_nmi) <= 1.0 and s["guidance"]["miss_nmi"] <= 1.0


def test_an_interface_at_zero_range_ends_on_the_site_as_before():
    """Regression: with the interface's range 0 the flight ends on the target itself, as every guided flight did
    (5,000/600 nmi: 0.15 nmi from it), its miss the distance to the target."""
    s = fly(guided(5000.0, 600.0, terminal={"range_nmi": 0.0})).summary
    t = guided(5000.0, 600.0)["bank"]["target"]
    miss = distance_nmi(s["final_latitude_deg"], s["final_longitude_deg"], t["latitude_deg"], t["longitude_deg"])
    assert miss <= 1.0 and s["guidance"]["miss_nmi"] == pytest.approx(miss, abs=1e-6)


@pytest.mark.parametrize(
    "terminal, field",
    [
        ({"range_nmi": -1}, "bank.terminal.range_nmi"),
        ({"heading_tolerance_deg": 200}, "bank.terminal.heading_tolerance_deg"),
        ({"altitude_tolerance_ft": -5}, "bank.terminal.altitude_tolerance_ft"),
    ],
)
def test_a_bad_interface_names_its_field(terminal, field):
    from pydantic import ValidationError

    from footprint.contracts.messages import error_line

    with pytest.raises(ValidationError) as info:
        parse("case", guided(5000.0, 600.0, terminal=terminal))
    assert error_line(info.value).startswith(field), error_line(info.value)
