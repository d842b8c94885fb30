"""The landing opportunities panel (issue 28 item 4), in Debian's chromium against the real service: the ISS's
element set of the worked example, two hours of window and three stored sites sent as an opportunities job; its
UTC timeline (a mark per opportunity at its landing, each site's nights as the service gives them, the ascending
nodes), each site's ranked table, and the chosen opportunity on the map (its revolution's ground track, the coast
arc, the entry, the footprint flown from it and the site) and the globe, each checked against the job's own JSON;
a bad TLE named next to its field; a job cancelled."""

import copy
import json
import re
import tempfile
import time
from datetime import datetime
from pathlib import Path

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
    labels: [...svg.querySelectorAll('text.site-label')].map((t) => t.textContent),
    names: [...svg.querySelectorAll('g.site-row-label > title')].map((t) => t.textContent),
    boxes: [...svg.querySelectorAll('text.site-label')].map((t) => { const b = t.getBBox(); return [b.y, b.y + b.height]; }),
    height: n(svg, 'height'), pane: svg.parentElement.clientHeight, scrolls: svg.parentElement.scrollHeight,
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


def downloaded(page, selector):
    with page.expect_download(timeout=WAIT_MS) as download:
        page.click(selector)
    return download.value.suggested_filename, Path(download.value.path()).read_bytes()


def assert_downloads(page, job_id, answer, k):
    """The panel's files, as a planner saves them: the job's calendar read back by icalendar (an event per
    opportunity that meets the rules, the answer's UIDs and burn seconds), the chosen one's OEM by the oem package and its
    CZML as JSON, each starting at its burn."""
    from icalendar import Calendar
    from oem import OrbitEphemerisMessage

    from footprint.contracts.opportunities import event_uid

    name, ics = downloaded(page, "#op-ics")
    assert name == f"opportunities-{job_id}.ics"
    events = Calendar.from_ical(ics).walk("VEVENT")
    taken = [o for o in answer["opportunities"] if o["meets_rules"]]
    assert [str(e["UID"]) for e in events] == [event_uid(answer["elements"]["satellite_number"], o) for o in taken]
    for e, o in zip(events, taken):
        assert (
            abs((e.decoded("DTSTART") - datetime.fromisoformat(o["burn_utc"].replace("Z", "+00:00"))).total_seconds())
            <= 0.5
        )
    burn = answer["opportunities"][k]["burn_utc"]
    name, oem = downloaded(page, "#op-oem")
    assert name == f"opportunity-{job_id}-{k}.oem"
    with tempfile.TemporaryDirectory() as folder:  # the oem package opens files
        (Path(folder) / name).write_bytes(oem)
        coast, entry = OrbitEphemerisMessage.open(Path(folder) / name)
    assert next(coast.states).epoch.isot[:23] + "Z" == burn and entry.metadata["REF_FRAME"] == "GRC"
    name, czml = downloaded(page, "#op-czml")
    assert name == f"opportunity-{job_id}-{k}.czml" and json.loads(czml)[1]["availability"].startswith(burn + "/")


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

    # the first to land chosen, the first row of its site's table (issue 53 item 7: the first meeting the rules
    # before, not the first row); the job's calendar and its coast and entry downloaded from the panel (issue 52)
    page.locator("#plot circle.op-mark.selected[data-index='0']").wait_for(state="attached", timeout=WAIT_MS)
    assert page.locator("#op-table tbody tr").first.get_attribute("data-index") == "0"
    assert page.locator("#op-table tbody tr.selected").get_attribute("data-index") == "0"
    assert_downloads(page, job["id"], a, 0)

    # the timeline: a mark per opportunity at its landing time in its site's row, filled when it meets the rules
    assert page.get_attribute("#plot-opportunities", "aria-pressed") == "true"
    page.locator("#plot circle.op-mark[data-index]").first.wait_for(state="attached", timeout=WAIT_MS)
    t = page.evaluate(TIMELINE_JS)
    sx = tick_scale(t["ticks"], START[:10])
    f, rows = t["frame"], len(a["sites"])
    row = f["h"] / rows
    assert t["labels"][2] == HOSTILE[:21] + "…" and t["labels"][:2] == [s["name"][:21] + "…" for s in SITES[:2]]
    assert t["names"] == [s["name"] for s in a["sites"]]  # whole on hover (issue 53 item 5)
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
    assert page.get_attribute("#op-oem", "href").endswith(f"/opportunities/{k}?format=oem")
    assert page.input_value("#op-site") == str(found[k]["site"])
    selected = page.locator("#op-table tr.selected")
    assert selected.count() == 1 and selected.get_attribute("data-index") == str(k)
    o = found[k]
    cells = selected.locator("td").all_inner_texts()
    assert (
        cells[1:5]
        == [  # the date with its year above the time to the millisecond (issue 53 item 7)
            f"{o['burn_utc'][:10]}\n{o['burn_utc'][11:23]}",
            f"{o['delta_v_fps']:,.1f}",
            f"{o['landing_utc'][:10]}\n{o['landing_utc'][11:23]}",
            f"{o['margin_nmi']:,.0f}",
        ]
    )
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

    # another site's best one, clicked in its table: each site's rows in landing order, the rank a column (issue 53
    # item 7: ranked by margin before, the rows jumping in time)
    page.select_option("#op-site", "2")
    assert HOSTILE in page.locator("#op-site option").nth(2).inner_text()  # the name as text
    mine = [i for i, o in enumerate(found) if o["site"] == 2]
    rows_shown = [
        int(x) for x in page.eval_on_selector_all("#op-table tbody tr", "(rs) => rs.map((r) => r.dataset.index)")
    ]
    assert rows_shown == mine  # the answer's order: landing order
    ranks = [found[i].get("rank") for i in rows_shown]
    assert sorted(r for r in ranks if r is not None) == list(range(1, 1 + sum(r is not None for r in ranks)))
    shown_ranks = page.eval_on_selector_all("#op-table tbody tr td:first-child", "(cs) => cs.map((c) => c.textContent)")
    assert shown_ranks == ["–" if r is None else str(r) for r in ranks]
    assert page.eval_on_selector_all("#op-table thead th", "(hs) => hs.map((h) => h.textContent)")[0] == "Rank"
    best = next((i for i in rows_shown if found[i].get("rank") == 1), rows_shown[0])
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
    assert f"landing {o['landing_utc'][:10]} {o['landing_utc'][11:23]} UTC" in words[0]
    assert f"burn {o['burn_utc'][:10]} {o['burn_utc'][11:23]} UTC" in words[1]
    assert f"Δv {o['delta_v_fps']:,.1f} ft/s" in words[1]

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


