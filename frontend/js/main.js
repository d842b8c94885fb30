// The map page: stored footprints on the cylindrical map and the globe, moved live around orbits through the
// transform endpoint, new jobs, dispersions, landing sites and reach, exports and the range plot.
import { api } from "./api.js";
import { DispersionPanel, fileStem, placeDispersion } from "./dispersion.js";
import { drawDispersionPlot } from "./dispersionplot.js";
import { exportCSV, exportDispersion, exportGeoJSON, exportPNG } from "./exporting.js";
import { el, fmt } from "./format.js";
import { orbitOfEntry, transformRequest, wrapLongitude } from "./geometry.js";
import { GlobeView, flightLine, lineMiddle } from "./globe.js";
import { GuidedPanel, drawBankPlot } from "./guided.js";
import { JobsPanel } from "./jobs.js";
import { MapView } from "./mapview.js";
import { OPPORTUNITY_STYLE, OpportunitiesPanel } from "./opportunities.js";
import { drawHistories } from "./histories.js";
import { drawRangePlot } from "./rangeplot.js";
import { coloredWindows, drawTimeline } from "./timeline.js";
import { SitesPanel } from "./sites.js";

const $ = (id) => document.getElementById(id);
const PALETTE = ["#1f6fbf", "#d1495b", "#2a9d8f", "#8e5dbf", "#e08a1e", "#5c7c2e", "#c2549b", "#3d5a80"];
const DEBOUNCE_MS = 150; // the polygon follows a dragged control without a request per pixel
const SAME_DEG = 1e-9;

const state = { footprints: new Map(), selectedId: null, view: "map", colorIndex: 0, optimum: null, reach: null,
                dispersion: null, plot: "range" };
const OPTIMUM_COLOR = "#111827";

function toast(message, isError = false) {
  const t = $("toast");
  t.textContent = message;
  t.className = `toast${isError ? " error" : ""}`;
  t.hidden = false;
  clearTimeout(toast.timer);
  toast.timer = setTimeout(() => { t.hidden = true; }, isError ? 6000 : 3000);
}

// a click picks the guided target while its toggle is on, else it may add a site
const mapView = new MapView($("map"), { onClick: (latlng) => guided.onMapClick(latlng) || sites.onMapClick(latlng) });
const globe = new GlobeView($("globe"));
const sites = new SitesPanel({ onChange: () => redrawSites(), onReach: (result) => showReach(result),
                               selectedFootprint: () => selected(), toast });
const jobs = new JobsPanel({ onSucceeded: (job) => showJobFootprints(job), onOptimum: (name, result) => showOptimum(name, result),
                             onDispersion: (name, d, job) => showDispersion(name, d, job), sites: () => sites.sites });
const dispersionPanel = new DispersionPanel({ onLayer: (kind, on) => { mapView.setDispersionLayer(kind, on); drawGlobeDispersion(); },
                                              onShowJob: (id) => showDispersionJob(id).catch(fail),
                                              onDownload: (format) => exportDispersion(state.dispersion, format).catch(fail) });
const guided = new GuidedPanel({ mapView, toast, onPick: () => sites.setAdding(false), onReach: (r) => sites.setGuided(r),
                                 onGlobe: (g) => globe.setGuided(g),
                                 onFlight: () => { $("plot-guided").disabled = false; setPlot("guided"); } });
const opportunities = new OpportunitiesPanel({
  onGuided: (what, study, o, site, buttonId) => (what === "fly" ? guided.flyOpportunity(study, o, site, buttonId)
    : guided.disperseOpportunity(study, o, site, buttonId)),
  mapView, onGlobe: (o) => globe.setOpportunity(o),
  onResult: () => { $("plot-opportunities").disabled = false; setPlot("opportunities"); },
  onSelect: () => { if (state.plot === "opportunities") drawPlot(); centerGlobeOnOpportunity(); },
});

