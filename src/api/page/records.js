// @ts-check
// Records. The service reads and stores them (POST /v1/records): the page
// sends a file as it is, asks what the service could not tell (the unit, dt,
// …), shows the stored record and sends its id in the spec.

import { headers, problemOf } from "./api.js";
import { G } from "./constants.js";
import { $, $control, $input, $select, $textarea, strong } from "./dom.js";
import { dateOf, fmt, plural } from "./format.js";
import { kind, layout, recordUse } from "./form.js";
import { motionSvg } from "./motion.js";
import { clearProblem, showProblem } from "./problems.js";
import { renderWarnings } from "./result.js";

/** @typedef {import('topple-api').components['schemas']} S */
/** @typedef {S['RecordView']} RecordView */
/** @typedef {import('./api.js').PageProblem} PageProblem */

/**
 * A file (or pasted text) on its way to the service, with the query
 * parameters sent and those the service asked for.
 * @typedef {{ text: string, name: string, params: Record<string, string>, asked: Set<string>,
 *   pasted?: boolean, largePga?: boolean }} Pending
 */

/** @type {RecordView | null} the record of a time history, record spectrum or forensic query */
let record = null;
/** @type {string[]} the ids of a fragility suite, in the order chosen */
let suite = [];
/** @type {RecordView | null} the record the preview shows */
let previewed = null;
/** @type {Pending | null} a file the service asked about */
let pending = null;
let recNote = "";       // what became of the last file sent
/** @type {RecordView[]} the stored records, newest first */
let stored = [];
/** @type {"unloaded" | "loading" | "loaded" | "failed"} */
let storedState = "unloaded";
/** @type {"one" | "suite" | "" | null} how the list is drawn: "one" (radios) or "suite" (checkboxes) */
let storedMode = null;
let sendSeq = 0, previewSeq = 0, askRound = 0;
/** @type {Map<string, { dt: number, acc: number[] }>} id → {dt, acc in g} */
const samplesCache = new Map();
// The query parameters the service may ask for, and the inputs that answer.
const ASKABLE = /** @type {Record<string, string>} */ ({ unit: "f-rec-unit", dt: "f-rec-dt", format: "f-rec-format", time_column: "f-rec-tcol", acc_column: "f-rec-acol" });
const UNIT_NAMES = /** @type {Record<string, string>} */ ({ g: "g", "m/s2": "m/s²", "cm/s2": "cm/s²" });

/** @param {string | undefined} id */
const recordById = (id) => stored.find((r) => r.id === id)
  || [record, previewed].find((r) => r && r.id === id) || null;

/** The record the form holds, as a spec's ground_motion: its id. */
export function groundMotionOf() {
  return { record: record ? record.id : null };
}

/** The record loaded for one-record kinds, or null. */
export const currentRecord = () => record;

/** The ids of the suite, in the order chosen. */
export const suiteIds = () => suite;

/** Another token may see other records: list them again when next in sight. */
export function forgetStored() {
  storedState = "unloaded";
  samplesCache.clear();
}

/**
 * The record fieldset came into sight, for one record or for a suite.
 * @param {"one" | "suite" | ""} use
 */
export function recordsShown(use) {
  if (storedState === "unloaded") refreshStored();
  if (storedMode !== use) {
    storedMode = use;
    renderStored();
    showPreview(use === "suite" ? recordById(suite[suite.length - 1]) : record);
  }
  recordStatus();
}

function recordStatus() {
  const use = recordUse(kind());
  let text = recNote;
  if (use === "suite") {
    const n = suite.length;
    text = (n ? `The suite: ${plural(n, "record", "records")}.` : "Tick the stored records of the suite, or choose a file to add one.") + (text ? " " + text : "");
  } else if (!text && !record) {
    text = "No record loaded: choose a file, pick a stored record or paste samples.";
  }
  $("rec-status").textContent = text;
}

