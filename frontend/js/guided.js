// Guided entry (issue 27 item 5): a target from its latitude and longitude, a click on the map or a stored landing
// site; one guided flight to it (POST /api/trajectories: its ground track, miss and bank history) and a guided
// dispersion job (POST /api/jobs: the guided and open-loop landing clouds about the miss circle of radius R) and a
// guided footprint job (its rings beside the report's and the true optimal footprints, and the margins).
/* global L */
import { api } from "./api.js";
import { levelWords, percent } from "./dispersion.js";
import { clearFieldErrors, inputForField, showFieldError } from "./fielderrors.js";
import { el, fmt } from "./format.js";
import { copyOffsets, listPoints, planarOutline, unwrapLongitudes, wrapLongitude } from "./geometry.js";
import { buildCase } from "./jobs.js";
import { gridAndTicks, niceTicks } from "./rangeplot.js";

const $ = (id) => document.getElementById(id);
const SVG_NS = "http://www.w3.org/2000/svg";
const EARTH_RADIUS_NMI = 3440.07; // R', the sphere of the report's ranges (eqs. 8-11) and of the service's miss
const CIRCLE_STEP_DEG = 5; // the miss circle's vertices: every 5 deg of bearing
const POLL_MS = 1000;
const DONE = ["succeeded", "failed", "cancelled"];
const TARGET_BOX_PX = 240; // "Zoom to target" fits the circle into a box this big (up to the map's max zoom)
// the dispersion of issue 27 item 5: entry state, aerodynamics and density spread about the case's nominal
const SPREADS = {
  entry: { gamma_deg: { normal: { std: 0.05 } }, velocity_fps: { normal: { std: 15 } }, heading_deg: { normal: { std: 0.05 } } },
  vehicle: { cl_multiplier: { truncated_normal: { std: 0.03, sigmas: 3 } },
             cd_multiplier: { truncated_normal: { std: 0.03, sigmas: 3 } } },
  density: { std: 0.05, correlation_length_ft: 30000 },
};
/** The guided layers' colours (CSS px), the map's and the bank plot's (styles.css has the same for the plot). */
export const GUIDED_STYLE = { track: "#b00068", guided: "#b00068", openLoop: "#7b8794", circle: "#b00068" };

// the guided footprint's rings, outermost first: [result key, legend words, colour, dash]
const RINGS = [["optimal", "true optimal (collocation)", "#111", "7 5"], ["report", "report's law, same end", "#7b8794", null],
               ["nominal_guided", "guided, undispersed", "#b00068", "2 4"], ["guided", "guided: within R in p", "#b00068", null]];

/** A distance for people: two decimals under 10 nmi (a guided miss), whole miles past 100. */
export const nmiWords = (x) => (x == null ? "–" : fmt(x, x < 10 ? 2 : x < 100 ? 1 : 0));

/** The points R nmi from a centre at each bearing 0..360 deg (a geodesic small circle on the sphere of R'), their
 * longitudes continuous about the centre's. */
export function smallCircle(latDeg, lonDeg, radiusNmi) {
  const rad = Math.PI / 180, d = radiusNmi / EARTH_RADIUS_NMI, p1 = latDeg * rad, out = [];
  for (let b = 0; b <= 360; b += CIRCLE_STEP_DEG) {
    const t = b * rad;
    const p2 = Math.asin(Math.sin(p1) * Math.cos(d) + Math.cos(p1) * Math.sin(d) * Math.cos(t));
    const dl = Math.atan2(Math.sin(t) * Math.sin(d) * Math.cos(p1), Math.cos(d) - Math.sin(p1) * Math.sin(p2));
    out.push([p2 / rad, lonDeg + dl / rad]);
  }
  return out;
}

/** A number input as the service would check it, so that a bad target never leaves the page: {value} or {error}
 * (worded with the field's path, as the service words it, for showFieldError to put the label in). */
function checkedNumber(id, lo, hi, unit) {
  const input = $(id), text = input.value.trim(), value = Number(text), field = input.dataset.field;
  if (text === "" || !Number.isFinite(value)) return { error: { field, message: `${field}: give a number` } };
  if (value < lo || value > hi) {
    return { error: { field, message: `${field}: ${text} is outside the allowed range ${lo} to ${hi} ${unit}` } };
  }
  return { value };
}
/** A number, or the text as it is for the service to name (as the job form sends it). */
const numberOrText = (id) => { const v = $(id).value.trim(); return v !== "" && Number.isFinite(+v) ? +v : v; };

/** A guided dispersion's clouds for the globe: {guided, open_loop} lists of [lon, lat], the samples that landed. */
function cloudPoints(r) {
  const out = {};
  for (const mode of ["open_loop", "guided"]) {
    const c = r.clouds?.[mode];
    if (c) out[mode] = c.latitude_deg.flatMap((lat, i) => (lat == null || c.longitude_deg[i] == null ? []
      : [[c.longitude_deg[i], lat]]));
  }
  return out;
}