const selected = () => state.footprints.get(state.selectedId) ?? null;
const visible = () => [...state.footprints.values()].filter((fp) => fp.visible && fp.shown);

// ------------------------------------------------------------------------------------------- footprints
function storedGeometry(fp) {
  const e = fp.item.entry;
  return { points: fp.detail.points, groundTrack: fp.detail.ground_track ?? [], outline: fp.detail.outline, geojson: null,
           reference: { latitude_deg: e.latitude_deg, longitude_deg: e.longitude_deg, heading_deg: e.heading_deg } };
}

function addItem(item) {
  if (state.footprints.has(item.id)) return state.footprints.get(item.id);
  const fp = { id: item.id, item, name: item.name || `${item.vehicle} ${item.method.replace(/_/g, " ")}`,
               color: PALETTE[state.colorIndex++ % PALETTE.length], visible: false, detail: null, shown: null,
               orbit: null, controls: null };
  state.footprints.set(item.id, fp);
  return fp;
}

async function loadDetail(fp) {
  if (fp.detail) return;
  fp.detail = await api(`/api/footprints/${fp.id}`);
  const e = fp.item.entry;
  fp.orbit = orbitOfEntry(e.latitude_deg, e.longitude_deg, e.heading_deg);
  fp.controls = { nodeLongitudeDeg: round(fp.orbit.nodeLongitudeDeg), inclinationDeg: round(fp.orbit.inclinationDeg),
                  stepDownrangeNmi: 0, earthRotation: "none" };
  fp.shown = storedGeometry(fp);
}
const round = (v) => Math.round(v * 100) / 100; // the controls show 0.01 deg

async function loadFootprints() {
  const { items, total } = await api("/api/footprints?limit=200");
  items.slice().reverse().forEach(addItem); // oldest first, so colours stay put as new ones arrive
  $("footprints-status").textContent = total ? "" : "No footprints stored yet: run a job below.";
  renderList();
  return items;
}

async function setVisible(fp, on) {
  fp.visible = on;
  if (on) await loadDetail(fp);
  redraw(fp);
  renderList();
}

async function select(id, { fit = false } = {}) {
  const fp = state.footprints.get(id);
  state.selectedId = id;
  if (!fp.visible) await setVisible(fp, true);
  renderList();
  setControls(fp);
  setPlot("range");
  if (fit) mapView.fitFootprint(fp);
  if (state.view === "globe") centerGlobe(fp);
}

function redraw(fp) {
  if (fp.visible && fp.shown) mapView.drawFootprint(fp); else mapView.removeFootprint(fp.id);
  mapView.setLegend(visible());
  globe.setData(visible(), sites.shown());
  if (fp.id === state.selectedId) drawPlot();
}

function redrawSites() {
  mapView.setSites(sites.shown());
  guided.setSites(sites.sites);
  opportunities.setSites(sites.sites);
  if (state.dispersion) drawDispersion(); // a site of the study is named on the map unless it is a stored one
  globe.setData(visible(), sites.shown());
}

function renderList() {
  $("footprint-list").replaceChildren(...[...state.footprints.values()].reverse().map((fp) => {
    const it = fp.item;
    const meta = `max X ${fmt(it.max_crossrange_nmi)} · D ${fmt(it.min_downrange_nmi)}–${fmt(it.max_downrange_nmi)} nmi`;
    const selected = fp.id === state.selectedId;
    return el("li", { class: selected ? "selected" : "", dataset: { id: fp.id } },
      el("input", { type: "checkbox", class: "fp-visible", checked: fp.visible, "aria-label": `Show ${fp.name}` }),
      el("span", { class: "swatch", style: { background: fp.color } }),
      el("button", { type: "button", class: "fp-select", "aria-pressed": String(selected) }, fp.name,
         el("span", { class: "meta" }, meta)),
      el("button", { type: "button", class: "fp-rename icon", "aria-label": `Rename ${fp.name}`, title: "Rename" }, "✎"),
      el("button", { type: "button", class: "fp-delete icon", "aria-label": `Delete ${fp.name}`, title: "Delete" }, "×"));
  }));
}

