"""The landing opportunities panel (issue 28 item 4), in Debian's chromium against the real service: the ISS's
element set of the worked example, two hours of window and three stored sites sent as an opportunities job; its
UTC timeline (a mark per opportunity at its landing, each site's nights as the service gives them, the ascending
nodes), each site's ranked table, and the chosen opportunity on the map (its revolution's ground track, the coast
arc, the entry, the footprint flown from it and the site) and the globe, each checked against the job's own JSON;
a bad TLE named next to its field; a job cancelled."""

import copy
import json
import re
import time
from datetime import datetime

import pytest

from .conftest import (
    FIGURES_DIR,
    JOB_TIMEOUT_S,
    ROOT,
    WAIT_MS,
    only_the_service,
    pixels_like,
    png_export,
    refusal,
)

EXAMPLE = json.loads((ROOT / "examples" / "opportunities_iss_20_sites.json").read_text())
TLE = EXAMPLE["tle"]
START, HOURS, STEP_S = "2008-09-21T00:00:00Z", 2, 60
BY_NAME = {s["name"]: s for s in EXAMPLE["sites"]}
HOSTILE = 'Christchurch <img src=x onerror=alert(1)> & "NZ" ${1}'
SITES = [  # Edwards lands at night in this window (an open mark), the others in daylight (filled)
    BY_NAME["Edwards AFB, California"],
    BY_NAME["Woomera, South Australia"],
    {**BY_NAME["Christchurch International, New Zealand"], "name": HOSTILE},
]
PX = 1.5  # a mark, a node or a night's edge from where the time puts it (SVG px)
COAST_RGB = (0xE4, 0x57, 0x2E)  # opportunities.js OPPORTUNITY_STYLE.coast: the coast arc and the burn

# the timeline as drawn: the frame, the time ticks (label, x), the marks, the nights and the nodes
TIMELINE_JS = """() => { const svg = document.querySelector('#plot svg.opportunity-plot'), f = svg.querySelector('rect.frame');
  const n = (e, a) => +e.getAttribute(a);
  return { frame: { x: n(f, 'x'), y: n(f, 'y'), w: n(f, 'width'), h: n(f, 'height') },
    ticks: [...svg.querySelectorAll(':scope > text.tick:not(.site-label)')].map((t) => [t.textContent, n(t, 'x')]),
    labels: [...svg.querySelectorAll(':scope > text.site-label')].map((t) => t.textContent),
    marks: [...svg.querySelectorAll('circle.op-mark[data-index]')].map((c) => ({ index: +c.dataset.index,
      site: +c.dataset.site, x: n(c, 'cx'), y: n(c, 'cy'), cls: c.getAttribute('class'), fill: getComputedStyle(c).fill })),
    nights: [...svg.querySelectorAll('rect.op-night[data-site]')].map((r) => ({ site: +r.dataset.site, x: n(r, 'x'),
      w: n(r, 'width'), y: n(r, 'y'), h: n(r, 'height') })),
    nodes: [...svg.querySelectorAll('line.op-node[data-utc]')].map((l) => [l.dataset.utc, n(l, 'x1')]),
    title: svg.querySelector('.plot-title').textContent }; }"""
# the chosen opportunity's main copy on the map: each layer's Leaflet vertices (a marker: its one point)
DRAWN_JS = """() => Object.fromEntries(window.footprintApp.opportunities.layer.getLayers()
  .filter((l) => l.options.className.endsWith(' op-copy-0'))
  .map((l) => [l.options.className.split(' ')[0],
               (l.getLatLngs ? l.getLatLngs().flat(3) : [l.getLatLng()]).map((p) => [p.lat, p.lng])]))"""


def ms(iso):
    return datetime.fromisoformat(iso.replace("Z", "+00:00")).timestamp() * 1000


def wrapped(deg):
    return (deg + 180) % 360 - 180


