"""A standalone folium map of one footprint that works offline (`footprint map FOOTPRINT.json -o map.html`, and
the service's GET /api/footprints/{id}/map).

folium loads Leaflet, jQuery and Bootstrap from CDNs by default; mission-planning networks are often closed, so
the map written here carries Leaflet's JS and CSS inline (from the npm `leaflet` package, as `npm ci` copies it
to frontend/vendor/ for the page) and no CDN at all, and its basemap is Natural Earth 1:110m countries from the
npm `world-atlas` package (public domain), inlined as GeoJSON: no tiles. The projection is the report's cylindrical
equidistant one (Leaflet's EPSG:4326 CRS).

The footprint is a dict as `footprint footprint` prints it or GET /api/footprints/{id} returns it: `points`
(the closed boundary, each with latitude_deg and longitude_deg; down-range, cross-range, flight time and
parameter shown on hover), `entry` (latitude_deg, longitude_deg, heading_deg) and, optionally, `ground_track`
and `name`. Longitudes are unwrapped about the entry so a footprint across +-180 deg is drawn whole; copies at
+-360 deg show the parts past the map's edge.

No user text (the name, a point's parameters) enters a script: folium's Tooltip writes its text into a JS template
literal, where `${...}` runs (issue 15 item 1). The labels sit in one JSON data block and are shown as text nodes,
so every inline script comes from our templates and numbers alone, and the page carries a Content-Security-Policy
that allows exactly those scripts by their sha256 hashes.
"""

import base64
import json
import os
import re
from html import escape
from pathlib import Path
from typing import Annotated

import numpy as np
from pydantic import BaseModel, Field, TypeAdapter

from footprint.contracts.fields import Range
from footprint.core.errors import InputError
from footprint.core.sphere import (
    MEAN_RADIUS_NMI,
    Reference,
    downrange_crossrange_nmi,
    great_circle,
    latlon_of,
    unit_vectors,
    unwrap_longitude,
)
from footprint.csp import inline_script_hashes, js_string, standalone_policy, with_policy_meta

FRONTEND_DIR = Path(__file__).resolve().parents[3] / "frontend"  # the page's folder in the repository
WORLD_COPIES_DEG = (-360.0, 0.0, 360.0)
GRATICULE_DEG = 30.0
TRACK_SAMPLE_DEG = 1.0  # the initial great circle's samples when the footprint carries no ground track
COLOR = "#1f6fbf"
LABELS_ID = "footprint-labels"
# footprintLabel(i): a new tooltip element showing label i of the JSON block as text (one element per layer:
# a DOM node has one parent); its newlines break lines, as Leaflet's tooltips do not wrap.
LABEL_JS = (
    "function footprintLabel(i) {\n"
    "  footprintLabel.all = footprintLabel.all || JSON.parse(document.getElementById(%s).textContent);\n"
    "  const div = document.createElement('div');\n"
    "  div.style.whiteSpace = 'pre';\n"
    "  div.textContent = footprintLabel.all[i];\n"
    "  return div;\n"
    "}" % js_string(LABELS_ID)
)


# ------------------------------------------------------------------------- the footprint file, checked
# What the map reads of a footprint (others' fields are ignored: a footprint file carries many more), each number
# finite and in range, so that a hand-edited file gets one line naming the field (pydantic's ValidationError).
MAX_RANGE_NMI = 250_000.0  # a flown down-range (contracts.transform's bound)


class _MapPlace(BaseModel):
    latitude_deg: Annotated[float, Range(-90, 90, "deg")]
    longitude_deg: Annotated[
        float, Range(-1080, 1080, "deg")
    ]  # an unwrapped ring's may pass +-180 (and the copies +-360)


class _MapEntry(_MapPlace):
    heading_deg: Annotated[float, Range(-360, 360, "deg")]


