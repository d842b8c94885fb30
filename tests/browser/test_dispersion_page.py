"""A dispersion job on the map page (issue 16), in Debian's chromium against the real service: submitted from the
job form with the stored landing sites, followed to 100 %, and drawn: the nominal boundary, the confidence
footprints, the 3-sigma ellipses, the landing points and the sites' probabilities, across the antimeridian."""

import csv
import io
import json
import time
from collections import Counter
from pathlib import Path

import numpy as np
import pytest

from footprint.core.outline import outline
from footprint.core.sphere import Reference, downrange_crossrange_nmi
from tests.authorities.report import example, table2_entry, table2_stop

from .conftest import (
    FIGURES_DIR,
    JOB_TIMEOUT_S,
    PNG_CROP_JS,
    PNG_PIXEL_RATIO,
    WAIT_MS,
    close,
    download,
    over,
    pixels_like,
    png_export,
)

ROOT = Path(__file__).resolve().parents[2]
FIGURES = FIGURES_DIR  # docs/figures only with FOOTPRINT_WRITE_FIGURES=1, else a temporary folder
SAMPLES = 128  # x 8 flights (4 banks mirrored and the shortest flight) = 1,024 trajectories, a few seconds
LEVELS = (0.5, 0.9)
MEAN_SHIFT_DEG = 5.0  # an ellipse's middle from its flight's nominal landing point: the mean's shift is < 1 deg here
PIXEL_DEG = 2.0  # a path's box read back through Leaflet's pixels at a whole-world zoom: 1 px < 0.5 deg
# entered at 0 N 0 E heading east (Table 2), the L/D 1.89 footprint runs past 180 E to about 112 W
HOSTILE_SITE = 'Nadi <img src=x onerror=alert(1)> & "Fiji" ${1}'
HOSTILE_JOB = "lod-1.89 dispersed <b>east</b> & </script>"
SITES = (
    ("Diego Garcia", -7.313, 72.411),
    ("Andersen AFB, Guam", 13.584, 144.93),
    ("Kwajalein", 8.72, 167.732),
    (HOSTILE_SITE, -17.755, 177.443),
    ("Pago Pago", -14.331, -170.711),
    ("Honolulu", 21.319, -157.922),
    ("Christchurch", -43.489, 172.532),
    ("Kennedy SLF", 28.615, -80.695),
)

# the study the job form builds from its defaults and the first test's inputs (Table 2's entry: 0 N 0 E heading east)
NORMAL = {
    "altitude_ft": 1000,
    "velocity_fps": 15,
    "gamma_deg": 0.05,
    "heading_deg": 0.05,
    "latitude_deg": 0.02,
    "longitude_deg": 0.02,
}
DISPERSION_STUDY = {
    "footprint": {
        "case": {
            "vehicle": {"builtin": "lod-1.89"},
            "planet": {"rotating": True},
            "entry": table2_entry(),
            "alpha": {"law": "max_ld"},
            "bank_start": "pullout",
            "stop": table2_stop(),
        },
        "method": "single_parameter",
        "mirror": True,
        "bank0_deg": [0, 45, 90, 135],
    },
    "samples": SAMPLES,
    "design": "sobol",
    "seed": 1,
    "entry": {k: {"normal": {"std": std}} for k, std in NORMAL.items()},
    "vehicle": {
        "cl_multiplier": {"truncated_normal": {"std": 0.03, "sigmas": 3}},
        "cd_multiplier": {"truncated_normal": {"std": 0.03, "sigmas": 3}},
        "wing_loading_psf": {"normal": {"std": 1}},
    },
    "density": {"std": 0.05, "correlation_length_ft": 30000},
    "confidence": list(LEVELS),
    "sites": [{"name": n, "latitude_deg": la, "longitude_deg": lo} for n, la, lo in SITES],
}

# the view from 30 W to 300 E (braced: fitBounds returns the map, which Playwright would serialize for tens of seconds)
FIT_ACROSS_180_JS = "() => { window.footprintApp.mapView.map.fitBounds([[-60, -30], [60, 300]], {animate: false}); }"
BBOX_JS = """(el) => { const b = el.getBBox(), map = window.footprintApp.mapView.map;
  const sw = map.layerPointToLatLng([b.x, b.y + b.height]), ne = map.layerPointToLatLng([b.x + b.width, b.y]);
  return {west: sw.lng, east: ne.lng, south: sw.lat, north: ne.lat}; }"""
