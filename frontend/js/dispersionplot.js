// A dispersion in the report's axes: cross-range against down-range (nmi) about the nominal entry, with the
// nominal boundary, the confidence footprints, each flight's 3-sigma ellipse, the landing points and the sites.
import { escapeHtml, fmt } from "./format.js";
import { confidenceOpacity, levelWords, percent } from "./dispersion.js";
import { plotSize, rangeAxes, showRangePlot } from "./rangeplot.js";

export function drawDispersionPlot(container, shown) {
  const size = plotSize(container);
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
  const axes = rangeAxes(all.map((p) => p[0]), all.map((p) => p[1]), size);
  const { sx, sy, x0, x1, y0, y1, parts } = axes;
  const path = (pts, close) => pts.map(([x, y], i) => `${i ? "L" : "M"}${sx(x).toFixed(1)},${sy(y).toFixed(1)}`).join("") + (close ? "Z" : "");
  confidence.forEach((c, rank) => c.rings.forEach((r) => parts.push(
    `<path class="dispersion-confidence" d="${path(r, true)}" style="fill-opacity:${confidenceOpacity(rank).toFixed(2)}">`
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
  showRangePlot(container, { axes, size, parts, entryColor: "#14304f", title: `${shown.name} · ${fmt(d.samples)} samples`,
                             label: `Cross-range against down-range of the dispersion ${shown.name}`,
                             className: "range-plot dispersion-plot" });
}
