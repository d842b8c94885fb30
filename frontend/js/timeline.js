// Timelines with one row per landing site. The landing windows of a reach analysis (Section IV, question 3): the
// requested hours across, a bar for each window from its first to its last deorbit time. The landing opportunities
// of an orbit (issue 28): UTC across, each site's nights shaded as the service gives them, each opportunity a mark
// at its landing time (filled: it meets the rules), the ascending nodes as thin lines. A planner reads "when".
// Both are built as DOM nodes: a site's name is set as text, never parsed.
import { fmt } from "./format.js";
import { niceTicks } from "./rangeplot.js";

const SVG_NS = "http://www.w3.org/2000/svg";
const MARGIN = { left: 150, right: 16, top: 28, bottom: 34 };
const NAME_CHARS = 22; // a longer site name is cut in its row's label (its whole name is in the marks' titles)
const TICK_PX = 80; // at least this far between two time ticks
const ROW_MIN_PX = 18; // a site's row: its name (12 px) and a mark clear of the next row's
const SCROLL_BAR_PX = 16; // a taller plot scrolls in its pane: its width leaves the bar room
const SITE_COLORS = ["#2e7d32", "#1f6fbf", "#d1495b", "#8e5dbf", "#e08a1e", "#2a9d8f", "#c2549b", "#5c7c2e"];

/** Each landing window of a reach result with its site's row and colour (the i-th site's: SITE_COLORS in turn): the
 * timeline's bars, the map's and the globe's deorbit lines. */
export function coloredWindows(reach) {
  const index = new Map(reach.sites.map((s, i) => [s.name, i]));
  return reach.windows.map((w) => {
    const row = index.get(w.site);
    return { row, color: SITE_COLORS[row % SITE_COLORS.length], window: w };
  });
}

/** A landing window in words: its site, revolution and deorbit hours (the timeline's bar, the deorbit line on the map
 * and on the globe). */
export const windowWords = (w) => `${w.site}: revolution ${w.revolution}, deorbit `
  + `${fmt(w.deorbit_time_start_s / 3600, 2)}–${fmt(w.deorbit_time_end_s / 3600, 2)} h`;

/** An SVG element: attributes set as attributes, strings appended as text. */
export function svgNode(tag, attributes = {}, ...children) {
  const node = document.createElementNS(SVG_NS, tag);
  for (const [k, v] of Object.entries(attributes)) if (v != null) node.setAttribute(k, String(v));
  node.append(...children.filter((c) => c != null && c !== ""));
  return node;
}
const px = (v) => +v.toFixed(2);

/** The frame both timelines share: one row per site (its name, cut to fit, whole on hover), vertical grid lines at
 * the ticks ([{at, label, cls}], at in the scale's units) and their labels. The rows share the container's height
 * but are never under ROW_MIN_PX: more sites make the plot taller, the pane scrolling (styles.css), not the names
 * overlap. Returns the svg, the rows' geometry and the box. */
function siteRows(container, { names, dimmed = [], ticks, sx, title, axisLabel, ariaLabel, cls, top = MARGIN.top, ...given }) {
  const { height, ...size } = plotSize(container, names.length, top), width = given.width ?? size.width; // sx's width
  const box = { left: MARGIN.left, top, width: width - MARGIN.left - MARGIN.right, height: height - top - MARGIN.bottom };
  const row = box.height / Math.max(names.length, 1);
  const svg = svgNode("svg", { xmlns: SVG_NS, class: `range-plot timeline-plot ${cls ?? ""}`.trim(),
                               viewBox: `0 0 ${width} ${height}`, width, height, role: "img", "aria-label": ariaLabel });
  for (const t of ticks) {
    const x = px(sx(t.at));
    svg.append(svgNode("line", { class: "grid", x1: x, x2: x, y1: box.top, y2: box.top + box.height }),
               svgNode("text", { class: `tick ${t.cls ?? ""}`.trim(), x, y: box.top + box.height + 14, "text-anchor": "middle" },
                       t.label));
  }
  names.forEach((name, i) => {
    svg.append(svgNode("g", { class: "site-row-label" }, svgNode("title", {}, name),
      svgNode("text", { class: `tick site-label${dimmed[i] ? " missed" : ""}`, x: box.left - 6,
                        y: px(box.top + i * row + row / 2 + 4), "text-anchor": "end" },
              name.length > NAME_CHARS ? name.slice(0, NAME_CHARS - 1) + "…" : name)));
  });
  svg.append(svgNode("rect", { class: "frame", x: box.left, y: box.top, width: px(box.width), height: px(box.height) }),
             svgNode("text", { class: "axis-label", x: px(box.left + box.width / 2), y: height - 6, "text-anchor": "middle" },
                     axisLabel),
             svgNode("text", { class: "plot-title", x: 6, y: 16 }, title));
  container.replaceChildren(svg);
  return { svg, box, row, width, height };
}

