// An optimum's flight against time, as the report plots its trajectories (Fig. 29's histories): alpha, bank,
// altitude and the radiation-equilibrium temperature (velocity when the study has no heating model).
import { escapeHtml, fmt } from "./format.js";
import { gridAndTicks, niceTicks } from "./rangeplot.js";

const SVG_NS = "http://www.w3.org/2000/svg";
const MARGIN = { left: 52, right: 22, top: 18, bottom: 22 };
const X_LABEL_PX = 14; // the bottom row's "Flight time (s)" under its ticks
const TITLE_PX = 20;
const TITLE_CHAR_PX = 7; // about a character of the title's 12 px bold: a longer title is cut with an ellipsis

/** The four panels of a flight: [key, label, scale] (scale turns the stored unit into the plotted one). A heating
 * model with no wall temperature (a heat-rate correlation: every temperature null) plots the velocity. */
export function historyPanels(flight) {
  const hot = (flight.temperature_R ?? []).some(Number.isFinite);
  return [["alpha_deg", "α (deg)", 1], ["bank_deg", "Bank (deg)", 1], ["altitude_ft", "Altitude (1,000 ft)", 1e-3],
          hot ? ["temperature_R", "Temperature (°R)", 1] : ["velocity_fps", "Velocity (ft/s)", 1]];
}

// the least span of a panel's axis, in its plotted unit: a bank held at 0 to 1e-4 deg is drawn flat, not as a
// wave filling the panel under ticks that all read 0.000
const MIN_SPAN = 1;

/** The values' range, widened about its middle to MIN_SPAN. */
export function axisRange(values) {
  const lo = Math.min(...values), hi = Math.max(...values), half = Math.max(0, (MIN_SPAN - (hi - lo)) / 2);
  return [lo - half, hi + half];
}

/** Tick labels with as many decimals as their spacing needs (an alpha that moves by tenths of a degree). */
const tickLabel = (ticks) => {
  const step = ticks.length > 1 ? ticks[1] - ticks[0] : 1;
  const digits = Math.min(3, Math.max(0, -Math.floor(Math.log10(step) + 1e-9)));
  return (v) => fmt(v, digits);
};

function panel(x, y, w, h, time, values, label, color, bottom) {
  const [lo, hi] = axisRange(values);
  const xt = niceTicks(0, Math.max(...time), 4), yt = niceTicks(lo, hi, 4);
  const [x0, x1] = [0, Math.max(xt[xt.length - 1], ...time)];
  const [y0, y1] = [Math.min(yt[0], lo), Math.max(yt[yt.length - 1], hi)];
  const pw = w - MARGIN.left - MARGIN.right, ph = h - MARGIN.top - MARGIN.bottom - (bottom ? X_LABEL_PX : 0);
  const sx = (v) => x + MARGIN.left + ((v - x0) / (x1 - x0 || 1)) * pw;
  const sy = (v) => y + MARGIN.top + ph - ((v - y0) / (y1 - y0 || 1)) * ph;
  const ylabel = tickLabel(yt);
  const parts = [`<rect class="frame" x="${sx(x0)}" y="${y + MARGIN.top}" width="${pw}" height="${ph}"/>`,
                 ...gridAndTicks({ xt, yt, sx, sy, left: sx(x0), top: y + MARGIN.top, width: pw, height: ph, yTick: ylabel })];
  const d = time.map((t, i) => `${i ? "L" : "M"}${sx(t).toFixed(1)},${sy(values[i]).toFixed(1)}`).join("");
  parts.push(`<path class="history" d="${d}" style="stroke:${color}"/>`);
  parts.push(`<text class="axis-label" x="${sx(x0)}" y="${y + MARGIN.top - 5}">${label}</text>`);
  if (bottom) {
    parts.push(`<text class="axis-label x-label" x="${sx(x0) + pw / 2}" y="${y + h - 4}" text-anchor="middle">`
               + "Flight time (s)</text>");
  }
  return parts.join("");
}

/** Where an optimum's flight lands, for its marker on the map and on the globe: [its ranges, its place and time]. */
export function landingWords(result) {
  const f = result.flight, s = result.summary, last = f.time_s.length - 1;
  return [`down-range ${fmt(s.downrange_nmi)} nmi, cross-range ${fmt(s.crossrange_nmi)} nmi`,
          `${fmt(f.latitude_deg[last], 2)}°, ${fmt(f.longitude_deg[last], 2)}° after ${fmt(f.time_s[last])} s`];
}

/** Draw `optimum` ({name, color, result}: an optimization job's result with its flight) into the container. */
export function drawHistories(container, optimum) {
  if (!optimum?.result?.flight) {
    container.innerHTML = '<p class="empty">Run an optimization to plot its α, bank, altitude and temperature.</p>';
    return;
  }
  const width = Math.max(container.clientWidth, 240), height = Math.max(container.clientHeight, 200);
  const { flight } = optimum.result;
  const panels = historyPanels(flight);
  const cols = width >= 2 * 220 ? 2 : 1, rows = Math.ceil(panels.length / cols);
  const w = width / cols, h = (height - TITLE_PX) / rows;
  const parts = panels.map(([key, label, scale], i) => panel((i % cols) * w, TITLE_PX + Math.floor(i / cols) * h, w, h,
                                                             flight.time_s, flight[key].map((v) => v * scale), label,
                                                             optimum.color, Math.floor(i / cols) === rows - 1));
  const s = optimum.result.summary;
  const numbers = `: cross-range ${fmt(s.crossrange_nmi)} nmi at down-range ${fmt(s.downrange_nmi)} nmi`;
  const room = Math.max(8, Math.floor((width - 12) / TITLE_CHAR_PX) - numbers.length);
  const name = optimum.name.length > room ? `${optimum.name.slice(0, room - 1)}…` : optimum.name;
  parts.push(`<text class="plot-title" x="6" y="14"><title>${escapeHtml(optimum.name + numbers)}</title>`
             + `${escapeHtml(name + numbers)}</text>`);
  container.innerHTML = `<svg xmlns="${SVG_NS}" class="range-plot history-plot" viewBox="0 0 ${width} ${height}" width="${width}" `
    + `height="${height}" role="img" aria-label="Histories of ${escapeHtml(optimum.name)}">${parts.join("")}</svg>`;
}