export class GuidedPanel {
  constructor({ mapView, onFlight, onPick, onReach, onGlobe, toast }) {
    this.mapView = mapView;
    this.map = mapView.map;
    this.onFlight = onFlight; // a bank history to plot
    this.onPick = onPick; // picking on the map: the sites panel stops adding sites
    this.onReach = onReach; // a guided reach's result: each stored site's guided probability
    this.onGlobe = onGlobe; // the track and rings for the globe: {track, rings} ([lon, lat] lines)
    this.globeLayers = { track: null, rings: [], clouds: null };
    this.toast = toast;
    this.form = $("guided-form");
    this.flight = null; // {time_s, bank_deg, bank_command_deg, predicted_miss_nmi?, title}: the bank plot's
    this.siteName = null; // the stored site the target came from, else null
    this.sites = [];
    this.anchorLon = null; // the shown track's end: the target and clouds go on its copy of the map
    this.picking = false;
    // the target is drawn once the panel is used (a target typed, picked, chosen or flown): its default alone is
    // no one's target, and it sat over India on every view (issue 53 item 9)
    this.used = false;
    this.resultLayer = L.layerGroup().addTo(this.map);
    this.targetLayer = L.layerGroup().addTo(this.map);
    this.footprintLayer = L.layerGroup().addTo(this.map);
    this.addLegend();
    this.form.addEventListener("submit", (e) => { e.preventDefault(); this.fly(); });
    $("g-disperse").addEventListener("click", () => this.disperse());
    $("g-footprint").addEventListener("click", () => this.traceFootprint());
    $("g-reach").addEventListener("click", () => this.reachSites());
    $("g-pick").addEventListener("click", () => this.setPicking(!this.picking));
    $("g-zoom").addEventListener("click", () => this.zoomToTarget());
    $("g-site").addEventListener("change", () => this.chooseSite($("g-site").value));
    for (const id of ["g-latitude", "g-longitude"]) $(id).addEventListener("input", () => this.typed());
    $("site-click-toggle").addEventListener("click", () => this.setPicking(false)); // one use of a map click at a time
    $("guided-jobs").addEventListener("click", (e) => {
      const id = e.target.closest("button[data-cancel]")?.dataset.cancel;
      if (id) api(`/api/jobs/${id}`, { method: "DELETE" }).catch((err) => this.toast(err.message, true));
    });
    this.form.addEventListener("focusin", (e) => { if (e.target.closest("#g-latitude, #g-longitude, #g-site")) this.use(); });
  }

  // ------------------------------------------------------------------------------------------- the target
  /** The panel is in use: its target shown from now on. */
  use() {
    if (this.used) return;
    this.used = true;
    this.drawTarget();
  }

  setPicking(on) {
    if (on) this.use();
    this.picking = on;
    $("g-pick").setAttribute("aria-pressed", String(on));
    this.map.getContainer().classList.toggle("picking-target", on);
    if (on) this.onPick?.();
  }

  /** A map click while picking sets the target (and is not a new site); false: not ours. */
  onMapClick(latlng) {
    if (!this.picking) return false;
    $("g-latitude").value = latlng.lat.toFixed(4);
    $("g-longitude").value = wrapLongitude(latlng.lng).toFixed(4);
    this.typed();
    return true;
  }

  typed() {
    this.used = true;
    this.siteName = null; // a target moved by hand is no longer the site's
    $("g-site").value = "";
    this.drawTarget();
  }

  /** The stored sites to choose from (their names as text), the chosen one kept when it still exists. */
  setSites(sites) {
    this.sites = sites;
    const chosen = $("g-site").value;
    $("g-site").replaceChildren(el("option", { value: "" }, sites.length ? "stored sites…" : "no stored sites"),
      ...sites.map((s) => el("option", { value: String(s.id) },
                             `${s.name} · ${fmt(s.latitude_deg, 2)}°, ${fmt(s.longitude_deg, 2)}°`)));
    if (sites.some((s) => String(s.id) === chosen)) $("g-site").value = chosen;
  }

  chooseSite(id) {
    const s = this.sites.find((t) => String(t.id) === id);
    if (!s) return;
    $("g-latitude").value = String(s.latitude_deg);
    $("g-longitude").value = String(s.longitude_deg);
    this.siteName = s.name;
    this.used = true;
    this.drawTarget();
  }

  /** The target of the inputs, or null with each bad input's message next to it (nothing is sent then). */
  readTarget() {
    const lat = checkedNumber("g-latitude", -90, 90, "deg"), lon = checkedNumber("g-longitude", -180, 180, "deg");
    for (const { error } of [lat, lon]) if (error) showFieldError(this.form, error, $("guided-error"));
    this.use();
    return lat.error || lon.error ? null : { latitude_deg: lat.value, longitude_deg: lon.value };
  }

