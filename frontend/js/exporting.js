// Export what is shown: GeoJSON and CSV of the shown footprints, and a PNG drawn on a canvas here (the
// basemap from the shipped Natural Earth data, the footprints on top): no tiles, no internet.
/* global d3 */
import { loadWorld, planarFeatures } from "./basemap.js";
import { api } from "./api.js";
import { DISPERSION_STYLE, confidenceOpacity, dispersionURL, featureShown, levelWords, percent,
         probabilityColor } from "./dispersion.js";
import { fmt } from "./format.js";
import { openRing, planarOutline, sameSite, sphericalRing, toCSV, unwrapLongitudes,
         unwrapRing } from "./geometry.js";
import { GLOBE_SITE_PX, dispersionFeatures, globeProjection, siteOpacity } from "./globe.js";
import { landingWords } from "./histories.js";
import { LABEL_FONT, graticuleStepDeg, latWords, lonWords, scaleBar } from "./mapview.js";

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
 * the sites, and the features of the shown dispersion ({jobId, name, layers}) that its layers show: one GeoJSON,
 * the service's, everywhere. */
export async function geoJSONOf(footprints, sites, dispersion = null) {
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
  if (dispersion) features.push(...await shownDispersionFeatures(dispersion));
  return { type: "FeatureCollection", features };
}

async function shownDispersionFeatures({ jobId, name, layers }) {
  const { features } = await api(dispersionURL(jobId, "geojson"));
  return features.filter((f) => featureShown(f.properties, layers))
    .map((f) => ({ ...f, properties: { ...f.properties, dispersion_job_id: jobId, dispersion_name: name } }));
}

export async function exportGeoJSON(footprints, sites, dispersion = null) {
  download("footprints.geojson", JSON.stringify(await geoJSONOf(footprints, sites, dispersion), null, 1),
           "application/geo+json");
}

/** The service's GeoJSON or sites CSV (format) of the shown dispersion, saved under the page's name for the job
 * (the service's own name for the CSV holds only the job's id). */
export async function exportDispersion({ jobId, fileStem }, format) {
  const body = await api(dispersionURL(jobId, format));
  if (format === "csv") download(`${fileStem}-sites.csv`, body, "text/csv");
  else download(`${fileStem}.geojson`, JSON.stringify(body), "application/geo+json");
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
  const flat = planar ? planarOutline(fp.shown) : null;
  const polygon = planar ? { type: "MultiPolygon", coordinates: flat.polygons ?? [] }
    : { type: "Polygon", coordinates: [sphericalRing(points, d3.geoArea)] };
  return {
    polygon,
    boundary: planar ? { type: "LineString", coordinates: flat.line } : polygon,
    track: { type: "LineString", coordinates: groundTrack.map((p, i) => [trackLons[i], p.latitude_deg]) },
    points: ring.map((p, i) => ({ type: "Point", coordinates: coords[i], mirrored: p.mirrored })),
    entry: { type: "Point", coordinates: [reference.longitude_deg, reference.latitude_deg] },
  };
}

/** A pen on a canvas: use(projection) sets where draw() and at() put longitude and latitude. */
function penOn(ctx) {
  const pen = {
    use(projection) { pen.projection = projection; pen.path = d3.geoPath(projection, ctx); },
    draw(feature, { fill, stroke, width = 1, dash = [], alpha = 1, radius = 4 }) {
      ctx.beginPath();
      pen.path.pointRadius(radius)(feature);
      ctx.globalAlpha = alpha;
      ctx.setLineDash(dash);
      if (fill) { ctx.fillStyle = fill; ctx.fill(); }
      if (stroke) { ctx.strokeStyle = stroke; ctx.lineWidth = width; ctx.stroke(); }
      ctx.globalAlpha = 1;
      ctx.setLineDash([]);
    },
    /** The canvas point of a place, or null where the view hides it (the globe's far side). */
    at(lonDeg, latDeg) {
      const xy = pen.path.centroid({ type: "Point", coordinates: [lonDeg, latDeg] });
      return Number.isFinite(xy[0]) ? xy : null;
    },
  };
  return pen;
}

