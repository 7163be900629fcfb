// @ts-check
// Jobs: a submission, the job followed (its event stream, or polling),
// canceled, and the tenant's jobs listed ("Your jobs").

import { eachEvent, headers, problemOf } from "./api.js";
import { MAX_LIST_LIMIT } from "./constants.js";
import { $, $textarea } from "./dom.js";
import { dateOf, plural } from "./format.js";
import { form, formSpec, kind, recordUse, state } from "./form.js";
import { clearProblem, labelOf, showProblem } from "./problems.js";
import { suiteIds, currentRecord } from "./records.js";
import { kindTitle, showResult } from "./result.js";

/** @typedef {import('topple-api').components['schemas']} S */
/** @typedef {S['JobView']} JobView */

const POLL_MS = 300;

/** @type {string | null} id of the job followed */
let current = null;
/** @type {ReturnType<typeof setTimeout> | null} */
let pollTimer = null;
/** @type {AbortController | null} of the followed event stream */
let stream = null;
let streamFailed = false;  // events unavailable: poll instead

/** The id of the job shown, or null. */
export const currentJobId = () => current;

// ---- following a job --------------------------------------------------------
function stopPolling() {
  if (pollTimer) clearTimeout(pollTimer);
  pollTimer = null;
  if (stream) stream.abort();
  stream = null;
}

/**
 * Follows a job through its Server-Sent Events (read with fetch, so that a
 * token can be sent); falls back to polling if the stream breaks off.
 * @param {string} id
 */
async function watch(id) {
  if (id !== current) return;
  const ctl = new AbortController();
  stream = ctl;
  let finished = false;
  try {
    const resp = await fetch(`/v1/jobs/${id}/events`, { headers: headers(), signal: ctl.signal, cache: "no-store" });
    if (!resp.ok || !resp.body) throw new Error("no event stream (" + resp.status + ")");
    $("job").dataset.follow = "events";
    await eachEvent(resp.body, (name, data) => {
      if (id !== current) return;
      /** @type {JobView} */
      const job = JSON.parse(data);
      if (!$("problem").hidden && job.status !== "failed") clearProblem();
      showJob(job);
      if (name === "done") {
        finished = true;
        if (job.status === "succeeded") showResult(job);
      }
    });
  } catch (e) {
    if (ctl.signal.aborted) return;
    streamFailed = true;
  }
  if (stream === ctl) stream = null;
  $("job").dataset.follow = finished ? "" : "poll";
  if (!finished && id === current && !ctl.signal.aborted) pollTimer = setTimeout(() => poll(id), POLL_MS);
}

/** @param {JobView} job */
function showJob(job) {
  $("empty").hidden = true;
  $("job").hidden = false;
  const status = $("status");
  status.textContent = job.status;
  status.className = "badge " + job.status;
  const pct = Math.round(Math.max(0, Math.min(1, job.progress || 0)) * 100);
  const progress = /** @type {HTMLProgressElement} */ ($("progress"));
  progress.value = Math.max(0, Math.min(1, job.progress || 0));
  progress.setAttribute("aria-valuetext", pct + " %");
  const active = job.status === "queued" || job.status === "running";
  let text = active || job.status === "canceled" ? pct + " %" : "";
  if (job.cached) text += (text ? " · " : "") + "identical job found (cached)";
  $("progress-text").textContent = text;
  progress.hidden = !active;
  $("job-id").textContent = job.id;
  $("job-kind").textContent = `${kindTitle(job.kind)}, submitted ${dateOf(job.created_at, true)}`;
  noteJob(job);
  const cancelButton = /** @type {HTMLButtonElement} */ ($("cancel"));
  cancelButton.disabled = !active;
  cancelButton.hidden = !active;
  if (job.status === "failed") {
    showProblem({ title: "The job failed", detail: job.error || "no reason given" });
  } else if (job.status === "canceled") {
    showProblem({ title: "The job was canceled", detail: "submit it again to compute it", notice: true });
  }
}

/** @param {string} id */
async function poll(id) {
  if (id !== current) return;
  /** @type {JobView} */
  let job;
  try {
    const resp = await fetch(`/v1/jobs/${id}`, { headers: headers(), cache: "no-store" });
    if (!resp.ok) {
      if (id === current) showProblem(await problemOf(resp), "Status");
      return;
    }
    job = await resp.json();
  } catch (e) {
    if (id === current) {
      showProblem({ title: "The service did not answer", detail: String(/** @type {Error} */ (e).message || e) + " — retrying" });
      pollTimer = setTimeout(() => poll(id), 2000);
    }
    return;
  }
  if (id !== current) return;
  if (!$("problem").hidden && job.status !== "failed") clearProblem();
  showJob(job);
  if (job.status === "queued" || job.status === "running") {
    if (streamFailed) pollTimer = setTimeout(() => poll(id), POLL_MS);
    else watch(id);
  } else if (job.status === "succeeded") {
    showResult(job);
  }
}

