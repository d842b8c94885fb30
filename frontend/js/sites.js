// Landing sites (stored by the service) and the reach of the selected footprint from an orbit (Section IV).
import { api } from "./api.js";
import { clearFieldErrors, showFieldError } from "./fielderrors.js";
import { el, escapeHtml, fmt } from "./format.js";
import { intervalWords, percent } from "./dispersion.js";
import { openRing, sameSite, wrapLongitude } from "./geometry.js";

const $ = (id) => document.getElementById(id);
const num = (id) => { const v = $(id).value.trim(); return v === "" ? null : +v; };

/** A site's stored verdict in a few words: "reached by lod-1.89 ... (node -30°, 45.9°)". */
function verdict(s) {
  const v = s.last_reach;
  if (!v) return null;
  return el("span", { class: `verdict ${v.reachable ? "reached" : "missed"}` },
    `${v.reachable ? "reached" : "not reached"} by ${v.footprint} `
    + `(node ${fmt(v.orbit.node_longitude_deg, 1)}°, i ${fmt(v.orbit.inclination_deg, 1)}°)`);
}

/** A site's probability in the dispersion shown: "P 97.7 % (93.3–99.5 %) in lod-1.89 dispersed". */
function dispersionVerdict(s, dispersion) {
  const hit = dispersion?.sites.find((t) => sameSite(t, s));
  if (!hit) return null;
  return el("span", { class: "dispersion-p" }, `P ${percent(hit.probability)} (${intervalWords(hit.interval)}) in `,
            el("em", {}, dispersion.name));
}

/** A site's guided probability from the last guided reach: "guided P 100 % (96–100 %) within 5 nmi". */
function guidedVerdict(s, guided) {
  const hit = guided?.sites.find((t) => sameSite(t, s));
  if (!hit) return null;
  return el("span", { class: "guided-p" },
            `guided P ${percent(hit.probability)} (${intervalWords(hit.interval)}) within ${+guided.radius_nmi.toFixed(3)} nmi`);
}

export class SitesPanel {
  constructor({ onChange, onReach, selectedFootprint, toast }) {
    this.sites = [];
    this.reach = null; // the last reach result, by site name
    this.dispersion = null; // {name, sites} of the dispersion shown
    this.guided = null; // the last guided reach: {radius_nmi, sites}
    this.lastReach = null; // the last reach analysis shown in the site table
    this.onChange = onChange;
    this.onReach = onReach;
    this.selectedFootprint = selectedFootprint;
    this.toast = toast;
    this.adding = false;
    $("site-click-toggle").addEventListener("click", () => this.setAdding(!this.adding));
    $("site-csv").addEventListener("change", (e) => this.uploadCsv(e.target.files[0]));
    $("sites-remove-all").addEventListener("click", () => this.removeAll());
    $("reach-form").addEventListener("submit", (e) => { e.preventDefault(); this.computeReach(); });
    $("site-list").addEventListener("click", (e) => {
      const id = e.target.closest("button[data-delete]")?.dataset.delete;
      if (id) this.remove(id);
    });
  }

  setAdding(on) {
    this.adding = on;
    $("site-click-toggle").setAttribute("aria-pressed", String(on));
    document.getElementById("map").classList.toggle("adding-sites", on);
  }

  /** The sites with the last reach verdict attached: this session's, else the one stored with the site (null:
   * never analysed). */
  shown() {
    return this.sites.map((s) => ({ ...s, reachable: this.reach?.get(s.name)?.reachable ?? s.last_reach?.reachable ?? null }));
  }

  async load() {
    this.sites = await api("/api/sites");
    this.render();
  }

  render() {
    $("sites-remove-all").hidden = this.sites.length < 2;
    $("site-list").replaceChildren(...this.shown().map((s) => el("li", {},
      el("span", {}, `${s.name} `, el("span", { class: "muted" }, `${fmt(s.latitude_deg, 2)}°, ${fmt(s.longitude_deg, 2)}°`),
         verdict(s), dispersionVerdict(s, this.dispersion), guidedVerdict(s, this.guided)),
      el("button", { type: "button", "data-delete": String(s.id), "aria-label": `Delete ${s.name}` }, "×"))));
    this.onChange();
  }

  /** The probabilities of the dispersion shown, beside the stored sites it has. */
  setDispersion(name, sites) {
    this.dispersion = { name, sites };
    this.render();
  }

  /** Each stored site's probability of being reached by the guided vehicle (a guided reach job's result). */
  setGuided(result) {
    this.guided = result;
    this.render();
    if (this.lastReach) this.renderReach(this.lastReach); // its table's Guided P column
  }