  targetWords(t) {
    const at = `${fmt(t.latitude_deg, 3)}°, ${fmt(t.longitude_deg, 3)}°`;
    return this.siteName ? `“${this.siteName}” (${at})` : at;
  }

  /** The target of the inputs on the map (when they hold one), on the copy of the shown track's end. */
  drawTarget() {
    this.targetLayer.clearLayers();
    if (!this.used) return;
    const lat = Number($("g-latitude").value), lon = Number($("g-longitude").value);
    if ($("g-latitude").value.trim() === "" || !(Math.abs(lat) <= 90 && Math.abs(lon) <= 180)) return;
    const placed = this.placeNearAnchor(lon);
    const tip = el("div", {}, el("strong", {}, this.siteName ?? "Guidance target"), el("br"),
                   `${fmt(lat, 3)}°, ${fmt(lon, 3)}°`);
    for (const offset of copyOffsets(placed, placed)) {
      L.marker([lat, placed + offset], { keyboard: false, icon: L.divIcon({ className: "guided-target", iconSize: [18, 18] }) })
        .bindTooltip(tip).addTo(this.targetLayer);
    }
  }

  placeNearAnchor(lon) {
    return this.anchorLon == null ? lon : this.anchorLon + wrapLongitude(lon - this.anchorLon);
  }

  zoomToTarget() {
    this.use();
    const lat = Number($("g-latitude").value), lon = this.placeNearAnchor(Number($("g-longitude").value));
    const radius = Number($("g-radius").value) > 0 ? Number($("g-radius").value) : 5;
    if (!Number.isFinite(lat) || !Number.isFinite(lon)) return;
    const ring = smallCircle(lat, lon, radius + (this.interfaceNmi ?? 0)); // the interface's band, and the target
    const size = this.map.getSize(), pad = (px) => Math.max(0, (px - TARGET_BOX_PX) / 2);
    this.map.fitBounds(L.latLngBounds(ring), { maxZoom: this.map.getMaxZoom(), animate: false,
                                               padding: [pad(size.x), pad(size.y)] });
  }

  // ------------------------------------------------------------------------------------------- requests
  /** The job form's case (vehicle, entry, alpha law, stop) with the guided bank law to the target, holding the
   *  vehicle's limits but its dynamic pressure, as examples/fly_guided_lod189.json does: within the 375 psf of a
   *  crewed glider the L/D 1.89 vehicle at (L/D)max reaches none of its usual targets (docs/guidance.md). */
  guidedCase(target) {
    return { ...buildCase(), bank: { law: "guided", target, max_dynamic_pressure_psf: null } };
  }

  clearErrors() {
    clearFieldErrors(this.form);
    clearFieldErrors($("job-form"));
    $("guided-error").hidden = true;
  }

  /** A refusal next to its field: the panel's own, else the job form's case inputs (said here too), else here. */
  showError(err) {
    const jobForm = $("job-form");
    if (inputForField(this.form, err.field) || !inputForField(jobForm, err.field)) {
      showFieldError(this.form, err, $("guided-error"));
      return;
    }
    $("job-panel").open = true;
    const note = showFieldError(jobForm, err, $("guided-error"));
    $("guided-error").textContent = `${note.textContent} (in the job form above)`;
    $("guided-error").hidden = false;
  }

  async fly() {
    this.clearErrors();
    const target = this.readTarget();
    if (!target) return;
    const words = this.targetWords(target), name = this.siteName;
    $("g-fly").disabled = true;
    $("guided-summary").replaceChildren(el("span", { class: "muted" }, `Flying guided to ${words}…`));
    try {
      const answer = await api("/api/trajectories", { method: "POST", body: this.guidedCase(target) });
      this.showFlight(answer, words, name);
    } catch (err) {
      $("guided-summary").replaceChildren();
      this.showError(err);
    } finally {
      $("g-fly").disabled = false;
    }
  }

  async disperse() {
    this.clearErrors();
    const target = this.readTarget();
    if (!target) return;
    const study = { case: this.guidedCase(target), samples: numberOrText("g-samples"), seed: 1,
                    radius_nmi: [numberOrText("g-radius")], ...structuredClone(SPREADS) };
    await this.submit("guided_dispersion", study, `guided dispersion to ${this.targetWords(target)}`.slice(0, 200), "g-disperse");
  }

  // ------------------------------------------------------------------------- an opportunity, flown guided
  /** An opportunities job's footprint case entering where the opportunity's coast reaches the interface, with the
   * guided law to its site (as the opportunities job flies it: contracts/opportunities.py guided_specs). */
  opportunityCase(study, o, site) {
    const c = structuredClone(study.footprint.case);
    c.entry = { ...c.entry, ...o.entry, velocity_frame: "relative" };
    c.bank = { law: "guided", target: { latitude_deg: site.latitude_deg, longitude_deg: wrapLongitude(site.longitude_deg) } };
    return c;
  }

