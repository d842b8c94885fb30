// Landing opportunities (issue 28 item 4): an element set (TLE), a UTC window, the deorbit burn, the rules, the stored
// landing sites and the job form's footprint study sent as an opportunities job (POST /api/jobs). Its answer: a UTC
// timeline (the plot), each site's ranked opportunities in a table, and the one chosen on the map and the globe:
// its revolution's ground track, the burn, the coast to the entry interface, the entry, the footprint flown from
// that entry and the site. Nothing about the sun is computed here: the nights are the service's.
/* global L */
import { api } from "./api.js";
import { clearFieldErrors, inputForField, showFieldError } from "./fielderrors.js";
import { el, fmt } from "./format.js";
import { copyOffsets, listPoints, openRing, placeOnRing, planarOutline, unwrapLongitudes, unwrapRing, wrapLongitude }
  from "./geometry.js";
import { asFootprintField, buildFootprintStudy, followJob } from "./jobs.js";
import { drawOpportunityTimeline, utcMs, utcWords } from "./timeline.js";

const $ = (id) => document.getElementById(id);
/** The chosen opportunity's colours on the map and the globe (styles.css has the globe's and the legend's). */
export const OPPORTUNITY_STYLE = { track: "#14304f", coast: "#e4572e", footprint: "#0a7d5a", site: "#111" };
// the footprint study of examples/opportunities_iss_20_sites.json: taken when the job form has none (no vehicles)
const EXAMPLE_FOOTPRINT = {
  case: { vehicle: { builtin: "lod-1.89" }, planet: { rotating: true, oblate: true, atmosphere: { model: "ardc1959" } },
          entry: { altitude_ft: 400000, velocity_fps: 24800, gamma_deg: -2 }, alpha: { law: "max_ld" },
          bank_start: "pullout", stop: { altitude_ft: 50000 } },
  method: "single_parameter", bank0_deg: [0, 15, 30, 45, 60, 75, 90, 105, 120, 135, 150], min_range: "zero_lift", mirror: true,
};

/** A number input's value: a number, null when blank, else the text for the service to name. */
function numberOrText(id) {
  const v = $(id).value.trim();
  return v === "" ? null : Number.isFinite(+v) ? +v : v;
}

/** The TLE as typed, its line ends made \n and each line's trailing blanks (a copied element set often has
 * them) and blank lines dropped; the service checks the rest. */
const tleText = () => $("op-tle").value.split(/\r?\n/).map((l) => l.trimEnd()).filter(Boolean).join("\n");

/** The footprint study flown from each burn's entry: the job form's (as the guided and dispersion studies take it),
 * on the rotating earth with the entry speed earth-relative (each burn's entry replaces its entry). */
function footprintStudy() {
  const study = $("job-vehicle").options.length ? buildFootprintStudy() : structuredClone(EXAMPLE_FOOTPRINT);
  study.case.planet = { ...study.case.planet, rotating: true };
  study.case.entry = { ...study.case.entry, velocity_frame: "relative" };
  return study;
}

/** A table's UTC time: its date ("2026-09-21") on a line above the time to the millisecond ("01:18:21.374"). */
const timeCell = (iso) => {
  const [day, time] = utcWords(iso).split(" ");
  return el("td", {}, el("span", { class: "op-day" }, day), time);
};
/** Hours of the clock as "HH:MM" (a local solar time). */
const hoursMinutes = (h) => {
  const m = Math.round(h * 60) % 1440, two = (n) => String(n).padStart(2, "0");
  return `${two(Math.floor(m / 60))}:${two(m % 60)}`;
};
const signed = (v, digits) => (v < 0 ? `−${fmt(-v, digits)}` : fmt(v, digits));
const asGiven = (v) => String(v).replace("-", "−"); // a rule's number as the planner gave it

/** The opportunity's guided flight to its site (the answer's `guided`) in a line: its miss, peaks and limits. */
export function guidedWords(g) {
  const gd = g.guidance, broken = g.limits_broken ?? [];
  const limits = broken.length ? `broke ${broken.map((n) => n.replaceAll("_", " ")).join(", ")}` : "within the vehicle's limits";
  const aim = gd.interface_range_nmi ? `its terminal-area interface (${fmt(gd.interface_range_nmi)} nmi out)` : "it";
  return `Flown guided to the site from this entry: ${gd.status}, ${fmt(gd.miss_nmi, 2)} nmi from ${aim} after `
    + `${fmt(g.flight_time_s)} s; peaks ${fmt(g.max_load_factor, 2)} g, ${fmt(g.max_dynamic_pressure_psf)} psf; ${limits}.`;
}