/** A timeline's size: the container's, taller when its rows would be under ROW_MIN_PX (then narrower by the
 * scroll bar the taller plot brings). */
export function plotSize(container, rows, top = MARGIN.top) {
  const needed = top + MARGIN.bottom + rows * ROW_MIN_PX, fits = needed <= Math.max(container.clientHeight, 160);
  return { width: Math.max(container.clientWidth - (fits ? 0 : SCROLL_BAR_PX), 320),
           height: Math.max(container.clientHeight, 160, needed) };
}

export function drawTimeline(container, reach) {
  if (!reach) {
    container.innerHTML = '<p class="empty">Run a reach analysis to see the landing windows in time.</p>';
    return;
  }
  const hours = reach.analysis.time_span_end_s / 3600;
  const sites = reach.sites;
  const { width } = plotSize(container, sites.length);
  const pw = width - MARGIN.left - MARGIN.right;
  const sx = (h) => MARGIN.left + (h / (hours || 1)) * pw;
  const { svg, box, row } = siteRows(container, {
    names: sites.map((s) => s.name), dimmed: sites.map((s) => !s.reachable), sx,
    ticks: niceTicks(0, hours, 8).map((t) => ({ at: t, label: fmt(t, t % 1 ? 1 : 0) })),
    axisLabel: "Deorbit time (h from the first node)", ariaLabel: "Landing windows against deorbit time",
    title: `Landing windows: ${reach.windows.length} over ${fmt(hours, 1)} h, `
      + `${sites.filter((s) => s.reachable).length} of ${sites.length} sites reached` });
  for (const { row: i, color, window: w } of coloredWindows(reach)) {
    const y = box.top + i * row + row * 0.2;
    const x0 = sx(w.deorbit_time_start_s / 3600), x1 = sx(w.deorbit_time_end_s / 3600);
    svg.append(svgNode("rect", { class: "window", x: px(x0), y: px(y), width: px(Math.max(x1 - x0, 2)), height: px(row * 0.6),
                                 style: `fill:${color}` },
      svgNode("title", {}, `${windowWords(w)} (u ${fmt(w.u_start_deg)}–${fmt(w.u_end_deg)}°), best margin `
        + `${fmt(w.max_margin_nmi)} nmi`)));
  }
}

// ------------------------------------------------------------------------------------------- UTC
const MINUTE_MS = 60_000;
const TICK_STEPS_MIN = [1, 2, 5, 10, 15, 20, 30, 60, 120, 180, 360, 720, 1440, 2880, 10080];

const ISO_UTC = /^(\d{4}-\d\d-\d\d)T(\d\d:\d\d):(\d\d)(?:\.(\d+))?Z$/; // as the service writes a time

/** A UTC time's ms since 1970 (POSIX: no leap second). One in a leap second ("23:59:60.250Z", which Date.parse
 * refuses) is put where POSIX puts it, on the next day's first second. */
