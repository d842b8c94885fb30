// The cylindrical equidistant map (Leaflet's EPSG:4326 CRS: x = longitude, y = latitude, as the report's
// Figs. 31-32), with Natural Earth land, coastlines and borders drawn from the shipped data.
/* global L */
import { loadWorld, planarFeatures } from "./basemap.js";
import { copyOffsets, describeParameter, openRing, planarOutline, sameSite, unwrapLongitudes,
         unwrapRing } from "./geometry.js";
import { el, escapeHtml, fmt } from "./format.js";
import { landingWords } from "./histories.js";
import { DISPERSION_STYLE as STYLE, LAYERS, confidenceOpacity, flightWords, intervalWords, levelWords, percent,
         probabilityColor, sigmaNmi } from "./dispersion.js";
import { placeLabels } from "./labels.js";
import { windowWords } from "./timeline.js";

const GRATICULE_DEG = 30;
const WORLD_COPIES_DEG = [-360, 0, 360]; // the map may be panned one world either way
export const LABEL_FONT = "11px 'DejaVu Sans', Arial, sans-serif"; // a site label's, on the map and in the PNG
const LABEL_BOX_PX = { padX: 4, h: 15 }; // a label's box round its text
const SITE_MARKER_PX = 8; // half a site marker (the dispersion's ring round a stored site: 11 px; its diamond: 7)
// the graticule's labels keep clear of the zoom buttons (top left) and the scale bar and attribution (bottom), px
const GRID_LABEL_CLEAR_TOP_PX = 84;
const GRID_LABEL_CLEAR_BOTTOM_PX = 20;
const GRID_LABEL_HEIGHT_PX = 14; // a label hangs below its point (Leaflet's own transform places the icon)

/** The graticule's spacing at a zoom, and its labels' words: "30°E", "180°", "0°"; "60°N". */
export const graticuleStepDeg = (zoom) => (zoom >= 3.5 ? 10 : GRATICULE_DEG);
export function lonWords(lon) {
  const w = ((lon + 180) % 360 + 360) % 360 - 180;
  return w === 0 ? "0°" : Math.abs(w) === 180 ? "180°" : `${Math.abs(w)}°${w > 0 ? "E" : "W"}`;
}
export const latWords = (lat) => (lat === 0 ? "0°" : `${Math.abs(lat)}°${lat > 0 ? "N" : "S"}`);

/** The map's scale bar: a round length in nmi along a meridian (where the map's scale is the same everywhere; east-west
 * it grows as 1 / cos latitude) at least 60 px long, and its length in px. */
export function scaleBar(map) {
  const c = map.getCenter(), y0 = map.latLngToContainerPoint(c).y;
  const pxPerNmi = Math.abs(map.latLngToContainerPoint([c.lat + 1, c.lng]).y - y0) / 60; // 1 deg = 60 nmi
  const nmi = [50, 100, 200, 500, 1000, 2000, 5000].find((n) => n * pxPerNmi >= 60) ?? 5000;
  return { nmi, px: nmi * pxPerNmi };
}

let measure = null;
const textWidth = (text) => {
  measure ??= document.createElement("canvas").getContext("2d");
  measure.font = LABEL_FONT;
  return measure.measureText(text).width;
};

/** A dispersion's landing points as small squares on a canvas renderer: one layer for all of them (22 flights x
 * 1,000 samples, on each copy of the map), projected once per zoom and drawn where the renderer redraws. */
const CloudPoints = L.Path.extend({
  options: { interactive: false, stroke: false, fill: true, fillColor: STYLE.cloud.color, fillOpacity: STYLE.cloud.opacity,
             size: STYLE.cloud.sizePx },

  initialize(latitudes, longitudes, offsets, options) {
    L.setOptions(this, options);
    this._lats = latitudes;
    this._lons = longitudes;
    this._offsets = offsets;
  },

  count() { return this._lats.length * this._offsets.length; },

  _project() {
    const map = this._map, n = this._lats.length, xy = new Float32Array(2 * n * this._offsets.length);
    let m = 0, x0 = Infinity, y0 = Infinity, x1 = -Infinity, y1 = -Infinity;
    for (const offset of this._offsets) {
      for (let i = 0; i < n; i++) {
        const p = map.latLngToLayerPoint([this._lats[i], this._lons[i] + offset]);
        xy[m++] = p.x; xy[m++] = p.y;
        if (p.x < x0) x0 = p.x; if (p.x > x1) x1 = p.x; if (p.y < y0) y0 = p.y; if (p.y > y1) y1 = p.y;
      }
    }
    this._xy = xy;
    this._pxBounds = m ? L.bounds([x0, y0], [x1, y1]) : null;
  },

  _update() { if (this._map) this._updatePath(); },

  _updatePath() {
    const r = this._renderer;
    if (!r._drawing || !this._xy) return; // the canvas renderer calls this again while it draws
    const ctx = r._ctx, b = r._bounds, size = this.options.size, half = size / 2, xy = this._xy;
    ctx.globalAlpha = this.options.fillOpacity;
    ctx.fillStyle = this.options.fillColor;
    for (let m = 0; m < xy.length; m += 2) {
      const x = xy[m], y = xy[m + 1];
      if (x >= b.min.x && x <= b.max.x && y >= b.min.y && y <= b.max.y) ctx.fillRect(x - half, y - half, size, size);
    }
  },

  _empty() { return !this._xy?.length; },
  _containsPoint() { return false; },
});

