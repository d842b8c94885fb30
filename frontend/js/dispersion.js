// A dispersion job's result (issue 16) on the page: its shapes placed on the map's copy of the world, the panel of
// its layers and counted outcomes, the site probabilities beside the reach table, the flights' table.
import { api } from "./api.js";
import { el, fmt } from "./format.js";
import { copyOffsets, describeParameter, listPoints, nearestAnchor, openRing, placeOnRing, planarOutline,
         unwrapRing, wrapLongitude } from "./geometry.js";
import { outcomeWords } from "./jobs.js";

const $ = (id) => document.getElementById(id);
export const LAYERS = ["nominal", "confidence", "ellipses", "clouds", "sites"];
const ELLIPSE_SIGMA = "3"; // the ellipses drawn: 3 sigma (the result also has 1 sigma)
/** How the map draws a dispersion's kinds (CSS pixels), and its PNG with them. */
export const DISPERSION_STYLE = {
  nominal: { color: "#14304f", widthPx: 2, dashPx: [8, 5] },
  confidence: { color: "#6a3d9a", widthPx: 1.6, opacity: 0.9, labelColor: "#4a2a6e" },
  ellipse: { color: "#d95f02", widthPx: 1.6 },
  cloud: { color: "#1d2733", opacity: 0.5, sizePx: 2 },
  site: { edgeColor: "#1d2733", widthPx: 1.5, radiusPx: 7, aroundStoredPx: 11 }, // a ring round a stored site's diamond
};
/** A confidence footprint's fill opacity: darker at a higher level (rank 0 the widest, lowest level). */
export const confidenceOpacity = (rank) => 0.1 + 0.14 * rank;

/** A colour between light grey (probability 0) and blue (1). */
export function probabilityColor(p) {
  const a = [217, 217, 217], b = [8, 81, 156]; // grey to blue: green and red are the reach verdict's (issue 25 item 4)
  return `rgb(${a.map((v, i) => Math.round(v + (b[i] - v) * Math.max(0, Math.min(1, p)))).join(",")})`;
}

// the layer that shows each kind of feature of GET /api/jobs/{id}/dispersion?format=geojson (the entry goes with the
// nominal footprint it starts; the landing points are no feature there)
const FEATURE_LAYER = { nominal_footprint: "nominal", entry: "nominal", confidence_footprint: "confidence",
                        ellipse: "ellipses", site: "sites" };

/** Whether the map shows a feature of the dispersion's GeoJSON with these layers on: of the ellipses, the 3 sigma. */
export function featureShown(properties, layers) {
  const { kind, sigma } = properties;
  return Boolean(layers[FEATURE_LAYER[kind]]) && (kind !== "ellipse" || sigma === Number(ELLIPSE_SIGMA));
}

/** The service's dispersion of a job as GeoJSON or CSV of its sites (docs/api.md). */
export const dispersionURL = (jobId, format) => `/api/jobs/${encodeURIComponent(jobId)}/dispersion?format=${format}`;

/** The start of a downloaded file's name: "dispersion-" and the job's ({id, name}) name in letters, digits, ".", "_"
 * and "-" (a file system takes them all), or its id when it has no name. */
export function fileStem(job) {
  const name = (job.name ?? "").replace(/[^\p{L}\p{N}_.-]+/gu, "-").replace(/^[-.]+|-+$/g, "").slice(0, 80);
  return `dispersion-${name || job.id}`;
}

/** A probability for people: "87.2 %", "0 %", "100 %". */
export const percent = (p) => (p == null ? "–" : p === 0 || p === 1 ? `${fmt(100 * p)} %` : `${fmt(100 * p, 1)} %`);
/** A confidence level for people: "99 %", "99.5 %". */
export const levelWords = (p) => `${+(100 * p).toFixed(1)} %`;
export const intervalWords = ([low, high]) => `${fmt(100 * low, 1)}–${fmt(100 * high, 1)} %`;