/** Draw the current view to a canvas and return it (the caller turns it into a PNG); `dispersion` is the shown one
 * ({name, dispersion, placed, layers}) or null, `optimum` the shown optimization's ({name, color, result}) or null,
 * `opportunity` the chosen landing opportunity's lines and points as the globe has them, with its `caption` and the
 * map's `style` (opportunities.js OPPORTUNITY_STYLE), or null; `reach` the landing windows as the globe has them
 * (timeline.coloredWindows) or null. */
export async function renderCanvas({ view, mapView, globe, footprints, sites, dispersion = null, optimum = null,
                                     opportunity = null, reach = null }) {
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
  const pen = penOn(ctx);
  const eachCopy = (copies, drawCopy) => { for (const offset of copies) { pen.use(frame(offset)); drawCopy(); } };
  ctx.fillStyle = globeView ? "#f3f5f8" : "#dce8f1";
  ctx.fillRect(0, 0, width, height);
  pen.use(frame(0));
  if (globeView) {
    pen.draw({ type: "Sphere" }, { fill: "#dce8f1" });
    pen.draw(d3.geoGraticule().step([30, 30])(), { stroke: "#b9c6d2", width: 0.6 });
  }
  eachCopy(offsets, () => {
    pen.draw(world.land, { fill: "#ece8dc", stroke: "#6f8294", width: 0.8 });
    pen.draw(world.borders, { stroke: "#a7a29a", width: 0.6 });
    if (!globeView) {
      const lines = [];
      for (let lon = -180; lon <= 180; lon += 30) lines.push([[lon, -90], [lon, 90]]);
      for (let lat = -90; lat <= 90; lat += 30) lines.push([[-180, lat], [180, lat]]);
      pen.draw({ type: "MultiLineString", coordinates: lines }, { stroke: "#b9c6d2", width: 0.6 });
    }
  });
  // as the map stacks them: the landing points (a canvas pane) under the footprints, the dispersion's shapes over
  // them, its sites and their probability, then the stored sites on top
  const dispersed = dispersion && !globeView ? dispersion.placed.offsets : [];
  if (dispersion?.layers.clouds) eachCopy(dispersed, () => drawClouds(ctx, pen.projection, dispersion.placed.clouds));
  eachCopy(offsets, () => { for (const fp of footprints) drawFootprint(pen, fp, !globeView); });
  if (optimum) eachCopy(offsets, () => drawOptimum(pen, optimum, !globeView));
  if (opportunity) eachCopy(offsets, () => drawOpportunity(pen, opportunity));
  if (reach) eachCopy(offsets, () => drawReach(pen, reach, !globeView));
  if (dispersion && globeView) drawGlobeDispersion(pen, ctx, dispersion);
  eachCopy(dispersed, () => drawMapDispersion(pen, ctx, dispersion));
  if (dispersion && !globeView) eachCopy(offsets, () => drawMapDispersionSites(pen, dispersion, sites));
  eachCopy(offsets, () => {
    for (const s of sites) {
      const fill = s.reachable == null ? "#5b6b7b" : s.reachable ? "#2e7d32" : "#b3261e";
      pen.draw({ type: "Point", coordinates: [s.longitude_deg, s.latitude_deg] }, { fill, stroke: "#fff", width: 1.5, radius: 5 });
      const at = globeView && pen.at(s.longitude_deg, s.latitude_deg);
      if (at) label(ctx, s.name, at[0] + GLOBE_SITE_PX.name, at[1] + 4);
    }
  });
  const crop = globeView ? { x: 0, y: 0, w: width, h: height } : worldCrop(mapView.map, width, height);
  // placed as the map places them (no two over one another), within the PNG's part of the view
  if (!globeView) drawSiteLabels(ctx, mapView.siteLabelsWithin(crop));
  if (globeView) pen.draw({ type: "Sphere" }, { stroke: "#5f7385", width: 1.2 });
  // the caption below the picture, where it covers nothing of the map
  const blocks = captionBlocks(footprints, dispersion && dispersionCaption(dispersion, globeView), sites, optimum,
                               opportunity, reach);
  const out = cropped(canvas, crop, legendHeight(blocks));
  const octx = out.getContext("2d");
  if (!globeView) drawGridAndScale(octx, mapView.map, crop);
  drawLegend(octx, blocks, globeView ? "Orthographic" : "Cylindrical equidistant", crop);
  return out;
}