export function pointTooltip(fp, p) {
  const rows = [
    ["Down-range", `${fmt(p.downrange_nmi)} nmi`],
    ["Cross-range", `${fmt(p.crossrange_nmi)} nmi`],
    ["Flight time", `${fmt(p.flight_time_s)} s`],
    ["Control", escapeHtml(describeParameter(p.parameter) || "–")],
    ["Lat, lon", `${fmt(p.latitude_deg, 2)}°, ${fmt(p.longitude_deg, 2)}°`],
  ];
  return `<strong>${escapeHtml(fp.name)}</strong><table>${rows.map(([k, v]) => `<tr><th>${k}</th><td>${v}</td></tr>`).join("")}</table>`;
}

/** The shortest arc of longitude [west, east] (east - west <= 360) that covers every [west, east] interval,
 * each taken at any multiple of 360 deg: the complement of the widest gap between them on the circle; placed on
 * the copy of the map whose middle is nearest nearDeg. */
export function shortestCover(intervals, nearDeg = 0) {
  if (intervals.some(([w, e]) => e - w >= 360)) return [-180, 180];
  const spans = intervals.map(([w, e]) => { const s = ((w % 360) + 360) % 360; return [s, s + (e - w)]; })
    .sort((a, b) => a[0] - b[0]);
  const merged = [];
  for (const [s, e] of spans) {
    if (merged.length && s <= merged[merged.length - 1][1]) merged[merged.length - 1][1] = Math.max(merged[merged.length - 1][1], e);
    else merged.push([s, e]);
  }
  let best = { gap: merged[0][0] + 360 - merged[merged.length - 1][1], start: 0 }; // the gap across 360
  for (let i = 1; i < merged.length; i++) {
    const gap = merged[i][0] - merged[i - 1][1];
    if (gap > best.gap) best = { gap, start: i };
  }
  if (best.gap <= 0) return [-180, 180];
  const west = merged[best.start][0];
  const east = best.start === 0 ? merged[merged.length - 1][1] : merged[best.start - 1][1] + 360;
  const shift = 360 * Math.round((nearDeg - (west + east) / 2) / 360);
  return [west + shift, east + shift];
}

export class MapView {
  constructor(element, { onClick } = {}) {
    this.map = L.map(element, { crs: L.CRS.EPSG4326, zoomSnap: 0.25, zoomDelta: 0.5, minZoom: 0, maxZoom: 9,
                                 worldCopyJump: false, keyboard: true, preferCanvas: false });
    this.map.fitBounds([[-60, -180], [80, 180]]);
    this.map.createPane("basemap").style.zIndex = 250;
    this.basemapRenderer = L.canvas({ pane: "basemap", padding: 0.5 });
    this.svgRenderer = L.svg({ padding: 0.5 });
    this.map.createPane("clouds").style.zIndex = 390; // a dispersion's landing points, under the vector layers
    this.cloudRenderer = L.canvas({ pane: "clouds", padding: 0.5 });
    this.dispersion = null; // {groups, placed, name}
    this.footprintLayers = new Map();
    this.landLayers = [];
    this.tileLayer = null; // the optional online tile layer (FOOTPRINT_TILE_URL, via GET /api/config)
    this.sitesLayer = L.layerGroup().addTo(this.map);
    this.map.attributionControl.setPrefix(false);
    this.map.attributionControl.addAttribution("Natural Earth (public domain), via world-atlas");
    this.legend = L.control({ position: "bottomright" });
    this.legend.onAdd = () => {
      this.legendDiv = L.DomUtil.create("div", "map-legend footprint-legend");
      this.legendDiv.hidden = true;
      L.DomEvent.disableClickPropagation(this.legendDiv); // a click on it is not a new site
      return this.legendDiv;
    };
    this.legendFolded = false; // folded to one button: the sites and labels under the box seen (issue 53 item 9)
    this.legend.addTo(this.map);
    this.map.on("click", (e) => onClick?.(e.latlng));
    this.gridLabels = L.layerGroup().addTo(this.map);
    this.map.on("moveend zoomend", () => this._labelGraticule());
    this.labelPane = this.map.createPane("siteLabels"); // over the shapes and markers, under the popups
    this.labelPane.style.zIndex = 640;
    this.labelPane.style.pointerEvents = "none";
    this.labels = []; // the site labels as last placed: {text, x, y, w, h, leader} in the container's px
    this.map.on("moveend zoomend viewreset resize", () => this.placeSiteLabels());
    this._addScale();
    this.ready = this._drawBasemap().then(() => this._labelGraticule());
  }

