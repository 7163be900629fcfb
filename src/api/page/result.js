// @ts-check
// A finished job's result: its outcome in a sentence, its warnings, its
// summary, its plot (enlarged on a click) and its downloads.

import { headers, problemOf } from "./api.js";
import { $, $input, line, strong } from "./dom.js";
import { fmt } from "./format.js";
import { pageOf } from "./form.js";
import { currentJobId } from "./jobs.js";
import { showProblem } from "./problems.js";

/** @typedef {import('topple-api').components['schemas']} S */
/** @typedef {S['JobView']} JobView */
/** @typedef {S['JobResult']} JobResult */

const WARNING_NAMES = /** @type {Record<string, string>} */ ({
  implausible_size: "implausible block size", sliding: "sliding", lift_off: "lift-off",
  demand_excludes_fall: "friction demand excludes the fall", free_rocking_truncated: "free rocking cut short",
  impact_list_truncated: "impact list truncated", near_separatrix: "near the separatrix",
  large_pga: "large PGA", baseline_drift: "baseline drift", coarse_dt: "coarse sampling", never_rocks: "never rocks",
  implausible_slide: "implausible slide"
});

/**
 * The kind in words ("time history").
 * @param {string} kind
 */
export const kindTitle = (kind) => pageOf(kind)?.title || kind;

/**
 * Warnings (of a result or a record) as a list in `box`; red when the
 * inputs themselves look wrong.
 * @param {HTMLElement} box
 * @param {{ kind: string, t?: number | null, message?: string }[] | null | undefined} list
 */
export function renderWarnings(box, list) {
  box.replaceChildren();
  if (!Array.isArray(list) || !list.length) { box.hidden = true; return; }
  const inputs = list.some((w) => w.kind === "implausible_size" || w.kind === "implausible_slide");
  box.className = inputs ? "problem" : "problem notice";
  box.append(line([strong(list.length === 1 ? "Warning" : `Warnings (${list.length})`)]));
  const ul = document.createElement("ul");
  for (const w of list) {
    const li = document.createElement("li");
    li.dataset.kind = w.kind;
    const name = WARNING_NAMES[w.kind] || String(w.kind).replace(/_/g, " ");
    li.append(strong(name), w.t != null ? ` (t = ${fmt(w.t)} s): ` : ": ", w.message || "");
    ul.append(li);
  }
  box.append(ul);
  box.hidden = false;
}

/**
 * The result's warnings ({kind, t?, message}), in sight above the plot.
 * @param {S['WarningDoc'][] | null | undefined} list
 */
function showWarnings(list) {
  renderWarnings($("warnings"), list);
}

/**
 * What a result says, in one sentence ("Overturned at 5.237 s, mode 1 …"),
 * with "overturned" or "stood" for its colour.
 * @param {string} kind
 * @param {JobResult} r
 * @returns {[string, string]}
 */
function outcomeOf(kind, r) {
  const page = /** @type {import('./kinds/index.js').KindPage<any> | undefined} */ (pageOf(kind));
  return page ? page.outcome(r) : ["", ""];
}

/**
 * The details beside the outcome, as [term, value, wide] items; a value is
 * text, or text and links. Every number says what it is of: the age, the
 * frequency, the stripe, the record.
 * @param {JobView} job
 * @param {JobResult} r
 */
function summaryItems(job, r) {
  /** @type {[string, string | (string | Node)[], string | undefined][]} */
  const items = [];
  // `wide`: the item takes a whole row.
  /** @type {import('./kinds/common.js').Add} */
  const add = (k, v, wide) => { items.push([k, v, wide]); };
  const page = /** @type {import('./kinds/index.js').KindPage<any> | undefined} */ (pageOf(job.kind));
  page?.summary(job, r, add);
  // The job's wall time (submitted work started to finished) and the
  // compute time summed over its tasks, which run side by side.
  const started = Date.parse(job.started_at || ""), finished = Date.parse(job.finished_at || "");
  if (Number.isFinite(started) && Number.isFinite(finished) && finished >= started) {
    add("Wall time (s)", fmt((finished - started) / 1000, 3));
  }
  /** @type {{ wall_time_s?: number, tasks?: number, simulations?: number, verification_simulations?: number } | undefined} */
  const numerics = /** @type {any} */ (r).numerics;
  const wall = numerics && numerics.wall_time_s;
  const tasks = numerics && numerics.tasks;
  if (typeof wall === "number" && Number.isFinite(wall)) {
    add(tasks !== undefined && tasks > 1 ? `Compute time, summed over ${tasks} tasks (s)` : "Compute time (s)", fmt(wall, 3));
  }
  const verified = numerics && numerics.verification_simulations;
  if (numerics && verified !== undefined && verified > 0) add("Simulations (of them verifying)", `${numerics.simulations} (${verified})`);
  return items;
}

