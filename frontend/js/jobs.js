// The job form: a footprint study, an optimization study or a dispersion study built from the inputs (or a
// dispersion study file), POST /api/jobs, progress from the job's event stream, and the new footprint, optimum or
// dispersion handed to the page when the job succeeds.
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

// the dispersion's spreads: [input id, group, input, distribution] (contracts/dispersion.py), a blank one left out
const SPREADS = [["d-altitude", "entry", "altitude_ft", "normal"], ["d-velocity", "entry", "velocity_fps", "normal"],
                 ["d-gamma", "entry", "gamma_deg", "normal"], ["d-heading", "entry", "heading_deg", "normal"],
                 ["d-latitude", "entry", "latitude_deg", "normal"], ["d-longitude", "entry", "longitude_deg", "normal"],
                 ["d-cl", "vehicle", "cl_multiplier", "truncated_normal"],
                 ["d-cd", "vehicle", "cd_multiplier", "truncated_normal"],
                 ["d-wing", "vehicle", "wing_loading_psf", "normal"]];
const TRUNCATED_SIGMAS = 3; // a multiplier's spread is cut at 3 sigma, as examples/disperse_lod189.json
export const DISPERSION_METHODS = ["single_parameter", "constant_bank", "staged"]; // fixed control laws (contracts.dispersion.LAWS)

/** The dispersion study of the form: its footprint study, samples and spreads, and the given landing sites. */
export function buildDispersionStudy(sites = []) {
  const study = { footprint: buildFootprintStudy(), samples: number("d-samples"), design: $("d-design").value,
                  seed: number("d-seed"), entry: {}, vehicle: {}, confidence: parseList($("d-confidence").value),
                  sites: sites.map((s) => ({ name: s.name, latitude_deg: s.latitude_deg, longitude_deg: s.longitude_deg })) };
  for (const [id, group, input, law] of SPREADS) {
    const std = number(id);
    if (std != null) study[group][input] = { [law]: law === "truncated_normal" ? { std, sigmas: TRUNCATED_SIGMAS } : { std } };
  }
  if (number("d-density") != null) study.density = { std: number("d-density"), correlation_length_ft: number("d-correlation") };
  return study;
}

/** A 422 about a dispersion's footprint study ("study.footprint.case.entry.velocity_fps", the service may add the
 * method's union tag: "study.footprint.single_parameter.case...") named as the form's footprint inputs name it
 * ("study.case.entry.velocity_fps"), so that it shows next to that input, worded by its label. */
export function asFootprintField(err) {
  const m = /^study\.footprint\.(?:(\w+)\.)?/.exec(err.field ?? "");
  if (!m) return err;
  const tag = [...$("job-method").options].some((o) => o.value === m[1]) ? m[0] : "study.footprint.";
  const path = tag.slice("study.".length);
  err.field = `study.${err.field.slice(tag.length)}`;
  if (err.message.startsWith(tag)) err.message = `study.${err.message.slice(tag.length)}`;
  else if (err.message.startsWith(path)) err.message = err.message.slice(path.length);
  return err;
}

/** One line of what a dispersion did: samples, flights and every outcome counted, so that none is dropped unseen. */
export function outcomeWords(d) {
  const { flights, landed, ...others } = d.outcomes;
  const rest = Object.entries(others).map(([what, n]) => `${fmt(n)} ${what}`);
  return `${fmt(d.samples)} samples, ${fmt(flights)} flights: ${fmt(landed ?? 0)} landed${rest.length ? ", " + rest.join(", ") : ""}`;
}

function showOptimizerFields() {
  const method = $("o-method").value;
  document.querySelectorAll("#optimize-fields [data-optimizer]").forEach((el) => { el.hidden = el.dataset.optimizer !== method; });
}

function showMethodFields() {
  const dispersing = $("disperse-toggle").checked;
  for (const option of $("job-method").options) option.disabled = dispersing && !DISPERSION_METHODS.includes(option.value);
  if (dispersing && !DISPERSION_METHODS.includes($("job-method").value)) $("job-method").value = DISPERSION_METHODS[0];
  const method = $("job-method").value;
  document.querySelectorAll("#method-fields [data-method]").forEach((el) => {
    el.hidden = !el.dataset.method.split(" ").includes(method);
  });
}