def tick_scale(ticks, day):
    """The time axis as its labels say it ("HH:MM", a date at midnight): ms -> x, fitted through the first and
    last tick, every tick on it within a tenth of a pixel."""
    times = []
    for label, _ in ticks:
        if re.fullmatch(r"\d{4}-\d\d-\d\d", label):
            day = label
            times.append(ms(f"{label}T00:00:00Z"))
        else:
            assert re.fullmatch(r"\d\d:\d\d", label), label
            times.append(ms(f"{day}T{label}:00Z"))
    assert len(times) >= 3 and times == sorted(times)
    (t0, x0), (t1, x1) = (times[0], ticks[0][1]), (times[-1], ticks[-1][1])

    def sx(t):
        return x0 + (t - t0) * (x1 - x0) / (t1 - t0)

    assert all(abs(sx(t) - x) < 0.1 for t, (_, x) in zip(times, ticks))
    (step,) = {b - a for a, b in zip(times, times[1:])}
    assert all(t % step == 0 for t in times)  # whole steps of the clock
    return sx


@pytest.fixture(scope="module")
def stored_sites(service):
    return [service.call("/api/sites", s) for s in SITES]


def fill(page, tle=TLE, hours=HOURS, step=STEP_S):
    page.fill("#op-tle", tle)
    page.fill("#op-start", START)
    page.fill("#op-hours", str(hours))
    page.fill("#op-step", str(step))


def find(page):
    """Find opportunities: the request body the page sent."""
    with page.expect_request(lambda r: r.url.endswith("/api/jobs") and r.method == "POST", timeout=WAIT_MS) as request:
        page.click("#op-find")
    return request.value.post_data_json


def assert_drawn(page, answer, k):
    """The opportunity k on the map's main copy, from the job's own JSON: the coast arc's vertices are its
    coast_track, continuous across 180 deg; the burn its first point; the entry, the site, the footprint's landings
    and the revolution's ground track (continuous) where the answer puts them. Returns the drawn layers."""
    o = answer["opportunities"][k]
    drawn = page.evaluate(DRAWN_JS)
    coast = drawn["op-coast"]
    assert len(coast) == len(o["coast_track"])
    for (lat, lon), (la, lo) in zip(coast, o["coast_track"]):
        assert lat == pytest.approx(la, abs=1e-9) and wrapped(lon - lo) == pytest.approx(0, abs=1e-9)
    assert all(abs(b[1] - a[1]) < 30 for a, b in zip(coast, coast[1:]))  # no jump of 360 deg
    gt = answer["ground_track"]
    rev = [i for i, r in enumerate(gt["revolution"]) if r == o["revolution"]]
    track = drawn["op-track"]
    assert len(track) == len(rev)
    for (lat, lon), i in zip(track, rev):
        assert lat == pytest.approx(gt["latitude_deg"][i]) and wrapped(lon - gt["longitude_deg"][i]) == pytest.approx(0)
    assert all(abs(b[1] - a[1]) < 30 for a, b in zip(track, track[1:]))
    assert drawn["op-burn"] == [pytest.approx(coast[0])]  # on the coast's copy
    ((lat, lon),) = drawn["op-entry"]
    assert lat == pytest.approx(o["entry"]["latitude_deg"]) and lon == pytest.approx(coast[-1][1])
    site = answer["sites"][o["site"]]
    ((lat, lon),) = drawn["op-site"]
    assert lat == pytest.approx(site["latitude_deg"]) and wrapped(lon - site["longitude_deg"]) == pytest.approx(0)
    ring = drawn["op-footprint"]
    fr = o["footprint_ring"]
    line = fr["outline"]
    assert len(ring) == len(line["latitude_deg"]) + 1 and ring[0] == ring[-1]  # the service's outline, closed
    for (lat, lon), la, lo in zip(ring, line["latitude_deg"], line["longitude_deg"]):
        assert lat == pytest.approx(la) and wrapped(lon - lo) == pytest.approx(0, abs=1e-9)
    for la, lo in zip(fr["latitude_deg"], fr["longitude_deg"]):  # every landing on it (the outline keeps 1e-4 deg)
        assert min(abs(la - a) + abs(wrapped(lo - b)) for a, b in ring) < 1e-3, (la, lo)
    # unwrapped from the entry: the outline's samples are close (no step of 30 deg)
    assert all(abs(b[1] - a[1]) < 30 for a, b in zip(ring, ring[1:]))
    assert min(abs(lon - b) for _, b in ring) < 30  # the site lies by the footprint it is in, on its copy
    return drawn


