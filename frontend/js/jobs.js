// The job form: a footprint study or an optimization study built from the inputs, POST /api/jobs, progress
// from the job's event stream, and the new footprint handed to the page when the job succeeds.
import { api } from "./api.js";
import { clearFieldErrors, showFieldError } from "./fielderrors.js";
import { el, fmt } from "./format.js";

const $ = (id) => document.getElementById(id);
const POLL_MS = 1000; // when the event stream fails, ask for the job once a second

/** "0, 15, 30" -> [0, 15, 30]; anything that is not a number stays, for the service to name. */
export function parseList(text) {
  return text.split(/[,\s;]+/).filter(Boolean).map((s) => (Number.isFinite(+s) ? +s : s));
}
const number = (id) => { const v = $(id).value.trim(); return v === "" ? null : Number.isFinite(+v) ? +v : v; };

export function buildCase() {
  const vehicle = $("job-vehicle").selectedOptions[0];
  return {
    vehicle: vehicle?.dataset.builtin === "false" ? { stored: vehicle.value } : { builtin: vehicle?.value ?? "" },
    planet: { rotating: $("planet-rotating").checked },
    entry: { altitude_ft: number("entry-altitude"), velocity_fps: number("entry-velocity"), velocity_frame: "relative",
             gamma_deg: number("entry-gamma"), heading_deg: number("entry-heading"),
             latitude_deg: number("entry-latitude"), longitude_deg: number("entry-longitude") },
    alpha: { law: "max_ld" },
    bank_start: "pullout",
    stop: { altitude_ft: 50000 },
  };
}

export function buildFootprintStudy() {
  const method = $("job-method").value;
  const study = { case: buildCase(), method, mirror: $("p-mirror").checked };
  if (method === "single_parameter") {
    study.bank0_deg = parseList($("p-bank0").value);
    if (number("p-limit") != null) study.limit_deg = number("p-limit");
  } else if (method === "constant_bank" || method === "staged") {
    study.bank_deg = parseList($("p-bank").value);
    if (method === "staged") study.turn_deg = number("p-turn");
  } else if (method === "two_parameter") {
    study.bank_gain = parseList($("p-k").value);
    study.sigma_f_deg = parseList($("p-sigma-f").value);
    if (number("p-limit") != null) study.limit_deg = number("p-limit");
  } else if (method === "constant_altitude") {
    study.steps = number("p-steps");
  } else if (method === "collocation") {
    study.points_per_half = number("p-points-per-half");
  }
  return study;
}

export function buildOptimizationStudy() {
  const c = buildCase();
  const constraints = [{ quantity: "downrange_nmi", equals: number("o-downrange"), tolerance: number("o-tolerance") }];
  if (number("o-temperature") != null) {
    constraints.push({ quantity: "max_temperature_R", at_most: number("o-temperature"), tolerance: 5 });
    c.heating = { model: "reference" }; // the temperature constraint needs the Section III heating model
  }
  const method = $("o-method").value;
  const study = { case: c, payoff: { quantity: $("o-payoff").value, goal: $("o-goal").value }, constraints, method };
  if (method === "creep_pattern") study.controls = $("o-controls").value.split(","); // IPOPT shapes both itself
  return study;
}

function showOptimizerFields() {
  const method = $("o-method").value;
  document.querySelectorAll("#optimize-fields [data-optimizer]").forEach((el) => { el.hidden = el.dataset.optimizer !== method; });
}

function showMethodFields() {
  const method = $("job-method").value;
  document.querySelectorAll("#method-fields [data-method]").forEach((el) => {
    el.hidden = !el.dataset.method.split(" ").includes(method);
  });
}

export class JobsPanel {
  constructor({ onSucceeded, onOptimum }) {
    this.onSucceeded = onSucceeded;
    this.onOptimum = onOptimum;
    this.form = $("job-form");
    $("job-method").addEventListener("change", showMethodFields);
    $("o-method").addEventListener("change", showOptimizerFields);
    $("optimize-toggle").addEventListener("change", (e) => {
      $("optimize-fields").hidden = !e.target.checked;
      $("method-fields").hidden = e.target.checked;
      $("job-submit").textContent = e.target.checked ? "Run optimization" : "Run job";
    });
    this.form.addEventListener("submit", (e) => { e.preventDefault(); this.submit(); });
    showMethodFields();
    showOptimizerFields();
  }