CLOUD_ALPHA_JS = """() => { const c = document.querySelector('.leaflet-clouds-pane canvas');
  if (!c) return 0; const d = c.getContext('2d').getImageData(0, 0, c.width, c.height).data;
  let n = 0; for (let i = 3; i < d.length; i += 4) if (d[i]) n++; return n; }"""


def percent(p):
    """As the page words a probability (dispersion.js percent)."""
    return f"{100 * p:,.0f} %" if p in (0, 1) else f"{100 * p:,.1f} %"


def level_words(p):
    """As the page words a confidence level (dispersion.js levelWords): "99 %", "99.5 %"."""
    return f"{round(100 * p, 1):g} %"


def interval(low_high):
    low, high = low_high
    return f"{100 * low:,.1f}–{100 * high:,.1f} %"


@pytest.fixture(scope="module")
def stored_sites(service):
    for name, lat, lon in SITES:
        service.call("/api/sites", {"name": name, "latitude_deg": lat, "longitude_deg": lon})
    return service.call("/api/sites")


def test_a_dispersion_job_is_drawn_across_the_antimeridian_with_its_site_probabilities(
    open_page, service, stored_sites
):
    t0 = time.monotonic()
    run = open_page(1280, 800)
    page, dialogs = run.page, []
    page.on("dialog", lambda d: (dialogs.append(d.message), d.dismiss()))
    page.fill("#job-name", HOSTILE_JOB)
    page.fill("#entry-heading", "90")
    page.fill("#entry-latitude", "0")
    page.fill("#entry-longitude", "0")
    page.fill("#p-bank0", "0, 45, 90, 135")
    page.check("#disperse-toggle")
    assert page.locator("#dispersion-fields").is_visible() and not page.locator("#optimize-fields").is_visible()
    assert page.locator("#job-method option[value=collocation]").is_disabled()  # a dispersion flies fixed laws
    assert page.locator("#job-submit").inner_text() == "Run dispersion"
    page.fill("#d-samples", str(SAMPLES))
    page.fill("#d-confidence", ", ".join(f"{p:g}" for p in LEVELS))
    page.click("#job-submit")
    item = page.locator("#job-list li").first
    # the status, not the percent: the last report's 100 % comes before the result is stored (a loaded machine
    # showed "running" at 100 %)
    item.locator(".job-status", has_text="succeeded").wait_for(timeout=JOB_TIMEOUT_S * 1000)
    assert item.locator(".job-percent").inner_text() == "100 %"
    assert HOSTILE_JOB in item.locator(".job-label").inner_text()  # the job's name is text
    job = service.call(f"/api/jobs/{item.get_attribute('data-job-id')}")
    d = job["result"]["dispersion"]
    assert job["study"] == DISPERSION_STUDY  # the form's study, with the stored sites
    page.locator("path.dispersion-nominal.disp-copy-0").wait_for(state="attached", timeout=WAIT_MS)
    page.evaluate(FIT_ACROSS_180_JS)
    page.wait_for_timeout(300)

    # the nominal boundary and each confidence level, on the main copy, run past 180 E
    nominal = page.locator("path.dispersion-nominal.disp-copy-0")
    assert nominal.count() == 1
    box = nominal.evaluate(BBOX_JS)
    far = max(lon % 360 for lon in d["nominal_boundary"]["longitude_deg"])
    assert box["east"] > 180 and abs(box["east"] - far) < PIXEL_DEG, (box, far)
    assert box["west"] > -PIXEL_DEG  # one area from the entry eastward: no piece folded back to 180 W
    for c in d["confidence"]:
        ring = page.locator(f"path.dispersion-confidence.level-{round(c['level'] * 1000)}.disp-copy-0")
        assert ring.count() == len(c["rings"]) >= 1
        # every vertex kept: the SVG path has as many as the ring (its closing one included)
        assert ring.first.get_attribute("d").count("L") + 1 == len(c["rings"][0]["latitude_deg"])
        ring_box = ring.first.evaluate(BBOX_JS)
        assert ring_box["east"] > 180 and ring_box["west"] > box["west"] - PIXEL_DEG
    labels = page.locator(".confidence-label").all_inner_texts()
    assert all(any(t == level_words(c["level"]) for t in labels) for c in d["confidence"]), labels

    # one 3-sigma ellipse per flight that landed twice or more, each beside its own nominal landing point on the
    # boundary's copy (the far one east of 180, not on the copy 360 deg west)
    drawn = [f for f in d["flights"] if f.get("ellipses")]
    ellipses = page.locator("path.dispersion-ellipse.disp-copy-0")
    assert ellipses.count() == len(drawn) == len(d["flights"])
    boxes = [e.evaluate(BBOX_JS) for e in ellipses.all()]
    for b, nominal_point in zip(boxes, d["nominal"]):
        # entered at 0 E heading east, the whole footprint lies in 0..360 E on the main copy
        assert abs((b["west"] + b["east"]) / 2 - nominal_point["longitude_deg"] % 360) < MEAN_SHIFT_DEG, (
            b,
            nominal_point,
        )
    zero_bank = boxes[0]  # flights[0]: bank 0, on the axis, the far end of the footprint (3 sigma: ~45 deg long)
    assert 180 < zero_bank["west"] < far < zero_bank["east"], (zero_bank, far)

    # the landing points: one canvas layer, every landed cloud point on each copy, shown and hidden by its toggle
    landed_points = sum(x is not None for row in d["clouds"]["latitude_deg"] for x in row)
    count = page.evaluate("""() => { const g = window.footprintApp.mapView.dispersion.groups.clouds;
        return g.getLayers()[0].count() / window.footprintApp.state.dispersion.placed.offsets.length; }""")
    assert count == landed_points == SAMPLES * len(d["flights"])
    assert page.evaluate(CLOUD_ALPHA_JS) > 200  # dots drawn
    page.uncheck("#dispersion-layers input[data-layer=clouds]")
    page.wait_for_timeout(100)
    assert page.evaluate(CLOUD_ALPHA_JS) == 0
    page.check("#dispersion-layers input[data-layer=clouds]")
    page.wait_for_timeout(100)
    assert page.evaluate(CLOUD_ALPHA_JS) > 200

    # the site table: every site with its probability, its 95 % interval and the nominal verdict; names as text
    rows = page.locator("#dispersion-sites table tbody tr")
    assert rows.count() == len(SITES)
    table = {r.locator("td.site-name").inner_text(): r.locator("td").all_inner_texts() for r in rows.all()}
    for s in d["sites"]:
        assert table[s["name"]][1:] == [
            percent(s["probability"]),
            interval(s["interval"]),
            "inside" if s["inside_nominal"] else "outside",
        ], (s, table[s["name"]])
    assert HOSTILE_SITE in table
    by_name = {s["name"]: s for s in d["sites"]}
    assert by_name[HOSTILE_SITE]["probability"] > 0.5 and by_name["Kennedy SLF"]["probability"] == 0
    assert "95 % interval" in page.locator("#dispersion-sites thead").inner_text()
    # on the map: a marker per site (and copy), its name and probability in one label beside it (as text)
    assert page.locator("path.dispersion-site").count() == 3 * len(SITES)
    assert (
        f"{HOSTILE_SITE} · {percent(by_name[HOSTILE_SITE]['probability'])}"
        in page.locator(".site-label-p").all_inner_texts()
    )
    # every outcome counted
    outcomes = page.locator("#dispersion-outcomes").inner_text()
    assert f"{d['outcomes']['landed']:,} of {d['outcomes']['flights']:,} flights landed" in outcomes
    assert all(what in outcomes for what in d["outcomes"] if what not in ("flights", "landed"))
    # no name became markup anywhere: no <img>, no <b> from a name, no dialog, no CSP violation
    assert (
        page.locator(
            "#dispersion-sites img, .leaflet-pane img.leaflet-marker-icon[src=x], .map-legend img, "
            "#job-list b, .map-legend b, #dispersion-panel b"
        ).count()
        == 0
    )
    assert HOSTILE_JOB in page.locator(".footprint-legend").inner_text()
    assert HOSTILE_JOB in page.locator("#dispersion-sites caption").inner_text()
    # the dispersion in the report's axes
    assert page.locator("#plot svg.dispersion-plot path.dispersion-ellipse").count() == len(drawn)
    assert page.locator("#plot svg.dispersion-plot path.dispersion-confidence").count() == sum(
        len(c["rings"]) for c in d["confidence"]
    )

    assert not any(word in page.locator("#dispersion-panel").inner_text() for word in ("null", "undefined", "NaN"))
    # per flight: landed, other outcomes, mean and spread, in a dialog
    page.click("#dispersion-flights")
    assert page.locator("#dispersion-dialog table tbody tr").count() == len(d["flights"])
    page.click("#dispersion-dialog-close")
    # the globe has it too (d3-geo on the sphere), its sites with their probability
    page.evaluate("() => window.footprintApp.setView('globe')")
    assert page.locator("path.globe-dispersion-confidence").count() == sum(len(c["rings"]) for c in d["confidence"])
    assert page.locator("path.globe-dispersion-ellipse").count() == len(drawn)
    page.evaluate("() => window.footprintApp.setView('map')")
    # the stored sites say their probability too
    stored_row = page.locator("#site-list li", has_text="Kwajalein")
    assert (
        stored_row.locator(".dispersion-p")
        .inner_text()
        .startswith(f"P {percent(by_name['Kwajalein']['probability'])} (")
    )

    FIGURES.mkdir(parents=True, exist_ok=True)
    page.evaluate("""async () => { const app = window.footprintApp;
        for (const fp of app.state.footprints.values()) if (fp.visible) await app.setVisible(fp, false);
        document.getElementById('job-panel').open = false; app.mapView.fitDispersion(); }""")
    page.evaluate("() => document.getElementById('dispersion-panel').scrollIntoView()")
    page.wait_for_timeout(400)
    page.screenshot(path=str(FIGURES / "map_dispersion.png"))
    page.wait_for_timeout(200)
    assert dialogs == [] and not run.errors and run.violations() == [], (dialogs, run.errors, run.violations())
    print(f"dispersion page test: {time.monotonic() - t0:.1f} s")