/** The part of the map's view that is the earth (CSS px of the container): latitudes -90 to 90 and one turn of
 * longitude about the view's centre, within the view. The PNG of a tall pane at world zoom was mostly the bands
 * beyond the poles (issue 25 item 5). */
function worldCrop(map, width, height) {
  const c = map.getCenter().lng, at = (lat, lon) => map.latLngToContainerPoint([lat, lon]);
  const x = Math.max(0, Math.floor(at(0, c - 180).x)), y = Math.max(0, Math.floor(at(90, c).y));
  return { x, y, w: Math.min(width, Math.ceil(at(0, c + 180).x)) - x, h: Math.min(height, Math.ceil(at(-90, c).y)) - y };
}

/** A new canvas of `crop` (CSS px) of the drawn one and `below` px more under it for the caption, scaled for
 * PIXEL_RATIO. */
function cropped(canvas, crop, below) {
  const out = document.createElement("canvas");
  out.width = Math.round(crop.w * PIXEL_RATIO);
  out.height = Math.round((crop.h + below) * PIXEL_RATIO);
  const ctx = out.getContext("2d");
  const h = Math.round(crop.h * PIXEL_RATIO);
  ctx.fillStyle = "#fff";
  ctx.fillRect(0, 0, out.width, out.height);
  ctx.drawImage(canvas, crop.x * PIXEL_RATIO, crop.y * PIXEL_RATIO, out.width, h, 0, 0, out.width, h);
  ctx.scale(PIXEL_RATIO, PIXEL_RATIO);
  return out;
}

/** The graticule's latitudes and longitudes along the PNG's left and bottom edges, and a scale bar in nautical miles
 * along a meridian (the map's scale there is the same everywhere), as the map shows them. */
function drawGridAndScale(ctx, map, crop) {
  const at = (lat, lon) => map.latLngToContainerPoint([lat, lon]);
  const b = map.getBounds(), step = graticuleStepDeg(map.getZoom());
  ctx.font = "10px 'DejaVu Sans', Arial, sans-serif";
  for (let lon = Math.ceil(b.getWest() / step) * step; lon <= b.getEast(); lon += step) {
    const x = at(0, lon).x - crop.x;
    if (x >= 20 && x <= crop.w - 20) label(ctx, lonWords(lon), x, crop.h - 4, { align: "center" });
  }
  for (let lat = Math.ceil(Math.max(b.getSouth(), -90) / step) * step; lat <= Math.min(b.getNorth(), 90); lat += step) {
    const y = at(lat, b.getWest()).y - crop.y;
    if (y >= 12 && y <= crop.h - 16) label(ctx, latWords(lat), 3, y + 3);
  }
  const { nmi, px: len } = scaleBar(map);
  const x0 = 40, y0 = crop.h - 22;
  ctx.fillStyle = "rgba(255,255,255,0.85)";
  ctx.fillRect(x0 - 4, y0 - 12, len + 150, 18);
  ctx.strokeStyle = "#1d2733";
  ctx.lineWidth = 1.5;
  ctx.beginPath();
  ctx.moveTo(x0, y0 - 4);
  ctx.lineTo(x0, y0);
  ctx.lineTo(x0 + len, y0);
  ctx.lineTo(x0 + len, y0 - 4);
  ctx.stroke();
  label(ctx, `${fmt(nmi)} nmi along a meridian`, x0 + len + 6, y0 + 1);
}