  /** The site made the target (its name kept for the summary). */
  targetSite(site) {
    $("g-latitude").value = String(site.latitude_deg);
    $("g-longitude").value = String(wrapLongitude(site.longitude_deg));
    $("g-site").value = "";
    this.siteName = site.name;
    this.drawTarget();
    $("guided-panel").open = true;
  }

  /** The opportunity's guided flight from its own entry to its site, shown as the panel's flight. */
  async flyOpportunity(study, o, site, buttonId) {
    this.clearErrors();
    this.targetSite(site);
    const words = `${site.name} from revolution ${o.revolution_number ?? o.revolution}'s entry`;
    $(buttonId).disabled = true;
    $("guided-summary").replaceChildren(el("span", { class: "muted" }, `Flying guided to ${words}…`));
    try {
      const answer = await api("/api/trajectories", { method: "POST", body: this.opportunityCase(study, o, site) });
      this.showFlight(answer, words, site.name);
    } catch (err) {
      $("guided-summary").replaceChildren();
      this.showError(err);
    } finally {
      $(buttonId).disabled = false;
    }
  }

  /** The opportunity's guided dispersion: each sample entering where its executed burn's coast does (the burn's
   * errors: contracts/guided_dispersion.py's burn), the vehicle and the air dispersed as the panel's. */
  async disperseOpportunity(study, o, site, buttonId) {
    this.clearErrors();
    this.targetSite(site);
    const orbit = study.tle != null ? { tle: study.tle } : { state: study.state };
    const burn = { ...orbit, burn_utc: o.burn_utc, delta_v_fps: o.delta_v_fps,
                   interface_altitude_ft: study.deorbit.interface_altitude_ft ?? 400000 };
    const { entry: _, ...spreads } = structuredClone(SPREADS); // the entries are the executed burns'
    const guided = { case: this.opportunityCase(study, o, site), samples: numberOrText("g-samples"), seed: 1,
                     radius_nmi: [numberOrText("g-radius")], ...spreads, burn };
    const name = `guided dispersion: ${site.name}, revolution ${o.revolution_number ?? o.revolution}`;
    await this.submit("guided_dispersion", guided, name.slice(0, 200), buttonId);
  }

  /** A job of this kind submitted (its button off meanwhile) and followed in the list; a refusal by its field. */
  async submit(kind, study, name, buttonId) {
    $(buttonId).disabled = true;
    try {
      const job = await api("/api/jobs", { method: "POST", body: { kind, name, study } });
      this.follow(job.id, name);
    } catch (err) {
      this.showError(err);
    } finally {
      $(buttonId).disabled = false;
    }
  }

  /** Every stored site made the target, flown guided in the dispersed samples: a guided reach job. */
  async reachSites() {
    this.clearErrors();
    if (!this.sites.length) {
      this.toast("Store a landing site first (the sites panel below)", true);
      return;
    }
    const target = { latitude_deg: this.sites[0].latitude_deg, longitude_deg: this.sites[0].longitude_deg };
    const sites = this.sites.map(({ name, latitude_deg, longitude_deg }) => ({ name, latitude_deg, longitude_deg }));
    const study = { case: this.guidedCase(target), sites, samples: numberOrText("g-samples"),
                    radius_nmi: numberOrText("g-radius"), seed: 1, ...structuredClone(SPREADS) };
    await this.submit("guided_reach", study, `guided P of ${sites.length} stored site${sites.length === 1 ? "" : "s"}`, "g-reach");
  }

  async traceFootprint() {
    this.clearErrors();
    const target = this.readTarget();
    if (!target) return;
    const study = { case: this.guidedCase(target), rays: numberOrText("gf-rays"), samples: numberOrText("gf-samples"),
                    probability: numberOrText("gf-probability"), radius_nmi: numberOrText("g-radius"),
                    optimal: $("gf-optimal").checked, seed: 1, ...structuredClone(SPREADS) };
    await this.submit("guided_footprint", study, "guided footprint", "g-footprint");
  }

  /** A row with progress and a cancel button, fed by polling GET /api/jobs/{id} until the job ends. */
  follow(id, label) {
    const li = el("li", { dataset: { jobId: id } },
      el("div", { class: "job-line" }, el("span", { class: "job-label" }, label), el("span", { class: "job-status" }, "queued")),
      el("progress", { max: "100", value: "0", "aria-label": `Progress of ${label}` }), " ",
      el("span", { class: "job-percent" }, "0 %"), " ",
      el("button", { type: "button", class: "job-cancel", dataset: { cancel: id } }, "Cancel"));
    $("guided-jobs").prepend(li);
    const poll = async () => {
      for (;;) {
        const job = await api(`/api/jobs/${id}`).catch(() => null);
        if (job) showProgress(li, job);
        if (job && DONE.includes(job.status)) return this.finished(li, job, label);
        await new Promise((r) => setTimeout(r, POLL_MS));
      }
    };
    poll().catch((err) => this.toast(err.message, true));
  }

