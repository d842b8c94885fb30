// Pure geometry of the page: longitudes across +-180, the orbit of an entry point, the service's outline on the
// map, CSV of footprints. No DOM and no Leaflet here, so that the browser tests can check it through the page.

import { fmt } from "./format.js";

const RAD_PER_DEG = Math.PI / 180.0;

/** A longitude in (-180, 180]. */
export function wrapLongitude(lonDeg) {
  const x = ((((lonDeg + 180.0) % 360.0) + 360.0) % 360.0) - 180.0;
  return x === -180.0 ? 180.0 : x;
}

const SAME_PLACE_DEG = 1e-6; // a site stored and the same site in a study (both as the planner typed them)

/** Whether two sites ({name, latitude_deg, longitude_deg}) are the same: one name at one place (longitudes that
 * differ by 360 deg name one place). */
export function sameSite(a, b) {
  return a.name === b.name && Math.abs(a.latitude_deg - b.latitude_deg) < SAME_PLACE_DEG
    && Math.abs(wrapLongitude(a.longitude_deg - b.longitude_deg)) < SAME_PLACE_DEG;
}

/** Longitudes made continuous: the first within 180 deg of referenceDeg, each next within 180 deg of the one
 * before, so that a ring or a track that crosses +-180 never jumps by 360 deg. */
export function unwrapLongitudes(lonsDeg, referenceDeg) {
  const out = [];
  let previous = referenceDeg;
  for (const lon of lonsDeg) {
    const u = previous + wrapLongitude(lon - previous);
    out.push(u);
    previous = u;
  }
  return out;
}

/** The longitudes of a footprint's ring made continuous and placed on the copy of the map where its point
 * nearest the entry lies within 180 deg of the entry. (Anchoring the ring's first point instead fails: that is
 * often the far, zero-bank point, 180 deg or more from the entry.) */
export function unwrapRing(points, reference) {
  const lons = unwrapLongitudes(points.map((p) => p.longitude_deg), points.length ? points[0].longitude_deg : 0);
  if (!lons.length) return lons;
  const r = unit(reference.latitude_deg, reference.longitude_deg);
  let nearest = 0, best = -2;
  points.forEach((p, i) => {
    const c = dot(unit(p.latitude_deg, p.longitude_deg), r);
    if (c > best) { best = c; nearest = i; }
  });
  const shift = 360 * Math.round((reference.longitude_deg - lons[nearest]) / 360);
  return lons.map((x) => x + shift);
}

/** Offsets (multiples of 360 deg) at which copies of a shape spanning [minLon, maxLon] are drawn so that every
 * part of it that wraps past +-180 also shows on the other side of the map. */
export function copyOffsets(minLonDeg, maxLonDeg) {
  const offsets = [];
  for (let k = -2; k <= 2; k++) {
    const lo = minLonDeg + 360 * k, hi = maxLonDeg + 360 * k;
    if (hi >= -540 && lo <= 540) offsets.push(360 * k); // the map may be panned one world either way
  }
  return offsets;
}

function unit(latDeg, lonDeg) {
  const la = latDeg * RAD_PER_DEG, lo = lonDeg * RAD_PER_DEG;
  return [Math.cos(la) * Math.cos(lo), Math.cos(la) * Math.sin(lo), Math.sin(la)];
}
const cross = (a, b) => [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]];
const dot = (a, b) => a[0] * b[0] + a[1] * b[1] + a[2] * b[2];

/** The orbit through an entry point with a heading (deg from north, clockwise): its inclination, the longitude
 * of its ascending node and the entry's argument of latitude u measured from that node (all deg). An
 * equatorial orbit has no node: the entry point itself stands for it (u = 0). */
export function orbitOfEntry(latitudeDeg, longitudeDeg, headingDeg) {
  const la = latitudeDeg * RAD_PER_DEG, lo = longitudeDeg * RAD_PER_DEG, h = headingDeg * RAD_PER_DEG;
  const r = unit(latitudeDeg, longitudeDeg);
  const north = [-Math.sin(la) * Math.cos(lo), -Math.sin(la) * Math.sin(lo), Math.cos(la)];
  const east = [-Math.sin(lo), Math.cos(lo), 0.0];
  const d = [0, 1, 2].map((i) => Math.cos(h) * north[i] + Math.sin(h) * east[i]);
  const n = cross(r, d); // the orbit's normal (angular momentum direction)
  const inclinationDeg = Math.acos(Math.max(-1, Math.min(1, n[2]))) / RAD_PER_DEG;
  const s = Math.hypot(n[0], n[1]);
  if (s < 1e-9) return { inclinationDeg, nodeLongitudeDeg: wrapLongitude(longitudeDeg), uDeg: 0.0 };
  const node = [-n[1] / s, n[0] / s, 0.0]; // z x n: the ascending node
  const ahead = cross(n, node); // 90 deg past the node along the orbit
  const uDeg = Math.atan2(dot(r, ahead), dot(r, node)) / RAD_PER_DEG;
  return { inclinationDeg, nodeLongitudeDeg: Math.atan2(node[1], node[0]) / RAD_PER_DEG, uDeg };
}

