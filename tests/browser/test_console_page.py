"""Issue 53: the page as a planner's console, in Debian's chromium against the real service. Each test reproduces
one of the issue's items as a first-time user met it."""

import json
import re
from pathlib import Path

import pytest

from tests.authorities.report import table2_entry, table2_stop

from .conftest import FIGURES_DIR, WAIT_MS, png_export, refusal

ROOT = Path(__file__).resolve().parents[2]
EXAMPLE = json.loads((ROOT / "examples" / "opportunities_iss_20_sites.json").read_text())
PYDANTIC_WORDS = ("Input should", "List should", "after validation", "(got None)", "e+0")


def script_errors(run):
    """The page's script errors (a refusal's 422 in the console is the service answering, not the page failing)."""
    return [e for e in run.errors if "status of 422" not in e]


def note_of(page, input_id):
    note = page.locator(f"#{input_id} + .field-error")
    note.wait_for(timeout=WAIT_MS)
    return note.inner_text()


def test_a_negative_target_downrange_is_refused_beside_its_field_and_not_queued(open_page, service):
    """Item 6: a down-range constraint of -4,000 nmi was queued and "succeeded" with a 139 g flight; a down-range is
    measured forward from the entry, so nothing at or below 0 nmi can be met."""
    run = open_page()
    page = run.page
    jobs = service.call("/api/jobs")["total"]
    page.check("#optimize-toggle")
    page.fill("#o-downrange", "-4000")
    page.click("#job-submit")
    text = note_of(page, "o-downrange")
    assert text.startswith("Down-range = (nmi): -4,000 ") and "more than 0" in text, text
    assert "e.g. 4000" in text, text  # the form's own default as the example
    assert page.locator("#job-list li").count() == 0
    assert service.call("/api/jobs")["total"] == jobs  # nothing queued
    page.screenshot(path=str(FIGURES_DIR / "issue53_negative_downrange.png"))
    assert not script_errors(run), run.errors


def test_the_pages_messages_are_in_the_forms_words_with_an_example(open_page, service):
    """Item 6: an empty number, an empty list and a time that is not one were answered in pydantic's words; each is
    said in the form's words, with the field's default or placeholder as an example."""
    run = open_page()
    page = run.page
    page.fill("#entry-velocity", "")
    page.click("#job-submit")
    text = note_of(page, "entry-velocity")
    assert text == "Velocity, earth-relative (ft/s): a number is needed; e.g. 24480", text
    page.fill("#entry-velocity", "24480")
    page.fill("#p-bank0", "")
    page.click("#job-submit")
    text = note_of(page, "p-bank0")
    assert text == "Initial banks φ0 (deg, list): give at least 1 value; e.g. 0, 15, 30, …", text
    page.fill("#p-bank0", "0, 45")
    page.fill("#entry-altitude", "5")
    page.click("#job-submit")
    text = note_of(page, "entry-altitude")
    assert "e+0" not in text and ",000" in text, text  # "1,000 to 3,000,000 ft", not "1000 to 3e+06 ft"
    page.fill("#entry-altitude", "364800")
    service.call("/api/sites", {"name": "Edwards", "latitude_deg": 34.9, "longitude_deg": -117.9})
    page.reload()
    page.wait_for_selector("body[data-ready=true]")
    page.fill("#op-tle", EXAMPLE["tle"])
    page.fill("#op-start", "yesterday")
    page.click("#op-find")
    text = note_of(page, "op-start")
    assert text == "Window start (UTC): 'yesterday' is not a date and time (UTC); e.g. 2008-09-21T00:00:00Z", text
    page.screenshot(path=str(FIGURES_DIR / "issue53_form_words.png"), full_page=True)
    for said in PYDANTIC_WORDS:
        assert said not in page.inner_text("body"), said
    assert not script_errors(run), run.errors


