"""`footprint map`: a standalone folium map that works offline (no script or stylesheet from the internet)."""

import json
import re
import subprocess
import sys

import pytest

from footprint.core.sphere import unwrap_longitude
from footprint.pictures.folium_page import FRONTEND_DIR, topojson_features, unwrap_ring

pytestmark = pytest.mark.skipif(not (FRONTEND_DIR / "vendor" / "leaflet").is_dir(),
                                reason="run `npm ci` in frontend/ (the map inlines the npm leaflet package)")

# Three points of a footprint entered at 170 E heading east: its boundary crosses longitude 180.
FOOTPRINT = {
    "method": "single_parameter", "entry": {"latitude_deg": 0.0, "longitude_deg": 170.0, "heading_deg": 90.0},
    "points": [{"latitude_deg": 0.0, "longitude_deg": -150.0, "downrange_nmi": 2400.0, "crossrange_nmi": 0.0,
                "flight_time_s": 2000.0, "parameter": {"bank0_deg": 0.0}, "mirrored": False},
               {"latitude_deg": 10.0, "longitude_deg": 179.0, "downrange_nmi": 900.0, "crossrange_nmi": 600.0,
                "flight_time_s": 1500.0, "parameter": {"bank0_deg": 90.0}, "mirrored": False},
               {"latitude_deg": -10.0, "longitude_deg": 179.0, "downrange_nmi": 900.0, "crossrange_nmi": -600.0,
                "flight_time_s": 1500.0, "parameter": {"bank0_deg": 90.0}, "mirrored": True}],
}


def run_cli(*args):
    return subprocess.run([sys.executable, "-m", "footprint.cli", *args], capture_output=True, text=True, timeout=120)


def test_map_command_writes_html_that_loads_nothing_from_the_internet(tmp_path):
    src = tmp_path / "footprint.json"
    src.write_text(json.dumps(FOOTPRINT))
    out = tmp_path / "map.html"
    res = run_cli("map", str(src), "-o", str(out))
    assert res.returncode == 0, res.stderr
    html = out.read_text()
    scripts = re.findall(r"<script[^>]*\bsrc\s*=\s*[\"']?([^\"' >]+)", html, re.I)
    styles = re.findall(r"<link[^>]*\bhref\s*=\s*[\"']?([^\"' >]+)", html, re.I)
    assert not [u for u in scripts + styles if re.match(r"(https?:)?//", u)], scripts + styles
    assert not re.search(r"@import\s+url\(\s*['\"]?(https?:)?//", html)
    assert "L.map(" in html and "crs: L.CRS.EPSG4326" in html  # Leaflet inline, the report's projection
    assert "Natural Earth" in html
    assert "down-range 2,400 nmi" in html  # the hover text of a point


def test_bad_footprint_file_is_one_line_and_status_2(tmp_path):
    src = tmp_path / "not_a_footprint.json"
    src.write_text(json.dumps({"points": []}))
    res = run_cli("map", str(src), "-o", str(tmp_path / "map.html"))
    assert res.returncode == 2
    assert res.stderr.startswith("error: points:") and len(res.stderr.strip().splitlines()) == 1


def test_ring_across_180_is_drawn_whole_next_to_its_entry():
    lon = unwrap_ring([0.0, 10.0, -10.0], [-150.0, 179.0, 179.0], FOOTPRINT["entry"])
    assert lon.tolist() == [210.0, 179.0, 179.0]  # -150 is drawn at 210, east of 180, not 330 deg away
    assert unwrap_longitude([170.0, -170.0, -150.0], 0.0).tolist() == [170.0, 190.0, 210.0]


def test_topojson_decoding_with_reversed_arcs():
    topology = {"type": "Topology", "transform": {"scale": [1.0, 1.0], "translate": [0.0, 0.0]},
                "arcs": [[[0, 0], [1, 0], [0, 1]], [[1, 1], [-1, 0], [0, -1]]],
                "objects": {"square": {"type": "GeometryCollection",
                                       "geometries": [{"type": "Polygon", "arcs": [[0, 1]]},
                                                      {"type": "Polygon", "arcs": [[~1, ~0]]}]}}}
    features = topojson_features(topology, "square")["features"]
    assert features[0]["geometry"]["coordinates"] == [[[0, 0], [1, 0], [1, 1], [0, 1], [0, 0]]]
    assert features[1]["geometry"]["coordinates"] == [[[0, 0], [0, 1], [1, 1], [1, 0], [0, 0]]]