  async _drawBasemap() {
    // the land's outline is the coastline (its rings run on past 180 deg, so they have no cut edges to hide)
    const sphere = await loadWorld("50m");
    const world = { land: planarFeatures(sphere.land), borders: planarFeatures(sphere.borders) };
    const canvas = { renderer: this.basemapRenderer, pane: "basemap", interactive: false };
    for (const offset of WORLD_COPIES_DEG) {
      const shifted = { coordsToLatLng: (c) => L.latLng(c[1], c[0] + offset) };
      this.landLayers.push(L.geoJSON(world.land, { ...canvas, ...shifted, style: this._landStyle() }).addTo(this.map));
      L.geoJSON(world.borders, { ...canvas, ...shifted, style: { color: "#a7a29a", weight: 0.6, fill: false } })
        .addTo(this.map);
    }
    // beyond the poles there is no earth: a neutral band, so that a zoomed-out map does not show "ocean" there
    for (const [a, b] of [[90, 1000], [-1000, -90]]) {
      L.rectangle([[a, -2000], [b, 2000]], { ...canvas, stroke: false, fillColor: "#eef1f4", fillOpacity: 1 }).addTo(this.map);
    }
    const lines = [];
    for (let lon = -540; lon <= 540; lon += GRATICULE_DEG) lines.push([[-90, lon], [90, lon]]);
    for (let lat = -90; lat <= 90; lat += GRATICULE_DEG) lines.push([[lat, -540], [lat, 540]]);
    L.polyline(lines, { ...canvas, color: "#b9c6d2", weight: 0.6 }).addTo(this.map);
  }

  /** Latitude and longitude labels of the graticule along the view's left and bottom edges. */
  _labelGraticule() {
    this.gridLabels.clearLayers();
    const b = this.map.getBounds(), step = graticuleStepDeg(this.map.getZoom());
    const icon = (text, cls) => L.divIcon({ className: `grid-label ${cls}`, html: text, iconSize: null });
    // the longitudes above the scale bar and the attribution, the latitudes below the zoom buttons and above the
    // scale bar: under them the labels were hidden (issue 53 item 9)
    const at = (y) => this.map.containerPointToLatLng([0, y]).lat, y = (lat) => this.map.latLngToContainerPoint([lat, 0]).y;
    const pane = this.map.getContainer().getBoundingClientRect(), bar = this._scaleDiv?.getBoundingClientRect();
    const lowest = Math.min(this.map.getSize().y - GRID_LABEL_CLEAR_BOTTOM_PX, bar?.height ? bar.top - pane.top - 2 : Infinity);
    const row = Math.min(lowest - GRID_LABEL_HEIGHT_PX, y(-90)), bottom = at(row), top = at(Math.max(GRID_LABEL_CLEAR_TOP_PX, y(90)));
    for (let lon = Math.ceil(b.getWest() / step) * step; lon <= b.getEast(); lon += step) {
      L.marker([bottom, lon], { icon: icon(lonWords(lon), "lon"), interactive: false, keyboard: false })
        .addTo(this.gridLabels);
    }
    for (let lat = Math.ceil(bottom / step) * step; lat <= top; lat += step) {
      if (y(lat) > row - GRID_LABEL_HEIGHT_PX) continue; // on the longitudes' row
      L.marker([lat, b.getWest()], { icon: icon(latWords(lat), "lat"), interactive: false, keyboard: false })
        .addTo(this.gridLabels);
    }
  }