/** The job shown is let go: the result panel is empty again. */
export function letGo() {
  stopPolling();
  current = null;
  if (location.hash) history.replaceState(null, "", location.pathname + location.search);
  $("job").hidden = true;
  $("result").hidden = true;
  $("job-id").textContent = "";
  $("empty").hidden = false;
  markOpen();
}

/** @param {JobView} job */
function follow(job) {
  stopPolling();
  current = job.id;
  history.replaceState(null, "", "#job=" + job.id);
  $("result").hidden = true;
  markOpen();
  showJob(job);
  if (job.status === "succeeded") showResult(job);
  else if (job.status === "queued" || job.status === "running") watch(job.id);
}

// ---- your jobs ------------------------------------------------------------------
// The tenant's jobs (GET /v1/jobs), newest first as the service lists
// them; a click opens one: its status, then its summary and figure.
const JOBS_PAGE = 20;
/** @type {S['JobView'][]} the jobs listed, newest first */
let jobsListed = [];
/** @type {string | null} the service's next_cursor after the last page read */
let jobsCursor = null;
let jobsSeq = 0;
/** @type {ReturnType<typeof setTimeout> | undefined} lists the jobs again while some are unfinished */
let jobsTimer;
let jobsDrawn = "";      // what the list shows, to draw it again only when it changed
const JOBS_POLL_MS = 2000;

/**
 * Lists the jobs again (as many as are listed, at least a page), or the
 * next page of older ones.
 * @param {boolean} [older]
 */
export async function refreshJobs(older) {
  const seq = ++jobsSeq;
  const limit = older ? JOBS_PAGE : Math.min(MAX_LIST_LIMIT, Math.max(JOBS_PAGE, jobsListed.length));
  const params = new URLSearchParams({ limit: String(limit) });
  if (older && jobsCursor) params.set("cursor", jobsCursor);
  let note = "";
  try {
    const resp = await fetch("/v1/jobs?" + params, { headers: headers(), cache: "no-store" });
    if (seq !== jobsSeq) return;
    if (resp.ok) {
      /** @type {S['JobPage']} */
      const body = await resp.json();
      if (seq !== jobsSeq) return;
      const page = Array.isArray(body.jobs) ? body.jobs : [];
      jobsListed = older ? jobsListed.concat(page.filter((j) => !jobsListed.some((k) => k.id === j.id))) : page;
      jobsCursor = body.next_cursor || null;
    } else {
      jobsListed = [];
      jobsCursor = null;
      note = resp.status === 401 ? "Listing your jobs needs the API token (below the form)."
        : `Your jobs could not be listed (${resp.status}).`;
      if (resp.status === 401) /** @type {HTMLDetailsElement} */ ($("token-box")).open = true;
    }
  } catch (_) {
    if (seq !== jobsSeq) return;
    note = "The service did not answer: your jobs are not listed.";
  }
  renderJobs(note);
}

/** @param {string} [note] */
function renderJobs(note) {
  // Drawn again only when something changed (a row is not pulled from
  // under the pointer).
  const drawn = JSON.stringify([note || "", jobsCursor, jobsListed.map((j) => [j.id, j.status])]);
  if (drawn !== jobsDrawn) drawJobs(note);
  jobsDrawn = drawn;
  // Jobs queued or running (here or elsewhere) are listed again until done.
  clearTimeout(jobsTimer);
  if (jobsListed.some((j) => j.status === "queued" || j.status === "running")) jobsTimer = setTimeout(() => refreshJobs(), JOBS_POLL_MS);
  markOpen();
}