function drawFootprint(pen, fp, planar) {
  const shape = footprintShapes(fp, planar);
  pen.draw(shape.polygon, { fill: fp.color, alpha: 0.22 });
  pen.draw(shape.boundary, { stroke: fp.color, width: 2 });
  if (shape.track.coordinates.length > 1) pen.draw(shape.track, { stroke: fp.color, width: 1.5, dash: [6, 5] });
  for (const q of shape.points) pen.draw(q, { fill: q.mirrored ? "#fff" : fp.color, stroke: fp.color, width: 1.2, radius: 3 });
  pen.draw(shape.entry, { fill: fp.color, stroke: "#fff", width: 2, radius: 6 });
}

/** An optimum's track and landing as the map (unwrapped from its entry, on each copy) or the globe draws them. */
function drawOptimum(pen, { color, result }, planar) {
  const f = result.flight, lons = planar ? unwrapLongitudes(f.longitude_deg, f.longitude_deg[0]) : f.longitude_deg;
  const track = lons.map((lon, i) => [lon, f.latitude_deg[i]]);
  pen.draw({ type: "LineString", coordinates: track }, { stroke: color, width: 3 });
  pen.draw({ type: "Point", coordinates: track.at(-1) }, { fill: color, stroke: "#111", width: 2, radius: 6 });
}

/** The chosen landing opportunity as the map draws it, from the globe's lines and points ([lon, lat], continuous on
 * one copy of the map): the footprint's edge, the revolution's ground track, the coast, the burn, entry and site. */
function drawOpportunity(pen, o) {
  const S = o.style, point = (at) => ({ type: "Point", coordinates: at });
  pen.draw(line(o.ring), { stroke: S.footprint, width: 2 });
  pen.draw(line(o.track), { stroke: S.track, width: 1.6, alpha: 0.8 });
  pen.draw(line(o.coast), { stroke: S.coast, width: 3 });
  pen.draw(point(o.burn), { fill: S.coast, stroke: "#fff", width: 2, radius: 5.5 });
  pen.draw(point(o.entry), { fill: S.footprint, stroke: "#fff", width: 2, radius: 5.5 });
  pen.draw(point(o.site), { stroke: S.site, width: 2.5, radius: 10 });
}

/** A reach result's landing windows as the map draws them: each window's deorbit points as a line along the orbit
 * (unwrapped from its first point on the map's copies), or a dot for one point. */
function drawReach(pen, reach, planar) {
  for (const { color, window: w } of reach) {
    const p = w.deorbit_points, lons = planar ? unwrapLongitudes(p.longitude_deg, p.longitude_deg[0]) : p.longitude_deg;
    const at = lons.map((lon, i) => [lon, p.latitude_deg[i]]);
    if (at.length > 1) pen.draw(line(at), { stroke: color, width: 3, alpha: 0.65 });
    else pen.draw({ type: "Point", coordinates: at[0] }, { fill: color, alpha: 0.8, radius: 4 });
  }
}

const STYLE = DISPERSION_STYLE;
const line = (coordinates) => ({ type: "LineString", coordinates });
const confidenceLine = { stroke: STYLE.confidence.color, width: STYLE.confidence.widthPx, alpha: STYLE.confidence.opacity };
const nominalLine = { stroke: STYLE.nominal.color, width: STYLE.nominal.widthPx, dash: STYLE.nominal.dashPx };
const ellipseLine = { stroke: STYLE.ellipse.color, width: STYLE.ellipse.widthPx };

/** A dispersion's landing points as the map's canvas layer draws them: small squares. */
function drawClouds(ctx, projection, clouds) {
  const size = STYLE.cloud.sizePx, half = size / 2;
  ctx.globalAlpha = STYLE.cloud.opacity;
  ctx.fillStyle = STYLE.cloud.color;
  clouds.latitude_deg.forEach((lat, i) => {
    const [x, y] = projection([clouds.longitude_deg[i], lat]);
    ctx.fillRect(x - half, y - half, size, size);
  });
  ctx.globalAlpha = 1;
}

/** The shapes placeDispersion placed, as the map draws them (its layer groups in the order the page adds them):
 * the nominal boundary, the confidence footprints, the 3-sigma ellipses, the confidence levels' labels on top. */