  finished(li, job, label) {
    const r = job.result?.guided_dispersion, fp = job.result?.guided_footprint;
    if (job.status === "succeeded" && r) {
      li.append(el("div", { class: "succeeded" }, withinWords(r, 0)));
      this.showDispersion(r, label);
    } else if (job.status === "succeeded" && job.result?.guided_reach) {
      const reach = job.result.guided_reach, reached = reach.sites.filter((t) => t.probability >= 0.99).length;
      li.append(el("div", { class: "succeeded" }, `${reached} of ${reach.sites.length} sites with guided P ≥ 99 %`));
      this.onReach?.(reach);
    } else if (job.status === "succeeded" && fp) {
      li.append(el("div", { class: "succeeded" }, footprintWords(fp)));
      this.showFootprint(fp);
    } else if (job.error) {
      li.append(el("div", { class: "failed" }, job.error));
    }
  }

  // ------------------------------------------------------------------------------------------- results
  /** One guided flight: its ground track to the terminal-area interface before the target, its miss of the
   * interface, status and reversals, the interface's state and the touchdown expected, its bank history. */
  showFlight({ summary, history: h }, words, name) {
    const g = summary.guidance, i = g.interface, td = g.touchdown_estimate;
    this.interfaceNmi = g.interface_range_nmi;
    const lons = this.drawResult(h.latitude_deg, h.longitude_deg, null);
    const last = lons.length - 1;
    const off = Object.entries(i.within).filter(([, ok]) => !ok).map(([k]) => k);
    $("guided-summary").replaceChildren(
      el("p", { class: `guided-line ${g.status === "reached" ? "reached" : "missed"}` },
         `Miss ${nmiWords(g.miss_nmi)} nmi · ${g.status} · ${fmt(g.reversals)} reversal${g.reversals === 1 ? "" : "s"}`),
      el("p", { class: "muted interface-line" }, `Terminal-area interface (${fmt(g.interface_range_nmi)} nmi before ${words}): `
         + `${fmt(i.altitude_ft)} ft, ${fmt(i.velocity_fps)} ft/s, ${nmiWords(i.range_to_site_nmi)} nmi from the site, `
         + `heading ${fmt(i.heading_error_deg, 1)}° off it, at ${fmt(i.time_s)} s (${fmt(h.latitude_deg[last], 3)}°, `
         + `${fmt(wrapLongitude(lons[last]), 3)}°); ${i.met ? "within every tolerance" : `outside the tolerance: ${off.join(", ")}`}. `
         + `Touchdown expected at the site at ${fmt(td.time_s)} s (${fmt(td.terminal_area_s)} s of terminal area).`),
      el("p", { class: "muted" }, `${fmt(g.cycles)} guidance cycles, `
         + `${fmt(g.saturated_cycles)} saturated${g.limit_bound ? ", bound by a path limit" : ""}.`));
    this.setFlight(h, `Guided bank${name ? ` to “${name}”` : ""}: miss ${nmiWords(g.miss_nmi)} nmi, ${g.status}, `
                      + `${fmt(g.reversals)} reversals`);
    this.fitTrack();
  }

  /** A guided dispersion: both clouds of ends, the bands of the interface circle about the target that count as
   * within each R, the nominal guided track. */
  showDispersion(r, label) {
    const f = r.nominal_flight;
    this.interfaceNmi = r.target.interface_range_nmi;
    this.drawResult(f.latitude_deg, f.longitude_deg, r);
    const lines = r.radii_nmi.map((radius, i) => el("p", { class: "guided-line" }, withinWords(r, i)));
    const landed = ["guided", "open_loop"].filter((m) => r[m]).map((m) => `${fmt(r[m].landed)} ${m.replace("_", " ")}`);
    $("guided-dispersion-summary").replaceChildren(el("p", {}, el("strong", {}, label)), ...lines,
      el("p", { class: "muted" }, `${fmt(r.samples)} samples, seed ${r.seed}: ${landed.join(", ")} landed; `
         + `${levelWords(r.guided.within[0]?.level ?? 0.95)} Clopper–Pearson intervals. Nominal guided miss ${nmiWords(r.nominal.guidance.miss_nmi)} nmi.`));
    this.setFlight(f, `Nominal guided bank of the dispersion: miss ${nmiWords(r.nominal.guidance.miss_nmi)} nmi, `
                      + `${fmt(r.nominal.guidance.reversals)} reversals`);
    this.fitTrack(true);
  }

