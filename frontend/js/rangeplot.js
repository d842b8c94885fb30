// The selected footprint in the report's axes (Figs. 8-21): down-range across, cross-range up, in nmi, about
// its own entry point and initial heading (positive cross-range to the left).
import { describeParameter, openRing } from "./geometry.js";
import { escapeHtml, fmt } from "./format.js";

const SVG_NS = "http://www.w3.org/2000/svg";
const MARGIN = { left: 62, right: 14, top: 26, bottom: 42 };

/** Round tick values covering [lo, hi] (about `count` of them). */
export function niceTicks(lo, hi, count = 5) {
  const span = hi - lo || Math.abs(hi) || 1;
  const raw = span / count, mag = 10 ** Math.floor(Math.log10(raw));
  const step = [1, 2, 2.5, 5, 10].map((m) => m * mag).find((s) => s >= raw);
  const ticks = [];
  for (let v = Math.ceil(lo / step) * step; v <= hi + step * 1e-9; v += step) ticks.push(+v.toFixed(10));
  return ticks;
}

/** The grid lines and tick labels of a plot box (left, top, width, height in px) with scales sx, sy; yTick
 * formats the y labels (fmt by default). Every plot of the page draws its axes with this. */
export function gridAndTicks({ xt, yt, sx, sy, left, top, width, height, yTick = fmt }) {
  const parts = [];
  for (const t of xt) parts.push(`<line class="grid" x1="${sx(t)}" x2="${sx(t)}" y1="${top}" y2="${top + height}"/>`
    + `<text class="tick" x="${sx(t)}" y="${top + height + 14}" text-anchor="middle">${fmt(t, t % 1 ? 1 : 0)}</text>`);
  for (const t of yt) parts.push(`<line class="grid" x1="${left}" x2="${left + width}" y1="${sy(t)}" y2="${sy(t)}"/>`
    + `<text class="tick" x="${left - 5}" y="${sy(t) + 4}" text-anchor="end">${yTick(t)}</text>`);
  return parts;
}

/** A plot's size in `container`: its width, and a height kept at most 5:4 (a tall column beside the map on a
 * wide screen keeps the figure's proportions, not a stretched one). */
export function plotSize(container) {
  const width = Math.max(container.clientWidth, 200);
  return { width, height: Math.max(Math.min(container.clientHeight, width * 0.8), 160) };
}

/** The report's axes (down-range across, cross-range up, nmi) over the values xs, ys, the entry (0, 0) always
 * inside: the scales sx, sy, the bounds, the box and its first parts (grid and ticks, the zero line, the frame). */
export function rangeAxes(xs, ys, { width, height }) {
  const xt = niceTicks(Math.min(0, ...xs), Math.max(...xs)), yt = niceTicks(Math.min(0, ...ys), Math.max(0, ...ys));
  const [x0, x1] = [Math.min(xt[0], ...xs), Math.max(xt[xt.length - 1], ...xs)];
  const [y0, y1] = [Math.min(yt[0], ...ys), Math.max(yt[yt.length - 1], ...ys)];
  const pw = width - MARGIN.left - MARGIN.right, ph = height - MARGIN.top - MARGIN.bottom;
  const sx = (v) => MARGIN.left + ((v - x0) / (x1 - x0 || 1)) * pw;
  const sy = (v) => MARGIN.top + ph - ((v - y0) / (y1 - y0 || 1)) * ph;
  const parts = gridAndTicks({ xt, yt, sx, sy, left: MARGIN.left, top: MARGIN.top, width: pw, height: ph });
  parts.push(`<line class="axis-zero" x1="${MARGIN.left}" x2="${MARGIN.left + pw}" y1="${sy(0)}" y2="${sy(0)}"/>`);
  parts.push(`<rect class="frame" x="${MARGIN.left}" y="${MARGIN.top}" width="${pw}" height="${ph}"/>`);
  return { sx, sy, x0, x1, y0, y1, pw, ph, parts };
}

/** Put a range plot into `container`: its parts, the entry point, the axis labels and its title (the title and
 * the aria label are the user's text: escaped here). */
export function showRangePlot(container, { axes, size, parts, entryColor, title, label, className = "range-plot" }) {
  const { sx, sy, pw, ph } = axes, { width, height } = size;
  parts.push(`<circle class="plot-entry" cx="${sx(0)}" cy="${sy(0)}" r="5" style="fill:${entryColor}"><title>entry point</title></circle>`);
  parts.push(`<text class="axis-label" x="${MARGIN.left + pw / 2}" y="${height - 6}" text-anchor="middle">Down-range (nmi)</text>`);
  parts.push(`<text class="axis-label" transform="translate(14,${MARGIN.top + ph / 2}) rotate(-90)" text-anchor="middle">Cross-range (nmi)</text>`);
  parts.push(`<text class="plot-title" x="${MARGIN.left}" y="16">${escapeHtml(title)}</text>`);
  container.innerHTML = `<svg xmlns="${SVG_NS}" class="${className}" viewBox="0 0 ${width} ${height}" width="${width}" `
    + `height="${height}" role="img" aria-label="${escapeHtml(label)}">${parts.join("")}</svg>`;
}

export function drawRangePlot(container, fp) {
  const size = plotSize(container);
  if (!fp) {
    container.innerHTML = '<p class="empty">Select a footprint to plot it in down-range and cross-range.</p>';
    return;
  }
  const pts = openRing(fp.shown.points).filter((p) => p.downrange_nmi != null);
  const axes = rangeAxes(pts.map((p) => p.downrange_nmi), pts.map((p) => p.crossrange_nmi), size);
  const { sx, sy, parts } = axes;
  if (pts.length) {
    const d = pts.map((p, i) => `${i ? "L" : "M"}${sx(p.downrange_nmi).toFixed(1)},${sy(p.crossrange_nmi).toFixed(1)}`).join("") + "Z";
    parts.push(`<path class="boundary" d="${d}" style="stroke:${fp.color};fill:${fp.color}"/>`);
  }
  pts.forEach((p) => parts.push(
    `<circle class="plot-point" cx="${sx(p.downrange_nmi)}" cy="${sy(p.crossrange_nmi)}" r="3.5" `
    + `style="stroke:${fp.color};fill:${p.mirrored ? "#fff" : fp.color}"><title>down-range ${fmt(p.downrange_nmi)} nmi, `
    + `cross-range ${fmt(p.crossrange_nmi)} nmi, ${fmt(p.flight_time_s)} s${p.parameter ? ", " + escapeHtml(describeParameter(p.parameter)) : ""}</title></circle>`));
  showRangePlot(container, { axes, size, parts, entryColor: fp.color, title: fp.name,
                             label: `Cross-range against down-range of ${fp.name}` });
}