def test_opportunities_are_found_put_in_time_and_drawn_on_the_map(open_page, service, stored_sites):
    t0 = time.monotonic()
    run = open_page(1280, 800)
    page, dialogs = run.page, []
    page.on("dialog", lambda d: (dialogs.append(d.message), d.dismiss()))
    assert page.inner_text("#op-sites-note").startswith("The 3 stored landing sites")
    fill(page)
    sent = find(page)
    item = page.locator("#op-jobs li").first
    item.locator(".job-status", has_text="succeeded").wait_for(timeout=JOB_TIMEOUT_S * 1000)
    assert item.locator(".job-percent").inner_text() == "100 %" and item.locator(".job-cancel").is_hidden()

    # what the page sent: the inputs, the stored sites, the job form's footprint on the rotating earth
    assert sent["kind"] == "opportunities"
    study = sent["study"]
    assert study["tle"] == TLE and study["window"] == {"start": START, "hours": HOURS}
    assert study["sites"] == [{k: s[k] for k in ("name", "latitude_deg", "longitude_deg")} for s in stored_sites]
    assert study["deorbit"] == {"entry_gamma_deg": -2} and study["burn_step_s"] == STEP_S
    assert study["rules"] == {"sun_elevation_min_deg": -0.833, "min_margin_nmi": 0}
    case = study["footprint"]["case"]
    assert study["footprint"]["method"] == "single_parameter" and case["vehicle"] == {"builtin": "lod-1.89"}
    assert case["planet"]["rotating"] is True and case["entry"]["velocity_frame"] == "relative"
    job = service.call(f"/api/jobs/{item.get_attribute('data-job-id')}")
    assert job["kind"] == "opportunities" and job["study"]["tle"] == TLE
    a = job["result"]["opportunities"]
    found = a["opportunities"]
    met = sum(o["meets_rules"] for o in found)
    assert 0 < met < len(found)  # filled marks and open ones
    assert f"{len(found)} opportunities over {a['run']['tasks']} revolution" in item.inner_text()

    # the timeline: a mark per opportunity at its landing time in its site's row, filled when it meets the rules
    assert page.get_attribute("#plot-opportunities", "aria-pressed") == "true"
    page.locator("#plot circle.op-mark[data-index]").first.wait_for(state="attached", timeout=WAIT_MS)
    t = page.evaluate(TIMELINE_JS)
    sx = tick_scale(t["ticks"], START[:10])
    f, rows = t["frame"], len(a["sites"])
    row = f["h"] / rows
    assert t["labels"][2] == HOSTILE[:21] + "…" and t["labels"][:2] == [s["name"][:21] + "…" for s in SITES[:2]]
    assert t["title"] == f"Landing opportunities from ISS (ZARYA): {len(found)}, {met} meet the rules"
    assert sorted(m["index"] for m in t["marks"]) == list(range(len(found)))
    for m in t["marks"]:
        o = found[m["index"]]
        assert abs(m["x"] - sx(ms(o["landing_utc"]))) < PX, (m, o["landing_utc"])
        assert m["site"] == o["site"] and abs(m["y"] - (f["y"] + (o["site"] + 0.5) * row)) < 0.01
        assert f["x"] < m["x"] < f["x"] + f["w"]
        assert ("meets" in m["cls"].split()) == o["meets_rules"]
        assert (m["fill"] == "rgb(255, 255, 255)") == (not o["meets_rules"]), m  # open: white inside
    # each site's nights as the service gives them, cut to the axis
    left, right = f["x"], f["x"] + f["w"]
    expected = sorted(
        (i, max(sx(ms(a0)), left), min(sx(ms(b0)), right))
        for i, s in enumerate(a["sites"])
        for a0, b0 in s["night_utc"]
        if min(sx(ms(b0)), right) - max(sx(ms(a0)), left) >= 0.5
    )
    drawn_nights = sorted((n["site"], n["x"], n["x"] + n["w"]) for n in t["nights"])
    assert len(drawn_nights) == len(expected) > 0
    for (i, x0, x1), (j, d0, d1) in zip(expected, drawn_nights):
        assert i == j and abs(x0 - d0) < PX and abs(x1 - d1) < PX, (i, x0, x1, d0, d1)
    for n in t["nights"]:
        assert f["y"] + n["site"] * row <= n["y"] and n["y"] + n["h"] <= f["y"] + (n["site"] + 1) * row
    # a night that begins inside the span: Edwards's, at sunset
    assert any(left + 5 < x0 for i, x0, _ in expected if i == 0)
    assert [u for u, _ in t["nodes"]] == a["ascending_nodes_utc"]
    assert all(abs(x - sx(ms(u))) < PX for u, x in t["nodes"])

    # an opportunity clicked on the timeline: the one whose coast crosses 180 deg, drawn on the map and chosen in the table
    def crossing(o):
        lons = [p[1] for p in o["coast_track"]]
        return any(abs(b - a0) > 180 for a0, b in zip(lons, lons[1:]))

    # (with the burns at their windows' middles, issue 52, no coast of this window crosses 180 deg: then site 0's)
    k = next((i for i, o in enumerate(found) if crossing(o)), next(i for i, o in enumerate(found) if o["site"] == 0))
    page.click(f"#plot circle.op-mark[data-index='{k}']")
    page.locator(f"#plot circle.op-mark.selected[data-index='{k}']").wait_for(state="attached", timeout=WAIT_MS)
    assert_drawn(page, a, k)
    assert page.input_value("#op-site") == str(found[k]["site"])
    selected = page.locator("#op-table tr.selected")
    assert selected.count() == 1 and selected.get_attribute("data-index") == str(k)
    o = found[k]
    cells = selected.locator("td").all_inner_texts()
    assert cells[1:5] == [
        o["burn_utc"][11:19],
        f"{o['delta_v_fps']:,.1f}",
        o["landing_utc"][11:19],
        f"{o['margin_nmi']:,.0f}",
    ]
    sun = f"{abs(o['sun_elevation_deg']):,.1f}"
    assert cells[5] == (f"−{sun}" if o["sun_elevation_deg"] < 0 else sun)
    h = round(o["local_solar_time_h"] * 60) % 1440
    assert cells[6] == f"{h // 60:02d}:{h % 60:02d}" and cells[0] == ("–" if o.get("rank") is None else str(o["rank"]))
    page.evaluate("""async () => { const app = window.footprintApp; // the figure: the opportunity alone on the map
        for (const fp of app.state.footprints.values()) if (fp.visible) await app.setVisible(fp, false); }""")
    page.evaluate("""() => { for (const id of ['job-panel', 'dispersion-panel', 'guided-panel'])
        document.getElementById(id).open = false; document.getElementById('opportunities-panel').scrollIntoView(); }""")
    page.wait_for_timeout(400)
    FIGURES_DIR.mkdir(parents=True, exist_ok=True)
    page.screenshot(path=str(FIGURES_DIR / "page_opportunities.png"))

    # another site's best one, clicked in its table: each site's rows ranked first, the others after
    page.select_option("#op-site", "2")
    assert HOSTILE in page.locator("#op-site option").nth(2).inner_text()  # the name as text
    mine = [i for i, o in enumerate(found) if o["site"] == 2]
    rows_shown = [
        int(x) for x in page.eval_on_selector_all("#op-table tbody tr", "(rs) => rs.map((r) => r.dataset.index)")
    ]
    assert sorted(rows_shown) == mine
    ranks = [found[i].get("rank") for i in rows_shown]
    assert [r for r in ranks if r is not None] == list(range(1, 1 + sum(r is not None for r in ranks)))
    best = rows_shown[0]
    page.click(f"#op-table tr[data-index='{best}'] button.op-show")
    assert_drawn(page, a, best)
    assert page.locator(f"#plot circle.op-mark.selected[data-index='{best}']").count() == 1

    # the globe draws the same opportunity: the track, the coast, the footprint and the site
    page.click("#view-globe")
    paths = page.evaluate("""() => Object.fromEntries(['track', 'coast', 'footprint', 'burn', 'entry', 'site']
      .map((k) => [k, document.querySelector(`#globe path.globe-op-${k}`)?.getAttribute('d') ?? null]))""")
    assert all(paths[k] for k in ("track", "coast", "footprint", "entry", "site")), paths
    page.screenshot(path=str(FIGURES_DIR / "page_opportunities_globe.png"))
    # the PNG export of either view draws it too (it drew none), its caption the chosen one's words
    assert pixels_like(png_export(page), COAST_RGB) > 100
    page.click("#view-map")
    assert pixels_like(png_export(page), COAST_RGB) > 100
    o = found[best]
    words = page.evaluate("() => window.footprintApp.opportunities.caption()")
    assert words[0].startswith(f"{a['sites'][o['site']]['name']}: landing ") and words[0].endswith(
        f" UTC, revolution {o['revolution_number']}"
    )
    assert o["landing_utc"][11:19] in words[0] and f"Δv {o['delta_v_fps']:,.1f} ft/s" in words[1]

    # no name became markup anywhere
    assert page.locator("#opportunities-panel img, #plot img, .leaflet-pane img[src=x]").count() == 0
    only_the_service(run, service)
    assert dialogs == [] and not run.errors and run.violations() == [], (dialogs, run.errors, run.violations())
    print(f"opportunities page test: {time.monotonic() - t0:.1f} s")