def test_an_earlier_dispersion_is_shown_again_after_a_reload(open_page, service, stored_sites):
    """The page keeps no dispersion itself: the panel lists the service's succeeded dispersion jobs and shows one."""
    jobs = service.call("/api/jobs?kind=dispersion&status=succeeded")["items"]
    if not jobs:
        pytest.skip("needs the dispersion job of the test before")
    run = open_page(1280, 800)
    page = run.page
    assert page.locator(f"#dispersion-jobs option[value='{jobs[0]['id']}']").count() == 1
    page.select_option("#dispersion-jobs", jobs[0]["id"])
    page.click("#dispersion-show")
    page.locator("path.dispersion-nominal.disp-copy-0").wait_for(state="attached", timeout=WAIT_MS)
    assert page.locator("#dispersion-sites table tbody tr").count() == len(SITES)
    assert not run.errors and run.violations() == []


@pytest.fixture(scope="module")
def dispersion_job(service, stored_sites):
    """A succeeded dispersion job of DISPERSION_STUDY: the first test's (submitted from the form) when it ran, else
    the same study submitted here."""
    for item in service.call("/api/jobs?kind=dispersion&status=succeeded")["items"]:
        job = service.call(f"/api/jobs/{item['id']}")
        if job["study"] == DISPERSION_STUDY:
            return job
    return service.run_job({"kind": "dispersion", "name": HOSTILE_JOB, "study": DISPERSION_STUDY})


