// The orthographic globe (the report's second projection, Fig. 33): the earth seen from far away, the hidden
// hemisphere clipped at 90 deg from the centre. Drag (or the arrow keys) to turn it; + and - to zoom.
/* global d3 */
import { loadWorld } from "./basemap.js";
import { listPoints, openRing, sphericalRing } from "./geometry.js";
import { escapeHtml, fmt } from "./format.js";
import { landingWords } from "./histories.js";
import { confidenceOpacity, levelWords, percent } from "./dispersion.js";
import { windowWords } from "./timeline.js";

const KEY_STEP_DEG = 10;
const DRAG_DEG_PER_PX = 0.25;
/** Beside a site: its name begins `name` px right of it, a dispersion's probability ends `probability` px left; a
 * dispersion's site is a disc of `disc` px. */
export const GLOBE_SITE_PX = { name: 10, probability: 9, disc: 6 };
/** A dispersion's site disc on the globe: faint at probability 0, full green at 1. */
export const siteOpacity = (p) => 0.15 + 0.85 * p;

export function footprintFeatures(fp) {
  const { points, groundTrack, reference } = fp.shown;
  return {
    polygon: { type: "Polygon", coordinates: [sphericalRing(points, d3.geoArea)] },
    track: { type: "LineString", coordinates: groundTrack.map((p) => [p.longitude_deg, p.latitude_deg]) },
    entry: { type: "Point", coordinates: [reference.longitude_deg, reference.latitude_deg] },
    points: openRing(points).map((p) => ({ type: "Point", coordinates: [p.longitude_deg, p.latitude_deg], p })),
  };
}

/** A dispersion's shapes on the sphere (d3-geo cuts nothing: a ring round a pole is one polygon): its confidence
 * footprints (widest first), nominal boundary and 3-sigma ellipses as closed rings; its landing points are left to
 * the map (thousands of them would slow the globe's turning). */
export function dispersionFeatures(d) {
  const closed = (lists) => { const r = openRing(listPoints(lists)).map((p) => [p.longitude_deg, p.latitude_deg]); return r.length > 2 ? r.concat([r[0]]) : null; };
  return {
    confidence: [...d.confidence].sort((a, b) => a.level - b.level).map((c) => ({ level: c.level,
      rings: c.rings.map((r) => ({ type: "Polygon", coordinates: [sphericalRing(listPoints(r), d3.geoArea)] })) })),
    nominal: closed(d.nominal_boundary) && { type: "LineString", coordinates: closed(d.nominal_boundary) },
    ellipses: d.flights.map((f) => closed(f.ellipses?.["3"])).filter(Boolean).map((c) => ({ type: "LineString", coordinates: c })),
  };
}

/** A flight's ground track as [lon, lat] pairs. */
export const flightLine = (f) => f.longitude_deg.map((lon, i) => [lon, f.latitude_deg[i]]);

/** The point half-way along a line by its arc ([lon, lat]): centred there, a track up to half-way round the earth
 * faces the viewer whole (each end within 90 deg), where the mean of its rows leans to its slow end. */
export function lineMiddle(coordinates) {
  if (coordinates.length < 2) return coordinates[0];
  const steps = coordinates.slice(1).map((p, i) => d3.geoDistance(coordinates[i], p));
  let left = steps.reduce((a, b) => a + b, 0) / 2, i = 0;
  while (i < steps.length - 1 && left > steps[i]) left -= steps[i++];
  return d3.geoInterpolate(coordinates[i], coordinates[i + 1])(steps[i] > 0 ? left / steps[i] : 0);
}

/** The globe's projection for a box of width x height pixels. */
export function globeProjection(width, height, rotate, zoom = 1) {
  return d3.geoOrthographic().clipAngle(90).precision(0.2).rotate(rotate)
    .translate([width / 2, height / 2]).scale(0.47 * Math.min(width, height) * zoom);
}