  /** A scale bar in nautical miles along a meridian, where this map's scale is the same everywhere (east-west it
   * grows as 1 / cos latitude). */
  _addScale() {
    const control = L.control({ position: "bottomleft" });
    control.onAdd = () => {
      const div = L.DomUtil.create("div", "map-scale");
      this._scaleDiv = div;
      const update = () => {
        const { nmi, px } = scaleBar(this.map);
        div.innerHTML = `<span class="bar" style="width:${Math.round(px)}px"></span>${fmt(nmi)} nmi along a meridian`;
      };
      this.map.on("zoomend moveend", update);
      update();
      return div;
    };
    control.addTo(this.map);
  }

  /** Land is filled, unless the online tiles are shown under the coastlines and borders. */
  _landStyle() {
    const tiles = this.tileLayer !== null && this.map.hasLayer(this.tileLayer);
    return { color: "#6f8294", weight: 0.8, fillColor: "#ece8dc", fillOpacity: tiles ? 0 : 1 };
  }

  /** Add the optional online tile layer (a Leaflet URL template in the map's plate carree, EPSG:4326) under the
   * Natural Earth coastlines, borders and graticule, shown at once, with a layer toggle. Only called when the
   * service has FOOTPRINT_TILE_URL: without it the page requests nothing beyond the service. */
  addTileLayer(url) {
    if (this.tileLayer || !url) return;
    this.tileLayer = L.tileLayer(url, { maxZoom: 9, className: "online-tiles" });
    const restyle = () => { for (const layer of this.landLayers) layer.setStyle(this._landStyle()); };
    this.tileLayer.on("add remove", restyle);
    this.tileLayer.addTo(this.map);
    L.control.layers(null, { "Online tiles": this.tileLayer }, { position: "topright", collapsed: false })
      .addTo(this.map);
  }

  /** Draw (or redraw) one footprint as it is shown: boundary, entry point, ground track, hoverable points. */
  drawFootprint(fp) {
    this.removeFootprint(fp.id);
    const { points, groundTrack, reference } = fp.shown;
    const ring = openRing(points);
    if (!ring.length) return;
    const ringLons = unwrapRing(ring, reference);
    const { polygons, line } = planarOutline(fp.shown);
    const trackLons = unwrapLongitudes(groundTrack.map((p) => p.longitude_deg), reference.longitude_deg);
    const all = line.map(([lon]) => lon).concat(trackLons, [reference.longitude_deg, -180, 180]); // the area: -180..180
    const group = L.layerGroup();
    const svg = { renderer: this.svgRenderer, smoothFactor: 0, noClip: true }; // every vertex kept, none clipped
    for (const offset of copyOffsets(Math.min(...all), Math.max(...all))) {
      const copy = `fp-${fp.id} fp-copy-${offset}`;
      if (polygons?.length) {
        L.polygon(polygons.map((rings) => rings.map((r) => r.map(([lon, lat]) => [lat, lon + offset]))),
                  { ...svg, stroke: false, fillColor: fp.color, fillOpacity: 0.22,
                    className: `fp-polygon ${copy}`, interactive: false }).addTo(group);
      }
      // the boundary's line: only the footprint's edge (the area's cuts at +-180 and its runs along a pole are not)
      L.polyline(line.map(([lon, lat]) => [lat, lon + offset]),
                 { ...svg, color: fp.color, weight: 2, className: `fp-boundary ${copy}`, interactive: false }).addTo(group);
      if (groundTrack.length > 1) {
        L.polyline(groundTrack.map((p, i) => [p.latitude_deg, trackLons[i] + offset]),
                   { ...svg, color: fp.color, weight: 1.5, dashArray: "6 5", opacity: 0.85,
                     className: `fp-track ${copy}`, interactive: false }).addTo(group);
      }
      L.circleMarker([reference.latitude_deg, reference.longitude_deg + offset],
                     { renderer: this.svgRenderer, radius: 6, color: "#fff", weight: 2, fillColor: fp.color,
                       fillOpacity: 1, className: `fp-entry ${copy}` })
        .bindTooltip(`<strong>${escapeHtml(fp.name)}</strong><br>entry ${fmt(reference.latitude_deg, 2)}°, `
                     + `${fmt(reference.longitude_deg, 2)}°, heading ${fmt(reference.heading_deg, 1)}°`)
        .addTo(group);
      ring.forEach((p, i) => {
        L.circleMarker([p.latitude_deg, ringLons[i] + offset],
                       { renderer: this.svgRenderer, radius: 4, color: fp.color, weight: 1.5,
                         fillColor: p.mirrored ? "#fff" : fp.color, fillOpacity: 1,
                         className: `fp-point ${copy}` })
          .bindTooltip(pointTooltip(fp, p), { className: "point-tooltip", direction: "auto" }) // the side with room
          .addTo(group);
      });
    }
    group.addTo(this.map);
    for (const layer of group.getLayers()) layer.getElement?.()?.classList.toggle("stale", Boolean(fp.stale));
    this.footprintLayers.set(fp.id, group);
  }