LAYERS = ("nominal", "confidence", "ellipses", "clouds", "sites")  # the panel's toggles (dispersion.js LAYERS)


def show_dispersion(page, job, *, footprints=True):
    """The job shown again from the panel's list, the stored footprints left on or taken off the map."""
    if not footprints:
        page.evaluate("""async () => { const app = window.footprintApp;
            for (const fp of app.state.footprints.values()) if (fp.visible) await app.setVisible(fp, false); }""")
    page.select_option("#dispersion-jobs", job["id"])
    page.click("#dispersion-show")
    page.locator("path.dispersion-nominal.disp-copy-0").wait_for(state="attached", timeout=WAIT_MS)


def set_layers(page, *shown):
    """The panel's toggles: the given layers on, the others off."""
    for layer in LAYERS:
        page.set_checked(f"#dispersion-layers input[data-layer={layer}]", layer in shown)


def test_the_panel_downloads_the_shown_dispersion_as_geojson_and_a_sites_csv(open_page, dispersion_job):
    """The Dispersion panel's two buttons save GET /api/jobs/{id}/dispersion as files named after the job: the GeoJSON
    holds every shape of the job's result and each site with its probability, the CSV a row per site."""
    run = open_page()
    page, d = run.page, dispersion_job["result"]["dispersion"]
    assert page.locator("#dispersion-downloads").is_hidden()  # nothing shown, nothing to download
    show_dispersion(page, dispersion_job)
    stem = "dispersion-lod-1.89-dispersed-b-east-b-script"  # HOSTILE_JOB in letters a file system takes
    name, body = download(page, "#dispersion-geojson")
    assert name == f"{stem}.geojson"
    collection = json.loads(body)
    kinds = Counter(f["properties"]["kind"] for f in collection["features"])
    assert kinds == {
        "nominal_footprint": 1,
        "entry": 1,
        "site": len(SITES),
        "confidence_footprint": sum(len(c["rings"]) for c in d["confidence"]),
        "ellipse": sum(len(f["ellipses"]) for f in d["flights"]),
    }, kinds
    probabilities = {s["name"]: s["probability"] for s in d["sites"]}
    sites = [f["properties"] for f in collection["features"] if f["properties"]["kind"] == "site"]
    assert {p["name"]: p["probability"] for p in sites} == probabilities
    name, body = download(page, "#dispersion-csv")
    assert name == f"{stem}-sites.csv"
    rows = list(csv.DictReader(io.StringIO(body.decode())))
    assert {r["name"]: float(r["probability"]) for r in rows} == probabilities
    assert len(rows) == len(SITES) and HOSTILE_SITE in {r["name"] for r in rows}
    assert not run.errors and run.violations() == []