class _MapPoint(_MapPlace):
    downrange_nmi: Annotated[float, Range(-MAX_RANGE_NMI, MAX_RANGE_NMI, "nmi")] | None = None
    crossrange_nmi: Annotated[float, Range(-MAX_RANGE_NMI, MAX_RANGE_NMI, "nmi")] | None = None
    flight_time_s: Annotated[float, Range(0, 1e7, "s")] | None = None
    parameter: dict[str, float | str | None] | None = None  # the control setting, shown on hover
    mirrored: bool = False


class _MapFootprint(BaseModel):
    name: str | None = Field(default=None, max_length=1_000)
    vehicle: str | None = Field(default=None, max_length=1_000)
    method: str | None = Field(default=None, max_length=1_000)
    entry: _MapEntry
    points: list[_MapPoint]
    ground_track: list[_MapPlace] | None = None


_MAP_FOOTPRINT = TypeAdapter(_MapFootprint)


def map_footprint(footprint) -> dict:
    """The fields of a footprint the map draws, checked (InputError for a file that is not a footprint at all,
    pydantic's ValidationError naming a bad field)."""
    points = footprint.get("points") if isinstance(footprint, dict) else None
    if not isinstance(points, list) or len(points) < 3 or not footprint.get("entry"):
        raise InputError(
            "points",
            "a footprint needs 'entry' and at least 3 boundary 'points' "
            "(as `footprint footprint` prints it or GET /api/footprints/{id} returns it)",
        )
    return _MAP_FOOTPRINT.validate_python(footprint).model_dump(exclude_none=True)


def vendor_dir() -> Path:
    """frontend/vendor/, where `npm ci` copies Leaflet and the map data the page serves (the service's
    FOOTPRINT_FRONTEND_DIR when set, as in the Docker image)."""
    vendor = Path(os.environ.get("FOOTPRINT_FRONTEND_DIR") or FRONTEND_DIR) / "vendor"
    if not (vendor / "leaflet" / "leaflet.js").is_file():
        raise InputError("map", f"Leaflet is not installed in {vendor}: run `npm ci` in {vendor.parent}")
    return vendor


def leaflet_assets() -> tuple[str, str]:
    """Leaflet's JS, and its CSS with the images it names inlined as data URIs."""
    dist = vendor_dir() / "leaflet"
    css = (dist / "leaflet.css").read_text()

    def inline(match):
        image = dist / match.group(1)
        return f"url(data:image/png;base64,{base64.b64encode(image.read_bytes()).decode()})"

    css = re.sub(r"url\((images/[\w.-]+\.png)\)", inline, css)
    return (dist / "leaflet.js").read_text(), css


# ------------------------------------------------------------------------------------- TopoJSON, decoded
def _decode_arcs(topology: dict) -> list[np.ndarray]:
    """The topology's arcs as (n, 2) arrays of lon, lat (delta-decoded and de-quantized)."""
    scale, translate = np.array(topology["transform"]["scale"]), np.array(topology["transform"]["translate"])
    return [np.cumsum(np.array(arc, float), axis=0) * scale + translate for arc in topology["arcs"]]


def _ring(arcs: list[np.ndarray], indices: list[int]) -> list[list[float]]:
    """A ring for a flat map: longitudes made continuous (a ring across +-180 deg runs on past it; the copies at
    +-360 deg show the rest), and a ring that goes once round a pole (Antarctica) closed along that pole and then by
    its first point again."""
    parts = []
    for k, i in enumerate(indices):
        arc = arcs[i] if i >= 0 else arcs[~i][::-1]  # ~i: arc i reversed (TopoJSON spec)
        parts.append(arc[1:] if k else arc)
    coords = np.vstack(parts)
    coords[:, 0] = unwrap_longitude(coords[:, 0], coords[0, 0])
    if abs(coords[-1, 0] - coords[0, 0]) > 180.0:
        pole = -90.0 if coords[:, 1].mean() < 0 else 90.0
        coords = np.vstack([coords, [[coords[-1, 0], pole], [coords[0, 0], pole], coords[0]]])  # closed (RFC 7946)
    return np.round(coords, 3).tolist()