  /** The ground track of an optimum ({name, color, result}) as a solid line, its landing point marked. */
  drawOptimum(optimum) {
    this.optimumLayer?.remove();
    const f = optimum.result.flight;
    const lons = unwrapLongitudes(f.longitude_deg, f.longitude_deg[0]);
    const last = f.time_s.length - 1;
    const group = L.layerGroup();
    const svg = { renderer: this.svgRenderer, smoothFactor: 0, noClip: true };
    for (const offset of copyOffsets(Math.min(...lons), Math.max(...lons))) {
      L.polyline(f.latitude_deg.map((lat, i) => [lat, lons[i] + offset]),
                 { ...svg, color: optimum.color, weight: 3, opacity: 0.95, className: `optimum-track opt-copy-${offset}`,
                   interactive: false }).addTo(group);
      L.circleMarker([f.latitude_deg[last], lons[last] + offset],
                     { renderer: this.svgRenderer, radius: 6, color: "#111", weight: 2, fillColor: optimum.color,
                       fillOpacity: 1, className: `optimum-landing opt-copy-${offset}` })
        .bindTooltip(`<strong>${escapeHtml(optimum.name)}</strong><br>${landingWords(optimum.result).join("<br>")}`)
        .addTo(group);
    }
    this.optimumLayer = group.addTo(this.map);
    this.optimum = optimum;
  }

  /** The deorbit points of each landing window of a reach result ({color, window}, timeline.coloredWindows): a line
   * along the orbit where deorbiting reaches the site, in the site's colour (as the timeline), with its revolution,
   * times and site. */
  drawReach(windows) {
    this.reachLayer?.remove();
    const group = L.layerGroup();
    for (const { color, window: w } of windows) {
      const p = w.deorbit_points, lons = unwrapLongitudes(p.longitude_deg, p.longitude_deg[0]);
      const tip = escapeHtml(windowWords(w));
      for (const offset of copyOffsets(Math.min(...lons), Math.max(...lons))) {
        const latlngs = p.latitude_deg.map((lat, i) => [lat, lons[i] + offset]);
        const style = { renderer: this.svgRenderer, color, className: "reach-deorbit" };
        (latlngs.length > 1 ? L.polyline(latlngs, { ...style, weight: 3, opacity: 0.65 })
          : L.circleMarker(latlngs[0], { ...style, radius: 4, fillOpacity: 0.8 })).bindTooltip(tip).addTo(group);
      }
    }
    this.reachLayer = group.addTo(this.map);
  }

  /** Fit the view to the optimum's ground track (its main copy). */
  fitOptimum() {
    const main = this.optimumLayer?.getLayers().find((l) => l instanceof L.Polyline && l.options.className.includes("opt-copy-0"));
    if (main) this.map.fitBounds(main.getBounds().pad(0.3), { maxZoom: 4 });
  }