  async loadVehicles() {
    const vehicles = await api("/api/vehicles");
    $("job-vehicle").replaceChildren(...vehicles.map((v) =>
      el("option", { value: v.id, "data-builtin": String(v.builtin !== false) }, `${v.id} · (L/D)max ${fmt(v.ld_max, 2)}`)));
    const preferred = vehicles.find((v) => v.id === "lod-1.89");
    if (preferred) $("job-vehicle").value = preferred.id;
  }

  async submit() {
    clearFieldErrors(this.form);
    $("job-form-error").hidden = true;
    const optimize = $("optimize-toggle").checked;
    const body = { kind: optimize ? "optimize" : "footprint", study: optimize ? buildOptimizationStudy() : buildFootprintStudy() };
    if ($("job-name").value.trim()) body.name = $("job-name").value.trim();
    $("job-submit").disabled = true;
    try {
      const job = await api("/api/jobs", { method: "POST", body });
      this.follow(job.id, body.name || `${body.kind} ${job.id.slice(0, 8)}`);
    } catch (err) {
      showFieldError(this.form, err, $("job-form-error"));
    } finally {
      $("job-submit").disabled = false;
    }
  }

  /** A row with a progress bar, fed by GET /api/jobs/{id}/events (polling if the stream breaks). */
  follow(id, label) {
    const li = document.createElement("li");
    li.dataset.jobId = id;
    li.append(el("div", { class: "job-line" }, el("span", { class: "job-label" }, label),
                         el("span", { class: "job-status" }, "queued")),
              el("progress", { max: "100", value: "0", "aria-label": `Progress of ${label}` }), " ",
              el("span", { class: "job-percent" }, "0 %"), el("div", { class: "job-note" }));
    $("job-list").prepend(li);
    const update = (status, progress, note) => {
      const pct = Math.round(100 * (status === "succeeded" ? 1 : progress ?? 0));
      li.querySelector("progress").value = pct;
      li.querySelector(".job-percent").textContent = `${pct} %`;
      li.querySelector(".job-note").textContent = status === "running" ? note ?? "" : "";  // IPOPT's iteration
      const s = li.querySelector(".job-status");
      s.textContent = status;
      s.className = `job-status ${status}`;
    };
    let finished = false;
    const finish = async () => {
      if (finished) return;
      finished = true;
      const job = await api(`/api/jobs/${id}`);
      update(job.status, job.progress, job.progress_note);
      if (job.status === "succeeded") {
        const o = job.result?.optimization;
        if (o) {
          const cost = o.method === "collocation" ? `${fmt(o.iterations)} IPOPT iterations` : `${fmt(o.trajectories)} trajectories`;
          li.insertAdjacentHTML("beforeend", `<div class="${o.feasible ? "succeeded" : "failed"}">optimum: cross-range `
            + `${fmt(o.summary.crossrange_nmi)} nmi at down-range ${fmt(o.summary.downrange_nmi)} nmi, `
            + `${cost}${o.feasible ? "" : ", constraints not met"}</div>`);
          this.onOptimum?.(label, o);
        }
        await this.onSucceeded(job);
      } else if (job.error) {
        li.append(el("div", { class: "failed" }, job.error));
      }
    };
    const poll = async () => {
      while (!finished) {
        const job = await api(`/api/jobs/${id}`).catch(() => null);
        if (job && ["succeeded", "failed", "cancelled"].includes(job.status)) return finish();
        if (job) update(job.status, job.progress, job.progress_note);
        await new Promise((r) => setTimeout(r, POLL_MS));
      }
    };
    const events = new EventSource(`/api/jobs/${id}/events`);
    events.addEventListener("progress", (e) => {
      const data = JSON.parse(e.data);
      update(data.status, data.progress, data.progress_note);
      if (["succeeded", "failed", "cancelled"].includes(data.status)) { events.close(); finish(); }
    });
    events.addEventListener("end", () => { events.close(); finish(); });
    events.onerror = () => { events.close(); if (!finished) poll(); };
  }
}