export class GlobeView {
  constructor(element) {
    this.element = element;
    this.rotate = [0, -20, 0];
    this.zoom = 1;
    this.footprints = [];
    this.sites = [];
    this.dispersion = null; // {name, features, sites, layers}
    this.guided = null; // {track, rings}: the guided panel's flight and footprint, [lon, lat] lines
    this.opportunity = null; // the landing opportunity shown: {track, coast, ring} lines, {burn, entry, site} points
    this.optimum = null; // an optimization job's optimum: {name, color, result}
    this.reach = null; // a reach result's landing windows, each {row, color, window}
    this.svg = d3svg(element);
    this.ready = loadWorld("110m").then((world) => { this.world = world; this.render(); });
    this._bindDrag();
    this._bindKeys();
  }

  setData(footprints, sites) { this.footprints = footprints; this.sites = sites; this.render(); }

  setDispersion(name, d, layers) {
    this.dispersion = { name, features: dispersionFeatures(d), sites: d.sites, layers };
    this.render();
  }

  /** The guided panel's track and footprint rings ({track: [[lon, lat]...] | null, rings: [{key, color, dash,
   * coordinates}]}), drawn as lines: d3 cuts them at the limb and carries them over the poles. */
  setGuided(g) { this.guided = g; this.render(); }

  /** A landing opportunity ([lon, lat]: its revolution's ground track, coast arc and footprint as lines; the burn,
   * entry and site as points), or null. */
  setOpportunity(o) { this.opportunity = o; this.render(); }

  /** An optimization job's optimum ({name, color, result}: the map's drawOptimum takes the same), or null. */
  setOptimum(o) { this.optimum = o; this.render(); }

  /** A reach result's landing windows, each {row, color, window} (timeline.coloredWindows, as the map draws them). */
  setReach(windows) { this.reach = windows; this.render(); }

  center(lonDeg, latDeg) { this.rotate = [-lonDeg, -latDeg, 0]; this.render(); }

  projection() {
    const { width, height } = this.element.getBoundingClientRect();
    return globeProjection(Math.max(width, 1), Math.max(height, 1), this.rotate, this.zoom);
  }

  render() {
    if (!this.world || this.element.hidden) return;
    const { width, height } = this.element.getBoundingClientRect();
    const projection = this.projection();
    const path = d3.geoPath(projection).pointRadius(4);
    const parts = [
      `<path class="globe-ocean" d="${path({ type: "Sphere" })}"/>`,
      `<path class="globe-graticule" d="${path(d3.geoGraticule().step([30, 30])())}"/>`,
      `<path class="globe-land" d="${path(this.world.land) || ""}"/>`,
      `<path class="globe-borders" d="${path(this.world.borders) || ""}"/>`,
      `<path class="globe-coast" d="${path(this.world.coastline) || ""}"/>`,
    ];
    for (const fp of this.footprints) {
      const f = footprintFeatures(fp);
      parts.push(`<path class="globe-footprint fp-${fp.id}" style="fill:${fp.color};stroke:${fp.color}" d="${path(f.polygon) || ""}"/>`);
      parts.push(`<path class="globe-track" style="stroke:${fp.color}" d="${path(f.track) || ""}"/>`);
      for (const q of f.points) {
        const d = path.pointRadius(3)(q);
        if (d) parts.push(`<path class="globe-point" style="stroke:${fp.color};fill:${q.p.mirrored ? "#fff" : fp.color}" d="${d}"><title>${escapeHtml(fp.name)}: down-range ${fmt(q.p.downrange_nmi)} nmi, cross-range ${fmt(q.p.crossrange_nmi)} nmi, ${fmt(q.p.flight_time_s)} s</title></path>`);
      }
      const e = path.pointRadius(6)(f.entry);
      if (e) parts.push(`<path class="globe-entry fp-${fp.id}" style="fill:${fp.color}" d="${e}"><title>${escapeHtml(fp.name)}: entry</title></path>`);
    }
    if (this.dispersion) parts.push(...this._dispersionParts(path, projection));
    if (this.guided) parts.push(...this._guidedParts(path));
    if (this.opportunity) parts.push(...this._opportunityParts(path));
    if (this.optimum) parts.push(...this._optimumParts(path));
    if (this.reach) parts.push(...this._reachParts(path));
    for (const s of this.sites) { // the map's marker: a diamond coloured by the reach verdict, and the site's name
      if (!path({ type: "Point", coordinates: [s.longitude_deg, s.latitude_deg] })) continue; // on the far side
      const [x, y] = projection([s.longitude_deg, s.latitude_deg]);
      const state = s.reachable == null ? "unknown" : s.reachable ? "reached" : "missed";
      parts.push(`<path class="globe-site site-${state}" d="M${x},${y - 7}L${x + 7},${y}L${x},${y + 7}L${x - 7},${y}Z">`
        + `<title>${escapeHtml(s.name)}: ${fmt(s.latitude_deg, 3)}°, ${fmt(s.longitude_deg, 3)}°</title></path>`
        + `<text class="globe-site-label" x="${x + GLOBE_SITE_PX.name}" y="${y + 4}">${escapeHtml(s.name)}</text>`);
    }
    parts.push(`<path class="globe-limb" d="${path({ type: "Sphere" })}"/>`);
    this.footprints.forEach((fp, i) => parts.push( // the legend, as the map's
      `<rect class="globe-legend-swatch" x="12" y="${14 + 18 * i}" width="14" height="10" style="fill:${fp.color}"/>`
      + `<text class="globe-legend" x="32" y="${23 + 18 * i}">${escapeHtml(fp.name)}</text>`));
    if (this.optimum) {
      const y = 14 + 18 * this.footprints.length;
      parts.push(`<rect class="globe-legend-swatch" x="12" y="${y + 4}" width="14" height="3" style="fill:${this.optimum.color}"/>`
        + `<text class="globe-legend" x="32" y="${y + 9}">${escapeHtml(this.optimum.name)} (optimum)</text>`);
    }
    this.svg.setAttribute("viewBox", `0 0 ${width} ${height}`);
    this.svg.innerHTML = parts.join("");
  }