/** The dispersion's shapes as the cylindrical map draws them, each {area, line} in [lon, lat] pairs from
 * planarOutline (the page's one placement of a footprint across +-180 and over a pole): the nominal boundary about
 * the entry as a stored footprint is placed, then every other shape next to the nominal point (or entry) nearest
 * it, so that an ellipse or a cloud at the far end of a footprint past 180 deg lies on the boundary's copy. */
export function placeDispersion(d) {
  const entry = d.entry;
  const boundary = openRing(listPoints(d.nominal_boundary));
  const shape = (lists, reference) => {
    const points = listPoints(lists); // planarOutline drops a closing point (once: a contour may repeat a vertex)
    if (points.length < 3) return null;
    const shown = { points, reference: reference ?? nearestAnchor(points, anchors), outline: lists.outline ?? null };
    const { polygons, line } = planarOutline(shown);
    // a ring round the earth's axis without the service's outline (core.outline): its edge and no area (a fill
    // would take the wrong side of the map)
    return polygons ? { area: polygons, line } : { area: null, line, holdsPole: true };
  };
  // each flight's nominal landing point on the copy where the drawn boundary has it (unwrapRing, as planarOutline)
  const boundaryLons = boundary.length ? unwrapRing(boundary, entry) : [];
  const landed = d.nominal.filter((n) => n.latitude_deg != null && n.longitude_deg != null);
  const placed = boundary.length ? placeOnRing(landed, boundary, boundaryLons)
    : landed.map((n) => entry.longitude_deg + wrapLongitude(n.longitude_deg - entry.longitude_deg));
  const anchorOf = new Map(landed.map((n, i) => [n, { latitude_deg: n.latitude_deg, longitude_deg: placed[i] }]));
  const anchors = [{ latitude_deg: entry.latitude_deg, longitude_deg: entry.longitude_deg }, ...anchorOf.values()];
  const flightAnchor = d.nominal.map((n) => anchorOf.get(n) ?? anchors[0]);

  const nominal = boundary.length >= 3 ? shape(d.nominal_boundary, entry) : null;
  const levels = [...d.confidence].sort((a, b) => a.level - b.level); // the widest (lowest level) first
  const confidence = levels.map((c) => ({ level: c.level, rings: c.rings.map((r) => ({ ...shape(r), area_nmi2: r.area_nmi2 }))
    .filter((r) => r.line) }));
  confidence.forEach((c, rank) => {
    // a level's label on its largest piece, at its northernmost point: the widest level's above its edge, the others
    // inside theirs
    if (c.rings.length) c.label = { at: c.rings[0].line.reduce((a, b) => (b[1] > a[1] ? b : a)), below: rank > 0 };
  });
  const ellipses = d.flights.map((f, j) => ({ flight: f, index: j, ...(shape(f.ellipses?.[ELLIPSE_SIGMA] ?? {}) ?? {}) }))
    .filter((e) => e.line);
  // the landing points: each next to its flight's nominal point (a cloud is far smaller than 180 deg)
  const lats = [], lons = [];
  (d.clouds?.latitude_deg ?? []).forEach((row, j) => {
    const a = flightAnchor[j].longitude_deg, lonRow = d.clouds.longitude_deg[j];
    row.forEach((lat, i) => {
      if (lat == null || lonRow[i] == null) return;
      lats.push(lat);
      lons.push(a + wrapLongitude(lonRow[i] - a));
    });
  });
  const clouds = { latitude_deg: Float64Array.from(lats), longitude_deg: Float64Array.from(lons),
                   perFlight: d.clouds?.latitude_deg?.[0]?.length ?? 0 };
  // the extent of the main copy: what the copies and the view's fit are taken from
  let west = Infinity, east = -Infinity, south = Infinity, north = -Infinity;
  const extend = (lon, lat) => {
    if (lon < west) west = lon; if (lon > east) east = lon; if (lat < south) south = lat; if (lat > north) north = lat;
  };
  const shapes = [nominal, ...confidence.flatMap((c) => c.rings), ...ellipses].filter(Boolean);
  for (const s of shapes) s.line.forEach(([lon, lat]) => extend(lon, lat));
  lons.forEach((lon, i) => extend(lon, lats[i]));
  extend(entry.longitude_deg, entry.latitude_deg);
  return { entry, nominal, confidence, ellipses, clouds, sites: d.sites, bounds: { west, east, south, north },
           offsets: copyOffsets(west, east), holdsPole: shapes.some((s) => s.holdsPole) };
}