  /** A guided footprint's rings on the map (each continuous from its entry, with its copies past +-180 deg; a ring
   * that holds a pole is drawn as a line, unfilled) and its areas and margins in words. */
  showFootprint(r) {
    this.footprintLayer.clearLayers();
    const svg = { renderer: this.mapView.svgRenderer, smoothFactor: 0, noClip: true, interactive: false };
    const main = [];
    this.globeLayers.rings = [];
    for (const [key, , color, dashArray] of RINGS) {
      const ring = r[key];
      if (!ring) continue;
      // placed as a stored footprint is (planarOutline: the service's outline, across +-180 deg and over a pole)
      const { polygons, line } = planarOutline({ points: listPoints(ring), reference: r.entry, outline: ring.outline });
      this.globeLayers.rings.push({ key, color, dash: dashArray, coordinates: line });
      const lons = line.map(([lon]) => lon).concat([-180, 180]); // the area lies within -180..180
      for (const offset of copyOffsets(Math.min(...lons), Math.max(...lons))) {
        if (key === "guided" && polygons?.length) {
          L.polygon(polygons.map((rings) => rings.map((q) => q.map(([lon, lat]) => [lat, lon + offset]))),
                    { ...svg, stroke: false, fillColor: color, fillOpacity: 0.12, className: `gf-area g-copy-${offset}` })
            .addTo(this.footprintLayer);
        }
        const edge = L.polyline(line.map(([lon, lat]) => [lat, lon + offset]),
                                { ...svg, color, weight: key === "guided" ? 2.5 : 1.6, dashArray,
                                  className: `gf-ring gf-${key.replace("_", "-")} g-copy-${offset}` })
          .addTo(this.footprintLayer);
        if (offset === 0) main.push(edge);
      }
    }
    this.onGlobe?.(this.globeLayers);
    $("guided-footprint-summary").replaceChildren(el("p", { class: "guided-line" }, footprintWords(r)),
      el("p", { class: "muted" }, `${fmt(r.settings.rays)} rays, ${fmt(r.settings.samples)} samples a target: `
         + `${fmt(r.flights)} guided flights in ${fmt(r.run.seconds, 1)} s.`));
    this.legend.getContainer().hidden = false;
    this.legendFootprint.hidden = false;
    for (const k of this.legendFootprint.children) k.hidden = !r[k.dataset.ring]; // the rings drawn
    const bounds = L.latLngBounds([]);
    for (const l of main) bounds.extend(l.getBounds());
    if (bounds.isValid()) this.map.fitBounds(bounds.pad(0.1), { maxZoom: 5, animate: false });
  }

  setFlight(h, title) {
    this.flight = { time_s: h.time_s, bank_deg: h.bank_deg, bank_command_deg: h.bank_command_deg,
                    predicted_miss_nmi: h.predicted_miss_nmi ?? null, title };
    this.onFlight?.(this.flight);
  }

  /** The track (unwrapped from its entry, with its copies), and with a dispersion its clouds and circles placed on
   * the copy of the track's end; the target follows. The track's continuous longitudes are returned. */
  drawResult(lats, lonsIn, dispersion) {
    this.resultLayer.clearLayers();
    const lons = unwrapLongitudes(lonsIn, lonsIn[0]);
    this.anchorLon = lons[lons.length - 1];
    this.globeLayers.track = lats.map((lat, i) => [lons[i], lat]);
    this.globeLayers.clouds = dispersion ? cloudPoints(dispersion) : null;
    this.onGlobe?.(this.globeLayers);
    const svg = { renderer: this.mapView.svgRenderer, smoothFactor: 0, noClip: true, interactive: false };
    for (const offset of copyOffsets(Math.min(...lons), Math.max(...lons))) {
      L.polyline(lats.map((lat, i) => [lat, lons[i] + offset]),
                 { ...svg, color: GUIDED_STYLE.track, weight: 2.5, className: `guided-track g-copy-${offset}` })
        .addTo(this.resultLayer);
    }
    if (dispersion) this.drawClouds(dispersion, svg);
    this.used = true; // a guided result shown: its target with it
    this.drawTarget();
    this.legend.getContainer().hidden = false;
    this.legendDispersion.hidden = !dispersion;
    return lons;
  }