def test_the_service_refuses_a_constraint_no_flight_can_meet(service):
    """Item 6 at the contract: the 422 names the constraint and the quantity's range, in thousands."""
    study = {
        "case": {
            "vehicle": {"builtin": "lod-1.89"},
            "entry": {
                "velocity_fps": 24480,
                "gamma_deg": -2,
                "heading_deg": 90,
                "altitude_ft": 364800,
                "latitude_deg": 0,
                "longitude_deg": 0,
            },
        },
        "payoff": {"quantity": "crossrange_nmi"},
        "constraints": [{"quantity": "downrange_nmi", "equals": -4000}],
    }
    body = refusal(service, "/api/jobs", {"kind": "optimize", "study": study})
    assert body["field"] == "study.constraints.0.equals", body
    assert body["detail"] == (
        "study.constraints.0.equals: -4,000 is outside the allowed range for downrange_nmi (more than 0)"
    ), body


def test_no_guidance_target_is_drawn_before_its_panel_is_used(open_page):
    """Item 9: the guided panel's default target (a crosshair over India, on Sriharikota) was drawn on every view
    before anyone used that panel; it appears once the panel's target is touched."""
    run = open_page()
    page = run.page
    page.wait_for_timeout(500)  # the page's first draw is done (body[data-ready]); give the layers a moment
    assert page.locator("#map .guided-target").count() == 0
    page.screenshot(path=str(FIGURES_DIR / "issue53_no_default_target.png"))
    page.fill("#g-latitude", "20")
    page.locator("#map .guided-target").first.wait_for(state="attached")
    assert not script_errors(run), run.errors


OVERLAPS_JS = """(selectors) => {
  const boxes = (s) => [...document.querySelectorAll(s)].map((e) => e.getBoundingClientRect())
    .filter((r) => r.width > 0 && r.height > 0);
  const hit = (a, b) => a.left < b.right && b.left < a.right && a.top < b.bottom && b.top < a.bottom;
  const labels = boxes('#map .grid-label'), controls = boxes(selectors);
  const hidden = [...document.querySelectorAll('#map .grid-label')]
    .filter((e) => controls.some((c) => hit(e.getBoundingClientRect(), c))).map((e) => e.textContent);
  return { labels: labels.length, hidden }; }"""


LABELS_APART_JS = """() => { const r = [...document.querySelectorAll('#map .grid-label')]
  .map((e) => [e.textContent, e.getBoundingClientRect()]);
  const hit = (a, b) => a.left < b.right && b.left < a.right && a.top < b.bottom && b.top < a.bottom;
  return r.flatMap(([t, a], i) => r.slice(i + 1).filter(([, b]) => hit(a, b)).map(([u]) => `${t} over ${u}`)); }"""


def test_graticule_labels_stay_clear_of_the_scale_bar_and_the_zoom_buttons(open_page):
    """Item 9: the longitudes along the bottom sat under the scale bar and the attribution."""
    run = open_page()
    page = run.page
    for zoom in (None, "in", "world"):
        if zoom == "in":
            page.click(".leaflet-control-zoom-in")
        elif zoom == "world":
            page.evaluate("() => window.footprintApp.mapView.map.fitBounds([[-90, -180], [90, 180]], {animate: false})")
        page.wait_for_timeout(800)
        seen = page.evaluate(OVERLAPS_JS, ".map-scale, .leaflet-control-attribution, .leaflet-control-zoom")
        assert seen["labels"] >= 6 and seen["hidden"] == [], seen
        assert page.evaluate(LABELS_APART_JS) == [], zoom
    page.screenshot(path=str(FIGURES_DIR / "issue53_graticule_labels.png"))


def submit_footprint(page, name, longitude_deg, banks="0, 45, 90"):
    page.fill("#job-name", name)
    page.fill("#entry-longitude", str(longitude_deg))
    page.fill("#p-bank0", banks)
    page.click("#job-submit")
    return page.locator("#job-list li", has_text=name).first


