"""Guided entry from the command line (issue 27 item 5), run as a user runs it: `footprint fly` with the guided law,
`footprint disperse` with a guided case, `footprint guided-footprint`; their files, and one line with exit 2 for a
mistake. The ends and the clouds are measured by haversine here (their misses of the terminal-area interface circle),
not by the code's own miss."""

import json

import pytest

from tests.core.test_guidance import INTERFACE_NMI, distance_nmi
from tests.test_cli import EXAMPLES, run, run_on_terminal

FLY = json.loads((EXAMPLES / "fly_guided_lod189.json").read_text())
TARGET = FLY["bank"]["target"]


def small(name, **change):
    data = json.loads((EXAMPLES / name).read_text())
    return data | change


def test_fly_guided_ends_on_its_terminal_area_interface(tmp_path):
    r = run("fly", EXAMPLES / "fly_guided_lod189.json", "--history", tmp_path / "h.csv")
    assert r.returncode == 0, r.stderr
    s = json.loads(r.stdout)
    to_site = distance_nmi(
        s["final_latitude_deg"], s["final_longitude_deg"], TARGET["latitude_deg"], TARGET["longitude_deg"]
    )
    miss = abs(to_site - INTERFACE_NMI)  # of the interface circle about the target
    assert miss <= 1.0 and s["guidance"]["miss_nmi"] == pytest.approx(miss, abs=1e-6)
    header = (tmp_path / "h.csv").read_text().splitlines()[0]
    assert "bank_command_deg" in header and "predicted_miss_nmi" in header


def test_disperse_a_guided_study_writes_its_figure_geojson_and_csv(tmp_path):
    study = small("disperse_guided_lod189.json", samples=4, chunk_samples=2, radius_nmi=[5.0])
    path = tmp_path / "study.json"
    path.write_text(json.dumps(study))
    files = {"--figure": tmp_path / "g.png", "--geojson": tmp_path / "g.geojson", "--csv": tmp_path / "g.csv"}
    r = run("disperse", path, "--workers", 0, *[x for kv in files.items() for x in kv])
    assert r.returncode == 0, r.stderr
    got = json.loads(r.stdout)
    cloud = got["clouds"]["guided"]
    within = sum(
        abs(distance_nmi(a, b, TARGET["latitude_deg"], TARGET["longitude_deg"]) - INTERFACE_NMI) <= 5.0
        for a, b in zip(cloud["latitude_deg"], cloud["longitude_deg"])
    )
    assert got["guided"]["within"][0]["samples_within"] == within == 4
    assert files["--figure"].read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    kinds = {f["properties"]["kind"] for f in json.loads(files["--geojson"].read_text())["features"]}
    assert {"target", "miss_circle", "nominal_guided_track"} <= kinds
    assert files["--csv"].read_text().count("\n") >= 2


def test_guided_footprint_traces_its_rays_and_says_its_margin(tmp_path):
    study = small("guided_footprint_lod189.json", rays=4, samples=2, probability=0.2, optimal=False)
    path = tmp_path / "study.json"
    path.write_text(json.dumps(study))
    png, geo = tmp_path / "f.png", tmp_path / "f.geojson"
    r = run("guided-footprint", path, "--workers", 0, "--figure", png, "--geojson", geo)
    assert r.returncode == 0, r.stderr
    got = json.loads(r.stdout)
    assert [x["angle_deg"] for x in got["rays"]] == [0.0, 90.0, 180.0, 270.0]
    assert got["margin_to_report"]["inside_at_every_ray"] and got["optimal"] is None
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    features = json.loads(geo.read_text())["features"]
    rings = {f["properties"]["kind"]: f for f in features}
    assert set(rings) == {"entry", "report_footprint", "nominal_guided_footprint", "guided_footprint"}
    assert rings["guided_footprint"]["properties"]["area_nmi2"] == got["guided"]["area_nmi2"]
    # on a terminal: the table of areas and margins
    code, text = run_on_terminal("guided-footprint", path, "--workers", 0)
    assert code == 0 and "margin" in text and f"{got['report']['area_nmi2']:,.0f}" in text, text


@pytest.mark.parametrize(
    ("change", "field"),
    [({"rays": 2}, "rays"), ({"probability": 0}, "probability"), ({"samples": 0}, "samples")],
)
def test_a_bad_guided_footprint_study_is_one_line_and_exit_2(tmp_path, change, field):
    path = tmp_path / "study.json"
    path.write_text(json.dumps(small("guided_footprint_lod189.json", **change)))
    r = run("guided-footprint", path, "--workers", 0)
    assert r.returncode == 2 and r.stdout == ""
    (line,) = r.stderr.strip().splitlines()
    assert line.startswith(f"error: {field}:"), line