export class OpportunitiesPanel {
  constructor({ mapView, onResult, onSelect, onGlobe, onGuided }) {
    this.mapView = mapView;
    this.map = mapView.map;
    this.onResult = onResult; // an answer to plot
    this.onSelect = onSelect; // another opportunity chosen (the plot redraws)
    this.onGlobe = onGlobe; // the chosen one's lines and points for the globe, [lon, lat]
    this.onGuided = onGuided; // (what: "fly" | "disperse", study, opportunity, site, button id): the guided panel's
    this.jobStudy = null; // the study of the shown answer's job (its orbit and footprint case), null without one
    for (const [id, what] of [["op-fly-guided", "fly"], ["op-disperse-guided", "disperse"]]) {
      $(id).addEventListener("click", () => {
        const o = this.answer?.opportunities[this.selected];
        if (o && this.jobStudy) this.onGuided?.(what, this.jobStudy, o, this.answer.sites[o.site], id);
      });
    }
    this.form = $("opportunities-form");
    this.sites = [];
    this.answer = null; // result.opportunities of the job shown
    this.jobId = null; // its job, whose files the downloads fetch (null: an answer not from a job of this page)
    this.selected = null; // the chosen opportunity's index in answer.opportunities
    this.globeCenter = null; // [lon, lat] between the chosen one's entry and its site
    this.layer = L.layerGroup().addTo(this.map);
    this.addLegend();
    this.form.addEventListener("submit", (e) => { e.preventDefault(); this.find(); });
    $("op-deorbit").addEventListener("change", () => this.showDeorbit());
    $("op-tle").addEventListener("blur", () => { $("op-tle").scrollLeft = 0; }); // the lines' starts: name, numbers
    $("op-site").addEventListener("change", () => this.renderTable());
    $("op-table").addEventListener("click", (e) => {
      const row = e.target.closest("tr[data-index]");
      if (row) this.select(Number(row.dataset.index));
    });
    this.showDeorbit();
    this.setSites([]);
  }

  showDeorbit() {
    const dv = $("op-deorbit").value === "dv";
    $("op-dv-label").hidden = !dv;
    $("op-gamma-label").hidden = dv;
  }

  /** The stored sites, which go with the study. */
  setSites(sites) {
    this.sites = sites;
    $("op-sites-note").textContent = sites.length
      ? `The ${sites.length} stored landing site${sites.length === 1 ? "" : "s"} (the sites panel) go with the study.`
      : "No stored landing sites yet: add some in the sites panel above.";
  }

  // ------------------------------------------------------------------------------------------- the job
  study() {
    const deorbit = $("op-deorbit").value === "dv" ? { delta_v_fps: numberOrText("op-dv") }
      : { entry_gamma_deg: numberOrText("op-gamma") };
    const study = {
      tle: tleText(), window: { start: $("op-start").value.trim(), hours: numberOrText("op-hours") },
      sites: this.sites.map(({ name, latitude_deg, longitude_deg }) => ({ name, latitude_deg, longitude_deg })),
      deorbit, footprint: footprintStudy(), rules: { sun_elevation_min_deg: numberOrText("op-sun") },
    };
    if (numberOrText("op-margin") != null) study.rules.min_margin_nmi = numberOrText("op-margin");
    if (numberOrText("op-step") != null) study.burn_step_s = numberOrText("op-step");
    return study;
  }

  clearErrors() {
    clearFieldErrors(this.form);
    clearFieldErrors($("job-form"));
    $("op-error").hidden = true;
  }

  /** A refusal next to its field: this panel's own; a footprint input's in the job form above (said here too). */
  showError(err) {
    const jobForm = $("job-form");
    const asForm = err.field?.startsWith("study.footprint.") // study.footprint.case... as the job form names it
      ? asFootprintField({ field: err.field, message: err.message }) : null;
    if (asForm && inputForField(jobForm, asForm.field)) {
      $("job-panel").open = true;
      const note = showFieldError(jobForm, asForm, $("op-error"));
      $("op-error").textContent = `${note.textContent} (in the job form above)`;
      $("op-error").hidden = false;
    } else {
      showFieldError(this.form, err, $("op-error")); // next to its input here, else under the form
    }
  }