def topojson_features(topology: dict, name: str) -> dict:
    """One object of a TopoJSON topology as a GeoJSON FeatureCollection (Polygon and MultiPolygon only)."""
    arcs = _decode_arcs(topology)
    features = []
    for g in topology["objects"][name]["geometries"]:
        if g["type"] == "Polygon":
            geometry = {"type": "Polygon", "coordinates": [_ring(arcs, r) for r in g["arcs"]]}
        elif g["type"] == "MultiPolygon":
            geometry = {"type": "MultiPolygon", "coordinates": [[_ring(arcs, r) for r in p] for p in g["arcs"]]}
        else:
            continue
        features.append({"type": "Feature", "properties": g.get("properties", {}), "geometry": geometry})
    return {"type": "FeatureCollection", "features": features}


def countries_geojson() -> dict:
    """Natural Earth 1:110m countries (world-atlas, public domain)."""
    topology = json.loads((vendor_dir() / "world" / "countries-110m.json").read_text())
    return topojson_features(topology, "countries")


# ---------------------------------------------------------------------------------------------- geometry
def unwrap_ring(latitude_deg, longitude_deg, entry: dict) -> np.ndarray:
    """A footprint ring's longitudes made continuous and placed where its point nearest the entry lies within
    180 deg of the entry (its first point is often the far zero-bank point, 180 deg or more away)."""
    lon = unwrap_longitude(longitude_deg, float(longitude_deg[0]))
    nearest = int(
        np.argmax(
            unit_vectors(latitude_deg, longitude_deg) @ unit_vectors(entry["latitude_deg"], entry["longitude_deg"])
        )
    )
    return lon + 360.0 * np.round((entry["longitude_deg"] - lon[nearest]) / 360.0)


def _area(points: list[dict], entry: dict, first_lon_deg: float):
    """core.outline of the boundary (the chart's edges sampled; its area on the map's one copy), its line on the
    copy where the ring's first point is at first_lon_deg."""
    from footprint.core.outline import outline

    ref = Reference(entry["latitude_deg"], entry["longitude_deg"], entry["heading_deg"])
    if all(p.get("downrange_nmi") is not None and p.get("crossrange_nmi") is not None for p in points):
        down, cross = [p["downrange_nmi"] for p in points], [p["crossrange_nmi"] for p in points]
    else:  # a file without ranges: the chart's, continued round the ring (one branch of it is as good)
        down, cross = downrange_crossrange_nmi(
            [p["latitude_deg"] for p in points],
            [p["longitude_deg"] for p in points],
            ref.latitude_deg,
            ref.longitude_deg,
            ref.heading_deg,
            unwrap=True,
        )
    o = outline(down, cross, ref)
    shift = 360.0 * round((first_lon_deg - o.longitude_deg[0]) / 360.0)
    return o.shifted(shift)


def _initial_great_circle(entry: dict, downrange_deg: float) -> list[tuple[float, float]]:
    """The ground track of zero bank on a non-rotating sphere: the initial great circle from the entry."""
    ref = Reference(entry["latitude_deg"], entry["longitude_deg"], entry["heading_deg"])
    lat, lon = latlon_of(great_circle(ref, np.arange(0.0, downrange_deg + TRACK_SAMPLE_DEG, TRACK_SAMPLE_DEG)))
    return list(zip(np.atleast_1d(lat).tolist(), np.atleast_1d(lon).tolist()))


def _hover(point: dict) -> str:
    """A boundary point's label, plain text (shown as a text node)."""

    def num(key, unit, digits=0):
        v = point.get(key)
        return "–" if v is None else f"{v:,.{digits}f} {unit}"

    parameter = point.get("parameter") or {}
    control = (
        ", ".join(
            f"{k} {v:g}" if isinstance(v, (int, float)) else f"{k} {v}" for k, v in parameter.items() if v is not None
        )
        if isinstance(parameter, dict)
        else str(parameter)
    )
    return (
        f"down-range {num('downrange_nmi', 'nmi')}\ncross-range {num('crossrange_nmi', 'nmi')}\n"
        f"flight time {num('flight_time_s', 's')}\ncontrol {control or '–'}"
    )