  /** A dispersion job's result, placed (dispersion.placeDispersion): the nominal boundary (dashed), each confidence
   * footprint (filled, darker at a higher level, labelled), the 3-sigma ellipses, the landing points and the sites
   * with their probability, each kind one layer group that the panel turns on and off. */
  drawDispersion(placed, { name, samples, layers }) {
    this.removeDispersion();
    const groups = Object.fromEntries(LAYERS.map((k) => [k, L.layerGroup()]));
    const svg = { renderer: this.svgRenderer, smoothFactor: 0, noClip: true };
    for (const offset of placed.offsets) {
      const copy = `disp-copy-${offset}`;
      const latlngs = (pairs) => pairs.map(([lon, lat]) => [lat, lon + offset]);
      placed.confidence.forEach((c, rank) => c.rings.forEach((r) => {
        if (r.area) L.polygon(r.area.map((rings) => rings.map(latlngs)), { ...svg, stroke: false, fillColor: STYLE.confidence.color, fillOpacity: confidenceOpacity(rank),
                                     className: `dispersion-confidence-area ${copy}`, interactive: false }).addTo(groups.confidence);
        L.polyline(latlngs(r.line), { ...svg, color: STYLE.confidence.color, weight: STYLE.confidence.widthPx,
                                      opacity: STYLE.confidence.opacity,
                                      className: `dispersion-confidence level-${Math.round(c.level * 1000)} ${copy}`,
                                      interactive: false }).addTo(groups.confidence);
      }));
      for (const c of placed.confidence.filter((level) => level.label)) {
        const [lon, lat] = c.label.at;
        L.marker([lat, lon + offset], { interactive: false, keyboard: false,
          icon: L.divIcon({ className: `confidence-label ${c.label.below ? "below" : "above"}`, iconSize: null,
                            html: el("span", {}, levelWords(c.level)) }) }).addTo(groups.confidence);
      }
      if (placed.nominal) {
        L.polyline(latlngs(placed.nominal.line), { ...svg, color: STYLE.nominal.color, weight: STYLE.nominal.widthPx,
                                                   dashArray: STYLE.nominal.dashPx.join(" "),
                                                   className: `dispersion-nominal ${copy}`, interactive: false }).addTo(groups.nominal);
      }
      for (const e of placed.ellipses) {
        const [sd, sc] = sigmaNmi(e.flight);
        const tip = el("div", {}, el("strong", {}, name), el("br"), `3σ ellipse · ${flightWords(e.flight)}`, el("br"),
          `${fmt(e.flight.landed)} of ${fmt(samples)} landed · mean ${fmt(e.flight.mean_downrange_nmi)} nmi down-range, `
          + `${fmt(e.flight.mean_crossrange_nmi)} nmi cross-range · σ ${fmt(sd)} × ${fmt(sc)} nmi`);
        L.polyline(latlngs(e.line), { ...svg, color: STYLE.ellipse.color, weight: STYLE.ellipse.widthPx, className: `dispersion-ellipse ${copy}` })
          .bindTooltip(tip, { sticky: true }).addTo(groups.ellipses);
      }
    }
    const c = placed.clouds;
    groups.clouds.addLayer(new CloudPoints(c.latitude_deg, c.longitude_deg, placed.offsets, { renderer: this.cloudRenderer }));
    const stored = this.storedSites ?? [];
    for (const s of placed.sites) {
      const named = !stored.some((t) => sameSite(t, s));
      const tip = el("div", {}, el("strong", {}, s.name), el("br"),
        `P ${percent(s.probability)} (${levelWords(s.interval_level)} interval ${intervalWords(s.interval)}) · ${fmt(s.samples_reaching)} samples reach it`,
        el("br"), `${s.inside_nominal ? "inside" : "outside"} the nominal footprint · ${fmt(s.downrange_nmi)} nmi down-range, `
        + `${fmt(s.crossrange_nmi)} nmi cross-range`);
      for (const offset of WORLD_COPIES_DEG) {
        // named, with its probability, by placeSiteLabels; its popup says the rest
        L.circleMarker([s.latitude_deg, s.longitude_deg + offset],
                       { renderer: this.svgRenderer, radius: named ? STYLE.site.radiusPx : STYLE.site.aroundStoredPx,
                         color: STYLE.site.edgeColor, weight: STYLE.site.widthPx, fillColor: probabilityColor(s.probability),
                         fillOpacity: 1, className: "dispersion-site" })
          .bindPopup(tip)
          .addTo(groups.sites);
      }
    }
    this.dispersion = { groups, placed, name };
    for (const [kind, on] of Object.entries(layers)) this.setDispersionLayer(kind, on);
  }

  setDispersionLayer(kind, on) {
    const g = this.dispersion?.groups[kind];
    if (!g) return;
    if (on) g.addTo(this.map); else g.remove();
    if (kind === "sites") this.placeSiteLabels();
  }

  removeDispersion() {
    for (const g of Object.values(this.dispersion?.groups ?? {})) g.remove();
    this.dispersion = null;
    this.placeSiteLabels();
  }