  async find() {
    this.clearErrors();
    if (!this.sites.length) {
      $("op-error").textContent = "Store a landing site first (the sites panel above).";
      $("op-error").hidden = false;
      return;
    }
    const study = this.study();
    const hours = study.window.hours;
    const name = `opportunities: ${study.sites.length} site${study.sites.length === 1 ? "" : "s"}, `
      + `${typeof hours === "number" ? `${fmt(hours, hours % 1 ? 1 : 0)} h` : "window"} from ${study.window.start || "?"}`;
    $("op-find").disabled = true;
    try {
      const job = await api("/api/jobs", { method: "POST", body: { kind: "opportunities", name: name.slice(0, 200), study } });
      followJob($("op-jobs"), job.id, name, { cancel: true, onDone: (j, li) => this.finished(j, li) });
    } catch (err) {
      this.showError(err);
    } finally {
      $("op-find").disabled = false;
    }
  }

  finished(job, li) {
    const a = job.result?.opportunities;
    if (job.status === "succeeded" && a) {
      const met = a.opportunities.filter((o) => o.meets_rules).length;
      li.append(el("div", { class: "succeeded" }, `${fmt(a.opportunities.length)} opportunities over ${fmt(a.run.tasks)} `
        + `revolution${a.run.tasks === 1 ? "" : "s"}, ${fmt(met)} meet the rules`));
      this.show(a, job.id, job.study);
    } else if (job.error) {
      li.append(el("div", { class: "failed" }, job.error));
    }
  }

  // ------------------------------------------------------------------------------------------- the answer
  /** An answer in the panel and the plot, the first to land chosen (the first row of its site's table); the
   * calendar's download its job's. */
  show(answer, jobId = null, study = null) {
    this.answer = answer;
    this.jobId = jobId;
    this.jobStudy = study;
    const e = answer.elements, rules = answer.rules;
    const sun = rules.sun_elevation_min_deg;
    const ruleWords = `${sun == null ? "the sun anywhere" : `the sun at least ${asGiven(sun)}°`} and a margin of at least `
      + `${asGiven(rules.min_margin_nmi)} nmi`;
    $("op-summary").replaceChildren(
      el("p", { class: "guided-line" }, `${e.name || `Satellite ${e.satellite_number}`} `,
         el("span", { class: "muted" }, `(${e.satellite_number}, ${fmt(e.inclination_deg, 2)}°, ${fmt(e.period_min, 1)} min; `
           + `elements of ${utcWords(e.epoch_utc)} UTC)`)),
      el("p", {}, `${utcWords(answer.window.start_utc)} to ${utcWords(answer.window.end_utc)} UTC: `
         + `${fmt(answer.opportunities.length)} opportunities at ${answer.sites.filter((s) => s.opportunities).length} of `
         + `${answer.sites.length} sites, ${fmt(answer.opportunities.filter((o) => o.meets_rules).length)} with ${ruleWords}.`));
    $("op-site").replaceChildren(...answer.sites.map((s, i) => el("option", { value: String(i) },
      `${s.name} · ${fmt(s.meeting_rules)} of ${fmt(s.opportunities)}`)));
    $("op-result").hidden = false;
    this.onResult?.();
    if (answer.opportunities.length) this.select(0);
    else { this.selected = null; this.clearDrawing(); this.renderTable(); }
    this.setDownloads();
  }

  /** The timeline of the answer shown in `container` (the plot area). */
  drawTimeline(container) {
    drawOpportunityTimeline(container, this.answer, { selected: this.selected, onSelect: (k) => this.select(k, true) });
  }

  /** One opportunity on the map, the globe, the table and the timeline; focus kept on its mark when chosen there. */
  select(k, fromTimeline = false) {
    const o = this.answer.opportunities[k];
    if (!o) return;
    this.selected = k;
    $("op-site").value = String(o.site);
    this.renderTable();
    this.renderDetail(o);
    this.setDownloads();
    $("op-guided").hidden = !this.jobStudy;
    this.draw(o);
    this.onSelect?.(k);
    if (fromTimeline) document.querySelector(`#plot .op-mark[data-index="${k}"]`)?.focus();
  }