def test_a_time_in_a_leap_second_is_written_as_it_is(open_page, service):
    """Issue 52/53: times with the year and to the millisecond; 23:59:60 (a leap second, as the service writes it)
    threw "Invalid time value" from Date before, and the timeline drew nothing."""
    run = open_page()
    got = run.page.evaluate("""async () => { const m = await import('./js/timeline.js');
      const t = ['2016-12-31T23:59:59.900Z', '2016-12-31T23:59:60.250Z', '2017-01-01T00:00:00.500Z'];
      return { words: t.map(m.utcWords), ms: t.map(m.utcMs), plain: m.utcWords('2026-09-21T01:18:21.374Z') }; }""")
    assert got["plain"] == "2026-09-21 01:18:21.374"
    assert got["words"] == ["2016-12-31 23:59:59.900", "2016-12-31 23:59:60.250", "2017-01-01 00:00:00.500"]
    assert got["ms"][0] < got["ms"][1] < got["ms"][2]  # drawn in their order (POSIX time has no second 60)
    assert not run.errors and run.violations() == []


def twenty_site_answer():
    """A two-hour answer at the worked example's 20 sites, planned in this process."""
    from footprint import parallel

    study = copy.deepcopy(EXAMPLE) | {"window": {"start": START, "hours": HOURS}, "burn_step_s": STEP_S}
    study["ring_step_deg"] = 30
    return parallel.run("opportunities", study)


ROWS_JS = """() => { const svg = document.querySelector('#plot svg.opportunity-plot');
  const boxes = [...svg.querySelectorAll('text.site-label')].map((t) => { const b = t.getBBox(); return [b.y, b.y + b.height]; });
  const marks = [...svg.querySelectorAll('circle.op-mark[data-index]')].map((c) => +c.getAttribute('cy'));
  return { boxes, marks, names: [...svg.querySelectorAll('g.site-row-label > title')].map((t) => t.textContent),
    frame: +svg.querySelector('rect.frame').getAttribute('height'), height: +svg.getAttribute('height'),
    width: +svg.getAttribute('width'), pane: svg.parentElement.clientHeight, paneWidth: svg.parentElement.clientWidth,
    scrolls: svg.parentElement.scrollHeight }; }"""