  drawClouds(r, svg) {
    const t = r.target, lon = this.placeNearAnchor(t.longitude_deg), radius = r.radii_nmi[0];
    for (const offset of copyOffsets(lon, lon)) {
      for (const R of r.radii_nmi) { // within R of the interface circle: a band (a disc when the circle is smaller)
        const outer = t.interface_range_nmi + R, inner = t.interface_range_nmi - R;
        const rings = [smallCircle(t.latitude_deg, lon + offset, outer)];
        if (inner > 0) rings.push(smallCircle(t.latitude_deg, lon + offset, inner));
        const band = L.polygon(rings, { ...svg, color: GUIDED_STYLE.circle, weight: 1.5, dashArray: "5 4", fillOpacity: 0.06,
                                        className: `guided-circle g-copy-${offset}` }).addTo(this.resultLayer);
        Object.assign(band.getElement().dataset, { radiusNmi: String(R), outerNmi: String(outer),
                                                   innerNmi: String(Math.max(inner, 0)) });
      }
      for (const mode of ["open_loop", "guided"]) { // the guided dots over the open loop's
        const c = r.clouds?.[mode];
        c?.latitude_deg.forEach((lat, i) => {
          if (lat == null || c.longitude_deg[i] == null) return; // a sample that did not land
          const at = [lat, lon + wrapLongitude(c.longitude_deg[i] - lon) + offset];
          const dot = L.circleMarker(at, { ...svg, radius: mode === "guided" ? 3 : 2.5, weight: 0, fillOpacity: 0.85,
            fillColor: mode === "guided" ? GUIDED_STYLE.guided : GUIDED_STYLE.openLoop,
            className: `guided-point guided-${mode.replace("_", "-")} g-copy-${offset}` }).addTo(this.resultLayer);
          Object.assign(dot.getElement().dataset, { mode, sample: String(i), missNmi: String(c.miss_nmi[i]),
                                                    within: String(c.miss_nmi[i] <= radius) });
        });
      }
    }
  }

  /** The view on the main copy of what is shown: the track, and a dispersion's far open-loop landings too. */
  fitTrack(withClouds = false) {
    const shown = this.resultLayer.getLayers().filter((l) => l.options.className.endsWith(" g-copy-0")
      && (withClouds || l.options.className.startsWith("guided-track")));
    const bounds = L.latLngBounds([]);
    for (const l of shown) bounds.extend(l.getBounds?.() ?? l.getLatLng());
    if (bounds.isValid()) this.map.fitBounds(bounds.pad(0.25), { maxZoom: 5, animate: false });
  }

  addLegend() {
    const key = (cls, text) => el("div", {}, el("span", { class: cls }), text);
    this.legendDispersion = el("div", { hidden: "" }, key("dot guided-dot", "guided ends (interface)"),
      key("dot open-loop-dot", "open loop (nominal guided bank)"), key("ring", "within R of the interface circle"));
    this.legendFootprint = el("div", { hidden: "" }, ...RINGS.map(([k, words]) =>
      el("div", { dataset: { ring: k } }, el("span", { class: `ring-key gf-key-${k.replace("_", "-")}` }), words)));
    this.legend = L.control({ position: "topright" });
    this.legend.onAdd = () => {
      const div = el("div", { class: "map-legend guided-legend" }, el("strong", {}, "Guided entry"),
                     key("line guided-line-key", "guided track"), key("target-key", "target"), this.legendDispersion,
                     this.legendFootprint);
      div.hidden = true;
      return div;
    };
    this.legend.addTo(this.map);
  }
}

function showProgress(li, job) {
  const pct = Math.round(100 * (job.status === "succeeded" ? 1 : job.progress ?? 0));
  li.querySelector("progress").value = pct;
  li.querySelector(".job-percent").textContent = `${pct} %`;
  const s = li.querySelector(".job-status");
  s.textContent = job.status;
  s.className = `job-status ${job.status}`;
  li.querySelector(".job-cancel").hidden = DONE.includes(job.status);
}

const bracketWords = ([lo, hi]) => `[${percent(lo)}, ${percent(hi)}]`;

/** "guided: P(within 5 nmi) = 100 % [63.1 %, 100 %], CEP 0.18 nmi; open loop: P = 0 % [0 %, 36.9 %], CEP 645 nmi". */
export function withinWords(r, i) {
  const words = (m) => {
    const w = r[m].within[i];
    return `${percent(w.probability)} ${bracketWords(w.interval)}, CEP ${nmiWords(r[m].miss_nmi?.cep)} nmi`;
  };
  const guided = `guided: P(within ${+r.radii_nmi[i].toFixed(3)} nmi) = ${words("guided")}`;
  return r.open_loop ? `${guided}; open loop: P = ${words("open_loop")}` : guided;
}

const areaWords = (nmi2) => `${fmt(nmi2 / 1e6, 2)} million nmi²`;

/** "guided footprint 24.37 million nmi²; margin to the report's 16.99 million nmi² (41 %), inside at every ray". */
export function footprintWords(r) {
  const margins = ["report", "optimal"].filter((k) => r[`margin_to_${k}`]).map((k) => {
    const m = r[`margin_to_${k}`];
    return `margin to the ${k === "report" ? "report's" : "true optimal"} ${areaWords(m.area_nmi2)} (${fmt(m.percent, 0)} %)`
      + `, ${m.inside_at_every_ray ? "inside at every ray" : "not inside at every ray"}`;
  });
  return [`guided footprint ${areaWords(r.guided.area_nmi2)}`, ...margins].join("; ");
}