  /** The job's files: its calendar, and the chosen opportunity's coast and entry as a CCSDS OEM and as CZML (the
   * service's, GET /api/jobs/{id}/opportunities...); hidden for an answer without its job. */
  setDownloads() {
    const base = this.jobId && `/api/jobs/${encodeURIComponent(this.jobId)}/opportunities`;
    $("op-downloads").hidden = !base;
    if (!base) return;
    $("op-ics").href = `${base}?format=ics`;
    const chosen = this.selected != null && this.answer?.opportunities[this.selected];
    for (const [id, format] of [["op-oem", "oem"], ["op-czml", "czml"]]) {
      $(id).hidden = !chosen;
      if (chosen) $(id).href = `${base}/${this.selected}?format=${format}`;
    }
  }

  /** The chosen site's opportunities in landing order, each with its rank by margin among those that meet the
   * rules. */
  renderTable() {
    const a = this.answer, site = Number($("op-site").value);
    if (!a) return;
    const mine = a.opportunities.map((o, k) => ({ o, k })).filter(({ o }) => o.site === site)
      .sort((x, y) => utcMs(x.o.landing_utc) - utcMs(y.o.landing_utc) || x.k - y.k);
    if (!mine.length) {
      $("op-table").replaceChildren(el("p", { class: "muted" }, "No opportunity at this site in the window."));
      return;
    }
    const head = ["Rank", "Burn", "Δv", "Landing", "Margin", "Sun", "Solar"];
    const rows = mine.map(({ o, k }) => el("tr", {
      class: `${o.meets_rules ? "meets" : "fails"}${k === this.selected ? " selected" : ""}`, dataset: { index: String(k) },
      "aria-selected": String(k === this.selected) },
      el("td", {}, el("button", { type: "button", class: "op-show",
                                  "aria-label": `Show the opportunity landing at ${utcWords(o.landing_utc)} UTC` },
                      o.rank == null ? "–" : String(o.rank))),
      timeCell(o.burn_utc), el("td", {}, fmt(o.delta_v_fps, 1)),
      timeCell(o.landing_utc), el("td", {}, fmt(o.margin_nmi)),
      el("td", {}, signed(o.sun_elevation_deg, 1)), el("td", {}, hoursMinutes(o.local_solar_time_h))));
    $("op-table").replaceChildren(el("table", { class: "reach op-opportunities" },
      el("caption", { class: "small muted" }, "In landing order; rank by margin among those that meet the rules (–: fails a "
         + "rule). Burn and landing UTC, Δv ft/s, margin nmi, sun elevation ° and local solar time at the site."),
      el("thead", {}, el("tr", {}, ...head.map((h) => el("th", { scope: "col" }, h)))), el("tbody", {}, ...rows)));
  }

  renderDetail(o) {
    const e = o.entry;
    $("op-detail").replaceChildren(
      el("p", { class: "guided-line" }, `Revolution ${o.revolution_number ?? o.revolution}: `
         + (o.touchdown_utc ? `touchdown ≈ ${utcWords(o.touchdown_utc)} UTC (guided to the terminal-area interface at `
            + `${utcWords(o.interface_utc)}), over the site at 50,000 ft ${utcWords(o.landing_utc)}`
           : `over the site at 50,000 ft ${utcWords(o.landing_utc)} UTC (the guided flight did not reach the interface)`)),
      el("p", {}, `Burn ${utcWords(o.burn_utc)} UTC, the middle of its window ${utcWords(o.burn_window_start_utc)}–`
         + `${utcWords(o.burn_window_end_utc)}${o.burn_window_clipped ? " (cut by the search's edge: no optimum)" : ""}, `
         + `at ${fmt(o.burn_altitude_ft)} ft over ${fmt(o.burn_latitude_deg, 2)}°, ${fmt(o.burn_longitude_deg, 2)}°; `
         + `Δv ${fmt(o.delta_v_fps, 1)} ft/s; coast ${fmt(o.coast_s)} s to the entry at `
         + `${utcWords(o.entry_utc)}: ${fmt(e.latitude_deg, 2)}°, ${fmt(e.longitude_deg, 2)}°, γ ${signed(e.gamma_deg, 2)}°, `
         + `heading ${fmt(e.heading_deg, 1)}°, ${fmt(e.velocity_fps)} ft/s.`),
      el("p", {}, `Flight ${fmt(o.flight_time_s)} s: ${fmt(o.downrange_nmi)} nmi down-range, ${fmt(o.crossrange_nmi)} nmi `
         + `cross-range, ${fmt(o.margin_nmi)} nmi inside the footprint (${fmt(o.downrange_margin_nmi)} along its down-range, `
         + `${fmt(o.crossrange_margin_nmi)} across); sun ${signed(o.sun_elevation_deg, 1)}°, local solar time `
         + `${hoursMinutes(o.local_solar_time_h)}${o.daylight ? " (day)" : " (night)"} at the ${o.sun_at ?? "arrival"}.`),
      ...(o.guided ? [el("p", {}, guidedWords(o.guided))] : []));
  }