@pytest.mark.parametrize("sites", [3, 20])
def test_the_timeline_grows_with_its_sites_and_names_them_whole(open_page, service, stored_sites, sites):
    """Issue 53 item 5: 20 sites' rows were squeezed into the pane (~6 px a row: the names overlapping, cut, and
    the pane could not grow); now each row is at least 18 px, the plot taller than its pane and scrolled there,
    each name whole in its row's title. Screenshots of the panel with 3 and 20 sites."""
    answer = twenty_site_answer() if sites == 20 else None
    run = open_page(1280, 800)
    page = run.page
    if answer is None:  # the three stored sites' answer, as the page's job gives it
        fill(page)
        find(page)
        item = page.locator("#op-jobs li").first
        item.locator(".job-status", has_text="succeeded").wait_for(timeout=JOB_TIMEOUT_S * 1000)
    else:
        page.evaluate("(a) => window.footprintApp.opportunities.show(a)", answer)
        assert page.locator("#op-downloads").is_hidden()  # an answer without its job: no files to fetch
        # the first to land is chosen though it fails a rule (the first meeting the rules was, issue 53 item 7)
        assert not answer["opportunities"][0]["meets_rules"]
        page.locator("#plot circle.op-mark.selected[data-index='0']").wait_for(state="attached", timeout=WAIT_MS)
        assert page.locator("#op-table tbody tr").first.get_attribute("data-index") == "0"
    page.locator("#plot circle.op-mark[data-index]").first.wait_for(state="attached", timeout=WAIT_MS)
    got = page.evaluate(ROWS_JS)
    table = page.evaluate(
        "() => { const t = document.getElementById('op-table'); return [t.scrollWidth, t.clientWidth]; }"
    )
    assert table[0] <= table[1], table  # the times with their year and milliseconds fit the sidebar's table
    assert len(got["names"]) == len(got["boxes"]) == sites
    row = got["frame"] / sites
    assert row >= 18.0, row
    assert all(b[1] <= c[0] for b, c in zip(got["boxes"], got["boxes"][1:])), got["boxes"]  # no name over another
    if sites == 20:
        assert got["names"] == [s["name"] for s in EXAMPLE["sites"]]
        assert got["height"] > got["pane"] and got["scrolls"] > got["pane"]  # taller than its pane: scrolled
        assert got["width"] <= got["paneWidth"]  # no sideways scroll
    page.evaluate("""async () => { const app = window.footprintApp; // the opportunity alone on the map
        for (const fp of app.state.footprints.values()) if (fp.visible) await app.setVisible(fp, false); }""")
    page.evaluate("""() => { for (const id of ['job-panel', 'dispersion-panel', 'guided-panel'])
        document.getElementById(id).open = false; document.getElementById('opportunities-panel').scrollIntoView(); }""")
    page.wait_for_timeout(400)
    FIGURES_DIR.mkdir(parents=True, exist_ok=True)
    if sites == 3:  # the panel's answer: the table, the words, the downloads (the page: page_opportunities.png)
        page.locator("#op-result").screenshot(path=str(FIGURES_DIR / "panel_opportunities_3_sites.png"))
    else:  # the page, and the timeline scrolled to its last rows
        page.screenshot(path=str(FIGURES_DIR / "page_opportunities_20_sites.png"))
        page.evaluate("() => { const p = document.getElementById('plot'); p.scrollTop = p.scrollHeight; }")
        page.screenshot(path=str(FIGURES_DIR / "page_opportunities_20_sites_scrolled.png"))
    assert not run.errors and run.violations() == [], (run.errors, run.violations())


def test_the_landing_window_timeline_grows_with_its_sites_too(open_page, service):
    """Issue 53 item 5: the reach's landing-window timeline shares the rows: 20 sites at least 18 px each, no name
    over another, each whole in its title, the plot scrolled in its pane."""
    run = open_page(1280, 800)
    names = [s["name"] for s in EXAMPLE["sites"]]
    reach = {
        "analysis": {"time_span_end_s": 6 * 3600},
        "sites": [{"name": n, "reachable": i % 3 != 0} for i, n in enumerate(names)],
        "windows": [
            {"site": n, "revolution": 1 + i % 4, "deorbit_time_start_s": 600.0 * i, "deorbit_time_end_s": 600.0 * i + 300,
             "u_start_deg": 10.0, "u_end_deg": 20.0, "max_margin_nmi": 100.0}
            for i, n in enumerate(names) if i % 3
        ],
    }  # fmt: skip
    got = run.page.evaluate(
        """async (reach) => { const m = await import('./js/timeline.js'), plot = document.getElementById('plot');
        m.drawTimeline(plot, reach); const svg = plot.querySelector('svg.timeline-plot');
        return { boxes: [...svg.querySelectorAll('text.site-label')].map((t) => { const b = t.getBBox(); return [b.y, b.y + b.height]; }),
          names: [...svg.querySelectorAll('g.site-row-label > title')].map((t) => t.textContent),
          frame: +svg.querySelector('rect.frame').getAttribute('height'), pane: plot.clientHeight,
          scrolls: plot.scrollHeight, width: +svg.getAttribute('width'), paneWidth: plot.clientWidth }; }""",
        reach,
    )
    assert got["names"] == names and got["frame"] / len(names) >= 18.0
    assert all(b[1] <= c[0] for b, c in zip(got["boxes"], got["boxes"][1:])), got["boxes"]
    assert got["scrolls"] > got["pane"] and got["width"] <= got["paneWidth"]
    assert not run.errors and run.violations() == []