export class JobsPanel {
  constructor({ onSucceeded, onOptimum, onDispersion, sites }) {
    this.onSucceeded = onSucceeded;
    this.onOptimum = onOptimum;
    this.onDispersion = onDispersion;
    this.sites = sites ?? (() => []); // the landing sites a dispersion study takes along
    this.form = $("job-form");
    $("job-method").addEventListener("change", showMethodFields);
    $("o-method").addEventListener("change", showOptimizerFields);
    // optimize and disperse are two kinds of job: one at a time
    $("optimize-toggle").addEventListener("change", (e) => { if (e.target.checked) $("disperse-toggle").checked = false; this.showKind(); });
    $("disperse-toggle").addEventListener("change", (e) => { if (e.target.checked) $("optimize-toggle").checked = false; this.showKind(); });
    $("d-file").addEventListener("change", (e) => this.submitFile(e.target.files[0]));
    this.form.addEventListener("submit", (e) => { e.preventDefault(); this.submit(); });
    this.showKind();
    showOptimizerFields();
  }

  kind() {
    return $("optimize-toggle").checked ? "optimize" : $("disperse-toggle").checked ? "dispersion" : "footprint";
  }

  showKind() {
    const kind = this.kind();
    $("optimize-fields").hidden = kind !== "optimize";
    $("method-fields").hidden = kind === "optimize";
    $("dispersion-fields").hidden = kind !== "dispersion";
    $("job-submit").textContent = { footprint: "Run job", optimize: "Run optimization", dispersion: "Run dispersion" }[kind];
    showMethodFields();
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
    const kind = this.kind();
    const study = { optimize: buildOptimizationStudy, footprint: buildFootprintStudy,
                    dispersion: () => buildDispersionStudy(this.sites()) }[kind]();
    await this.post({ kind, study });
  }

  /** POST the job (named by the form's name field) and follow it; a refusal shown next to its field. */
  async post(body) {
    if ($("job-name").value.trim()) body.name = $("job-name").value.trim();
    $("job-submit").disabled = true;
    try {
      const job = await api("/api/jobs", { method: "POST", body });
      this.follow(job.id, body.name || job.name || `${body.kind} ${job.id.slice(0, 8)}`); // the service names it for what it is
    } catch (err) {
      showFieldError(this.form, body.kind === "dispersion" ? asFootprintField(err) : err, $("job-form-error"));
    } finally {
      $("job-submit").disabled = false;
    }
  }

  /** A dispersion study file run as it is (its own footprint study, spreads and sites). */
  async submitFile(file) {
    if (!file) return;
    clearFieldErrors(this.form);
    $("job-form-error").hidden = true;
    let study;
    try { study = JSON.parse(await file.text()); } catch (err) {
      $("job-form-error").textContent = `${file.name} is not JSON: ${err.message}`;
      $("job-form-error").hidden = false;
      $("d-file").value = "";
      return;
    }
    $("d-file").value = "";
    await this.post({ kind: "dispersion", study });
  }

  /** A row in the job list, its result handed to the page when the job succeeds. */
  follow(id, label) {
    followJob($("job-list"), id, label, { onDone: (job, li) => this.finished(job, li, label), cancel: true });
  }

  async finished(job, li, label) {
    if (job.status === "succeeded") {
      const o = job.result?.optimization;
      if (o) {
        const cost = o.method === "collocation" ? `${fmt(o.iterations)} IPOPT iterations` : `${fmt(o.trajectories)} trajectories`;
        li.insertAdjacentHTML("beforeend", `<div class="${o.feasible ? "succeeded" : "failed"}">optimum: cross-range `
          + `${fmt(o.summary.crossrange_nmi)} nmi at down-range ${fmt(o.summary.downrange_nmi)} nmi, `
          + `${cost}${o.feasible ? "" : ", constraints not met"}</div>`);
        this.onOptimum?.(label, o);
      }
      const d = job.result?.dispersion;
      if (d) {
        li.append(el("div", { class: "succeeded" }, outcomeWords(d)));
        this.onDispersion?.(label, d, job);
      }
      await this.onSucceeded(job);
    } else if (job.error) {
      li.append(el("div", { class: "failed" }, job.error));
    }
  }
}

const TERMINAL = ["succeeded", "failed", "cancelled"];
const QUEUE_POLL_MS = 2000; // how often the rows of unfinished jobs say where they stand in the queue

/** "1 min 20 s", "40 s", "2 h 05 min": a wait as a planner reads it. */
export function durationWords(s) {
  if (s < 60) return `${Math.max(1, Math.round(s))} s`;
  if (s < 3600) return `${Math.floor(s / 60)} min${Math.round(s % 60) ? ` ${Math.round(s % 60)} s` : ""}`;
  return `${Math.floor(s / 3600)} h ${String(Math.round((s % 3600) / 60)).padStart(2, "0")} min`;
}

/** Where a job stands in GET /api/queue's answer: what runs or waits ahead of it and when it should end, from each
 * kind's measured cost ("2 ahead: a (running 40 %), b (queued) · ends in about 3 min"). */