  _guidedParts(path) {
    const line = (coordinates) => path({ type: "LineString", coordinates }) || "";
    const parts = this.guided.rings.map((r) => `<path class="globe-guided-ring gr-${r.key}" style="stroke:${r.color}`
      + `${r.dash ? `;stroke-dasharray:${r.dash}` : ""}" d="${line(r.coordinates)}"/>`);
    if (this.guided.track) parts.push(`<path class="globe-guided-track" d="${line(this.guided.track)}"/>`);
    for (const [mode, points] of Object.entries(this.guided.clouds ?? {})) { // a dispersion's ends, guided on top
      const d = path.pointRadius(mode === "guided" ? 2 : 1.6)({ type: "MultiPoint", coordinates: points });
      if (d) parts.push(`<path class="globe-guided-cloud gc-${mode.replace("_", "-")}" d="${d}"/>`);
    }
    path.pointRadius(4); // as render() set it
    return parts;
  }

  /** The optimum's ground track as one line (d3 carries it over a pole and cuts it at the limb), its landing point
   * marked with the map's words. */
  _optimumParts(path) {
    const { name, color, result } = this.optimum, f = result.flight;
    const track = { type: "LineString", coordinates: flightLine(f) };
    const parts = [`<path class="globe-optimum-track" style="stroke:${color}" d="${path(track) || ""}"/>`];
    const landing = path.pointRadius(6)({ type: "Point", coordinates: track.coordinates.at(-1) });
    if (landing) {
      parts.push(`<path class="globe-optimum-landing" style="fill:${color}" d="${landing}">`
        + `<title>${escapeHtml(name)}: ${landingWords(result).join(", ")}</title></path>`);
    }
    return parts;
  }

  /** Each landing window's deorbit points, as the map draws them: a line along the orbit (a dot for one point). */
  _reachParts(path) {
    return this.reach.map(({ color, window: w }) => {
      const p = w.deorbit_points, line = p.longitude_deg.map((lon, i) => [lon, p.latitude_deg[i]]);
      const d = line.length > 1 ? path({ type: "LineString", coordinates: line })
        : path.pointRadius(4)({ type: "Point", coordinates: line[0] });
      const style = line.length > 1 ? `stroke:${color}` : `stroke:${color};fill:${color}`;
      return `<path class="globe-reach-deorbit${line.length > 1 ? "" : " dot"}" style="${style}" d="${d || ""}">`
        + `<title>${escapeHtml(windowWords(w))}</title></path>`;
    });
  }