/** A flight's setting in words: "initial bank 45°, left". */
export function flightWords(f) {
  const side = f.side === "axis" ? "" : `, ${f.side}`;
  return `${describeParameter(f.parameter) || "nominal"}${side}`;
}

const std = (cov, i) => (cov ? Math.sqrt(Math.max(0, cov[i][i])) : null);
export const sigmaNmi = (f) => [std(f.covariance_nmi2, 0), std(f.covariance_nmi2, 1)];

/** The sidebar's dispersion panel (layers, outcomes, earlier jobs, the flights' table) and the site probabilities
 * in the landing-sites panel. Every name reaches the page as text (el, textContent). */
export class DispersionPanel {
  constructor({ onLayer, onShowJob, onDownload }) {
    this.onLayer = onLayer;
    this.onShowJob = onShowJob;
    $("dispersion-downloads").addEventListener("click", (e) => {
      const format = e.target.closest("button")?.dataset.format;
      if (format) onDownload(format);
    });
    $("dispersion-layers").addEventListener("change", (e) => {
      const layer = e.target.dataset.layer;
      if (layer) this.onLayer(layer, e.target.checked);
    });
    $("dispersion-show").addEventListener("click", () => { if ($("dispersion-jobs").value) this.onShowJob($("dispersion-jobs").value); });
    $("dispersion-flights").addEventListener("click", () => $("dispersion-dialog").showModal());
  }

  layers() {
    return Object.fromEntries([...$("dispersion-layers").querySelectorAll("input[data-layer]")]
      .map((input) => [input.dataset.layer, input.checked]));
  }

  /** The succeeded dispersion jobs of the service, newest first, to show one again. */
  async loadJobs() {
    const { items } = await api("/api/jobs?kind=dispersion&status=succeeded&limit=50");
    $("dispersion-jobs").replaceChildren(el("option", { value: "" }, items.length ? "earlier dispersions…" : "no earlier dispersions"),
      ...items.map((j) => el("option", { value: j.id },
                             `${j.name || `dispersion ${j.id.slice(0, 8)}`} · ${(j.finished_at || "").slice(0, 16).replace("T", " ")}`)));
  }

  show(name, d, placed) {
    $("dispersion-title").replaceChildren(el("strong", {}, name), ` · ${fmt(d.samples)} samples, ${d.design ?? ""} design`
      + `${d.seed != null ? `, seed ${d.seed}` : ""}`);
    $("dispersion-title").classList.remove("muted");
    $("dispersion-layers").disabled = false;
    $("dispersion-downloads").hidden = false;
    this.renderOutcomes(d, placed);
    this.renderSites(name, d);
    this.renderFlights(name, d);
    $("dispersion-flights").hidden = false;
  }