/** @param {JobView} job */
async function showSummary(job) {
  const dl = $("summary");
  dl.replaceChildren();
  $("outcome").textContent = "";
  showWarnings([]);
  try {
    const resp = await fetch(`/v1/jobs/${job.id}/result`, { headers: headers() });
    if (!resp.ok || job.id !== currentJobId()) return;
    /** @type {JobResult} */
    const r = await resp.json();
    if (job.id !== currentJobId()) return;
    const [sentence, tone] = outcomeOf(job.kind, r);
    $("outcome").textContent = sentence;
    $("outcome").className = tone;
    showWarnings("warnings" in r ? r.warnings : undefined);
    for (const [k, v, wide] of summaryItems(job, r)) {
      const div = document.createElement("div");
      if (wide) div.className = "wide";
      const dt = document.createElement("dt"); dt.textContent = k;
      const dd = document.createElement("dd"); dd.append(.../** @type {(string | Node)[]} */ ([]).concat(v));
      div.append(dt, dd);
      dl.append(div);
    }
  } catch (_) { /* the summary is optional; the plot and downloads remain */ }
}

/** @param {JobView} job */
async function showPlot(job) {
  const box = $("plot-box");
  box.replaceChildren();
  const url = `/v1/jobs/${job.id}/plot.svg`;
  const img = document.createElement("img");
  img.id = "plot";
  img.alt = `Plot of the ${kindTitle(job.kind)} result of job ${job.id}`;
  img.title = "Click (or Enter) to enlarge";
  const wait = document.createElement("p");
  wait.className = "hint";
  wait.textContent = "Drawing the plot…";
  const zoomHint = document.createElement("span");
  zoomHint.className = "zoom-hint";
  zoomHint.textContent = "click to enlarge";
  zoomHint.hidden = true;
  img.addEventListener("load", () => { wait.remove(); zoomHint.hidden = false; });
  img.addEventListener("click", () => enlarge(img));
  img.tabIndex = 0;
  img.addEventListener("keydown", (ev) => {
    if (ev.key === "Enter" || ev.key === " ") { ev.preventDefault(); enlarge(img); }
  });
  img.addEventListener("error", async () => {
    wait.remove();
    img.remove();
    zoomHint.remove();
    if (job.id !== currentJobId()) return;
    try {
      const resp = await fetch(url, { headers: headers() });
      if (!resp.ok) { showProblem(await problemOf(resp), "Plot"); return; }
    } catch (_) { /* reported below */ }
    showProblem({ title: "The plot could not be shown", detail: url });
  });
  box.append(wait, img, zoomHint);
  if ($input("f-token").value.trim()) {
    // Reads may need the token, which an <img> cannot send: fetch the SVG
    // and show it from a data: URL.
    try {
      const resp = await fetch(url, { headers: headers() });
      if (!resp.ok) { showProblem(await problemOf(resp), "Plot"); return; }
      const svg = await resp.text();
      img.src = "data:image/svg+xml;charset=utf-8," + encodeURIComponent(svg);
    } catch (e) {
      showProblem({ title: "The plot could not be fetched", detail: String(/** @type {Error} */ (e).message || e) });
    }
  } else {
    img.src = url;
  }
}

/**
 * The plot across the whole window, its labels at (or above) full size.
 * @param {HTMLImageElement} img
 */
function enlarge(img) {
  const zoom = /** @type {HTMLDialogElement} */ ($("zoom"));
  const big = /** @type {HTMLImageElement} */ ($("zoom-img"));
  big.src = img.src;
  big.alt = img.alt;
  if (!zoom.open) zoom.showModal();
}

/** @param {JobView} job */
export function showResult(job) {
  $("result").hidden = false;
  const base = `/v1/jobs/${job.id}/result`;
  const csv = /** @type {HTMLAnchorElement} */ ($("csv-link"));
  csv.href = base + "?format=csv";
  csv.setAttribute("download", `topple-${job.kind}-${job.id}.csv`);
  /** @type {HTMLAnchorElement} */ ($("json-link")).href = base;
  /** @type {HTMLAnchorElement} */ ($("svg-link")).href = `/v1/jobs/${job.id}/plot.svg`;
  showPlot(job);
  showSummary(job);
}

/**
 * Downloads with the token: fetch, then save from a blob.
 * @param {MouseEvent} ev
 */
export async function authorisedDownload(ev) {
  if (!$input("f-token").value.trim()) return;
  ev.preventDefault();
  const a = /** @type {HTMLAnchorElement} */ (ev.currentTarget);
  try {
    const resp = await fetch(a.href, { headers: headers() });
    if (!resp.ok) { showProblem(await problemOf(resp), "Download"); return; }
    const blob = await resp.blob();
    const tmp = document.createElement("a");
    tmp.href = URL.createObjectURL(blob);
    tmp.download = a.getAttribute("download") || a.pathname.split("/").filter(Boolean).slice(-2).join("-");
    document.body.append(tmp);
    tmp.click();
    tmp.remove();
    setTimeout(() => URL.revokeObjectURL(tmp.href), 10000);
  } catch (e) {
    showProblem({ title: "The download failed", detail: String(/** @type {Error} */ (e).message || e) });
  }
}

export function initResult() {
  $("zoom").addEventListener("click", () => /** @type {HTMLDialogElement} */ ($("zoom")).close());
  for (const id of ["csv-link", "json-link", "svg-link"]) $(id).addEventListener("click", authorisedDownload);
}