export function queueWords(job, queue) {
  const ahead = queue.jobs.slice(0, job.ahead);
  const named = ahead.slice(0, 3).map((j) => `${j.name || j.kind} (${j.status === "running" ? `running ${Math.round(100 * j.progress)} %` : "queued"})`);
  const more = ahead.length > 3 ? ` and ${ahead.length - 3} more` : "";
  const where = ahead.length ? `${ahead.length} ahead: ${named.join(", ")}${more}` : job.status === "queued" ? "next in line" : "running";
  const unmeasured = [...new Set([...ahead, job].map((j) => j.kind).filter((k) => !queue.costs[k]))];
  const when = job.ends_in_s == null ? `no estimate yet (no ${unmeasured.join(", ")} job finished here)`
    : `ends in about ${durationWords(job.ends_in_s)}`;
  const cost = queue.costs[job.kind];
  const measured = cost ? ` (a ${job.kind} job took ${durationWords(cost.median_s)} here, the median of ${cost.jobs})` : "";
  return `${where} · ${when}${measured}`;
}

let queueTimer = null;

/** While any job row on the page is unfinished, GET /api/queue every 2 s and say in each row where it stands. */
function watchQueue() {
  if (queueTimer) return;
  const look = async () => {
    const rows = [...document.querySelectorAll("li[data-job-id]")]
      .filter((li) => !TERMINAL.includes(li.querySelector(".job-status")?.textContent));
    if (!rows.length) { queueTimer = null; return; }
    const queue = await api("/api/queue").catch(() => null);
    for (const li of rows) {
      const job = queue?.jobs.find((j) => j.id === li.dataset.jobId);
      const note = li.querySelector(".job-queue");
      if (note) note.textContent = job ? queueWords(job, queue) : "";
    }
    queueTimer = setTimeout(look, QUEUE_POLL_MS);
  };
  queueTimer = setTimeout(look, 0);
}

/** A job's row at the top of `list` (its label, status, progress bar, percent and what it is doing, the service's
 * progress_note), fed by GET /api/jobs/{id}/events, polling once a second if the stream breaks. With `cancel`, a
 * Cancel button (DELETE /api/jobs/{id}) until the job ends. `onDone(job, li)`: the finished job, once. */
export function followJob(list, id, label, { onDone, cancel = false } = {}) {
  const li = el("li", { dataset: { jobId: id } },
    el("div", { class: "job-line" }, el("span", { class: "job-label" }, label), el("span", { class: "job-status" }, "queued")),
    el("progress", { max: "100", value: "0", "aria-label": `Progress of ${label}` }), " ",
    el("span", { class: "job-percent" }, "0 %"),
    cancel ? el("button", { type: "button", class: "job-cancel", "aria-label": `Cancel ${label}` }, "Cancel") : null,
    el("div", { class: "job-note" }), el("div", { class: "job-queue" }));
  list.prepend(li);
  watchQueue();
  const update = (status, progress, note) => {
    const pct = Math.round(100 * (status === "succeeded" ? 1 : progress ?? 0));
    li.querySelector("progress").value = pct;
    li.querySelector(".job-percent").textContent = `${pct} %`;
    li.querySelector(".job-note").textContent = status === "running" ? note ?? "" : ""; // IPOPT's iteration, a revolution
    const s = li.querySelector(".job-status");
    s.textContent = status;
    s.className = `job-status ${status}`;
    if (cancel) li.querySelector(".job-cancel").hidden = TERMINAL.includes(status);
    if (TERMINAL.includes(status)) li.querySelector(".job-queue").textContent = "";
  };
  li.querySelector(".job-cancel")?.addEventListener("click", () => {
    api(`/api/jobs/${id}`, { method: "DELETE" }).catch((err) => li.append(el("div", { class: "failed" }, err.message)));
  });
  let finished = false;
  const finish = async () => {
    if (finished) return;
    finished = true;
    const job = await api(`/api/jobs/${id}`);
    update(job.status, job.progress, job.progress_note);
    await onDone?.(job, li);
  };
  const poll = async () => {
    while (!finished) {
      const job = await api(`/api/jobs/${id}`).catch(() => null);
      if (job && TERMINAL.includes(job.status)) return finish();
      if (job) update(job.status, job.progress, job.progress_note);
      await new Promise((r) => setTimeout(r, POLL_MS));
    }
  };
  const events = new EventSource(`/api/jobs/${id}/events`);
  events.addEventListener("progress", (e) => {
    const data = JSON.parse(e.data);
    update(data.status, data.progress, data.progress_note);
    if (TERMINAL.includes(data.status)) { events.close(); finish(); }
  });
  events.addEventListener("end", () => { events.close(); finish(); });
  events.onerror = () => { events.close(); if (!finished) poll(); };
  return li;
}