def test_the_header_geojson_holds_the_dispersion_layers_that_are_shown(open_page, dispersion_job):
    """The header's GeoJSON: the shown footprints and sites, and beside them the shown dispersion's features (each
    naming its job) of the layers that are on; the ellipses as drawn, 3 sigma."""
    run = open_page()
    page, d = run.page, dispersion_job["result"]["dispersion"]
    show_dispersion(page, dispersion_job)

    def exported():
        features = json.loads(download(page, "#export-geojson")[1])["features"]
        ours = [f["properties"] for f in features if "dispersion_job_id" in f["properties"]]
        assert {(p["dispersion_job_id"], p["dispersion_name"]) for p in ours} <= {(dispersion_job["id"], HOSTILE_JOB)}
        assert any(f["properties"]["kind"] == "footprint" for f in features)  # the stored footprints stay
        return Counter(p["kind"] for p in ours), ours

    kinds, ours = exported()
    assert kinds == {
        "nominal_footprint": 1,
        "entry": 1,
        "site": len(SITES),
        "confidence_footprint": sum(len(c["rings"]) for c in d["confidence"]),
        "ellipse": sum("3" in f["ellipses"] for f in d["flights"]),
    }, kinds
    assert {p["sigma"] for p in ours if p["kind"] == "ellipse"} == {3}
    sites = {p["name"]: p["probability"] for p in ours if p["kind"] == "site"}
    assert sites == {s["name"]: s["probability"] for s in d["sites"]}
    set_layers(page, "nominal", "ellipses", "clouds")
    assert set(exported()[0]) == {"nominal_footprint", "entry", "ellipse"}
    set_layers(page)
    assert exported()[0] == {}
    assert not run.errors and run.violations() == []


ABOVE_SITE_PX = 9  # a probe over a site: past the stored site's disc (5 px), above the labels beside it, inside
# the dispersion's ring round it (11 px)
CONFIDENCE_RGB = (0x6A, 0x3D, 0x9A)  # dispersion.js DISPERSION_STYLE.confidence
ELLIPSE_RGB = (0xD9, 0x5F, 0x02)
SITE_RGB = {1: (8, 81, 156), 0: (217, 217, 217)}  # dispersion.js probabilityColor at P 1 and 0: grey to blue