// the list is drawn afresh on every change: give the focus back to the control the user was on
const refocus = (id, selector) => document.querySelector(`#footprint-list li[data-id="${id}"] ${selector}`)?.focus();
$("footprint-list").addEventListener("change", (e) => {
  const id = e.target.closest("li")?.dataset.id;
  if (id && e.target.classList.contains("fp-visible")) {
    setVisible(state.footprints.get(id), e.target.checked).then(() => refocus(id, ".fp-visible")).catch(fail);
  }
});
$("footprint-list").addEventListener("click", (e) => {
  const button = e.target.closest("button");
  const id = button?.closest("li").dataset.id;
  if (!id) return;
  if (button.classList.contains("fp-select")) select(id, { fit: true }).then(() => refocus(id, ".fp-select")).catch(fail);
  else if (button.classList.contains("fp-rename")) startRename(id);
  else if (button.classList.contains("fp-delete")) deleteFootprint(id).catch(fail);
});

/** The name becomes a text field: Enter stores the new name (the service may number it), Escape keeps the old. */
function startRename(id) {
  const fp = state.footprints.get(id), li = document.querySelector(`#footprint-list li[data-id="${id}"]`);
  const input = document.createElement("input");
  Object.assign(input, { value: fp.name, className: "fp-name-input", maxLength: 200 });
  input.setAttribute("aria-label", `New name of ${fp.name}`);
  li.querySelector(".fp-select").replaceWith(input);
  input.focus();
  input.select();
  input.addEventListener("keydown", async (e) => {
    if (e.key === "Escape") { renderList(); refocus(id, ".fp-rename"); return; }
    if (e.key !== "Enter") return;
    try {
      const item = await api(`/api/footprints/${id}`, { method: "PATCH", body: { name: input.value } });
      fp.item = { ...fp.item, name: item.name };
      fp.name = item.name;
      renderList();
      redraw(fp);
      refocus(id, ".fp-select");
    } catch (err) { toast(err.message, true); }
  });
}

async function deleteFootprint(id) {
  const fp = state.footprints.get(id);
  if (!window.confirm(`Delete the footprint “${fp.name}” and its points for good?`)) return;
  await api(`/api/footprints/${id}`, { method: "DELETE" });
  mapView.removeFootprint(id);
  state.footprints.delete(id);
  if (state.selectedId === id) state.selectedId = null;
  renderList();
  mapView.setLegend(visible());
  globe.setData(visible(), sites.shown());
  drawPlot();
  toast(`Deleted “${fp.name}”`);
}

async function showJobFootprints(job) {
  const ids = (job.result?.footprints ?? []).map((url) => url.split("/").pop());
  await loadFootprints();
  for (const id of ids) if (state.footprints.has(id)) await setVisible(state.footprints.get(id), true);
  if (ids.length && state.footprints.has(ids[0])) await select(ids[0], { fit: true });
  toast(ids.length ? `Job done: ${ids.length} footprint${ids.length > 1 ? "s" : ""} added` : "Job done");
}

// ------------------------------------------------------------------------------------------ plot, optimum
const PLOTS = { range: () => drawRangePlot($("plot"), selected()), optimum: () => drawHistories($("plot"), state.optimum),
                reach: () => drawTimeline($("plot"), state.reach), dispersion: () => drawDispersionPlot($("plot"), state.dispersion),
                guided: () => drawBankPlot($("plot"), guided.flight), opportunities: () => opportunities.drawTimeline($("plot")) };
const drawPlot = () => PLOTS[state.plot]();

function setPlot(which) {
  state.plot = which;
  for (const name of Object.keys(PLOTS)) $(`plot-${name}`).setAttribute("aria-pressed", String(which === name));
  drawPlot();
}