function drawMapDispersion(pen, ctx, { placed, layers }) {
  if (layers.nominal && placed.nominal) pen.draw(line(placed.nominal.line), nominalLine);
  if (layers.confidence) {
    placed.confidence.forEach((c, rank) => c.rings.forEach((r) => {
      if (r.area) pen.draw({ type: "MultiPolygon", coordinates: r.area },
                           { fill: STYLE.confidence.color, alpha: confidenceOpacity(rank) });
      pen.draw(line(r.line), confidenceLine);
    }));
  }
  if (layers.ellipses) for (const e of placed.ellipses) pen.draw(line(e.line), ellipseLine);
  if (!layers.confidence) return;
  for (const c of placed.confidence.filter((level) => level.label)) {
    const [x, y] = pen.at(...c.label.at);
    label(ctx, levelWords(c.level), x, y + (c.label.below ? 3 : -3), { align: "center", bold: true,
          baseline: c.label.below ? "top" : "bottom", color: STYLE.confidence.labelColor });
  }
}

/** The sites with their probability as the map marks them: a ring round a stored site, a smaller disc round a site of
 * the study only; their names and probabilities are the map's labels (drawSiteLabels). */
function drawMapDispersionSites(pen, { placed, layers }, storedSites) {
  if (!layers.sites) return;
  for (const s of placed.sites) {
    const named = !storedSites.some((t) => sameSite(t, s));
    pen.draw({ type: "Point", coordinates: [s.longitude_deg, s.latitude_deg] },
             { fill: probabilityColor(s.probability), stroke: STYLE.site.edgeColor, width: STYLE.site.widthPx,
               radius: named ? STYLE.site.radiusPx : STYLE.site.aroundStoredPx });
  }
}

/** The map's site labels (MapView.placeSiteLabels: boxes in the container's px, leaders where they stand off). */
function drawSiteLabels(ctx, labels) {
  ctx.font = LABEL_FONT;
  ctx.textBaseline = "middle";
  for (const l of labels) {
    if (l.leader) {
      ctx.strokeStyle = "#1d2733";
      ctx.lineWidth = 1;
      ctx.beginPath();
      ctx.moveTo(l.leader[0], l.leader[1]);
      ctx.lineTo(l.leader[2], l.leader[3]);
      ctx.stroke();
    }
    ctx.fillStyle = "rgba(255,255,255,0.85)";
    ctx.fillRect(l.x, l.y, l.w, l.h);
    ctx.fillStyle = "#1d2733";
    ctx.fillText(l.text, l.x + 4, l.y + l.h / 2 + 0.5);
  }
  ctx.textBaseline = "alphabetic";
}

/** The dispersion as the globe draws it (globe.js): its confidence footprints, nominal boundary and 3-sigma ellipses
 * on the sphere, its sites shaded by their probability, which is written beside them. */
function drawGlobeDispersion(pen, ctx, { dispersion, layers }) {
  const f = dispersionFeatures(dispersion);
  if (layers.confidence) {
    f.confidence.forEach((c, rank) => c.rings.forEach((r) => {
      pen.draw(r, { fill: STYLE.confidence.color, alpha: confidenceOpacity(rank) });
      pen.draw(r, confidenceLine);
    }));
  }
  if (layers.nominal && f.nominal) pen.draw(f.nominal, nominalLine);
  if (layers.ellipses) for (const e of f.ellipses) pen.draw(e, ellipseLine);
  if (!layers.sites) return;
  for (const s of dispersion.sites) {
    const at = pen.at(s.longitude_deg, s.latitude_deg);
    if (!at) continue; // on the far side
    const disc = { type: "Point", coordinates: [s.longitude_deg, s.latitude_deg] };
    pen.draw(disc, { fill: probabilityColor(1), alpha: siteOpacity(s.probability), radius: GLOBE_SITE_PX.disc });
    pen.draw(disc, { stroke: STYLE.site.edgeColor, width: STYLE.site.widthPx, radius: GLOBE_SITE_PX.disc });
    label(ctx, percent(s.probability), at[0] - GLOBE_SITE_PX.probability, at[1] + 4, { align: "right", bold: true });
  }
}