  _opportunityParts(path) {
    const o = this.opportunity;
    const line = (cls, coordinates) => `<path class="${cls}" d="${path({ type: "LineString", coordinates }) || ""}"/>`;
    const point = (cls, at, r) => `<path class="${cls}" d="${path.pointRadius(r)({ type: "Point", coordinates: at }) || ""}"/>`;
    return [line("globe-op-footprint", o.ring), line("globe-op-track", o.track), line("globe-op-coast", o.coast),
            point("globe-op-burn", o.burn, 4), point("globe-op-entry", o.entry, 4.5), point("globe-op-site", o.site, 8)];
  }

  _dispersionParts(path, projection) {
    const { features: f, sites, layers } = this.dispersion, parts = [];
    if (layers.confidence) {
      f.confidence.forEach((c, rank) => c.rings.forEach((r) => parts.push(
        `<path class="globe-dispersion-confidence" style="fill-opacity:${confidenceOpacity(rank).toFixed(2)}" d="${path(r) || ""}">`
        + `<title>confidence footprint ${levelWords(c.level)}</title></path>`)));
    }
    if (layers.nominal && f.nominal) parts.push(`<path class="globe-dispersion-nominal" d="${path(f.nominal) || ""}"/>`);
    if (layers.ellipses) for (const e of f.ellipses) parts.push(`<path class="globe-dispersion-ellipse" d="${path(e) || ""}"/>`);
    if (layers.sites) {
      for (const s of sites) {
        if (!path({ type: "Point", coordinates: [s.longitude_deg, s.latitude_deg] })) continue; // on the far side
        const [x, y] = projection([s.longitude_deg, s.latitude_deg]);
        parts.push(`<circle class="globe-dispersion-site" cx="${x}" cy="${y}" r="${GLOBE_SITE_PX.disc}" style="fill-opacity:${siteOpacity(s.probability).toFixed(2)}">`
          + `<title>${escapeHtml(s.name)}: P ${percent(s.probability)}</title></circle>`
          + `<text class="globe-site-label globe-dispersion-p" x="${x - GLOBE_SITE_PX.probability}" y="${y + 4}" text-anchor="end">${percent(s.probability)}</text>`);
      }
    }
    return parts;
  }

  _bindDrag() {
    let last = null;
    this.svg.addEventListener("pointerdown", (e) => { last = [e.clientX, e.clientY]; this.svg.setPointerCapture(e.pointerId); });
    this.svg.addEventListener("pointermove", (e) => {
      if (!last) return;
      const k = DRAG_DEG_PER_PX / this.zoom;
      this.rotate = [this.rotate[0] + (e.clientX - last[0]) * k,
                     Math.max(-90, Math.min(90, this.rotate[1] - (e.clientY - last[1]) * k)), 0];
      last = [e.clientX, e.clientY];
      this.render();
    });
    const stop = () => { last = null; };
    this.svg.addEventListener("pointerup", stop);
    this.svg.addEventListener("pointercancel", stop);
    this.svg.addEventListener("wheel", (e) => {
      e.preventDefault();
      this.zoom = Math.max(0.6, Math.min(8, this.zoom * (e.deltaY < 0 ? 1.15 : 1 / 1.15)));
      this.render();
    }, { passive: false });
  }

  _bindKeys() {
    this.svg.addEventListener("keydown", (e) => {
      const turns = { ArrowLeft: [KEY_STEP_DEG, 0], ArrowRight: [-KEY_STEP_DEG, 0], ArrowUp: [0, -KEY_STEP_DEG],
                      ArrowDown: [0, KEY_STEP_DEG] };
      if (turns[e.key]) {
        const [dl, dp] = turns[e.key];
        this.rotate = [this.rotate[0] + dl, Math.max(-90, Math.min(90, this.rotate[1] + dp)), 0];
      } else if (e.key === "+" || e.key === "=") this.zoom = Math.min(8, this.zoom * 1.25);
      else if (e.key === "-") this.zoom = Math.max(0.6, this.zoom / 1.25);
      else return;
      e.preventDefault();
      this.render();
    });
  }
}

function d3svg(element) {
  const svg = document.createElementNS("http://www.w3.org/2000/svg", "svg");
  svg.setAttribute("class", "globe-svg");
  svg.setAttribute("tabindex", "0");
  svg.setAttribute("role", "img");
  svg.setAttribute("aria-label", "Orthographic globe: drag or use the arrow keys to turn it, + and - to zoom");
  element.appendChild(svg);
  return svg;
}