class _Labels:
    """The map's tooltip texts: each layer's script names its label by index; the texts go into one JSON block."""

    def __init__(self):
        self.texts: list[str] = []

    def bind(self, layer, text: str, **options):
        from branca.element import MacroElement
        from jinja2 import Template

        self.texts.append(str(text))
        label = MacroElement()
        label._name, label.index, label.options = "Label", len(self.texts) - 1, {"sticky": True, **options}
        label._template = Template("""{% macro script(this, kwargs) %}
            {{ this._parent.get_name() }}.bindTooltip(footprintLabel({{ this.index }}), {{ this.options|tojson }});
        {% endmacro %}""")
        layer.add_child(label)
        return layer

    def block(self) -> str:
        """The JSON data block (not run: no CSP hash needed; <, >, & escaped so no text closes the element) and
        the script that reads it."""
        texts = "[" + ",".join(js_string(t) for t in self.texts) + "]"
        return f'<script type="application/json" id="{LABELS_ID}">{texts}</script>\n<script>{LABEL_JS}</script>'


def footprint_map(footprint: dict, title: str | None = None):
    """The folium Map of one footprint (see the module docstring for the input)."""
    import folium

    footprint = map_footprint(footprint)
    points, entry = footprint["points"], footprint["entry"]
    name = (
        title
        or footprint.get("name")
        or f"{footprint.get('vehicle', '')} {footprint.get('method', '')}".strip().replace("_", " ")
    )
    lat = np.array([p["latitude_deg"] for p in points], float)
    lon = unwrap_ring(lat, np.array([p["longitude_deg"] for p in points], float), entry)
    area = _area(points, entry, lon[0])
    if footprint.get("ground_track"):
        track = [(p["latitude_deg"], p["longitude_deg"]) for p in footprint["ground_track"]]
    else:
        far_deg = np.degrees(max((p.get("downrange_nmi") or 0.0) for p in points) / MEAN_RADIUS_NMI)
        track = _initial_great_circle(entry, max(far_deg, 1.0))
    track_lon = unwrap_longitude([t[1] for t in track], entry["longitude_deg"])

    labels = _Labels()
    m = folium.Map(
        location=[float(lat.mean()), float(lon.mean())],
        zoom_start=2,
        tiles=None,
        crs="EPSG4326",
        control_scale=False,
        prefer_canvas=False,
    )
    m.default_js, m.default_css = [], []  # no CDN: Leaflet goes inline below
    js, css = leaflet_assets()
    m.get_root().header.add_child(folium.Element(f"<style>{css}</style>\n<script>{js}</script>"), name="leaflet_inline")
    m.get_root().header.add_child(folium.Element("<style>.leaflet-container{background:#dce8f1}</style>"), name="ocean")

    world = countries_geojson()
    for offset in WORLD_COPIES_DEG:
        shifted = _shift(world, offset)
        folium.GeoJson(
            shifted,
            name="Natural Earth 1:110m" if offset == 0 else None,
            control=False,
            style_function=lambda _: {"fillColor": "#ece8dc", "fillOpacity": 1.0, "color": "#8a9aa8", "weight": 0.6},
        ).add_to(m)
    lines = [[(-90.0, x), (90.0, x)] for x in np.arange(-540.0, 540.1, GRATICULE_DEG)]
    lines += [[(y, -540.0), (y, 540.0)] for y in np.arange(-90.0, 90.1, GRATICULE_DEG)]
    folium.PolyLine(lines, color="#b9c6d2", weight=0.6).add_to(m)

    span = np.concatenate([area.longitude_deg, track_lon, [-180.0, 180.0]])  # the area lies on the one copy
    for offset in WORLD_COPIES_DEG:
        if span.max() + offset < -540 or span.min() + offset > 540:
            continue
        for piece in area.area:  # the footprint on this copy of the map (a pole's cap or a hole included)
            labels.bind(
                folium.Polygon(
                    [[(float(y), float(x) + offset) for x, y in ring] for ring in piece],
                    stroke=False,
                    fill=True,
                    fill_color=COLOR,
                    fill_opacity=0.22,
                    smooth_factor=0,
                    no_clip=True,
                ),
                name,
            ).add_to(m)
        edge_lat, edge_lon = np.append(area.latitude_deg, area.latitude_deg[0]), area.longitude_deg + offset
        folium.PolyLine(
            list(zip(edge_lat.tolist(), np.append(edge_lon, edge_lon[0]).tolist())),
            color=COLOR,
            weight=2,
            smooth_factor=0,
            no_clip=True,
        ).add_to(m)
        labels.bind(
            folium.PolyLine(
                [(t[0], float(x) + offset) for t, x in zip(track, track_lon)], color=COLOR, weight=1.5, dash_array="6 5"
            ),
            "ground track",
        ).add_to(m)
        labels.bind(
            folium.CircleMarker(
                [entry["latitude_deg"], entry["longitude_deg"] + offset],
                radius=6,
                color="#ffffff",
                weight=2,
                fill=True,
                fill_color=COLOR,
                fill_opacity=1.0,
            ),
            f"entry, heading {float(entry['heading_deg']):.1f} deg",
        ).add_to(m)
        for p, x in zip(points, lon):
            labels.bind(
                folium.CircleMarker(
                    [p["latitude_deg"], float(x) + offset],
                    radius=4,
                    color=COLOR,
                    weight=1.5,
                    fill=True,
                    fill_color="#ffffff" if p.get("mirrored") else COLOR,
                    fill_opacity=1.0,
                ),
                _hover(p),
            ).add_to(m)
    m.fit_bounds(
        [
            [float(area.latitude_deg.min()), float(area.longitude_deg.min())],
            [float(area.latitude_deg.max()), float(area.longitude_deg.max())],
        ],
        padding=(30, 30),
    )
    m.get_root().html.add_child(
        folium.Element(
            f'<div style="position:fixed;top:10px;left:54px;z-index:1000;background:rgba(255,255,255,.92);'
            f'padding:5px 9px;border-radius:4px;font:13px sans-serif;box-shadow:0 1px 4px rgba(0,0,0,.3)">'
            f"<b>{escape(name)}</b> · cylindrical equidistant · Natural Earth (public domain)</div>"
        )
    )
    m.get_root().header.add_child(folium.Element(labels.block()), name="labels")
    return m