def test_a_finished_footprint_is_drawn_and_selected_when_it_finishes(open_page, service):
    """Item 4: first-time users saw no footprint from a finished job until they ticked it and clicked it. Two jobs
    in a row, as a user queues them: each is drawn, and the last to finish is the selected one, in the list and the
    range plot, when it finishes."""
    run = open_page()
    page = run.page
    first = submit_footprint(page, "first of two", -40)
    second = submit_footprint(page, "second of two", 20)
    ids = []
    for item in (first, second):
        item.locator(".job-status", has_text="succeeded").wait_for(timeout=WAIT_MS * 5)
        job = service.call(f"/api/jobs/{item.get_attribute('data-job-id')}")
        ids.append(job["result"]["footprints"][0].rsplit("/", 1)[1])
    for fid in ids:
        page.locator(f"path.fp-polygon.fp-{fid}.fp-copy-0").wait_for(state="attached")
        assert page.locator(f"#footprint-list li[data-id='{fid}'] input.fp-visible").is_checked()
    last = page.locator("#footprint-list li.selected")
    last.wait_for()
    assert last.get_attribute("data-id") == ids[-1]
    assert page.get_attribute(f"#footprint-list li[data-id='{ids[-1]}'] .fp-select", "aria-pressed") == "true"
    assert page.locator("#plot .plot-title").first.text_content() == "second of two"
    page.screenshot(path=str(FIGURES_DIR / "issue53_finished_drawn.png"))
    assert not script_errors(run), run.errors


HEX_ID = re.compile(r"\b[0-9a-f]{8}\b")


def test_results_are_named_for_what_they_are(open_page, service):
    """Item 3: a result without a name was "footprint a5dde2ec" in the list, the plot's title and the legend, and an
    optimization "optimize fae955f1"; the Name field promises "vehicle, method, entry". Both are named so, the
    method in words, the entry as the form has it (364,800 ft, 24,480 ft/s, -2 deg)."""
    run = open_page()
    page = run.page
    page.fill("#p-bank0", "0, 45, 90")
    rows = page.locator("#job-list li").count()
    page.click("#job-submit")
    page.wait_for_function("(n) => document.querySelectorAll('#job-list li').length === n", arg=rows + 1)
    name = "lod-1.89 · single parameter · 364.8 kft 24,480 ft/s -2°"
    item = page.locator("#job-list li").first
    assert item.locator(".job-label").inner_text() == name
    item.locator(".job-status", has_text="succeeded").wait_for(timeout=WAIT_MS * 5)
    fid = service.call(f"/api/jobs/{item.get_attribute('data-job-id')}")["result"]["footprints"][0].rsplit("/", 1)[1]
    page.locator(f"#footprint-list li[data-id='{fid}'].selected").wait_for()
    assert page.locator(f"#footprint-list li[data-id='{fid}'] .fp-select").inner_text().startswith(name)
    assert page.locator("#plot .plot-title").first.text_content() == name
    assert name in page.inner_text("#map .footprint-legend")
    page.check("#optimize-toggle")
    rows = page.locator("#job-list li").count()
    page.click("#job-submit")
    page.wait_for_function("(n) => document.querySelectorAll('#job-list li').length === n", arg=rows + 1)
    item = page.locator("#job-list li").first
    optimum = "lod-1.89 · creep+pattern · 364.8 kft 24,480 ft/s -2°"
    assert item.locator(".job-label").inner_text() == optimum
    item.locator(".job-status", has_text="succeeded").wait_for(timeout=WAIT_MS * 5)
    page.locator("#plot .plot-title", has_text=optimum).first.wait_for()
    page.screenshot(path=str(FIGURES_DIR / "issue53_named_results.png"))
    for where in ("#job-list", "#footprint-list", "#map .map-legend"):
        assert not HEX_ID.search(page.inner_text(where)), page.inner_text(where)
    assert "single_parameter" not in page.inner_text("body") and "creep_pattern" not in page.inner_text("body")
    assert not script_errors(run), run.errors