  /** Every flight counted: landed, and each other way a flight ended, with the flights it happened to. */
  renderOutcomes(d, placed) {
    const { flights, landed, ...others } = d.outcomes;
    const perSample = d.samples ? Math.round(flights / d.samples) : 0;
    const items = [el("li", {}, `${fmt(landed ?? 0)} of ${fmt(flights)} flights landed (${fmt(d.samples)} samples × ${perSample})`)];
    for (const [what, n] of Object.entries(others)) {
      const which = d.flights.filter((f) => f.outcomes?.[what]).map((f) => `${flightWords(f)} ${fmt(f.outcomes[what])}`);
      items.push(el("li", { class: "dispersion-outcome-other" }, `${fmt(n)} ${what}`,
                    which.length ? el("span", { class: "muted" }, ` (${which.join("; ")})`) : null));
    }
    const conf = d.confidence.map((c) => `${levelWords(c.level)}: ${fmt(c.rings.reduce((a, r) => a + r.area_nmi2, 0) / 1e6, 2)}`
      + ` million nmi² in ${c.rings.length} piece${c.rings.length === 1 ? "" : "s"}`);
    $("dispersion-outcomes").replaceChildren(...[el("ul", { class: "dispersion-outcomes" }, ...items),
      conf.length ? el("p", { class: "muted" }, `Confidence footprints (reached in at least that share of the samples): ${conf.join("; ")}.`) : null,
      placed?.holdsPole ? el("p", { class: "field-error" }, "A footprint here goes round a pole: its edge is drawn, "
        + "not its area (the result has no outline closed along the pole).") : null].filter(Boolean));
  }

  /** The probability of each site, its interval and whether the nominal footprint holds it; the likeliest first. */
  renderSites(name, d) {
    if (!d.sites.length) {
      $("dispersion-sites").replaceChildren(el("p", { class: "muted" }, "The dispersion had no landing sites: add sites, then run it again."));
      return;
    }
    const level = d.sites[0].interval_level ?? 0.95;
    const sites = [...d.sites].sort((a, b) => b.probability - a.probability || a.name.localeCompare(b.name));
    const rows = sites.map((s) => el("tr", { class: s.probability > 0 ? "reached" : "missed" },
      el("td", { class: "site-name" }, s.name),
      el("td", { class: "probability" }, percent(s.probability)),
      el("td", { class: "interval" }, intervalWords(s.interval)),
      el("td", { class: s.inside_nominal ? "reached" : "missed" }, s.inside_nominal ? "inside" : "outside")));
    $("dispersion-sites").replaceChildren(el("table", { class: "reach dispersion-sites" },
      el("caption", { class: "small muted" }, "Probability of reaching each site in ", el("strong", {}, name),
         ` (${fmt(d.samples)} samples; ${levelWords(level)} Clopper–Pearson interval)`),
      el("thead", {}, el("tr", {}, el("th", {}, "Site"), el("th", {}, "P"), el("th", {}, `${levelWords(level)} interval`),
                              el("th", { title: "inside the nominal (undispersed) footprint" }, "Nominal"))),
      el("tbody", {}, ...rows)));
  }

  /** Per control setting and side: landed, other outcomes, mean and spread of the landing point, heating. */
  renderFlights(name, d) {
    const heat = d.flights.some((f) => f.max_temperature_R);
    const rows = d.flights.map((f) => {
      const [sd, sc] = sigmaNmi(f);
      const other = Object.entries(f.outcomes ?? {}).map(([what, n]) => `${fmt(n)} ${what}`).join(", ");
      return el("tr", {}, el("td", {}, flightWords(f)), el("td", {}, `${fmt(f.landed)} / ${fmt(d.samples)}`),
        el("td", {}, other || "–"), el("td", {}, fmt(f.mean_downrange_nmi)), el("td", {}, fmt(f.mean_crossrange_nmi)),
        el("td", {}, fmt(sd)), el("td", {}, fmt(sc)),
        heat ? el("td", {}, f.max_temperature_R ? `${fmt(f.max_temperature_R.p50)} (${fmt(f.max_temperature_R.p99)})` : "–") : null);
    });
    $("dispersion-flight-table").replaceChildren(el("table", { class: "reach dispersion-flights" },
      el("caption", { class: "small muted" }, name, ` · ${outcomeWords(d)}`),
      el("thead", {}, el("tr", {}, ...["Flight", "Landed", "Other outcomes", "Mean D (nmi)", "Mean X (nmi)", "σ D (nmi)",
                                       "σ X (nmi)", ...(heat ? ["Max temperature p50 (p99) °R"] : [])].map((t) => el("th", {}, t)))),
      el("tbody", {}, ...rows)));
  }
}