/** @param {string} [note] */
function drawJobs(note) {
  const box = $("jobs-list");
  box.replaceChildren();
  for (const j of jobsListed) {
    const row = document.createElement("button");
    row.type = "button";
    row.className = "job-row";
    row.dataset.id = j.id;
    row.title = `Open job ${j.id}`;
    const badge = document.createElement("span");
    badge.className = `badge ${j.status}`;
    badge.textContent = j.status;
    const name = document.createElement("span");
    name.className = "job-k";
    name.textContent = kindTitle(j.kind);
    const when = document.createElement("span");
    when.className = "job-t";
    when.textContent = `${dateOf(j.created_at, true)} · …${j.id.slice(-6)}`;
    row.append(badge, name, when);
    row.addEventListener("click", () => openJob(j.id));
    box.append(row);
  }
  if (note || !jobsListed.length) {
    const p = document.createElement("p");
    p.className = "empty";
    p.textContent = note || "No jobs yet: submit one.";
    box.append(p);
  }
  $("jobs-more").hidden = !jobsCursor;
  $("jobs-note").textContent = jobsListed.length ? `${plural(jobsListed.length, "job", "jobs")}, newest first` : "";
}

/** The job shown is marked in the list. */
function markOpen() {
  for (const el of $("jobs-list").querySelectorAll(".job-row")) {
    const row = /** @type {HTMLElement} */ (el);
    row.setAttribute("aria-current", String(row.dataset.id === current));
  }
}

/**
 * A job seen (submitted, followed): its row says its status; a job not
 * listed yet brings the list up to date.
 * @param {JobView} job
 */
function noteJob(job) {
  const i = jobsListed.findIndex((j) => j.id === job.id);
  if (i < 0) { refreshJobs(); return; }
  if (jobsListed[i].status === job.status) return;
  jobsListed[i] = Object.assign({}, jobsListed[i], { status: job.status, progress: job.progress });
  renderJobs();
}

/**
 * Shows a job of the list (or of the address): its status, and once it
 * succeeded its summary, figure and downloads.
 * @param {string} id
 */
export function openJob(id) {
  clearProblem();
  stopPolling();
  current = id;
  history.replaceState(null, "", "#job=" + id);
  $("result").hidden = true;
  markOpen();
  poll(id);
}

// ---- actions ------------------------------------------------------------------
/** @param {SubmitEvent} ev */
async function submit(ev) {
  ev.preventDefault();
  clearProblem();
  let body;
  if (kind() === "raw") {
    body = $textarea("f-raw").value;
    if (body.trim() === "") { showProblem({ title: "No job spec", detail: "write the spec as JSON, or fill it from the form" }); return; }
  } else {
    const missing = /** @type {HTMLInputElement[]} */ ([...form.querySelectorAll("input[required]:not(:disabled)")]).find((el) => el.value.trim() === "");
    if (missing) {
      showProblem({ title: "Missing value", detail: `${labelOf(missing)} is needed` });
      missing.setAttribute("aria-invalid", "true");
      missing.focus();
      return;
    }
    const use = recordUse(state.formKind);
    if (use === "one" && !currentRecord()) {
      showProblem({ title: "No record", detail: "choose a file, pick a stored record or paste samples: the job names the record by its id" });
      $("f-rec-file").focus();
      return;
    }
    if (use === "suite" && !suiteIds().length) {
      showProblem({ title: "No records in the suite", detail: "tick the stored records the simulations take turns on (or choose a file to add one)" });
      $("f-rec-file").focus();
      return;
    }
    body = JSON.stringify(formSpec());
  }
  const button = /** @type {HTMLButtonElement} */ ($("submit"));
  button.disabled = true;
  try {
    const resp = await fetch("/v1/jobs", {
      method: "POST",
      headers: headers({ "Content-Type": "application/json" }),
      body
    });
    if (!resp.ok) { showProblem(await problemOf(resp), "Submission"); return; }
    follow(await resp.json());
  } catch (e) {
    showProblem({ title: "The service did not answer", detail: String(/** @type {Error} */ (e).message || e) });
  } finally {
    button.disabled = false;
  }
}

async function cancel() {
  if (!current) return;
  const id = current;
  const button = /** @type {HTMLButtonElement} */ ($("cancel"));
  button.disabled = true;
  try {
    const resp = await fetch(`/v1/jobs/${id}/cancel`, { method: "POST", headers: headers() });
    if (!resp.ok) {
      const pb = await problemOf(resp);
      if (pb.status !== 409) showProblem(pb, "Cancel");
      button.disabled = false;
      return;
    }
    stopPolling();
    if (id === current) showJob(await resp.json());
  } catch (e) {
    showProblem({ title: "The service did not answer", detail: String(/** @type {Error} */ (e).message || e) });
    button.disabled = false;
  }
}

export function initJobs() {
  form.addEventListener("submit", submit);
  $("cancel").addEventListener("click", cancel);
  $("jobs-refresh").addEventListener("click", () => refreshJobs());
  $("jobs-more").addEventListener("click", () => refreshJobs(true));
}