  async onMapClick(latlng) {
    if (!this.adding) return;
    const name = $("site-name").value.trim() || `Site ${this.sites.length + 1}`;
    try {
      await api("/api/sites", { method: "POST",
                                body: { name, latitude_deg: +latlng.lat.toFixed(4), longitude_deg: +wrapLongitude(latlng.lng).toFixed(4) } });
      $("site-name").value = "";
      await this.load();
    } catch (err) { this.toast(err.message, true); }
  }

  async uploadCsv(file) {
    if (!file) return;
    $("sites-error").hidden = true;
    try {
      const res = await api("/api/sites/csv", { method: "POST", body: await file.text(), contentType: "text/csv" });
      this.toast(`${res.created} sites added, ${res.updated} already stored (kept by name)`);
      await this.load();
    } catch (err) {
      $("sites-error").textContent = err.message;
      $("sites-error").hidden = false;
    }
    $("site-csv").value = "";
  }

  /** Every stored site removed at once, once the planner says so (17 sites took 17 clicks). */
  async removeAll() {
    if (!this.sites.length || !window.confirm(`Remove all ${this.sites.length} landing sites?`)) return;
    try {
      const { deleted } = await api("/api/sites", { method: "DELETE" });
      this.toast(`${deleted} sites removed`);
      await this.load();
    } catch (err) { this.toast(err.message, true); }
  }

  async remove(id) {
    try { await api(`/api/sites/${id}`, { method: "DELETE" }); await this.load(); } catch (err) { this.toast(err.message, true); }
  }

  async computeReach() {
    const form = $("reach-form");
    clearFieldErrors(form);
    $("reach-error").hidden = true;
    const fp = this.selectedFootprint();
    if (!fp?.detail) { $("reach-error").textContent = "Select a footprint first."; $("reach-error").hidden = false; return; }
    if (!this.sites.length) { $("reach-error").textContent = "Add a landing site first."; $("reach-error").hidden = false; return; }
    const points = openRing(fp.detail.points).map((p) => ({ downrange_nmi: p.downrange_nmi, crossrange_nmi: p.crossrange_nmi,
                                                            flight_time_s: p.flight_time_s }));
    const orbit = fp.controls; // the live orbit controls of the selected footprint
    const body = { // the stored sites, so that the service keeps each one's verdict with it
      description: fp.name,
      footprint: { points },
      orbit: { inclination_deg: orbit.inclinationDeg, altitude_nmi: num("r-altitude"), node_longitude_deg: orbit.nodeLongitudeDeg },
      revolutions: { first: 1, hours: num("r-hours") },
      earth_rotation: $("r-rotation").value,
    };
    $("reach-submit").disabled = true;
    try {
      const result = await api("/api/reach?store_verdicts=true", { method: "POST", body });
      this.reach = new Map(result.sites.map((s) => [s.name, s]));
      this.renderReach(result);
      await this.load(); // the verdicts as stored
      this.onReach?.(result, fp);
    } catch (err) {
      showFieldError(form, err, $("reach-error"));
    } finally {
      $("reach-submit").disabled = false;
    }
  }

  renderReach(result) {
    this.lastReach = result;
    const guidedP = (s) => { // the last guided reach's probability of this site, when it has the site
      const hit = this.guided?.sites.find((t) => sameSite(t, s));
      return hit ? `${percent(hit.probability)} (${intervalWords(hit.interval)})` : "–";
    };
    const rows = result.sites.map((s) => `<tr><td>${escapeHtml(s.name)}</td>`
      + `<td class="${s.reachable ? "reached" : "missed"}">${s.reachable ? "yes" : "no"}</td><td>${s.windows}</td>`
      + `<td>${s.revolutions.slice(0, 4).join(", ")}${s.revolutions.length > 4 ? "…" : ""}</td>`
      + `<td>${fmt(s.best_margin_nmi)}</td><td>${s.first_deorbit_time_s == null ? "–" : fmt(s.first_deorbit_time_s / 3600, 2)}</td>`
      + `<td class="guided-p-cell">${guidedP(s)}</td></tr>`);
    const notes = (result.notes || []).map((n) => `<p class="muted small">${escapeHtml(n)}</p>`).join("");
    const reached = result.sites.filter((s) => s.reachable).length;
    $("reach-summary").innerHTML = `${reached} of ${result.sites.length} sites reached, ${result.windows.length} landing `
      + `windows (the timeline below the map) <button type="button" id="reach-table">Site table</button>${notes}`;
    $("reach-table").addEventListener("click", () => $("reach-dialog").showModal());
    $("reach-result").innerHTML = `<table class="reach"><caption class="small muted">${fmt(result.analysis.placements)} deorbit points, `
      + `${fmt(result.analysis.seconds, 2)} s</caption><thead><tr><th>Site</th><th>Reach</th><th>Windows</th><th>Revs</th>`
      + `<th>Best margin (nmi)</th><th>First (h)</th><th>Guided P</th></tr></thead><tbody>${rows.join("")}</tbody></table>`;
  }
}