def test_a_moves_earth_rotation_is_said_in_words(open_page, service):
    """Item 3: the move's status said "(none earth rotation)"."""
    run = open_page()
    page = run.page
    node0 = float(page.input_value("#node-longitude"))
    page.fill("#node-longitude", f"{node0 + 20:.2f}")
    page.locator("#live-status", has_text="no earth rotation").wait_for()
    assert "none earth rotation" not in page.inner_text("#live-status")


def sites_csv(sites) -> bytes:
    rows = [f'"{s["name"]}",{s["latitude_deg"]},{s["longitude_deg"]}' for s in sites]
    return ("name,latitude_deg,longitude_deg\n" + "\n".join(rows) + "\n").encode()


def test_twenty_sites_list_whole_upload_again_without_duplicates_and_go_at_once(open_page, service):
    """Item 5: the sites list was a ~100 px scroll box; the same CSV uploaded again made 23 sites of 20 names (the
    reach then said "17 of 23"); removing 17 sites took 17 clicks."""
    run = open_page()
    page = run.page
    page.on("dialog", lambda d: d.accept())
    service.call("/api/sites", method="DELETE")
    page.reload()
    page.wait_for_selector("body[data-ready=true]")
    body = sites_csv(EXAMPLE["sites"])
    names = sorted(s["name"] for s in EXAMPLE["sites"])
    for upload in range(2):
        page.set_input_files("#site-csv", files=[{"name": "sites.csv", "mimeType": "text/csv", "buffer": body}])
        page.wait_for_function("(n) => document.querySelectorAll('#site-list li').length === n", arg=len(names))
        page.wait_for_timeout(500)  # a second upload would have added its rows by now
        assert page.locator("#site-list li").count() == len(names), upload
    assert sorted(s["name"] for s in service.call("/api/sites")) == names
    box = page.evaluate(
        "() => { const l = document.getElementById('site-list'); "
        "return { scroll: l.scrollHeight, client: l.clientHeight }; }"
    )
    assert box["scroll"] <= box["client"] + 1, box  # every row shown: the list grows, the sidebar scrolls
    page.locator("#sites-remove-all").scroll_into_view_if_needed()
    page.screenshot(path=str(FIGURES_DIR / "issue53_twenty_sites_list.png"))
    page.click("#sites-remove-all")
    page.wait_for_function("() => document.querySelectorAll('#site-list li').length === 0")
    assert service.call("/api/sites") == []
    assert not script_errors(run), run.errors


POLAR_JOB = {
    "kind": "footprint",
    "study": {
        "case": {
            "vehicle": {"builtin": "lod-1.89"},
            "entry": table2_entry(heading_deg=0.0, latitude_deg=40.0, longitude_deg=10.0),
            "alpha": {"law": "max_ld"},
            "bank_start": "pullout",
            "stop": table2_stop(),
        },
        "method": "single_parameter",
        "bank0_deg": [0, 45, 90, 135],
    },
}


@pytest.mark.parametrize("count", [3, 20])
def test_the_changed_views_with_3_and_20_sites_over_a_pole_and_across_180(open_page, service, count):
    """The views issue 53 changed, looked at: no guidance target before its panel is used, graticule labels clear of
    the scale bar, results named for what they are, the sites list whole; the seeded footprint crosses 180 deg, the
    polar one holds the north pole. On the map, the globe and the PNG export."""
    service.call("/api/sites", method="DELETE")
    for site in EXAMPLE["sites"][:count]:
        service.call("/api/sites", site)
    polar = service.run_job(POLAR_JOB)["result"]["footprints"][0].rsplit("/", 1)[1]
    run = open_page(1280, 800)
    page = run.page
    for where, show in (("across_180", service.footprint["id"]), ("over_the_pole", polar)):
        page.evaluate("(id) => window.footprintApp.select(id, {fit: true})", show)
        page.wait_for_timeout(800)
        assert page.locator("#map .guided-target").count() == 0
        seen = page.evaluate(OVERLAPS_JS, ".map-scale, .leaflet-control-attribution, .leaflet-control-zoom")
        assert seen["hidden"] == [], (where, seen)
        page.screenshot(path=str(FIGURES_DIR / f"issue53_map_{count}_sites_{where}.png"))
        png_export(page).save(FIGURES_DIR / f"issue53_png_{count}_sites_{where}.png")
        page.evaluate("() => window.footprintApp.setView('globe')")
        page.locator("path.globe-footprint").first.wait_for()
        page.screenshot(path=str(FIGURES_DIR / f"issue53_globe_{count}_sites_{where}.png"))
        page.evaluate("() => window.footprintApp.setView('map')")
    assert page.locator("#site-list li").count() == count
    assert not script_errors(run), run.errors