  /** The view on the dispersion's main copy, all of it. */
  fitDispersion() {
    const b = this.dispersion?.placed.bounds;
    if (!b || !Number.isFinite(b.west)) return;
    // the legend (bottom right) is tall with a dispersion in it: a wide footprint goes above it
    const legend = this.legendDiv.hidden ? 0 : this.legendDiv.offsetHeight;
    this.map.fitBounds([[b.south, b.west], [b.north, b.east]], { maxZoom: 4, paddingTopLeft: [50, 30],
                                                                 paddingBottomRight: [40, Math.max(70, legend + 30)], animate: false });
  }

  removeFootprint(id) {
    this.footprintLayers.get(id)?.remove();
    this.footprintLayers.delete(id);
  }

  setLegend(footprints) {
    this._legendFootprints = footprints;
    const reach = this.reachLayer ? '<div class="legend-key">coloured lines: where deorbiting reaches a site (as the '
      + "landing-window timeline)</div>" : "";
    const optimum = this.optimum
      ? `<div><span class="line" style="background:${this.optimum.color}"></span>${escapeHtml(this.optimum.name)} (optimum)</div>` : "";
    // one meaning per colour: green and red say the last reach analysis's verdict, blue a dispersion's probability
    const sites = this.storedSites?.length ? '<div class="legend-key legend-sites"><span class="site-icon site-reached">'
      + '</span>reached · <span class="site-icon site-missed"></span>not · <span class="site-icon site-unknown"></span>'
      + "not checked (last reach)</div>" : "";
    this.legendDiv.innerHTML = footprints.length || optimum
      ? footprints.map((fp) => `<div><span class="swatch" style="background:${fp.color}"></span>${escapeHtml(fp.name)}</div>`).join("")
        + optimum + '<div class="legend-key"><span class="dash"></span>ground track · <span class="dot"></span>entry</div>' + reach
        + sites
      : sites;
    this.legendDiv.hidden = !(footprints.length || optimum || sites);
    this._addLegendFold();
    if (this.dispersion) {
      const key = (cls, style, text) => el("div", {}, el("span", { class: cls, style }), text);
      const levels = this.dispersion.placed.confidence.map((c) => levelWords(c.level)).join(", ");
      this.legendDiv.append(el("div", { class: "legend-dispersion" }, el("strong", {}, this.dispersion.name),
        key("dash", { borderTopColor: STYLE.nominal.color }, "nominal footprint"),
        key("swatch", { background: STYLE.confidence.color }, `confidence footprints ${levels}`),
        key("line", { background: STYLE.ellipse.color }, "3σ ellipse of each flight"),
        key("dot", { background: STYLE.cloud.color }, "landing points"),
        key("dot site", { background: `linear-gradient(90deg, ${probabilityColor(0)}, ${probabilityColor(1)})` },
            "P of reaching a site with the dispersions (grey 0 to blue 1), in its label")));
      this.legendDiv.hidden = false;
    }
  }

  /** The legend's fold button, first in it: folded, the legend is that button alone. */
  _addLegendFold() {
    // its glyph drawn by CSS, so that the legend's text stays the keys' (an export, a test read it)
    const words = this.legendFolded ? "Show the legend" : "Fold the legend away: what it covers shows";
    const fold = el("button", { type: "button", class: "legend-fold", "aria-expanded": String(!this.legendFolded),
                                "aria-label": words, title: words });
    fold.addEventListener("click", () => {
      this.legendFolded = !this.legendFolded;
      fold.remove();
      this._addLegendFold().focus();
    });
    this.legendDiv.classList.toggle("folded", this.legendFolded);
    this.legendDiv.prepend(fold);
    return fold;
  }

  /** Landing sites as diamonds; green when the last reach analysis reached them, red when it did not. */
  setSites(sites) {
    this.storedSites = sites;
    this.sitesLayer.clearLayers();
    for (const s of sites) {
      const state = s.reachable == null ? "unknown" : s.reachable ? "reached" : "missed";
      for (const offset of WORLD_COPIES_DEG) {
        L.marker([s.latitude_deg, s.longitude_deg + offset],
                 { icon: L.divIcon({ className: "site-marker", html: `<span class="site-icon site-${state}"></span>`,
                                     iconSize: [14, 14] }), keyboard: false,
                   title: `${s.name}: ${fmt(s.latitude_deg, 3)}°, ${fmt(s.longitude_deg, 3)}°` })
          .addTo(this.sitesLayer);
      }
    }
    this.placeSiteLabels();
    if (this._legendFootprints) this.setLegend(this._legendFootprints);
  }

