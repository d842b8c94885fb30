// Export what is shown: GeoJSON and CSV of the shown footprints, and a PNG drawn on a canvas here (the
// basemap from the shipped Natural Earth data, the footprints on top): no tiles, no internet.
/* global d3 */
import { loadWorld, planarFeatures } from "./basemap.js";
import { api } from "./api.js";
import { fmt } from "./format.js";
import { boundaryLine, openRing, planarOutline, sphericalRing, toCSV, unwrapLongitudes, unwrapRing } from "./geometry.js";
import { globeProjection } from "./globe.js";

const PIXEL_RATIO = 2; // a PNG sharp enough for a report page

export function download(filename, content, type) {
  const blob = content instanceof Blob ? content : new Blob([content], { type });
  const a = document.createElement("a");
  a.href = URL.createObjectURL(blob);
  a.download = filename;
  document.body.appendChild(a);
  a.click();
  a.remove();
  setTimeout(() => URL.revokeObjectURL(a.href), 1000);
}

const ROUND = 1e6; // coordinates to 1e-6 deg, as the API writes them (RFC 7946 sec. 11.2)

/** The API's GeoJSON of each shown footprint (a moved one's from its transform), named and coloured as shown,
 * and the sites: one GeoJSON, the service's, everywhere. */
export async function geoJSONOf(footprints, sites) {
  const features = [];
  for (const fp of footprints) {
    const collection = fp.shown.geojson ?? await api(`/api/footprints/${fp.id}?format=geojson`);
    for (const f of collection.features) {
      features.push({ ...f, properties: { ...f.properties, footprint_id: fp.id, name: fp.name, color: fp.color } });
    }
  }
  for (const s of sites) {
    features.push({ type: "Feature", properties: { kind: "site", name: s.name, reachable: s.reachable ?? null },
                    geometry: { type: "Point", coordinates: [Math.round(s.longitude_deg * ROUND) / ROUND,
                                                             Math.round(s.latitude_deg * ROUND) / ROUND] } });
  }
  return { type: "FeatureCollection", features };
}

export async function exportGeoJSON(footprints, sites) {
  download("footprints.geojson", JSON.stringify(await geoJSONOf(footprints, sites), null, 1), "application/geo+json");
}

export function exportCSV(footprints) {
  download("footprints.csv", toCSV(footprints), "text/csv");
}

/** The map view as the map draws it: x = longitude, y = latitude (deg), straight between vertices, so that the
 * PNG matches the screen; copies one world either way, as on the map. */
function planarFrame(bounds, width) {
  const west = bounds.getWest(), north = bounds.getNorth(), k = width / (bounds.getEast() - west);
  return (offsetDeg) => d3.geoIdentity().reflectY(true).scale(k).translate([(offsetDeg - west) * k, north * k]);
}

function footprintShapes(fp, planar) {
  const { points, groundTrack, reference } = fp.shown;
  const ring = openRing(points);
  const lons = planar ? unwrapRing(ring, reference) : ring.map((p) => p.longitude_deg);
  const trackLons = planar ? unwrapLongitudes(groundTrack.map((p) => p.longitude_deg), reference.longitude_deg)
                           : groundTrack.map((p) => p.longitude_deg);
  const coords = ring.map((p, i) => [lons[i], p.latitude_deg]);
  const area = planar ? planarOutline(fp.shown) : [];
  const polygon = { type: "Polygon", coordinates: [planar ? area.concat([area[0]]) : sphericalRing(points, d3.geoArea)] };
  return {
    polygon,
    boundary: planar ? { type: "LineString", coordinates: boundaryLine(fp.shown, area) } : polygon,
    track: { type: "LineString", coordinates: groundTrack.map((p, i) => [trackLons[i], p.latitude_deg]) },
    points: ring.map((p, i) => ({ type: "Point", coordinates: coords[i], mirrored: p.mirrored })),
    entry: { type: "Point", coordinates: [reference.longitude_deg, reference.latitude_deg] },
  };
}