def png_probes(page, places, view):
    """Where each (lat, lon) lands in the PNG, ABOVE_SITE_PX over it: the map's (Leaflet's) or the globe's point."""
    js = """([places, view, above]) => { const app = window.footprintApp;
      const xy = view === "globe" ? ((lat, lon) => app.globe.projection()([lon, lat]))
        : ((lat, lon) => { const p = app.mapView.map.latLngToContainerPoint([lat, lon]); return [p.x, p.y]; });
      return places.map(([lat, lon]) => { const [x, y] = xy(lat, lon); return [x, y - above]; }); }"""
    points = page.evaluate(js, [places, view, ABOVE_SITE_PX])
    crop = page.evaluate(PNG_CROP_JS) if view == "map" else {"x": 0, "y": 0}  # the map's PNG is the world's part
    return [(round((x - crop["x"]) * PNG_PIXEL_RATIO), round((y - crop["y"]) * PNG_PIXEL_RATIO)) for x, y in points]


def test_the_png_export_draws_the_dispersion_as_the_map_and_the_globe_show_it(open_page, dispersion_job):
    """The PNG of the cylindrical map has the dispersion where the map has it, past 180 E on the boundary's copy: the
    sites' probability discs, the confidence footprints' fill under a site every sample reaches (and under one past
    180 E), none under a site no sample reaches, the ellipses' colour; each layer toggled off leaves the PNG. The
    globe's PNG fills the confidence footprints on the sphere too."""
    run = open_page(1280, 800)
    page, d = run.page, dispersion_job["result"]["dispersion"]
    show_dispersion(page, dispersion_job, footprints=False)
    page.evaluate(FIT_ACROSS_180_JS)
    page.wait_for_timeout(300)
    by_name = {s["name"]: s for s in d["sites"]}
    certain, far = by_name["Diego Garcia"], by_name["Pago Pago"]  # every sample reaches one; the other lies past 180 E
    never = [by_name["Kennedy SLF"], by_name["Christchurch"]]
    assert certain["probability"] == 1 and far["probability"] > max(LEVELS)
    assert all(s["probability"] == 0 for s in never)
    places = [(s["latitude_deg"], s["longitude_deg"] % 360) for s in (certain, far, *never)]  # the view: 0..360 E
    probes = png_probes(page, places, "map")

    shown = png_export(page)
    shown.save(FIGURES / "export_dispersion.png")
    set_layers(page, "nominal", "confidence", "ellipses", "clouds")
    unmarked = png_export(page)
    set_layers(page)
    bare = png_export(page)
    crop = page.evaluate(PNG_CROP_JS)  # the world within the view (issue 25 item 5), not the bands past the poles
    assert shown.width == round(crop["w"] * PNG_PIXEL_RATIO)  # and the caption under the map's part
    assert round(crop["h"] * PNG_PIXEL_RATIO) < shown.height < round((crop["h"] + 120) * PNG_PIXEL_RATIO)

    # the sites' discs, coloured by their probability
    for xy, s in zip(probes[:1] + probes[2:], (certain, *never)):
        assert close(shown.getpixel(xy), SITE_RGB[s["probability"]]), (s["name"], xy, shown.getpixel(xy))
    # without them: the two confidence levels over the basemap by the certain site and the one past 180 E, the
    # basemap alone by the sites no sample reaches
    alphas = [0.1, 0.1 + 0.14]  # dispersion.js confidenceOpacity(0), (1)
    for xy in probes[:2]:
        assert close(unmarked.getpixel(xy), over(bare.getpixel(xy), CONFIDENCE_RGB, alphas)), unmarked.getpixel(xy)
    for xy in probes[2:]:
        assert close(unmarked.getpixel(xy), bare.getpixel(xy)), (xy, unmarked.getpixel(xy), bare.getpixel(xy))
    assert pixels_like(shown, ELLIPSE_RGB) > 500 and pixels_like(bare, ELLIPSE_RGB) == 0
    # the globe, turned to the dispersion, fills its confidence footprints on the sphere
    set_layers(page, "confidence")
    page.evaluate("() => window.footprintApp.setView('globe')")
    probes = png_probes(page, places[:1] + places[3:], "globe")  # Christchurch: on this side of the globe
    filled = png_export(page)
    set_layers(page)
    bare = png_export(page)
    inside, outside = probes
    assert close(filled.getpixel(inside), over(bare.getpixel(inside), CONFIDENCE_RGB, alphas)), filled.getpixel(inside)
    assert close(filled.getpixel(outside), bare.getpixel(outside))
    assert not run.errors and run.violations() == []


