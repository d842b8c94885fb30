// A dispersion in the report's axes: cross-range against down-range (nmi) about the nominal entry, with the
// nominal boundary, the confidence footprints, each flight's 3-sigma ellipse, the landing points and the sites.
import { escapeHtml, fmt } from "./format.js";
import { levelWords, percent } from "./dispersion.js";
import { gridAndTicks, niceTicks } from "./rangeplot.js";

const SVG_NS = "http://www.w3.org/2000/svg";
const MARGIN = { left: 62, right: 14, top: 26, bottom: 42 };

export function drawDispersionPlot(container, shown) {
  const width = Math.max(container.clientWidth, 200), height = Math.max(Math.min(container.clientHeight, width * 0.8), 160);
  if (!shown) {
    container.innerHTML = '<p class="empty">Run or show a dispersion to plot it in down-range and cross-range.</p>';
    return;
  }
  const d = shown.dispersion;
  const rings = (lists) => (lists?.downrange_nmi ?? []).map((x, i) => [x, lists.crossrange_nmi[i]]).filter(([x, y]) => x != null && y != null);
  const nominal = rings(d.nominal_boundary);
  const confidence = d.confidence.map((c) => ({ level: c.level, rings: c.rings.map(rings) })).sort((a, b) => a.level - b.level);
  const ellipses = d.flights.map((f) => rings(f.ellipses?.["3"]));
  const cloud = [];
  (d.clouds?.downrange_nmi ?? []).forEach((row, j) => row.forEach((x, i) => {
    const y = d.clouds.crossrange_nmi[j][i];
    if (x != null && y != null) cloud.push([x, y]);
  }));
  const all = [...nominal, ...confidence.flatMap((c) => c.rings.flat()), ...ellipses.flat(), ...cloud];
  if (!all.length) {
    container.innerHTML = '<p class="empty">No flight of this dispersion landed: nothing to plot.</p>';
    return;
  }
  const xs = all.map((p) => p[0]), ys = all.map((p) => p[1]);
  const xt = niceTicks(Math.min(0, ...xs), Math.max(...xs)), yt = niceTicks(Math.min(0, ...ys), Math.max(0, ...ys));
  const [x0, x1] = [Math.min(xt[0], ...xs), Math.max(xt[xt.length - 1], ...xs)];
  const [y0, y1] = [Math.min(yt[0], ...ys), Math.max(yt[yt.length - 1], ...ys)];
  const pw = width - MARGIN.left - MARGIN.right, ph = height - MARGIN.top - MARGIN.bottom;
  const sx = (v) => MARGIN.left + ((v - x0) / (x1 - x0 || 1)) * pw;
  const sy = (v) => MARGIN.top + ph - ((v - y0) / (y1 - y0 || 1)) * ph;
  const path = (pts, close) => pts.map(([x, y], i) => `${i ? "L" : "M"}${sx(x).toFixed(1)},${sy(y).toFixed(1)}`).join("") + (close ? "Z" : "");
  const parts = gridAndTicks({ xt, yt, sx, sy, left: MARGIN.left, top: MARGIN.top, width: pw, height: ph });
  parts.push(`<line class="axis-zero" x1="${MARGIN.left}" x2="${MARGIN.left + pw}" y1="${sy(0)}" y2="${sy(0)}"/>`);
  parts.push(`<rect class="frame" x="${MARGIN.left}" y="${MARGIN.top}" width="${pw}" height="${ph}"/>`);
  confidence.forEach((c, rank) => c.rings.forEach((r) => parts.push(
    `<path class="dispersion-confidence" d="${path(r, true)}" style="fill-opacity:${(0.1 + 0.14 * rank).toFixed(2)}">`
    + `<title>confidence footprint ${levelWords(c.level)}</title></path>`)));
  if (cloud.length) {
    parts.push(`<path class="dispersion-cloud" d="${cloud.map(([x, y]) => `M${sx(x).toFixed(1)} ${sy(y).toFixed(1)}h0`).join("")}"/>`);
  }
  ellipses.forEach((e) => { if (e.length) parts.push(`<path class="dispersion-ellipse" d="${path(e, true)}"/>`); });
  if (nominal.length) parts.push(`<path class="dispersion-nominal" d="${path(nominal, true)}"><title>nominal footprint</title></path>`);
  for (const s of d.sites) {
    if (s.downrange_nmi < x0 || s.downrange_nmi > x1 || s.crossrange_nmi < y0 || s.crossrange_nmi > y1) continue;
    parts.push(`<rect class="dispersion-plot-site" x="${(sx(s.downrange_nmi) - 4).toFixed(1)}" y="${(sy(s.crossrange_nmi) - 4).toFixed(1)}" `
      + `width="8" height="8" transform="rotate(45 ${sx(s.downrange_nmi).toFixed(1)} ${sy(s.crossrange_nmi).toFixed(1)})">`
      + `<title>${escapeHtml(s.name)}: P ${percent(s.probability)}</title></rect>`);
  }
  parts.push(`<circle class="plot-entry" cx="${sx(0)}" cy="${sy(0)}" r="5" style="fill:#14304f"><title>entry point</title></circle>`);
  parts.push(`<text class="axis-label" x="${MARGIN.left + pw / 2}" y="${height - 6}" text-anchor="middle">Down-range (nmi)</text>`);
  parts.push(`<text class="axis-label" transform="translate(14,${MARGIN.top + ph / 2}) rotate(-90)" text-anchor="middle">Cross-range (nmi)</text>`);
  parts.push(`<text class="plot-title" x="${MARGIN.left}" y="16">${escapeHtml(shown.name)} · ${fmt(d.samples)} samples</text>`);
  container.innerHTML = `<svg xmlns="${SVG_NS}" class="range-plot dispersion-plot" viewBox="0 0 ${width} ${height}" width="${width}" `
    + `height="${height}" role="img" aria-label="Cross-range against down-range of the dispersion ${escapeHtml(shown.name)}">${parts.join("")}</svg>`;
}