// ------------------------------------------------------------------------------------------- the bank plot
const M = { left: 48, right: 14, top: 40, bottom: 34 };

/** An SVG path through (t, v), broken where a value is missing. */
function pathData(time, values, sx, sy) {
  let d = "", pen = "M";
  values.forEach((v, i) => {
    if (v == null || !Number.isFinite(v)) { pen = "M"; return; }
    d += `${pen}${sx(time[i]).toFixed(1)},${sy(v).toFixed(1)}`;
    pen = "L";
  });
  return d;
}

/** One panel of series against flight time: frame, grid, ticks, the zero line and each series ({values, cls}). */
function seriesPanel({ x, w, h, time, series, label, zeroClass }) {
  const values = series.flatMap((s) => s.values).filter((v) => v != null && Number.isFinite(v));
  const tmax = Math.max(...time);
  const xt = niceTicks(0, tmax, Math.max(2, Math.floor(w / 90)));
  const yt = niceTicks(Math.min(0, ...values), Math.max(0, ...values), 4);
  const [x0, x1, y0, y1] = [0, Math.max(xt.at(-1), tmax), Math.min(yt[0], ...values), Math.max(yt.at(-1), ...values)];
  const left = x + M.left, pw = w - M.left - M.right, ph = h - M.top - M.bottom;
  const sx = (v) => left + ((v - x0) / (x1 - x0 || 1)) * pw;
  const sy = (v) => M.top + ph - ((v - y0) / (y1 - y0 || 1)) * ph;
  const parts = gridAndTicks({ xt, yt, sx, sy, left, top: M.top, width: pw, height: ph });
  const zero = sy(0).toFixed(1); // as the paths' vertices: a zero value lies on the line
  parts.push(`<line class="axis-zero ${zeroClass}" x1="${left}" x2="${left + pw}" y1="${zero}" y2="${zero}"/>`,
             `<rect class="frame" x="${left}" y="${M.top}" width="${pw}" height="${ph}"/>`,
             ...series.map((s) => `<path class="history ${s.cls}" d="${pathData(time, s.values, sx, sy)}"/>`),
             `<text class="axis-label" x="${left}" y="${M.top - 6}">${label}</text>`,
             `<text class="axis-label" x="${left + pw / 2}" y="${h - 4}" text-anchor="middle">Flight time (s)</text>`);
  return { parts, right: left + pw };
}

/** The bank a guided flight flew and the one its guidance commanded against time (a reversal: a change of sign),
 * and beside it, when the flight has it and there is room, the miss the guidance predicted at each cycle. */
export function drawBankPlot(container, flight) {
  if (!flight) {
    container.innerHTML = '<p class="empty">Fly a guided entry to plot its bank, flown and commanded.</p>';
    return;
  }
  const width = Math.max(container.clientWidth, 240), height = Math.max(container.clientHeight, 160);
  const miss = flight.predicted_miss_nmi && width >= 640;
  const bankWidth = miss ? Math.round(width * 0.62) : width;
  const bank = seriesPanel({ x: 0, w: bankWidth, h: height, time: flight.time_s, label: "Bank (deg)", zeroClass: "bank-zero",
                             series: [{ values: flight.bank_command_deg, cls: "bank-command" },
                                      { values: flight.bank_deg, cls: "bank-flown" }] });
  const parts = [...bank.parts, legendKeys(bank.right, M.top - 10)];
  if (miss) {
    parts.push(...seriesPanel({ x: bankWidth, w: width - bankWidth, h: height, time: flight.time_s, zeroClass: "miss-zero",
                                label: "Predicted miss (nmi; + long, − short)", series: [{ values: flight.predicted_miss_nmi, cls: "predicted-miss" }] }).parts);
  }
  container.innerHTML = `<svg xmlns="${SVG_NS}" class="range-plot bank-plot" viewBox="0 0 ${width} ${height}" width="${width}" `
    + `height="${height}" role="img"><text class="plot-title" x="6" y="15"></text>${parts.join("")}</svg>`;
  // the title may name a site: set as text, never parsed
  container.querySelector(".plot-title").textContent = flight.title;
  container.querySelector("svg").setAttribute("aria-label", flight.title);
}

function legendKeys(right, y) {
  const key = (x, cls, text) => `<line class="history ${cls}" x1="${x}" x2="${x + 18}" y1="${y - 4}" y2="${y - 4}"/>`
    + `<text class="tick" x="${x + 22}" y="${y}">${text}</text>`;
  return key(right - 180, "bank-flown", "flown") + key(right - 110, "bank-command", "commanded");
}