  /** The chosen opportunity in words, for a PNG's caption (exporting.js), or null. */
  caption() {
    if (this.selected == null || !this.answer) return null;
    const o = this.answer.opportunities[this.selected];
    return [`${this.answer.sites[o.site].name}: landing ${utcWords(o.landing_utc)} UTC, revolution ${o.revolution_number ?? o.revolution}`,
            `burn ${utcWords(o.burn_utc)} UTC, Δv ${fmt(o.delta_v_fps, 1)} ft/s; margin ${fmt(o.margin_nmi)} nmi`];
  }

  // ------------------------------------------------------------------------------------------- the map
  clearDrawing() {
    this.layer.clearLayers();
    this.legend.getContainer().hidden = true;
    this.globeCenter = null;
    this.onGlobe?.(null);
  }

  /** The places of an opportunity, its longitudes continuous on one copy of the map: the revolution's ground track
   * from its first point; the coast from the track's point at the burn time; the entry at the coast's end; the
   * footprint about that entry (planarOutline, as every footprint of the page); the site next to the footprint's
   * landing nearest it. */
  place(o) {
    const gt = this.answer.ground_track, site = this.answer.sites[o.site];
    const rev = gt.revolution.flatMap((r, i) => (r === o.revolution ? [i] : []));
    const track = { lat: rev.map((i) => gt.latitude_deg[i]), lon: [] };
    track.lon = unwrapLongitudes(rev.map((i) => gt.longitude_deg[i]), rev.length ? gt.longitude_deg[rev[0]] : 0);
    const burnMs = utcMs(o.burn_utc);
    let at = -1, gap = Infinity; // the track's point nearest the burn in time
    rev.forEach((i, j) => { const d = Math.abs(utcMs(gt.utc[i]) - burnMs); if (d < gap) { gap = d; at = j; } });
    const coastLat = o.coast_track.map((p) => p[0]);
    const coastLon = unwrapLongitudes(o.coast_track.map((p) => p[1]), at >= 0 ? track.lon[at] : o.coast_track[0][1]);
    const end = coastLon[coastLon.length - 1];
    const entry = { latitude_deg: o.entry.latitude_deg, longitude_deg: end + wrapLongitude(o.entry.longitude_deg - end),
                    heading_deg: o.entry.heading_deg };
    const points = listPoints(o.footprint_ring);
    // the service's sampled outline when the answer has one; else the landings joined by straight lines
    const footprint = planarOutline({ points, reference: entry, outline: o.footprint_ring.outline });
    const ring = openRing(points);
    const siteLon = ring.length ? placeOnRing([site], ring, unwrapRing(ring, entry))[0] : site.longitude_deg;
    return { track, coast: { lat: coastLat, lon: coastLon }, entry, footprint, site: { ...site, longitude_deg: siteLon } };
  }