async function refreshStored() {
  storedState = "loading";
  let note = "";
  try {
    const resp = await fetch("/v1/records?limit=50", { headers: headers(), cache: "no-store" });
    if (resp.ok) {
      /** @type {S['RecordPage']} */
      const body = await resp.json();
      stored = Array.isArray(body.records) ? body.records : [];
      storedState = "loaded";
    } else {
      storedState = "failed";
      note = resp.status === 401 ? "Listing the stored records needs the API token."
        : `The stored records could not be listed (${resp.status}).`;
    }
  } catch (_) {
    storedState = "failed";
    note = "The service did not answer: the stored records are not listed.";
  }
  renderStored(note);
}

/**
 * The stored records: radios to pick one, or checkboxes to make a suite.
 * @param {string} [note]
 */
function renderStored(note) {
  const box = $("rec-stored");
  const multi = storedMode === "suite";
  box.replaceChildren();
  for (const r of stored) {
    const row = document.createElement("label");
    row.className = "rec-row";
    const input = document.createElement("input");
    input.type = multi ? "checkbox" : "radio";
    input.name = multi ? "rec-suite" : "rec-pick";
    input.value = r.id;
    input.checked = multi ? suite.includes(r.id) : !!record && record.id === r.id;
    const name = document.createElement("span");
    name.className = "rec-n";
    name.textContent = r.name || r.id;
    name.title = r.name || r.id;
    const meta = document.createElement("span");
    meta.className = "rec-m";
    meta.textContent = `${r.samples} samples · PGA ${fmt(r.pga_g, 3)} g · ${dateOf(r.created_at)}`;
    row.append(input, name, meta);
    box.append(row);
  }
  if (note || !stored.length) {
    const p = document.createElement("p");
    p.className = "empty";
    p.textContent = note || (storedState === "loading" ? "Listing the stored records…" : "No stored records yet: choose a file.");
    box.append(p);
  }
}

/**
 * A record the service answered with: first in the list.
 * @param {RecordView} rec
 */
function remember(rec) {
  stored = [rec, ...stored.filter((r) => r.id !== rec.id)];
}

/**
 * A stored record ticked or picked in the list.
 * @param {Event} ev
 */
function picked(ev) {
  const input = /** @type {HTMLInputElement} */ (ev.target);
  const r = recordById(input.value);
  if (!r) return;
  recNote = "";
  cancelAsk();
  if (input.type === "checkbox") {
    suite = suite.filter((id) => id !== r.id);
    if (input.checked) {
      suite.push(r.id);
      showPreview(r);
    } else if (previewed && previewed.id === r.id) {
      showPreview(recordById(suite[suite.length - 1]));
    }
  } else {
    record = r;
    showPreview(r);
  }
  recordStatus();
}

/**
 * Sends a file (or pasted text) as it is; the service reads it.
 * @param {Pending} p
 */
async function sendRecord(p) {
  const seq = ++sendSeq;
  const params = new URLSearchParams();
  for (const [k, v] of Object.entries(p.params)) if (v !== undefined && v !== "") params.set(k, String(v));
  if (p.name) params.set("name", p.name);
  recNote = `Sending ${p.name} to the service…`;
  recordStatus();
  /** @type {Response} */
  let resp;
  /** @type {any} */
  let body = null;
  try {
    resp = await fetch("/v1/records?" + params, {
      method: "POST", body: p.text, headers: headers({ "Content-Type": "text/plain" })
    });
    body = resp.ok ? await resp.json() : await problemOf(resp);
  } catch (e) {
    if (seq !== sendSeq) return;
    recNote = "";
    recordStatus();
    showProblem({ title: "The service did not answer", detail: String(/** @type {Error} */ (e).message || e), file: p.name }, "Record");
    return;
  }
  if (seq !== sendSeq) return;
  recNote = "";
  if (resp.ok) {
    /** @type {RecordView} */
    const rec = body;
    pending = null;
    hideAsk();
    clearProblem();
    remember(rec);
    recNote = resp.status === 201 ? `${rec.name}: stored.` : `${rec.name}: the service had it already.`;
    if (recordUse(kind()) === "suite") {
      if (!suite.includes(rec.id)) suite.push(rec.id);
    } else {
      record = rec;
    }
    renderStored();
    showPreview(rec);
  } else if ((resp.status === 422 || resp.status === 400) && Object.hasOwn(ASKABLE, body.parameter || "")) {
    // Something only the user knows (the unit, dt, …), missing, out of
    // range or at odds with the file: ask, then send again.
    p.asked.add(body.parameter);
    pending = p;
    clearProblem();
    showAsk(p, body);
  } else {
    pending = null;
    hideAsk();
    showProblem(Object.assign({}, body, { pointer: undefined, file: p.name }), "Record");
    $("f-rec-file").setAttribute("aria-invalid", "true");
  }
  recordStatus();
}