/** The body of POST /api/footprints/{id}/transform that puts the footprint's entry on the orbit of the given
 * node longitude and inclination, at the entry's own argument of latitude (the service's orbit place), then
 * stepDownrangeNmi further on. */
export function transformRequest(orbit, controls) {
  return {
    to: { node_longitude_deg: controls.nodeLongitudeDeg, inclination_deg: controls.inclinationDeg,
          argument_of_latitude_deg: orbit.uDeg },
    step_downrange_nmi: controls.stepDownrangeNmi,
    earth_rotation: controls.earthRotation,
  };
}

/** The ring of a boundary without a repeated closing point. */
export function openRing(points) {
  if (points.length > 1) {
    const a = points[0], b = points[points.length - 1];
    if (a.latitude_deg === b.latitude_deg && a.longitude_deg === b.longitude_deg) return points.slice(0, -1);
  }
  return points;
}

// a footprint point's control parameters in the words of the report (Sections II.5-II.6, App. C)
const PARAMETER_WORDS = {
  bank0_deg: ["initial bank", "°"], bank_gain: ["K", ""], sigma_f_deg: ["σf", "°"], bank_deg: ["bank", "°"],
  turn_deg: ["wings level after a turn of", "°"], limit_deg: ["bank limit", "°"], downrange_target_nmi: ["down-range held at", " nmi"],
  agreement_deg: ["re-flown within", "°"], iterations: ["IPOPT iterations", ""], steps: ["steps", ""],
  inverted_s: ["upside down at negative lift for", " s"],
};
const MIN_RANGE_WORDS = { zero_lift: "zero lift (shortest flight)", cl_max: "C_L max, no bank (shortest flight)" };

/** A parameter dict ({"bank0_deg": 105, "bank_gain": 1.17}) in words: "initial bank 105°, K 1.17". */
export function describeParameter(parameter) {
  if (parameter == null) return "";
  if (typeof parameter !== "object") return String(parameter);
  return Object.entries(parameter).filter(([k, v]) => v != null && !k.startsWith("nlp_"))
    .map(([k, v]) => {
      if (k === "min_range") return MIN_RANGE_WORDS[v] ?? `shortest flight: ${v}`;
      const [word, unit] = PARAMETER_WORDS[k] ?? [k.replace(/_/g, " "), ""];
      const shown = typeof v === "number" ? (Math.abs(v) >= 100 ? fmt(v) : +v.toFixed(Math.abs(v) < 1 ? 3 : 2)) : v;
      return `${word} ${shown}${unit}`;
    }).join(", ");
}

/** The footprint as the cylindrical map draws it. `polygons`: its area within -180..180 deg, to be drawn at every
 * copy offset: the service's outline (core.outline: polygons of [outer, holes...] rings of [lon, lat], a pole -- or
 * both -- taken in when the footprint holds it). `line`: its boundary as [lon, lat] pairs, continuous, on the copy
 * where unwrapRing places the ring, ending on the copy of its first point (once round the axis: 360 deg on).
 * Without the service's outline the ring is its own area, unless it goes round the earth's axis: then `polygons`
 * is null (which side holds the pole only the footprint's chart can say). */
export function planarOutline(shown) {
  const ring = openRing(shown.points);
  if (!ring.length) return { polygons: [], line: [] };
  const ringLons = unwrapRing(ring, shown.reference);
  const o = shown.outline;
  const line = o?.longitude_deg?.length
    ? o.longitude_deg.map((lon, i) => [lon + 360 * Math.round((ringLons[0] - o.longitude_deg[0]) / 360),
                                       o.latitude_deg[i]])
    : ring.map((p, i) => [ringLons[i], p.latitude_deg]);
  const [x0, y0] = line[0], [xn] = line[line.length - 1];
  const turns = Math.round((xn + wrapLongitude(x0 - xn) - x0) / 360); // the closing step is at most 180 deg
  line.push([x0 + 360 * turns, y0]);
  if (o?.area) return { polygons: o.area, line };
  return { polygons: turns ? null : [[line]], line };
}

/** The points of a shape given as lists ({latitude_deg: [...], longitude_deg: [...], downrange_nmi: [...],
 * crossrange_nmi: [...]}, as a dispersion's rings and ellipses come), as planarOutline and unwrapRing take them; a
 * point without a latitude (a flight that did not land) is left out. */