  draw(o) {
    this.layer.clearLayers();
    const p = this.place(o);
    const svg = { renderer: this.mapView.svgRenderer, smoothFactor: 0, noClip: true };
    const lons = [...p.track.lon, ...p.coast.lon, ...p.footprint.line.map(([lon]) => lon), p.site.longitude_deg];
    const S = OPPORTUNITY_STYLE, main = [];
    for (const offset of copyOffsets(Math.min(...lons), Math.max(...lons))) {
      const cls = (name) => `${name} op-copy-${offset}`;
      const add = (layer) => { layer.addTo(this.layer); if (offset === 0) main.push(layer); return layer; };
      if (p.footprint.polygons?.length) {
        L.polygon(p.footprint.polygons.map((rings) => rings.map((q) => q.map(([lon, lat]) => [lat, lon + offset]))),
                  { ...svg, stroke: false, fillColor: S.footprint, fillOpacity: 0.12, interactive: false, className: cls("op-area") })
          .addTo(this.layer);
      }
      add(L.polyline(p.footprint.line.map(([lon, lat]) => [lat, lon + offset]),
                     { ...svg, color: S.footprint, weight: 2, interactive: false, className: cls("op-footprint") }));
      L.polyline(p.track.lat.map((lat, i) => [lat, p.track.lon[i] + offset]),
                 { ...svg, color: S.track, weight: 1.6, opacity: 0.8, interactive: false, className: cls("op-track") })
        .addTo(this.layer);
      add(L.polyline(p.coast.lat.map((lat, i) => [lat, p.coast.lon[i] + offset]),
                     { ...svg, color: S.coast, weight: 3, interactive: false, className: cls("op-coast") }));
      L.circleMarker([p.coast.lat[0], p.coast.lon[0] + offset],
                     { ...svg, radius: 5.5, color: "#fff", weight: 2, fillColor: S.coast, fillOpacity: 1, className: cls("op-burn") })
        .bindTooltip(`Burn ${utcWords(o.burn_utc)} UTC, Δv ${fmt(o.delta_v_fps, 1)} ft/s`).addTo(this.layer);
      L.circleMarker([p.entry.latitude_deg, p.entry.longitude_deg + offset],
                     { ...svg, radius: 5.5, color: "#fff", weight: 2, fillColor: S.footprint, fillOpacity: 1, className: cls("op-entry") })
        .bindTooltip(`Entry ${utcWords(o.entry_utc)} UTC at ${fmt(o.entry.altitude_ft)} ft, γ ${signed(o.entry.gamma_deg, 2)}°`)
        .addTo(this.layer);
      add(L.circleMarker([p.site.latitude_deg, p.site.longitude_deg + offset],
                         { ...svg, radius: 10, color: S.site, weight: 2.5, fill: false, className: cls("op-site") })
        .bindTooltip(el("div", {}, el("strong", {}, p.site.name), el("br"), `landing ${utcWords(o.landing_utc)} UTC, `
                        + `margin ${fmt(o.margin_nmi)} nmi`)));
    }
    this.legendRevolution.textContent = `ground track, revolution ${o.revolution_number ?? o.revolution}`;
    this.legend.getContainer().hidden = false;
    const bounds = L.latLngBounds([]);
    for (const l of main) bounds.extend(l.getBounds?.() ?? l.getLatLng());
    if (bounds.isValid()) this.map.fitBounds(bounds.pad(0.08), { maxZoom: 5, animate: false });
    // on the globe the same places; it turns to between the entry and the site
    const pairs = (lat, lon) => lat.map((la, i) => [lon[i], la]);
    this.globeCenter = midpoint([p.entry.longitude_deg, p.entry.latitude_deg], [p.site.longitude_deg, p.site.latitude_deg]);
    this.onGlobe?.({ track: pairs(p.track.lat, p.track.lon), coast: pairs(p.coast.lat, p.coast.lon), ring: p.footprint.line,
                     burn: [p.coast.lon[0], p.coast.lat[0]], entry: [p.entry.longitude_deg, p.entry.latitude_deg],
                     site: [p.site.longitude_deg, p.site.latitude_deg] });
  }

  addLegend() {
    const key = (cls, text) => el("div", {}, el("span", { class: cls }), text);
    this.legendRevolution = el("span", {}, "ground track");
    this.legend = L.control({ position: "topright" });
    this.legend.onAdd = () => {
      const div = el("div", { class: "map-legend op-legend-map" }, el("strong", {}, "Landing opportunity"),
        el("div", {}, el("span", { class: "line op-key-track" }), this.legendRevolution),
        key("dot op-key-burn", "burn, then the coast to the entry"), key("dot op-key-entry", "entry interface"),
        key("swatch op-key-footprint", "footprint flown from that entry"), key("op-key-site", "the site"));
      div.hidden = true;
      return div;
    };
    this.legend.addTo(this.map);
  }
}

/** The point half-way between two places on the sphere ([lon, lat] deg). */
function midpoint([lon1, lat1], [lon2, lat2]) {
  const r = Math.PI / 180, v = (lon, lat) => [Math.cos(lat * r) * Math.cos(lon * r), Math.cos(lat * r) * Math.sin(lon * r), Math.sin(lat * r)];
  const a = v(lon1, lat1), b = v(lon2, lat2), m = a.map((x, i) => x + b[i]);
  return [Math.atan2(m[1], m[0]) / r, Math.atan2(m[2], Math.hypot(m[0], m[1])) / r];
}