def _shift(collection: dict, offset_deg: float) -> dict:
    if offset_deg == 0:
        return collection

    def move(c):
        return [move(x) for x in c] if isinstance(c[0], list) else [c[0] + offset_deg, c[1]]

    return {
        "type": "FeatureCollection",
        "features": [
            {**f, "geometry": {**f["geometry"], "coordinates": move(f["geometry"]["coordinates"])}}
            for f in collection["features"]
        ],
    }


def footprint_map_html(footprint: dict, title: str | None = None) -> str:
    """The standalone HTML of footprint_map: no script or stylesheet from the internet, and a <meta>
    Content-Security-Policy allowing only its own inline scripts (a file opened from disk has no headers; the
    service sends the same policy as a header, see map_policy)."""
    # the HTML parser turns CR LF into LF before the browser hashes a script: hash what it will see
    html = footprint_map(footprint, title).get_root().render().replace("\r\n", "\n")
    return with_policy_meta(html, standalone_policy(inline_script_hashes(html), header=False))


def map_policy(html: str) -> str:
    """The Content-Security-Policy header for footprint_map_html's page."""
    return standalone_policy(inline_script_hashes(html), header=True)


def write_footprint_map(footprint: dict, path, title: str | None = None) -> Path:
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(footprint_map_html(footprint, title))
    return path