function label(ctx, text, x, y, { align = "left", baseline = "alphabetic", bold = false, color = "#1d2733" } = {}) {
  ctx.font = `${bold ? "600 " : ""}11px 'DejaVu Sans', Arial, sans-serif`;
  ctx.textAlign = align;
  ctx.textBaseline = baseline;
  ctx.lineWidth = 3;
  ctx.strokeStyle = "rgba(255,255,255,0.85)";
  ctx.strokeText(text, x, y);
  ctx.fillStyle = color;
  ctx.fillText(text, x, y);
  ctx.textAlign = "left";
  ctx.textBaseline = "alphabetic";
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

/** What a shown dispersion is and which of its kinds the PNG has (its layers on), for the caption; null when none. */
export function dispersionCaption({ name, dispersion: d, placed, layers }, globeView) {
  const shapes = [layers.nominal && "nominal footprint (dashed)",
                  layers.confidence && `confidence footprints ${placed.confidence.map((c) => levelWords(c.level)).join(", ")}`,
                  layers.ellipses && "3σ ellipse of each flight"].filter(Boolean);
  const points = [layers.clouds && !globeView && "landing points", // the globe leaves them to the map
                  layers.sites && "P of reaching each site"].filter(Boolean);
  if (!shapes.length && !points.length) return null;
  return [`${name}: dispersion, ${fmt(d.samples)} samples${d.design ? `, ${d.design} design` : ""}`,
          shapes.join(", "), points.join(", ")].filter(Boolean);
}

const LEGEND_LINE_PX = 15, LEGEND_GAP_PX = 6;

/** The caption's blocks: [colour, lines] per footprint, the optimum's, the opportunity's, the dispersion's, and the
 * sites' key (as the map's legend). */
function captionBlocks(footprints, dispersionLines, sites, optimum, opportunity, reach) {
  const blocks = footprints.map((fp) => [fp.color, caption(fp)]);
  if (optimum) blocks.push([optimum.color, [`${optimum.name} (optimum)`, landingWords(optimum.result).join(", ")]]);
  if (opportunity?.caption) blocks.push([opportunity.style.coast, opportunity.caption]);
  if (dispersionLines) blocks.push([STYLE.confidence.color, dispersionLines]);
  if (sites.length) {
    blocks.push(["#2e7d32", ["sites: green reached, red not reached, grey not checked (the last reach analysis)"
                             + (dispersionLines ? "; a dispersion's P of reaching one: grey 0 to blue 1" : "")]]);
  }
  if (reach?.length) {
    blocks.push(["#5b6b7b", ["coloured lines: where deorbiting reaches a site, in its colour in the timeline"]]);
  }
  return blocks;
}

const legendHeight = (blocks) => 30 + blocks.reduce((sum, [, ls]) => sum + ls.length * LEGEND_LINE_PX + LEGEND_GAP_PX, 0);

/** The caption under the picture: the projection and data, then what each footprint (and dispersion) is. */
function drawLegend(ctx, blocks, projectionName, crop) {
  ctx.font = "12px 'DejaVu Sans', Arial, sans-serif";
  ctx.fillStyle = "#9aa8b5";
  ctx.fillRect(0, crop.h, crop.w, 1);
  ctx.fillStyle = "#34495e";
  ctx.fillText(`${projectionName} · Natural Earth`, 10, crop.h + 18);
  let y = crop.h + 26;
  for (const [color, ls] of blocks) {
    ctx.globalAlpha = 0.85;
    ctx.fillStyle = color;
    ctx.fillRect(10, y, 14, 10);
    ctx.globalAlpha = 1;
    ls.forEach((t, k) => { ctx.fillStyle = k ? "#4a5a6a" : "#1d2733"; ctx.fillText(t, 30, y + 9 + k * LEGEND_LINE_PX); });
    y += ls.length * LEGEND_LINE_PX + LEGEND_GAP_PX;
  }
}

export async function exportPNG(options) {
  const canvas = await renderCanvas(options);
  const blob = await new Promise((resolve) => canvas.toBlob(resolve, "image/png"));
  download(`footprints-${options.view === "globe" ? "orthographic" : "equirectangular"}.png`, blob);
}
