// The landing windows of a reach analysis as a timeline (Section IV, question 3): one row per site, the
// requested hours across, a bar for each window from its first to its last deorbit time; a planner reads
// "when" from it.
import { escapeHtml, fmt } from "./format.js";
import { gridAndTicks, niceTicks } from "./rangeplot.js";

const SVG_NS = "http://www.w3.org/2000/svg";
const MARGIN = { left: 150, right: 16, top: 28, bottom: 34 };
export const SITE_COLORS = ["#2e7d32", "#1f6fbf", "#d1495b", "#8e5dbf", "#e08a1e", "#2a9d8f", "#c2549b", "#5c7c2e"];

/** The colour of the i-th site of a reach result (the map's deorbit points use the same). */
export const siteColor = (i) => SITE_COLORS[i % SITE_COLORS.length];

export function drawTimeline(container, reach) {
  if (!reach) {
    container.innerHTML = '<p class="empty">Run a reach analysis to see the landing windows in time.</p>';
    return;
  }
  const width = Math.max(container.clientWidth, 320), height = Math.max(container.clientHeight, 160);
  const hours = reach.analysis.time_span_end_s / 3600;
  const sites = reach.sites;
  const pw = width - MARGIN.left - MARGIN.right, ph = height - MARGIN.top - MARGIN.bottom;
  const row = ph / Math.max(sites.length, 1);
  const sx = (h) => MARGIN.left + (h / (hours || 1)) * pw;
  const parts = [`<rect class="frame" x="${MARGIN.left}" y="${MARGIN.top}" width="${pw}" height="${ph}"/>`,
                 ...gridAndTicks({ xt: niceTicks(0, hours, 8), yt: [], sx, sy: null, left: MARGIN.left, top: MARGIN.top,
                                   width: pw, height: ph })];
  sites.forEach((s, i) => {
    const y = MARGIN.top + i * row;
    parts.push(`<text class="tick site-label${s.reachable ? "" : " missed"}" x="${MARGIN.left - 6}" y="${y + row / 2 + 4}" `
      + `text-anchor="end">${escapeHtml(s.name.length > 22 ? s.name.slice(0, 21) + "…" : s.name)}</text>`);
  });
  const index = new Map(sites.map((s, i) => [s.name, i]));
  for (const w of reach.windows) {
    const i = index.get(w.site), y = MARGIN.top + i * row + row * 0.2;
    const x0 = sx(w.deorbit_time_start_s / 3600), x1 = sx(w.deorbit_time_end_s / 3600);
    parts.push(`<rect class="window" x="${x0}" y="${y}" width="${Math.max(x1 - x0, 2)}" height="${row * 0.6}" `
      + `style="fill:${siteColor(i)}"><title>${escapeHtml(w.site)}: revolution ${w.revolution}, deorbit `
      + `${fmt(w.deorbit_time_start_s / 3600, 2)}–${fmt(w.deorbit_time_end_s / 3600, 2)} h (u ${fmt(w.u_start_deg)}–`
      + `${fmt(w.u_end_deg)}°), best margin ${fmt(w.max_margin_nmi)} nmi</title></rect>`);
  }
  parts.push(`<text class="axis-label" x="${MARGIN.left + pw / 2}" y="${height - 6}" text-anchor="middle">Deorbit time (h from the first node)</text>`);
  parts.push(`<text class="plot-title" x="6" y="16">Landing windows: ${reach.windows.length} over ${fmt(hours, 1)} h, `
    + `${sites.filter((s) => s.reachable).length} of ${sites.length} sites reached</text>`);
  container.innerHTML = `<svg xmlns="${SVG_NS}" class="range-plot timeline-plot" viewBox="0 0 ${width} ${height}" width="${width}" `
    + `height="${height}" role="img" aria-label="Landing windows against deorbit time">${parts.join("")}</svg>`;
}