PLACEMENT_JS = """async (capOutline) => {
  const { placeDispersion } = await import("/js/dispersion.js");
  const lists = (pts) => ({ latitude_deg: pts.map((p) => p[1]), longitude_deg: pts.map((p) => p[0]) });
  const wrap = (lon) => ((lon + 540) % 360) - 180;
  // a boundary from 10 E to 250 E (110 W) about the equator, entered at 0 N 0 E heading east
  const east = [], west = [];
  for (let lon = 10; lon <= 250; lon += 20) { east.push([wrap(lon), 10]); west.unshift([wrap(lon), -10]); }
  const boundary = [...east, ...west];
  const ellipse = []; // round the far end, 250 E, across nothing but drawn as lists of wrapped longitudes
  for (let k = 0; k <= 36; k++) ellipse.push([wrap(250 + 8 * Math.cos(k * Math.PI / 18)), 2 * Math.sin(k * Math.PI / 18)]);
  const cap = []; // a ring round the north pole at 70 N
  for (let lon = 0; lon <= 360; lon += 10) cap.push([wrap(lon), 70]);
  const d = { samples: 1, entry: { latitude_deg: 0, longitude_deg: 0, heading_deg: 90 }, outcomes: { flights: 1, landed: 1 },
              nominal: [{ parameter: { bank0_deg: 0 }, side: "axis", latitude_deg: 0, longitude_deg: wrap(250) }],
              nominal_boundary: lists(boundary),
              flights: [{ parameter: { bank0_deg: 0 }, side: "axis", landed: 1, outcomes: {}, ellipses: { 3: lists(ellipse) } }],
              confidence: [{ level: 0.9, rings: [{ ...lists(boundary), area_nmi2: 1 }, { ...lists(cap), area_nmi2: 1 },
                                                { ...lists(cap), area_nmi2: 1, outline: capOutline }] }],
              sites: [], clouds: { latitude_deg: [[1, -1]], longitude_deg: [[wrap(251), wrap(249)]] } };
  const p = placeDispersion(d), lons = (shape) => shape.line.map(([lon]) => lon);
  return { nominal: [Math.min(...lons(p.nominal)), Math.max(...lons(p.nominal))],
           ellipse: [Math.min(...lons(p.ellipses[0])), Math.max(...lons(p.ellipses[0]))],
           clouds: Array.from(p.clouds.longitude_deg), ring: p.confidence[0].rings[0].area !== null,
           cap: { area: p.confidence[0].rings[1].area, holdsPole: p.confidence[0].rings[1].holdsPole }, holdsPole: p.holdsPole,
           outlined: p.confidence[0].rings[2].area };
}"""


def test_every_shape_lies_on_the_boundary_copy_and_a_ring_round_a_pole_is_filled_only_by_its_outline(open_page):
    """dispersion.placeDispersion on a made-up result: the far end of a footprint past 180 E keeps its ellipse and
    landing points beside it (250 E, not 110 W); a ring round the pole with no outline from the service (core.outline)
    is drawn as its edge, never filled across the map; with one, it is filled to the pole."""
    run = open_page()
    cap_lons = np.arange(0.0, 360.0, 10.0)  # the made-up ring round the pole at 70 N, outlined as the service does
    down, cross = downrange_crossrange_nmi(np.full_like(cap_lons, 70.0), cap_lons, 0.0, 0.0, 0.0)  # flown north
    placed = run.page.evaluate(PLACEMENT_JS, outline(down, cross, Reference(0.0, 0.0, 0.0)).to_dict())
    assert placed["nominal"] == pytest.approx([10, 250])
    assert placed["ellipse"] == pytest.approx([242, 258])
    assert placed["clouds"] == pytest.approx([251, 249])
    assert placed["ring"] and placed["cap"] == {"area": None, "holdsPole": True} and placed["holdsPole"]
    # with its outline the same ring is filled up to the pole (its area: polygons of [lon, lat] rings)
    lons, lats = np.array([xy for polygon in placed["outlined"] for ring in polygon for xy in ring]).T
    assert lats.max() == 90.0 and lats.min() == pytest.approx(70.0, abs=0.01)
    assert lons.max() - lons.min() == pytest.approx(360.0, abs=0.1)
    assert not run.errors