export function listPoints(lists) {
  const out = [];
  (lists?.latitude_deg ?? []).forEach((lat, i) => {
    if (lat == null || lists.longitude_deg[i] == null) return;
    out.push({ latitude_deg: lat, longitude_deg: lists.longitude_deg[i], downrange_nmi: lists.downrange_nmi?.[i] ?? null,
               crossrange_nmi: lists.crossrange_nmi?.[i] ?? null });
  });
  return out;
}

/** Of `anchors` (points whose longitudes are already placed on a copy of the map), the one nearest on the sphere to
 * any of `points`: as the reference of planarOutline it puts a shape on the same copy as the anchors, however far
 * from the entry it lies (a dispersion's ellipse at the far end of a footprint that runs past 180 deg). */
export function nearestAnchor(points, anchors) {
  let best = anchors[0], bestDot = -2;
  const step = Math.max(1, Math.floor(points.length / 200)); // a few hundred vertices decide as well as all
  for (const a of anchors) {
    const u = unit(a.latitude_deg, a.longitude_deg);
    for (let i = 0; i < points.length; i += step) {
      const c = dot(unit(points[i].latitude_deg, points[i].longitude_deg), u);
      if (c > bestDot) { bestDot = c; best = a; }
    }
  }
  return best;
}

/** Each of `points` given the longitude of its copy next to the nearest vertex of a placed ring (its points and
 * their longitudes as unwrapRing placed them): the flights of a footprint put where its drawn boundary is. */
export function placeOnRing(points, ring, ringLons) {
  const units = ring.map((p) => unit(p.latitude_deg, p.longitude_deg));
  return points.map((p) => {
    const u = unit(p.latitude_deg, p.longitude_deg);
    let nearest = -1, best = -2;
    units.forEach((v, i) => { const c = dot(u, v); if (c > best) { best = c; nearest = i; } });
    if (nearest < 0) return p.longitude_deg;
    return ringLons[nearest] + wrapLongitude(p.longitude_deg - ring[nearest].longitude_deg);
  });
}

function pointFields(p) {
  return { latitude_deg: p.latitude_deg, longitude_deg: p.longitude_deg, downrange_nmi: p.downrange_nmi ?? null,
           crossrange_nmi: p.crossrange_nmi ?? null, flight_time_s: p.flight_time_s ?? null,
           parameter: p.parameter == null ? null : JSON.stringify(p.parameter), mirrored: p.mirrored ?? null };
}

export const CSV_COLUMNS = ["footprint_id", "name", "index", "latitude_deg", "longitude_deg", "downrange_nmi",
                            "crossrange_nmi", "flight_time_s", "parameter", "mirrored"];

// a spreadsheet runs a cell that starts so as a formula (OWASP CSV injection; contracts/records.py csv_cell)
const FORMULA_START = /^[=+\-@\t\r]/;

/** A CSV cell: empty for null; text a spreadsheet would run as a formula behind an apostrophe; quoted if needed. */
export function csvCell(v) {
  if (v == null) return "";
  const text = typeof v === "string" && FORMULA_START.test(v) ? `'${v}` : String(v);
  return /[",\n\r]/.test(text) ? `"${text.replace(/"/g, '""')}"` : text;
}

/** One CSV row per shown boundary point. */
export function toCSV(footprints) {
  const rows = [CSV_COLUMNS.join(",")];
  for (const fp of footprints) {
    openRing(fp.shown.points).forEach((p, i) => {
      const row = { footprint_id: fp.id, name: fp.name, index: i, ...pointFields(p) };
      rows.push(CSV_COLUMNS.map((c) => csvCell(row[c])).join(","));
    });
  }
  return rows.join("\n") + "\n";
}

/** Twice the signed area of the points' (down-range, cross-range) polygon: > 0 when its inside lies to the left of
 * the points' order (the order of every footprint), 0 where the points carry no ranges. */
function rangeTurn(points) {
  let twice = 0;
  points.forEach((p, i) => {
    const q = points[(i + 1) % points.length];
    twice += p.downrange_nmi * q.crossrange_nmi - q.downrange_nmi * p.crossrange_nmi;
  });
  return Number.isFinite(twice) ? twice : 0;
}

/** A closed [lon, lat] ring wound as d3-geo wants (clockwise: its inside to the right). The points' down- and
 * cross-range say which side is inside (cross-range to the left of the flight, as north is left of east: the same
 * turn on the map), so a footprint past half-way round and larger than a hemisphere keeps its side; points without
 * ranges (a dispersion's rings) bound the smaller of their two regions. */
export function sphericalRing(points, geoArea) {
  const open = openRing(points);
  const ring = open.map((p) => [p.longitude_deg, p.latitude_deg]);
  if (!ring.length) return ring;
  ring.push(ring[0]);
  const turn = rangeTurn(open);
  const polygon = { type: "Polygon", coordinates: [ring] };
  if (turn !== 0 ? turn > 0 : geoArea && geoArea(polygon) > 2 * Math.PI) ring.reverse();
  return ring;
}