def _haversine_nmi(lat1, lon1, lat2, lon2, radius_nmi=3440.07):  # IUGG mean earth radius 6,371.0088 km / 1.852
    import math

    p1, p2, dl = math.radians(lat1), math.radians(lat2), math.radians(lon2 - lon1)
    a = math.sin((p2 - p1) / 2) ** 2 + math.cos(p1) * math.cos(p2) * math.sin(dl / 2) ** 2
    return 2 * radius_nmi * math.asin(math.sqrt(a))


def test_an_opportunity_is_flown_guided_and_dispersed_from_its_own_entry(open_page, service, stored_sites):
    """Issue 52 item 5 on the page: "Fly it guided" flies the chosen opportunity's entry to its site (before, the guided
    panel flew the job form's abstract entry, 0 deg, 0 deg, east, and said "miss 5,249 nmi" for Kennedy), and "Its
    guided dispersion" submits the burn itself, whose executed errors give the samples' entries."""
    run = open_page(1280, 800)
    page = run.page
    fill(page)
    find(page)
    item = page.locator("#op-jobs li").first
    item.locator(".job-status", has_text="succeeded").wait_for(timeout=JOB_TIMEOUT_S * 1000)
    job_id = item.get_attribute("data-job-id") or page.evaluate("window.footprintApp.opportunities.jobId")
    answer = service.call(f"/api/jobs/{job_id}")["result"]["opportunities"]
    k = page.evaluate("window.footprintApp.opportunities.selected")
    o = answer["opportunities"][k]
    site = answer["sites"][o["site"]]
    assert page.locator("#op-detail").inner_text().count("Flown guided to the site from this entry") == 1
    with page.expect_response(lambda r: r.url.endswith("/api/trajectories"), timeout=WAIT_MS * 20) as flown:
        page.click("#op-fly-guided")
    sent, answered = flown.value.request.post_data_json, flown.value.json()
    assert (
        sent["entry"]["latitude_deg"] == o["entry"]["latitude_deg"]
        and sent["entry"]["gamma_deg"] == o["entry"]["gamma_deg"]
    )
    assert sent["bank"]["target"]["latitude_deg"] == site["latitude_deg"]
    end, job_end = answered["summary"], o["guided"]
    apart = _haversine_nmi(end["final_latitude_deg"], end["final_longitude_deg"], job_end["final_latitude_deg"],
                           job_end["final_longitude_deg"])  # fmt: skip
    assert apart < 0.05  # the page's flight is the job's own guided flight of this opportunity
    page.locator("#guided-summary", has_text=site["name"][:12]).wait_for(timeout=WAIT_MS)
    page.wait_for_timeout(400)
    assert "Predicted miss (nmi; + long, − short)" in page.inner_text("#plot")  # issue 53 item 9: the sign in words
    page.screenshot(path=str(FIGURES_DIR / "page_opportunity_guided.png"))
    page.fill("#g-samples", "8")
    with page.expect_request(lambda r: r.url.endswith("/api/jobs") and r.method == "POST", timeout=WAIT_MS) as req:
        page.click("#op-disperse-guided")
    body = req.value.post_data_json
    assert body["kind"] == "guided_dispersion"
    burn = body["study"]["burn"]
    assert burn["tle"] == TLE and burn["burn_utc"] == o["burn_utc"] and burn["delta_v_fps"] == o["delta_v_fps"]
    assert "entry" not in body["study"]  # the executed burns give the entries
    done = page.locator("#guided-jobs li").first
    done.locator(".job-status", has_text="succeeded").wait_for(timeout=JOB_TIMEOUT_S * 1000)
    # its ends on the globe too, over the site (before, the globe drew a guided track and rings, no clouds)
    page.click("#view-globe")
    page.evaluate(f"() => window.footprintApp.globe.center({site['longitude_deg']}, {site['latitude_deg']})")
    moves = page.evaluate("""() => Object.fromEntries([...document.querySelectorAll('#globe path.globe-guided-cloud')]
      .map((p) => [p.getAttribute('class'), (p.getAttribute('d').match(/M/g) || []).length]))""")
    assert moves.get("globe-guided-cloud gc-guided") == 8, moves  # one circle a landed sample, all on this side
    page.screenshot(path=str(FIGURES_DIR / "page_opportunity_dispersion_globe.png"))