/** A reach analysis: the deorbit points of each window on the map, the windows in time in the plot. */
function showReach(result) {
  state.reach = result;
  const windows = coloredWindows(result);
  mapView.drawReach(windows);
  globe.setReach(windows);
  mapView.setLegend(visible());
  $("plot-reach").disabled = false;
  setPlot("reach");
}

/** An optimization job's optimum: its ground track on the map and its histories in the plot. */
function showOptimum(name, result) {
  if (!result.flight) return;
  state.optimum = { name, color: OPTIMUM_COLOR, result };
  mapView.drawOptimum(state.optimum);
  mapView.setLegend(visible());
  mapView.fitOptimum();
  globe.setOptimum(state.optimum);
  if (state.view === "globe") centerGlobeOnOptimum();
  $("plot-optimum").disabled = false;
  setPlot("optimum");
}
/** A dispersion job's result on the map, in the panels and in the plot (`job`: its {id, name}). */
function showDispersion(name, dispersion, job) {
  state.dispersion = { name, dispersion, placed: placeDispersion(dispersion), jobId: job.id, fileStem: fileStem(job) };
  dispersionPanel.show(name, dispersion, state.dispersion.placed);
  sites.setDispersion(name, dispersion.sites); // redraws the sites, and with them draws the dispersion
  mapView.fitDispersion();
  $("plot-dispersion").disabled = false;
  setPlot("dispersion");
  dispersionPanel.loadJobs().catch(fail);
}

function drawDispersion() {
  const { name, dispersion, placed } = state.dispersion;
  mapView.drawDispersion(placed, { name, samples: dispersion.samples, layers: dispersionPanel.layers() });
  mapView.setLegend(visible());
  drawGlobeDispersion();
}

function drawGlobeDispersion() {
  if (state.dispersion) globe.setDispersion(state.dispersion.name, state.dispersion.dispersion, dispersionPanel.layers());
}

async function showDispersionJob(id) {
  const job = await api(`/api/jobs/${id}`);
  if (!job.result?.dispersion) throw new Error(`job ${id} has no dispersion result`);
  showDispersion(job.name || `dispersion ${id.slice(0, 8)}`, job.result.dispersion, job);
}

$("plot-range").addEventListener("click", () => setPlot("range"));
$("plot-dispersion").addEventListener("click", () => setPlot("dispersion"));
$("plot-optimum").addEventListener("click", () => setPlot("optimum"));
$("plot-reach").addEventListener("click", () => setPlot("reach"));
$("plot-guided").addEventListener("click", () => setPlot("guided"));
$("plot-opportunities").addEventListener("click", () => setPlot("opportunities"));

// ---------------------------------------------------------------------------------- live geometry
const CONTROLS = [["node-longitude", "nodeLongitudeDeg"], ["inclination", "inclinationDeg"], ["step-downrange", "stepDownrangeNmi"]];
let liveTimer = null, liveSequence = 0, liveAbort = null;

function setControls(fp) {
  $("live-controls").disabled = !fp?.controls;
  if (!fp?.controls) return;
  $("live-target").textContent = `Moving “${fp.name}”: its entry rides the orbit at argument of latitude ${fmt(fp.orbit.uDeg, 1)}°.`;
  for (const [id, key] of CONTROLS) { $(id).value = fp.controls[key]; $(`${id}-range`).value = fp.controls[key]; }
  $("earth-rotation").value = fp.controls.earthRotation;
}

function readControls() {
  const fp = selected();
  if (!fp?.controls) return;
  for (const [id, key] of CONTROLS) fp.controls[key] = Number($(id).value) || 0;
  fp.controls.earthRotation = $("earth-rotation").value;
  clearTimeout(liveTimer);
  liveTimer = setTimeout(() => moveFootprint(fp), DEBOUNCE_MS);
}

