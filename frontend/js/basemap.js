// Natural Earth land and country borders, shipped with the page (world-atlas, copied to vendor/ at install).
/* global topojson */
import { unwrapLongitudes } from "./geometry.js";

const cache = new Map();

/** {land, borders, coastline} as GeoJSON at "50m" or "110m" (Natural Earth 1:50m or 1:110m), in spherical
 * coordinates as d3-geo wants them. */
export function loadWorld(scale = "50m") {
  if (!cache.has(scale)) {
    cache.set(scale, Promise.all([
      fetch(`vendor/world/land-${scale}.json`).then((r) => r.json()),
      fetch(`vendor/world/countries-${scale}.json`).then((r) => r.json()),
    ]).then(([land, countries]) => ({
      land: topojson.feature(land, land.objects.land),
      coastline: topojson.mesh(land, land.objects.land),
      borders: topojson.mesh(countries, countries.objects.countries, (a, b) => a !== b),
    })));
  }
  return cache.get(scale);
}

/** A ring for a flat map: longitudes made continuous (a ring across +-180 runs on past it, and the copies of the
 * map at +-360 show the rest); a ring that goes once round a pole (Antarctica) is closed along that pole, and then
 * by its first point again: d3-geo takes a ring's last point for the repeat of its first and leaves it out, which
 * dropped the corner on the pole and drew a slanted edge across Antarctica (issue 25 item 5). */
function planarRing(ring) {
  const lons = unwrapLongitudes(ring.map((c) => c[0]), ring[0][0]);
  const out = ring.map((c, i) => [lons[i], c[1]]);
  const turn = lons[lons.length - 1] - lons[0];
  if (Math.abs(turn) > 180) {
    const pole = ring.reduce((s, c) => s + c[1], 0) < 0 ? -90 : 90;
    out.push([lons[lons.length - 1], pole], [lons[0], pole], out[0]);
  }
  return out;
}

/** GeoJSON geometry (polygons and lines) redrawn for the flat map by planarRing / continuous longitudes. */
export function planarGeometry(geometry) {
  const line = (l) => { const lons = unwrapLongitudes(l.map((c) => c[0]), l[0][0]); return l.map((c, i) => [lons[i], c[1]]); };
  switch (geometry.type) {
    case "Polygon": return { type: "Polygon", coordinates: geometry.coordinates.map(planarRing) };
    case "MultiPolygon": return { type: "MultiPolygon", coordinates: geometry.coordinates.map((p) => p.map(planarRing)) };
    case "LineString": return { type: "LineString", coordinates: line(geometry.coordinates) };
    case "MultiLineString": return { type: "MultiLineString", coordinates: geometry.coordinates.map(line) };
    case "GeometryCollection": return { type: "GeometryCollection", geometries: geometry.geometries.map(planarGeometry) };
    default: return geometry;
  }
}

export function planarFeatures(geojson) {
  if (geojson.type === "FeatureCollection") {
    return { ...geojson, features: geojson.features.map((f) => ({ ...f, geometry: planarGeometry(f.geometry) })) };
  }
  if (geojson.type === "Feature") return { ...geojson, geometry: planarGeometry(geojson.geometry) };
  return planarGeometry(geojson);
}