  /** The sites' names (and a shown dispersion's probability of reaching each) placed where they cover no other
   * label and no marker (labels.placeLabels): the stored sites first, then a dispersion's own; a name with no room
   * is left out, its marker still names it on hover. */
  placeSiteLabels() {
    const size = this.map.getSize();
    this.labels = this.siteLabelsWithin({ x: 0, y: 0, w: size.x, h: size.y });
    this._drawSiteLabels();
  }

  /** The site labels placed within `bounds` (the container's px): {text, p, x, y, w, h, leader} each (the PNG places
   * them within its crop). */
  siteLabelsWithin(bounds) {
    const items = [];
    const shownP = this.dispersion && this.map.hasLayer(this.dispersion.groups.sites) ? this.dispersion.placed.sites : [];
    const stored = this.storedSites ?? [];
    const texts = stored.map((s) => {
      const d = shownP.find((t) => sameSite(t, s));
      return [s, d ? `${s.name} · ${percent(d.probability)}` : s.name, Boolean(d)];
    }).concat(shownP.filter((t) => !stored.some((s) => sameSite(t, s))).map((t) => [t, `${t.name} · ${percent(t.probability)}`, true]));
    for (const [s, text, p] of texts) {
      for (const offset of WORLD_COPIES_DEG) {
        const at = this.map.latLngToContainerPoint([s.latitude_deg, s.longitude_deg + offset]);
        if (at.x < bounds.x - 50 || at.y < bounds.y - 50 || at.x > bounds.x + bounds.w + 50
            || at.y > bounds.y + bounds.h + 50) continue;
        items.push({ x: at.x, y: at.y, w: textWidth(text) + 2 * LABEL_BOX_PX.padX, h: LABEL_BOX_PX.h, text, p });
      }
    }
    const placed = placeLabels(items, { markerPx: SITE_MARKER_PX, bounds });
    return items.flatMap((it, i) => (placed[i] ? [{ ...it, ...placed[i] }] : []));
  }

  _drawSiteLabels() {
    const origin = this.map.containerPointToLayerPoint([0, 0]), size = this.map.getSize();
    this.labelPane.replaceChildren();
    const svg = document.createElementNS("http://www.w3.org/2000/svg", "svg");
    svg.setAttribute("class", "site-leaders");
    svg.setAttribute("width", size.x);
    svg.setAttribute("height", size.y);
    L.DomUtil.setPosition(svg, origin);
    for (const l of this.labels) {
      if (l.leader) {
        const line = document.createElementNS("http://www.w3.org/2000/svg", "line");
        [["x1", 0], ["y1", 1], ["x2", 2], ["y2", 3]].forEach(([k, i]) => line.setAttribute(k, l.leader[i].toFixed(1)));
        svg.append(line);
      }
      const div = el("div", { class: `site-label${l.p ? " site-label-p" : ""}` }, l.text);
      div.style.width = `${l.w}px`;
      L.DomUtil.setPosition(div, origin.add([l.x, l.y]));
      this.labelPane.append(div);
    }
    this.labelPane.prepend(svg);
  }

  /** Fit the view to the shown footprints on one world copy: their longitude spans placed on the circle so that
   * together they cover the shortest arc (footprints either side of 180 deg side by side, not 2.5 worlds apart). */
  fitFootprints(footprints) {
    const boxes = footprints.map((fp) => this.mainBoundary(fp)?.getBounds()).filter(Boolean);
    if (!boxes.length) return;
    // on the copy of the first footprint's main boundary line (its area is cut at 180 deg; the line runs on)
    const [west, east] = shortestCover(boxes.map((b) => [b.getWest(), b.getEast()]), boxes[0].getCenter().lng);
    const south = Math.min(...boxes.map((b) => b.getSouth())), north = Math.max(...boxes.map((b) => b.getNorth()));
    this.map.fitBounds([[south, west], [north, east]], { maxZoom: 4, paddingTopLeft: [50, 30], paddingBottomRight: [40, 70],
                                                         animate: false });
  }

  fitFootprint(fp) {
    const main = this.mainBoundary(fp);
    if (main) this.map.fitBounds(main.getBounds().pad(0.35), { maxZoom: 4 });
  }

  /** The footprint's edge on the main copy: continuous in longitude, as far past 180 deg as it runs. */
  mainBoundary(fp) {
    return this.footprintLayers.get(fp.id)?.getLayers()
      .find((l) => l.options.className?.includes("fp-boundary") && l.options.className.includes("fp-copy-0"));
  }

  invalidate() { this.map.invalidateSize(); }
}