for (const [id] of CONTROLS) {
  $(`${id}-range`).addEventListener("input", () => { $(id).value = $(`${id}-range`).value; readControls(); });
  $(id).addEventListener("input", () => { $(`${id}-range`).value = $(id).value; readControls(); });
}
$("earth-rotation").addEventListener("change", readControls);
$("live-reset").addEventListener("click", () => {
  const fp = selected();
  if (!fp?.orbit) return;
  fp.controls = { nodeLongitudeDeg: round(fp.orbit.nodeLongitudeDeg), inclinationDeg: round(fp.orbit.inclinationDeg),
                  stepDownrangeNmi: 0, earthRotation: "none" };
  setControls(fp);
  readControls();
});

function atStoredOrbit(fp) {
  const c = fp.controls, o = fp.orbit;
  return c.earthRotation === "none" && c.stepDownrangeNmi === 0 && Math.abs(c.inclinationDeg - round(o.inclinationDeg)) < SAME_DEG
    && Math.abs(wrapLongitude(c.nodeLongitudeDeg - round(o.nodeLongitudeDeg))) < SAME_DEG;
}

/** POST the transform; a response that a newer request has overtaken is dropped, never drawn. */
async function moveFootprint(fp) {
  const sequence = ++liveSequence;
  liveAbort?.abort();
  liveAbort = new AbortController();
  if (atStoredOrbit(fp)) {
    fp.shown = storedGeometry(fp);
    fp.stale = false;
    $("live-status").textContent = "At the stored orbit.";
    redraw(fp);
    return;
  }
  $("live-status").textContent = fp.controls.earthRotation === "exact" ? "Flying again on the rotating earth…" : "Moving…";
  try {
    const result = await api(`/api/footprints/${fp.id}/transform`,
                             { method: "POST", body: transformRequest(fp.orbit, fp.controls), signal: liveAbort.signal });
    if (sequence !== liveSequence) return;
    fp.shown = shownFromTransform(fp, result);
    fp.stale = false;
    const r = fp.shown.reference;
    const e = fp.shown.approximateError;
    $("live-status").textContent = `Entry at ${fmt(r.latitude_deg, 2)}°, ${fmt(r.longitude_deg, 2)}°, heading ${fmt(r.heading_deg, 1)}°`
      + ` (${ROTATION_WORDS[result.earth_rotation] ?? result.earth_rotation}).`
      + (e?.points ? ` The approximate shift (IV.3) lies up to ${fmt(e.max)} nmi from the exact points, ${fmt(e.mean)} nmi `
                     + `on average over ${e.points}.` : "");
    redraw(fp);
  } catch (err) {
    if (err.name === "AbortError" || sequence !== liveSequence) return;
    fp.stale = true; // the drawing no longer matches the controls: say so on the map and under them
    $("live-status").textContent = `Not moved: ${err.message}. The footprint drawn (hatched) is where the last `
      + "accepted move put it.";
    redraw(fp);
  }
}

/** The transform's moved points, with each stored point's control parameter kept (the moved points come back in
 * the same order; an "exact" transform flies again and names its own parameters). */
// a move's earth rotation as the controls say it ("(none earth rotation)" read as code)
const ROTATION_WORDS = { none: "no earth rotation", approximate: "earth rotation approximated, IV.3",
                         exact: "flown again on the rotating earth" };

function shownFromTransform(fp, result) {
  let points = result.points;
  if (result.earth_rotation === "exact") points = points.filter((p) => p.on_boundary !== false);
  else if (points.length === fp.detail.points.length) {
    points = points.map((p, i) => ({ parameter: fp.detail.points[i].parameter, ...p }));
  }
  return { points, groundTrack: result.ground_track ?? [], reference: result.reference, outline: result.outline,
           geojson: result.geojson, approximateError: result.approximate_error_nmi ?? null };
}

