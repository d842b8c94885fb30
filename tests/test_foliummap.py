"""`footprint map`: a standalone folium map that works offline (no script or stylesheet from the internet)."""

import json
import re
import subprocess
import sys

import pytest

from footprint.core.sphere import unwrap_longitude
from footprint.pictures.folium_page import FRONTEND_DIR, topojson_features, unwrap_ring

pytestmark = pytest.mark.skipif(
    not (FRONTEND_DIR / "vendor" / "leaflet").is_dir(),
    reason="run `npm ci` in frontend/ (the map inlines the npm leaflet package)",
)

# Three points of a footprint entered at 170 E heading east: its boundary crosses longitude 180.
FOOTPRINT = {
    "method": "single_parameter",
    "entry": {"latitude_deg": 0.0, "longitude_deg": 170.0, "heading_deg": 90.0},
    "points": [
        {
            "latitude_deg": 0.0,
            "longitude_deg": -150.0,
            "downrange_nmi": 2400.0,
            "crossrange_nmi": 0.0,
            "flight_time_s": 2000.0,
            "parameter": {"bank0_deg": 0.0},
            "mirrored": False,
        },
        {
            "latitude_deg": 10.0,
            "longitude_deg": 179.0,
            "downrange_nmi": 900.0,
            "crossrange_nmi": 600.0,
            "flight_time_s": 1500.0,
            "parameter": {"bank0_deg": 90.0},
            "mirrored": False,
        },
        {
            "latitude_deg": -10.0,
            "longitude_deg": 179.0,
            "downrange_nmi": 900.0,
            "crossrange_nmi": -600.0,
            "flight_time_s": 1500.0,
            "parameter": {"bank0_deg": 90.0},
            "mirrored": True,
        },
    ],
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
    topology = {
        "type": "Topology",
        "transform": {"scale": [1.0, 1.0], "translate": [0.0, 0.0]},
        "arcs": [[[0, 0], [1, 0], [0, 1]], [[1, 1], [-1, 0], [0, -1]]],
        "objects": {
            "square": {
                "type": "GeometryCollection",
                "geometries": [{"type": "Polygon", "arcs": [[0, 1]]}, {"type": "Polygon", "arcs": [[~1, ~0]]}],
            }
        },
    }
    features = topojson_features(topology, "square")["features"]
    assert features[0]["geometry"]["coordinates"] == [[[0, 0], [1, 0], [1, 1], [0, 1], [0, 0]]]
    assert features[1]["geometry"]["coordinates"] == [[[0, 0], [0, 1], [1, 1], [1, 0], [0, 0]]]


HOSTILE_NAME = "x ${alert(document.domain)} </script><img src=x onerror=alert(1)> \"'"


def test_user_text_never_enters_a_script_and_the_scripts_are_pinned_by_hash():
    """Issue 15 item 1: folium's tooltips put text into a JS template literal, where `${...}` runs. The name and a
    point's parameter now live in a JSON data block only, escaped so that nothing closes it, and the <meta>
    policy allows exactly the file's inline scripts."""
    from footprint.csp import inline_script_hashes
    from footprint.pictures.folium_page import footprint_map_html

    points = [dict(p, parameter={"bank0_deg`${alert(2)}`": 1.0}) for p in FOOTPRINT["points"]]
    html = footprint_map_html(dict(FOOTPRINT, points=points), title=HOSTILE_NAME)
    running = [
        text
        for attrs, text in re.findall(r"<script(\s[^>]*)?>(.*?)</script>", html, re.S)
        if "application/json" not in (attrs or "")
    ]
    assert running and not any("alert" in text for text in running)
    labels = re.search(r'<script type="application/json" id="footprint-labels">(.*?)</script>', html, re.S).group(1)
    assert "<" not in labels and HOSTILE_NAME in json.loads(labels)
    assert "&lt;/script&gt;&lt;img src=x onerror=alert(1)&gt;" in html  # the title, as HTML text
    policy = re.search(r'<head>\s*<meta http-equiv="Content-Security-Policy" content="([^"]+)">', html).group(1)
    policy = policy.replace("&#x27;", "'")
    assert "'unsafe-inline'" not in policy.split("script-src")[1].split(";")[0]
    assert f"script-src {' '.join(inline_script_hashes(html))};" in policy
    assert "object-src 'none'" in policy and "base-uri 'none'" in policy


def test_js_string_is_safe_in_a_script_element():
    from footprint.csp import js_string

    text = "</script>\u2028\u2029&`${x}`'\""
    literal = js_string(text)
    assert json.loads(literal) == text
    assert not set(literal) & {"<", ">", "&", "\u2028", "\u2029"}