def test_a_bad_tle_is_named_next_to_its_field(open_page, service, stored_sites):
    run = open_page()
    page = run.page
    bad = TLE[:-1] + str((int(TLE[-1]) + 1) % 10)  # the last check digit
    fill(page, tle=bad)
    sent = find(page)
    note = page.locator("#op-tle + .field-error")
    note.wait_for(timeout=WAIT_MS)
    refused = refusal(service, "/api/jobs", copy.deepcopy(sent))  # the service's own words for the same study
    assert refused["field"] == "study.tle"
    assert note.inner_text() == "TLE (2 or 3 lines): " + refused["detail"].split(": ", 1)[1], note.inner_text()
    assert page.get_attribute("#op-tle", "aria-invalid") == "true"
    assert page.locator(".field-error:visible").count() == 1 and page.locator("#op-jobs li").count() == 0
    # a bad footprint input is the job form's: named next to it there, and said under this panel
    page.fill("#op-tle", TLE)
    page.fill("#entry-velocity", "5")
    sent = find(page)
    refused = refusal(service, "/api/jobs", copy.deepcopy(sent))
    assert refused["field"] == "study.footprint.case.entry.velocity_fps"
    velocity = page.locator("#entry-velocity + .field-error")
    velocity.wait_for(timeout=WAIT_MS)
    example = page.get_attribute("#entry-velocity", "value")  # the field's default (issue 53 item 6)
    words = "Velocity, earth-relative (ft/s): " + refused["detail"].split(": ", 1)[1] + f"; e.g. {example}"
    assert velocity.inner_text() == words and page.inner_text("#op-error") == words + " (in the job form above)"
    assert page.locator("#op-tle + .field-error").count() == 0 and page.locator("#op-jobs li").count() == 0
    refused_logged = "Failed to load resource: the server responded with a status of 422 (Unprocessable Entity)"
    assert run.errors == [refused_logged] * 2 and run.violations() == [], run.errors


def test_an_opportunities_job_is_cancelled(open_page, service, stored_sites):
    run = open_page()
    page = run.page
    fill(page, hours=72, step=10)  # hundreds of revolutions' worth of burns: long enough to cancel
    find(page)
    item = page.locator("#op-jobs li").first
    item.locator(".job-cancel").click()
    item.locator(".job-status", has_text="cancelled").wait_for(timeout=WAIT_MS)
    assert service.call(f"/api/jobs/{item.get_attribute('data-job-id')}")["status"] == "cancelled"
    assert re.fullmatch(r"\d+ %", item.locator(".job-percent").inner_text()) and item.locator(".job-cancel").is_hidden()
    assert not run.errors and run.violations() == []