export function utcMs(iso) {
  const m = ISO_UTC.exec(iso);
  if (!m || +m[3] < 60) return Date.parse(iso);
  return Date.parse(`${m[1]}T${m[2]}:59${m[4] ? `.${m[4]}` : ""}Z`) + 1000;
}

/** Clock-time ticks over [t0, t1] (ms, UTC) at least `minMs` apart, at whole steps from midnight: "HH:MM", and the
 * date ("2008-09-22") at midnight. */
export function utcTicks(t0, t1, minMs) {
  const step = (TICK_STEPS_MIN.find((m) => m * MINUTE_MS >= minMs) ?? TICK_STEPS_MIN.at(-1)) * MINUTE_MS;
  const ticks = [];
  for (let t = Math.ceil(t0 / step) * step; t <= t1; t += step) {
    const iso = new Date(t).toISOString(), midnight = iso.slice(11, 16) === "00:00";
    ticks.push({ at: t, label: midnight ? iso.slice(0, 10) : iso.slice(11, 16), cls: midnight ? "date" : null });
  }
  return ticks;
}

/** A UTC time in words, with its year and to the millisecond: "2026-09-21 01:18:21.374" (the caller says UTC); a
 * leap second's 60 as written. */
export function utcWords(iso) {
  const m = ISO_UTC.exec(iso);
  if (m) return `${m[1]} ${m[2]}:${m[3]}.${(m[4] ?? "").padEnd(3, "0").slice(0, 3)}`;
  const t = new Date(utcMs(iso)).toISOString();
  return `${t.slice(0, 10)} ${t.slice(11, 23)}`;
}

/** The time span a landing-opportunities answer is drawn over (ms): the window, on to the last landing, and a
 * little beyond so that no mark sits on the frame. */
export function opportunitySpan(answer) {
  const t0 = utcMs(answer.window.start_utc);
  const t1 = Math.max(utcMs(answer.window.end_utc), ...answer.opportunities.map((o) => utcMs(o.landing_utc)));
  return [t0, t1 + 0.03 * (t1 - t0)];
}

/** The opportunities of an answer (result.opportunities) against UTC: a row per site with its nights shaded
 * (sites[i].night_utc), a mark per opportunity at its landing (filled when it meets the rules, open when not; the
 * `selected` one ringed), a thin line at each ascending node. A mark clicked (or Enter on it) calls onSelect with
 * the opportunity's index in answer.opportunities. */