/**
 * A new file (or paste): what was loaded for one record is let go.
 * @param {Omit<Pending, "asked">} file
 */
function startRecord(file) {
  /** @type {Pending} */
  const p = Object.assign(file, { asked: new Set() });
  cancelAsk();
  clearProblem();
  for (const [param, id] of Object.entries(ASKABLE)) $control(id).value = p.params[param] || "";
  $input("f-rec-large").checked = false;
  if (recordUse(kind()) === "one") {
    record = null;
    showPreview(null);
    renderStored();
  }
  sendRecord(p);
}

/**
 * Asks what the service could not tell of a file.
 * @param {Pending} p
 * @param {PageProblem} pb
 */
function showAsk(p, pb) {
  $("rec-ask-text").replaceChildren(strong(`${p.name}: `), pb.detail || `the service needs ${pb.parameter}.`);
  for (const el of $("rec-ask").querySelectorAll("[data-param]")) {
    const box = /** @type {HTMLElement} */ (el);
    box.hidden = !p.asked.has(box.dataset.param ?? "");
  }
  // No value: "choose" one that was missing, "leave out" one at odds with the file.
  /** @param {string} param */
  const given = (param) => (p.params[param] ?? "") !== "";
  $select("f-rec-unit").options[0].textContent = given("unit") ? "(leave out)" : "choose…";
  $select("f-rec-format").options[0].textContent = given("format") ? "(detect)" : "choose…";
  $input("f-rec-dt").placeholder = given("dt") ? "leave out" : "";
  // A unit that makes the PGA implausible: the PGA may be right after all.
  if (pb.parameter === "unit" && /PGA|allow_large_pga/i.test(pb.detail || "")) p.largePga = true;
  $("rec-ask-large").hidden = !p.largePga;
  $("rec-ask").hidden = false;
  $("rec-ask").dataset.round = String(++askRound);
  layout();  // the inputs in sight take part again
  $(ASKABLE[pb.parameter ?? ""]).focus();
}

function hideAsk() {
  if ($("rec-ask").hidden) return;
  $("rec-ask").hidden = true;
  layout();
}

function cancelAsk() {
  pending = null;
  sendSeq++;
  hideAsk();
}

function resend() {
  const p = pending;
  if (!p) return;
  // An empty answer leaves the parameter out (the file says it, or the
  // service asks again).
  for (const param of p.asked) {
    const value = $control(ASKABLE[param]).value.trim();
    if (value === "") delete p.params[param];
    else p.params[param] = value;
  }
  if (p.largePga && $input("f-rec-large").checked) p.params.allow_large_pga = "true";
  else delete p.params.allow_large_pga;
  // Pasted samples: the paste's fields say what was answered.
  if (p.pasted) {
    if (p.asked.has("unit")) $select("f-rec-paste-unit").value = p.params.unit || "";
    if (p.asked.has("dt")) $input("f-rec-paste-dt").value = p.params.dt || "";
  }
  sendRecord(p);
}

async function fileChosen() {
  const input = $input("f-rec-file");
  const file = input.files?.[0];
  if (!file) return;
  clearProblem();
  let text;
  try {
    text = await file.text();
  } catch (e) {
    showProblem({ title: "The file could not be read", detail: String(/** @type {Error} */ (e).message || e), file: file.name }, "Record");
    return;
  }
  input.value = "";  // the same file may be chosen again
  startRecord({ text, name: file.name, params: {} });
}

function sendPasted() {
  const text = $textarea("f-rec-text").value;
  if (text.trim() === "") {
    showProblem({ title: "Nothing pasted", detail: "paste the samples, one a line (or columns)" }, "Record");
    $("f-rec-text").focus();
    return;
  }
  startRecord({
    text, name: $input("f-rec-paste-name").value.trim() || "pasted", pasted: true,
    params: { unit: $select("f-rec-paste-unit").value, dt: $input("f-rec-paste-dt").value.trim() }
  });
}