/** Draw the current view to a canvas and return it (the caller turns it into a PNG). */
export async function renderCanvas({ view, mapView, globe, footprints, sites }) {
  const globeView = view === "globe";
  const element = globeView ? globe.element : mapView.map.getContainer();
  const { width, height } = element.getBoundingClientRect();
  const canvas = document.createElement("canvas");
  canvas.width = Math.round(width * PIXEL_RATIO);
  canvas.height = Math.round(height * PIXEL_RATIO);
  const ctx = canvas.getContext("2d");
  ctx.scale(PIXEL_RATIO, PIXEL_RATIO);
  const sphere = await loadWorld(globeView ? "110m" : "50m");
  const world = globeView ? sphere : { land: planarFeatures(sphere.land), borders: planarFeatures(sphere.borders) };
  const frame = globeView ? () => globeProjection(width, height, globe.rotate, globe.zoom)
                          : planarFrame(mapView.map.getBounds(), width);
  const offsets = globeView ? [0] : [-360, 0, 360];
  let path = d3.geoPath(frame(0), ctx);
  const draw = (feature, { fill, stroke, width: lw = 1, dash = [], alpha = 1, radius = 4 }) => {
    ctx.beginPath();
    path.pointRadius(radius)(feature);
    ctx.globalAlpha = alpha;
    ctx.setLineDash(dash);
    if (fill) { ctx.fillStyle = fill; ctx.fill(); }
    if (stroke) { ctx.strokeStyle = stroke; ctx.lineWidth = lw; ctx.stroke(); }
    ctx.globalAlpha = 1;
    ctx.setLineDash([]);
  };
  ctx.fillStyle = globeView ? "#f3f5f8" : "#dce8f1";
  ctx.fillRect(0, 0, width, height);
  if (globeView) {
    draw({ type: "Sphere" }, { fill: "#dce8f1" });
    draw(d3.geoGraticule().step([30, 30])(), { stroke: "#b9c6d2", width: 0.6 });
  }
  for (const offset of offsets) {
    path = d3.geoPath(frame(offset), ctx);
    draw(world.land, { fill: "#ece8dc", stroke: "#6f8294", width: 0.8 });
    draw(world.borders, { stroke: "#a7a29a", width: 0.6 });
    if (!globeView) {
      const lines = [];
      for (let lon = -180; lon <= 180; lon += 30) lines.push([[lon, -90], [lon, 90]]);
      for (let lat = -90; lat <= 90; lat += 30) lines.push([[-180, lat], [180, lat]]);
      draw({ type: "MultiLineString", coordinates: lines }, { stroke: "#b9c6d2", width: 0.6 });
    }
  }
  for (const offset of offsets) { // the footprints over every copy of the basemap
    path = d3.geoPath(frame(offset), ctx);
    for (const fp of footprints) {
      const shape = footprintShapes(fp, !globeView);
      draw(shape.polygon, { fill: fp.color, alpha: 0.22 });
      draw(shape.boundary, { stroke: fp.color, width: 2 });
      if (shape.track.coordinates.length > 1) draw(shape.track, { stroke: fp.color, width: 1.5, dash: [6, 5] });
      for (const q of shape.points) draw(q, { fill: q.mirrored ? "#fff" : fp.color, stroke: fp.color, width: 1.2, radius: 3 });
      draw(shape.entry, { fill: fp.color, stroke: "#fff", width: 2, radius: 6 });
    }
    for (const s of sites) {
      const fill = s.reachable == null ? "#5b6b7b" : s.reachable ? "#2e7d32" : "#b3261e";
      draw({ type: "Point", coordinates: [s.longitude_deg, s.latitude_deg] }, { fill, stroke: "#fff", width: 1.5, radius: 5 });
      const at = path.centroid({ type: "Point", coordinates: [s.longitude_deg, s.latitude_deg] });
      if (Number.isFinite(at[0])) label(ctx, s.name, at[0] + 8, at[1] + 4);
    }
  }
  if (globeView) draw({ type: "Sphere" }, { stroke: "#5f7385", width: 1.2 });
  drawLegend(ctx, footprints, globeView ? "Orthographic" : "Cylindrical equidistant");
  return canvas;
}

function label(ctx, text, x, y) {
  ctx.font = "11px 'DejaVu Sans', Arial, sans-serif";
  ctx.lineWidth = 3;
  ctx.strokeStyle = "rgba(255,255,255,0.85)";
  ctx.strokeText(text, x, y);
  ctx.fillStyle = "#1d2733";
  ctx.fillText(text, x, y);
}

/** What a footprint is, for the PNG's caption (three lines): name, vehicle and method; entry state; where it
 * is shown (the live orbit controls). */
export function caption(fp) {
  const e = fp.item.entry, c = fp.controls;
  return [`${fp.name}: ${fp.item.vehicle}, ${fp.item.method.replace(/_/g, " ")}`,
          `entry ${fmt(e.altitude_ft)} ft, ${fmt(e.velocity_fps)} ft/s, γ ${fmt(e.gamma_deg, 1)}°, heading `
          + `${fmt(e.heading_deg, 1)}° at ${fmt(e.latitude_deg, 2)}°, ${fmt(e.longitude_deg, 2)}°`,
          c ? `node ${fmt(c.nodeLongitudeDeg, 2)}°, inclination ${fmt(c.inclinationDeg, 2)}°, step `
              + `${fmt(c.stepDownrangeNmi)} nmi, earth rotation ${c.earthRotation}` : "as stored"];
}

function drawLegend(ctx, footprints, projectionName) {
  const LINE = 15, GAP = 6;
  ctx.font = "12px 'DejaVu Sans', Arial, sans-serif";
  const blocks = footprints.map((fp) => [fp.color, caption(fp)]);
  const w = Math.max(180, ...blocks.flatMap(([, ls]) => ls.map((t) => ctx.measureText(t).width + 34)));
  const h = 26 + blocks.reduce((sum, [, ls]) => sum + ls.length * LINE + GAP, 0);
  ctx.fillStyle = "rgba(255,255,255,0.92)";
  ctx.fillRect(10, 10, w, h);
  ctx.strokeStyle = "#9aa8b5";
  ctx.strokeRect(10, 10, w, h);
  ctx.fillStyle = "#34495e";
  ctx.fillText(`${projectionName} · Natural Earth`, 18, 27);
  let y = 36;
  for (const [color, ls] of blocks) {
    ctx.globalAlpha = 0.85;
    ctx.fillStyle = color;
    ctx.fillRect(18, y, 14, 10);
    ctx.globalAlpha = 1;
    ls.forEach((t, k) => { ctx.fillStyle = k ? "#4a5a6a" : "#1d2733"; ctx.fillText(t, 38, y + 9 + k * LINE); });
    y += ls.length * LINE + GAP;
  }
}

export async function exportPNG(options) {
  const canvas = await renderCanvas(options);
  const blob = await new Promise((resolve) => canvas.toBlob(resolve, "image/png"));
  download(`footprints-${options.view === "globe" ? "orthographic" : "equirectangular"}.png`, blob);
}