export function drawOpportunityTimeline(container, answer, { selected = null, onSelect } = {}) {
  if (!answer) {
    container.innerHTML = '<p class="empty">Find landing opportunities (the panel on the left) to see them in time.</p>';
    return;
  }
  const [t0, t1] = opportunitySpan(answer);
  const top0 = MARGIN.top + 18; // the key under the title: the most the plot's top can be
  const width = plotSize(container, answer.sites.length, top0).width, pw = width - MARGIN.left - MARGIN.right;
  const sx = (t) => MARGIN.left + ((t - t0) / (t1 - t0)) * pw;
  const met = answer.opportunities.filter((o) => o.meets_rules).length;
  const title = `Landing opportunities from ${answer.elements.name || `satellite ${answer.elements.satellite_number}`}: `
    + `${answer.opportunities.length}, ${met} meet the rules`;
  // the key beside the title when both fit on one line, else under it
  const top = TITLE_CHAR_PX * title.length + legendWidth() + 20 > width ? top0 : MARGIN.top;
  const { svg, box, row } = siteRows(container, {
    names: answer.sites.map((s) => s.name), dimmed: answer.sites.map((s) => !s.opportunities), sx, cls: "opportunity-plot",
    ticks: utcTicks(t0, t1, (TICK_PX / pw) * (t1 - t0)), top, title, width,
    axisLabel: `Landing time (UTC) from ${answer.window.start_utc.slice(0, 10)} · grey: night at the site`,
    ariaLabel: "Landing opportunities against UTC" });
  const clip = (t) => Math.min(Math.max(t, t0), t1);
  const nights = svgNode("g", { class: "op-nights" });
  answer.sites.forEach((s, i) => {
    for (const [a, b] of s.night_utc ?? []) {
      const x0 = sx(clip(utcMs(a))), x1 = sx(clip(utcMs(b)));
      if (x1 - x0 < 0.5) continue; // outside the span drawn
      nights.append(svgNode("rect", { class: "op-night", x: px(x0), y: px(box.top + i * row + 1), width: px(x1 - x0),
                                      height: px(Math.max(row - 2, 1)), "data-site": i, "data-start": a, "data-end": b }));
    }
  });
  svg.prepend(nights); // under the grid, the frame and the marks
  for (const iso of answer.ascending_nodes_utc) {
    const x = px(sx(utcMs(iso)));
    svg.append(svgNode("line", { class: "op-node", x1: x, x2: x, y1: box.top, y2: box.top + box.height, "data-utc": iso },
                       svgNode("title", {}, `ascending node ${utcWords(iso)} UTC`)));
  }
  const radius = Math.max(2.5, Math.min(5.5, row * 0.3));
  const marks = answer.opportunities.map((o, k) => ({ o, k })).sort((a, b) => (a.k === selected) - (b.k === selected));
  for (const { o, k } of marks) { // the selected one last: on top
    const words = `${o.site_name}: landing ${utcWords(o.landing_utc)} UTC, revolution ${o.revolution_number ?? o.revolution}; burn `
      + `${utcWords(o.burn_utc)}, Δv ${fmt(o.delta_v_fps, 1)} ft/s; margin ${fmt(o.margin_nmi)} nmi, sun `
      + `${fmt(o.sun_elevation_deg, 1)}°${o.meets_rules ? "" : " (fails a rule)"}`;
    svg.append(svgNode("circle", { class: `op-mark ${o.meets_rules ? "meets" : "fails"}${k === selected ? " selected" : ""}`,
                                   cx: px(sx(utcMs(o.landing_utc))), cy: px(box.top + o.site * row + row / 2),
                                   r: k === selected ? radius + 1.5 : radius, tabindex: 0, role: "button",
                                   "aria-label": words, "data-index": k, "data-site": o.site },
                       svgNode("title", {}, words)));
  }
  svg.append(legend(box, width));
  const pick = (e) => {
    const mark = e.target.closest?.(".op-mark[data-index]");
    if (!mark || (e.type === "keydown" && e.key !== "Enter" && e.key !== " ")) return;
    e.preventDefault();
    onSelect?.(Number(mark.dataset.index));
  };
  svg.addEventListener("click", pick);
  svg.addEventListener("keydown", pick);
}

const LEGEND = [["meets", "meets the rules"], ["fails", "fails a rule"], ["night", "night"], ["node", "ascending node"]];
const TICK_CHAR_PX = 6.2, TITLE_CHAR_PX = 7; // the widths of a character of the ticks' and the title's font, about
const KEY_PX = 32; // a key's symbol and its gaps
const legendWidth = () => LEGEND.reduce((w, [, text]) => w + TICK_CHAR_PX * text.length + KEY_PX, 0);

/** The marks' key, above the frame's right end. */
function legend(box, width) {
  const y = box.top - 10;
  const g = svgNode("g", { class: "op-legend" });
  let x = width - MARGIN.right - legendWidth();
  for (const [kind, text] of LEGEND) {
    x += 10;
    g.append(kind === "night" ? svgNode("rect", { class: "op-night", x: x - 5, y: y - 5, width: 11, height: 10 })
      : kind === "node" ? svgNode("line", { class: "op-node", x1: x, x2: x, y1: y - 6, y2: y + 6 })
        : svgNode("circle", { class: `op-mark ${kind}`, cx: x, cy: y, r: 4.5 }));
    x += 10;
    g.append(svgNode("text", { class: "tick", x, y: y + 4 }, text));
    x += TICK_CHAR_PX * text.length + KEY_PX - 20;
  }
  return g;
}