/**
 * The record's name, numbers, motion and warnings, before anything is submitted.
 * @param {RecordView | null} rec
 */
async function showPreview(rec) {
  previewed = rec;
  const seq = ++previewSeq;
  $("rec-preview").hidden = !rec;
  if (!rec) return;
  $("rec-name").textContent = rec.name || rec.id;
  $("rec-source").textContent = [rec.format && rec.format.toUpperCase(), rec.unit && `in ${UNIT_NAMES[rec.unit] || rec.unit}`]
    .filter(Boolean).join(", ");
  const facts = $("rec-facts");
  facts.replaceChildren();
  for (const [k, v] of [["dt", `${fmt(rec.dt)} s`], ["Samples", String(rec.samples)], ["Duration", `${fmt(rec.duration_s)} s`],
    ["PGA", `${fmt(rec.pga_g)} g`], ["PGV", `${fmt(rec.pgv_m_s)} m/s`], ["PGD", `${fmt(rec.pgd_m)} m`]]) {
    const div = document.createElement("div");
    const dt = document.createElement("dt"); dt.textContent = k;
    const dd = document.createElement("dd"); dd.textContent = v;
    div.append(dt, dd);
    facts.append(div);
  }
  renderWarnings($("rec-warnings"), rec.warnings);
  const plot = $("rec-plot");
  const wait = document.createElement("p");
  wait.className = "hint";
  wait.textContent = "Fetching the samples…";
  plot.replaceChildren(wait);
  try {
    let m = samplesCache.get(rec.id);
    if (!m) {
      const resp = await fetch(`/v1/records/${encodeURIComponent(rec.id)}?format=json`, { headers: headers() });
      if (!resp.ok) throw new Error(`${resp.status} ${resp.statusText}`);
      /** @type {S['RecordSamples']} */
      const body = await resp.json();
      const toG = body.unit === "g" ? 1 : body.unit === "cm/s2" ? 0.01 / G : 1 / G;
      m = { dt: body.dt, acc: body.acc.map((a) => a * toG) };
      if (samplesCache.size >= 8) samplesCache.delete(/** @type {string} */ (samplesCache.keys().next().value));
      samplesCache.set(rec.id, m);
    }
    if (seq !== previewSeq) return;
    plot.replaceChildren(motionSvg(m.dt, m.acc, rec.name || rec.id));
  } catch (e) {
    if (seq !== previewSeq) return;
    wait.textContent = `The samples could not be fetched: ${/** @type {Error} */ (e).message || e}`;
  }
}

export function initRecords() {
  $("rec-stored").addEventListener("change", picked);
  $("rec-refresh").addEventListener("click", refreshStored);
  $("f-rec-file").addEventListener("change", fileChosen);
  $("rec-paste-load").addEventListener("click", sendPasted);
  $("rec-resend").addEventListener("click", resend);
  $("rec-ask-cancel").addEventListener("click", () => { cancelAsk(); recNote = ""; recordStatus(); });
  // Enter answers the question (or loads the paste) instead of submitting the job.
  $("rec-ask").addEventListener("keydown", (ev) => {
    if (ev.key === "Enter" && /** @type {HTMLElement} */ (ev.target).tagName !== "BUTTON") { ev.preventDefault(); resend(); }
  });
  for (const id of ["f-rec-paste-dt", "f-rec-paste-name"]) {
    $(id).addEventListener("keydown", (ev) => { if (ev.key === "Enter") { ev.preventDefault(); sendPasted(); } });
  }
  // An example to paste: a one-sine pulse of 0.5 g at 1 Hz, sampled every 0.01 s.
  $textarea("f-rec-text").value = Array.from({ length: 101 }, (_, k) => Number((0.5 * Math.sin(2 * Math.PI * k / 100)).toFixed(5))).join("\n");
  $input("f-rec-paste-name").value = "one-sine 0.5 g, 1 Hz";
}