// ------------------------------------------------------------------------------------- views, exports
function setView(view) {
  state.view = view;
  $("view-map").setAttribute("aria-pressed", String(view === "map"));
  $("view-globe").setAttribute("aria-pressed", String(view === "globe"));
  $("map").hidden = view !== "map";
  $("globe").hidden = view !== "globe";
  if (view === "map") mapView.invalidate();
  else {
    if (state.plot === "dispersion" && state.dispersion) centerGlobeOn(state.dispersion.dispersion.nominal);
    else if (state.plot === "opportunities" && opportunities.globeCenter) centerGlobeOnOpportunity();
    else if (state.plot === "optimum" && state.optimum) centerGlobeOnOptimum();
    else if (selected()) centerGlobe(selected());
    globe.render();
  }
}

const centerGlobe = (fp) => centerGlobeOn(fp.shown.points);
// the chosen landing opportunity: between its entry and its site
const centerGlobeOnOpportunity = () => { if (opportunities.globeCenter) globe.center(...opportunities.globeCenter); };

// the optimum's ground track, whole in view (to a pole, over one and on past it)
const centerGlobeOnOptimum = () => globe.center(...lineMiddle(flightLine(state.optimum.result.flight)));

function centerGlobeOn(points) {
  // the middle of the footprint's points (mean of unit vectors), so the whole footprint faces the viewer
  let x = 0, y = 0, z = 0;
  for (const p of points) {
    if (p.latitude_deg == null) continue;
    const la = p.latitude_deg * Math.PI / 180, lo = p.longitude_deg * Math.PI / 180;
    x += Math.cos(la) * Math.cos(lo); y += Math.cos(la) * Math.sin(lo); z += Math.sin(la);
  }
  globe.center(Math.atan2(y, x) * 180 / Math.PI, Math.atan2(z, Math.hypot(x, y)) * 180 / Math.PI);
}

$("view-map").addEventListener("click", () => setView("map"));
$("view-globe").addEventListener("click", () => setView("globe"));
// the shown dispersion as its layers show it, for the exports
const shownDispersion = () => state.dispersion && { ...state.dispersion, layers: dispersionPanel.layers() };
$("export-geojson").addEventListener("click", () => exportGeoJSON(visible(), sites.shown(), shownDispersion()).catch(fail));
$("export-csv").addEventListener("click", () => exportCSV(visible()));
// the chosen landing opportunity as the globe draws it (the map's places), with its words
const shownOpportunity = () => globe.opportunity
  && { ...globe.opportunity, caption: opportunities.caption(), style: OPPORTUNITY_STYLE };
$("export-png").addEventListener("click", () => exportPNG({ view: state.view, mapView, globe, footprints: visible(),
                                                             sites: sites.shown(), dispersion: shownDispersion(),
                                                             optimum: state.optimum, opportunity: shownOpportunity(),
                                                             reach: globe.reach })
  .catch(fail));
new ResizeObserver(() => { drawPlot(); if (state.view === "globe") globe.render(); }).observe($("plot"));

function fail(err) { console.error(err); toast(err.message || String(err), true); }

// ------------------------------------------------------------------------------------------- start
async function start() {
  // the optional online tile layer: only when the service has one (FOOTPRINT_TILE_URL); a failure only costs it
  const config = api("/api/config").then((c) => { if (c.tile_url) mapView.addTileLayer(c.tile_url); })
    .catch((err) => console.warn(`no tile layer: ${err.message || err}`));
  await Promise.all([mapView.ready, globe.ready, config]);
  const [items] = await Promise.all([loadFootprints(), jobs.loadVehicles(), sites.load(), dispersionPanel.loadJobs()]);
  const first = items.slice(0, 6); // the newest few drawn at once; the rest one tick away in the list
  for (const item of first) await setVisible(state.footprints.get(item.id), true);
  if (first.length) await select(first[0].id);
  mapView.fitFootprints(visible());
  drawPlot();
  document.body.dataset.ready = "true"; // the browser tests wait for this
  console.info(`map page ready in ${Math.round(performance.now())} ms`);
}

window.footprintApp = { state, mapView, globe, sites, jobs, guided, opportunities, setView, select, setVisible, showDispersionJob,
                        ready: start().catch(fail) };