def test_a_waiting_job_says_what_runs_ahead_and_when_it_should_end_and_is_cancelled(open_page, service):
    """Item 2: a long job kept the rest at "queued · 0 %" for many minutes with no position, estimate, or sign of
    what ran ahead. Behind minutes of IPOPT (Betts' collocation), a footprint job's row names the job ahead, says
    when it should end (or why it cannot say yet) and is cancelled from its row."""
    run = open_page()
    page = run.page
    betts = json.loads((ROOT / "examples" / "optimize_betts_collocation.json").read_text())
    long_id = service.call("/api/jobs", {"kind": "optimize", "study": betts, "name": "Betts ahead"})["id"]
    try:
        item = submit_footprint(page, "waiting behind Betts", 10)
        note = item.locator(".job-queue")
        note.filter(has_text="Betts ahead").wait_for()
        text = note.inner_text()
        assert text.startswith("1 ahead: Betts ahead (") and ("ends in about" in text or "no estimate yet" in text)
        page.screenshot(path=str(FIGURES_DIR / "issue53_queue.png"))
        item.locator(".job-cancel").click()
        item.locator(".job-status", has_text="cancelled").wait_for()
        assert note.inner_text() == ""
        assert service.call(f"/api/jobs/{item.get_attribute('data-job-id')}")["status"] == "cancelled"
    finally:
        service.call(f"/api/jobs/{long_id}", method="DELETE")
    assert not script_errors(run), run.errors


COVERED_JS = """() => { const box = document.querySelector('#map .footprint-legend').getBoundingClientRect();
  return [...document.querySelectorAll('#map .site-marker')].filter((m) => { const r = m.getBoundingClientRect();
    return r.left < box.right && box.left < r.right && r.top < box.bottom && box.top < r.bottom; }).length; }"""


def test_the_legend_folds_away_from_the_sites_it_covers(open_page, service):
    """Item 9: the legend box covered sites (bottom right) with no way to see them but to pan."""
    service.call("/api/sites", method="DELETE")
    for site in EXAMPLE["sites"]:
        service.call("/api/sites", site)
    run = open_page()
    page = run.page
    # a site put under the middle of the legend, as a planner's pan would
    page.evaluate("""() => { const m = window.footprintApp.mapView.map, box = document.querySelector(
        '#map .footprint-legend').getBoundingClientRect(), r = document.querySelector('#map .site-marker')
        .getBoundingClientRect(); m.panBy([r.x + r.width / 2 - (box.x + box.width / 2),
        r.y + r.height / 2 - (box.y + box.height / 2)], { animate: false }); }""")
    page.wait_for_timeout(800)
    covered = page.evaluate(COVERED_JS)
    assert covered >= 1  # this view puts sites under the open legend
    page.click("#map .footprint-legend .legend-fold")
    assert page.evaluate(COVERED_JS) < covered
    assert page.get_attribute("#map .footprint-legend .legend-fold", "aria-expanded") == "false"
    page.screenshot(path=str(FIGURES_DIR / "issue53_legend_folded.png"))
    assert page.locator("#site-list li").count() == len(EXAMPLE["sites"])  # the click added no site
    page.click("#map .footprint-legend .legend-fold")
    assert page.evaluate(COVERED_JS) == covered
    assert not script_errors(run), run.errors
