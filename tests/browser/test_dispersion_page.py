"""A dispersion job on the map page (issue 16), in Debian's chromium against the real service: submitted from the
job form with the stored landing sites, followed to 100 %, and drawn: the nominal boundary, the confidence
footprints, the 3-sigma ellipses, the landing points and the sites' probabilities, across the antimeridian."""

import time
from pathlib import Path

import numpy as np
import pytest
from footprint.core.outline import outline
from footprint.core.sphere import Reference, downrange_crossrange_nmi

from .conftest import JOB_TIMEOUT_S

ROOT = Path(__file__).resolve().parents[2]
FIGURES = ROOT / "docs" / "figures"
SAMPLES = 128  # x 8 flights (4 banks mirrored and the shortest flight) = 1,024 trajectories, a few seconds
LEVELS = (0.5, 0.9)
MEAN_SHIFT_DEG = 5.0  # an ellipse's middle from its flight's nominal landing point: the mean's shift is < 1 deg here
PIXEL_DEG = 2.0  # a path's box read back through Leaflet's pixels at a whole-world zoom: 1 px < 0.5 deg
# entered at 0 N 0 E heading east (Table 2), the L/D 1.89 footprint runs past 180 E to about 112 W
HOSTILE_SITE = "Nadi <img src=x onerror=alert(1)> & \"Fiji\" ${1}"
HOSTILE_JOB = "lod-1.89 dispersed <b>east</b> & </script>"
SITES = (("Diego Garcia", -7.313, 72.411), ("Andersen AFB, Guam", 13.584, 144.93), ("Kwajalein", 8.72, 167.732),
         (HOSTILE_SITE, -17.755, 177.443), ("Pago Pago", -14.331, -170.711), ("Honolulu", 21.319, -157.922),
         ("Christchurch", -43.489, 172.532), ("Kennedy SLF", 28.615, -80.695))

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


def test_a_dispersion_job_is_drawn_across_the_antimeridian_with_its_site_probabilities(open_page, service, stored_sites):
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
    item.locator(".job-percent", has_text="100 %").wait_for(timeout=JOB_TIMEOUT_S * 1000)
    assert item.locator(".job-status").inner_text() == "succeeded"
    assert HOSTILE_JOB in item.locator(".job-label").inner_text()  # the job's name is text
    job = service.call(f"/api/jobs/{item.get_attribute('data-job-id')}")
    d = job["result"]["dispersion"]
    assert job["study"]["sites"] == [{"name": n, "latitude_deg": la, "longitude_deg": lo} for n, la, lo in SITES]
    page.locator("path.dispersion-nominal.disp-copy-0").wait_for(state="attached", timeout=10_000)
    page.evaluate("() => window.footprintApp.mapView.map.fitBounds([[-60, -30], [60, 300]], {animate: false})")
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
        assert abs((b["west"] + b["east"]) / 2 - nominal_point["longitude_deg"] % 360) < MEAN_SHIFT_DEG, (b, nominal_point)
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
        assert table[s["name"]][1:] == [percent(s["probability"]), interval(s["interval"]),
                                        "inside" if s["inside_nominal"] else "outside"], (s, table[s["name"]])
    assert HOSTILE_SITE in table
    by_name = {s["name"]: s for s in d["sites"]}
    assert by_name[HOSTILE_SITE]["probability"] > 0.5 and by_name["Kennedy SLF"]["probability"] == 0
    assert "95 % interval" in page.locator("#dispersion-sites thead").inner_text()
    # on the map: a marker per site (and copy), its probability beside it
    assert page.locator("path.dispersion-site").count() == 3 * len(SITES)
    assert percent(by_name[HOSTILE_SITE]["probability"]) in page.locator(".dispersion-p").all_inner_texts()
    # every outcome counted
    outcomes = page.locator("#dispersion-outcomes").inner_text()
    assert f"{d['outcomes']['landed']:,} of {d['outcomes']['flights']:,} flights landed" in outcomes
    assert all(what in outcomes for what in d["outcomes"] if what not in ("flights", "landed"))
    # no name became markup anywhere: no <img>, no <b> from a name, no dialog, no CSP violation
    assert page.locator("#dispersion-sites img, .leaflet-pane img.leaflet-marker-icon[src=x], .map-legend img, "
                        "#job-list b, .map-legend b, #dispersion-panel b").count() == 0
    assert HOSTILE_JOB in page.locator(".map-legend").inner_text()
    assert HOSTILE_JOB in page.locator("#dispersion-sites caption").inner_text()
    # the dispersion in the report's axes
    assert page.locator("#plot svg.dispersion-plot path.dispersion-ellipse").count() == len(drawn)
    assert page.locator("#plot svg.dispersion-plot path.dispersion-confidence").count() == sum(len(c["rings"]) for c in d["confidence"])

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
    assert stored_row.locator(".dispersion-p").inner_text().startswith(f"P {percent(by_name['Kwajalein']['probability'])} (")

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
    page.locator("path.dispersion-nominal.disp-copy-0").wait_for(state="attached", timeout=10_000)
    assert page.locator("#dispersion-sites table tbody tr").count() == len(SITES)
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
    lons, lats = np.array(placed["outlined"]).T  # with its outline the same ring is filled up to the pole
    assert lats.max() == 90.0 and lats.min() == pytest.approx(70.0, abs=0.01)
    assert lons.max() - lons.min() == pytest.approx(360.0, abs=0.1)
    assert not run.errors


@pytest.mark.parametrize("field, value, words", [("#d-samples", "0", "Samples: "),
                                                 ("#entry-velocity", "50", "Velocity, earth-relative (ft/s): ")])
def test_a_refused_dispersion_names_its_field(open_page, field, value, words):
    """A 422 of a dispersion study shows next to the input that holds the field: its own (samples) or one of its
    footprint study's ("study.footprint.case.entry.velocity_fps", the form's case input); no job is queued."""
    run = open_page()
    page = run.page
    page.check("#disperse-toggle")
    page.fill(field, value)
    page.click("#job-submit")
    note = page.locator(f"{field} + .field-error")
    note.wait_for(timeout=10_000)
    assert note.inner_text().startswith(words) and value in note.inner_text(), note.inner_text()
    assert page.locator(".field-error:visible").count() == 1 and page.locator("#job-list li").count() == 0