@pytest.mark.parametrize(
    "field, value, words",
    [("#d-samples", "0", "Samples: "), ("#entry-velocity", "50", "Velocity, earth-relative (ft/s): ")],
)
def test_a_refused_dispersion_names_its_field(open_page, field, value, words):
    """A 422 of a dispersion study shows next to the input that holds the field: its own (samples) or one of its
    footprint study's ("study.footprint.case.entry.velocity_fps", the form's case input); no job is queued."""
    run = open_page()
    page = run.page
    page.check("#disperse-toggle")
    page.fill(field, value)
    page.click("#job-submit")
    note = page.locator(f"{field} + .field-error")
    note.wait_for(timeout=WAIT_MS)
    assert note.inner_text().startswith(words) and value in note.inner_text(), note.inner_text()
    assert page.locator(".field-error:visible").count() == 1 and page.locator("#job-list li").count() == 0


POLAR_SITES = (("Svalbard", 78.25, 15.5), ("Thule", 76.53, -68.7), ("Hobart", -42.8, 147.5))


def test_a_dispersion_over_the_pole_is_filled_to_the_pole(open_page, service, stored_sites):  # sites: one figure
    """Entered at 60 N heading north, the L/D 1.89 footprint reaches round the north pole and down the far side to
    10 N: each confidence footprint is drawn as a polar cap (its area up to 90 N across all 360 deg of longitude),
    on the map, on the globe and in the PNG; Svalbard, past the pole from nowhere, is reached in every sample."""
    fp = example("footprint_lod189") | {"bank0_deg": [0, 30, 60, 90, 120]}
    fp["case"]["entry"] |= {"latitude_deg": 60.0, "longitude_deg": -30.0, "heading_deg": 0.0}
    study = {
        "footprint": fp,
        "samples": 64,
        "seed": 2,
        "entry": {"gamma_deg": {"normal": {"std": 0.05}}},
        "confidence": [0.5, 0.9],
        "sites": [{"name": n, "latitude_deg": la, "longitude_deg": lo} for n, la, lo in POLAR_SITES],
    }
    job = service.run_job({"kind": "dispersion", "name": "lod-1.89 north from 60 N", "study": study})
    assert job["status"] == "succeeded", job
    result = job["result"]["dispersion"]
    assert {s["name"]: s["probability"] for s in result["sites"]} == {"Svalbard": 1.0, "Thule": 0.0, "Hobart": 0.0}
    run = open_page(1280, 800)
    page = run.page
    page.evaluate("""async () => { const app = window.footprintApp;
        for (const fp of app.state.footprints.values()) if (fp.visible) await app.setVisible(fp, false); }""")
    show_dispersion(page, job)
    page.evaluate("""() => { document.getElementById('job-panel').open = false; window.footprintApp.mapView.fitDispersion();
        document.getElementById('dispersion-panel').scrollIntoView(); }""")
    page.wait_for_timeout(400)
    for level in result["confidence"]:
        area = page.locator("path.dispersion-confidence-area.disp-copy-0").nth(result["confidence"].index(level))
        box = area.evaluate(BBOX_JS)
        assert box["north"] > 89.0 and box["east"] - box["west"] > 359.0, box  # a cap, not a band across the map
    assert "goes round a pole" not in page.inner_text("#dispersion-outcomes")  # the outline closes it
    page.screenshot(path=str(FIGURES / "map_dispersion_polar.png"))
    page.click("#view-globe")
    page.evaluate("() => window.footprintApp.globe.center(-30, 80)")
    page.wait_for_timeout(400)
    page.screenshot(path=str(FIGURES / "globe_dispersion_polar.png"))
    assert not run.errors and run.violations() == []
