// @ts-check
// The form: what it describes (the kind, how the block is given, what shakes
// it, the floor), which of its parts are in sight, its hints, the job spec it
// makes, and the field a JSON pointer of that spec names.

import { FLOOR_KINDS, G, MAX_MU, R_MAX_M, R_MIN_M, VERTICAL_RATIO_KINDS } from "./constants.js";
import { $, $control, $select, $textarea, find, num, setHint } from "./dom.js";
import { fmt } from "./format.js";
import { KIND_PAGES } from "./kinds/index.js";
import { fragilityBlockText } from "./kinds/fragility.js";
import { observationCount, observationHints, observationLayout } from "./observations.js";
import { recordsShown, suiteIds } from "./records.js";

/** @typedef {import('./kinds/index.js').KindName} KindName */
/** @typedef {import('./kinds/index.js').KindPage<any>} KindPage */

/**
 * A block as the page works with it: α and p, its size R (m), and b and h
 * when given by them.
 * @typedef {{ alpha: number, p: number, size: number, b?: number, h?: number }} Block
 */

export const form = /** @type {HTMLFormElement} */ ($("job-form"));

/** @param {string} name */
const checked = (name) => /** @type {HTMLInputElement} */ (form.querySelector(`input[name=${name}]:checked`)).value;

/** The kind chosen: a job kind, or "raw" (the JSON editor). */
export const kind = () => checked("kind");

/**
 * What the form remembers: the kind its fields describe (the last one
 * chosen other than raw; at first, the first kind offered).
 */
export const state = { formKind: /** @type {HTMLInputElement} */ (form.querySelector("input[name=kind]")).value };

/**
 * The page of the kind `k` (none for "raw").
 * @param {string} k
 * @returns {KindPage | undefined}
 */
export const pageOf = (k) => Object.hasOwn(KIND_PAGES, k) ? KIND_PAGES[/** @type {KindName} */ (k)] : undefined;

/** How the block is given: "params" (α, p) or "geometry" (b, h). */
export const blockBy = () => checked("block-by");
/** How a fragility's uncertain blocks are given: "params" (α, p) or "geometry" (b, h). */
export const fgBlockBy = () => checked("fg-block-by");
/** What shook a forensic query's blocks: "pulse" or "record". */
export const foBy = () => checked("fo-by");
/** What shakes a time history's block: "pulse" or "record". */
export const thBy = () => checked("th-by");
/** What shakes a fragility's blocks: "pulse" or "records" (a suite). */
export const fgBy = () => checked("fg-by");
/** The floor: "no_sliding" (pure rocking) or "coulomb". */
export const contactModel = () => checked("contact");

/**
 * Whether the kind k runs on a Coulomb floor.
 * @param {string} k
 */
export const onCoulomb = (k) => /** @type {readonly string[]} */ (FLOOR_KINDS).includes(k) && contactModel() === "coulomb";

/**
 * What the kind k needs of the records: "one" (a record), "suite" or "".
 * @param {string} k
 * @returns {"one" | "suite" | ""}
 */
export function recordUse(k) {
  return pageOf(k)?.recordUse?.() ?? "";
}

export function layout() {
  const k = kind();
  const page = pageOf(k);
  for (const el of form.querySelectorAll("[data-kinds]")) {
    const box = /** @type {HTMLElement} */ (el);
    box.hidden = !(box.dataset.kinds ?? "").split(" ").includes(k);
  }
  for (const el of form.querySelectorAll("[data-form]")) {
    const box = /** @type {HTMLElement} */ (el);
    if (k === "raw") box.hidden = true;
    else if (!box.dataset.kinds) box.hidden = false;
  }
  // Whether a record (or a suite) takes the place of a pulse.
  const use = recordUse(k);
  const onRecord = use !== "";
  if (k !== "raw") $("fs-motion").hidden = !onRecord;
  // What each kind shows of its own fields.
  page?.layout?.(onRecord);
  $("vert-ratio").hidden = $select("f-vert").value !== "ratio";
  $("vert-samples").hidden = $select("f-vert").value !== "samples";
  // On a Coulomb floor its μ takes the place of the block's (which only
  // sets pure rocking's sliding warning), the equations are the nonlinear
  // ones, and a time history asks for no end of its own (it runs to rest,
  // overturning or lift-off): its series, yes, with the slip and the mode.
  const coulomb = onCoulomb(k);
  $("contact-mu").hidden = !coulomb;
  $("mu-field").hidden = coulomb;
  $("duration-field").hidden = coulomb;
  /** @type {HTMLOptionElement} */ ($select("f-formulation").querySelector("option[value=linear]")).disabled = coulomb;
  if (coulomb && $select("f-formulation").value === "linear") $select("f-formulation").value = "nonlinear";
  $("fg-params").hidden = fgBlockBy() !== "params";
  $("fg-geometry").hidden = fgBlockBy() !== "geometry";
  $("rec-legend").textContent = use === "suite" ? "Records of the suite" : "Record";
  $("rec-stored-label").textContent = use === "suite" ? "Tick the stored records of the suite" : "Or pick a stored record";
  if (onRecord) recordsShown(use);
  $("show-json").hidden = k === "raw";
  $("block-params").hidden = blockBy() !== "params";
  $("block-geometry").hidden = blockBy() !== "geometry";
  $("n-field").hidden = $select("f-type").value !== "cn" || onRecord;
  $("mp-fields").hidden = $select("f-type").value !== "mavroeidis_papageorgiou" || onRecord;
  find($("fs-pulse"), "legend").textContent = page?.pulseLegend ?? (onRecord ? "Equation of motion" : "Pulse");
  observationLayout(coulomb);
  // Fields out of sight take no part in validation.
  for (const el of form.querySelectorAll("input, select, textarea")) {
    const input = /** @type {import('./dom.js').Control} */ (el);
    const hiddenAncestor = input.closest("[hidden]");
    input.disabled = !!hiddenAncestor;
  }
  if (k === "raw" && $textarea("f-raw").value.trim() === "") fillRawFromForm();
  hints();
}

/**
 * α and p of a block given by α and p, or by its half-width b and
 * half-height h (R = √(b² + h²), α = atan(b/h), p = √(3g/(4R))); null when
 * not computable. `size` is R, m.
 * @param {string} by
 * @param {number | undefined} first
 * @param {number | undefined} second
 * @returns {Block | null}
 */
export function derive(by, first, second) {
  if (by === "params") {
    const alpha = first, p = second;
    return alpha !== undefined && p !== undefined && alpha > 0 && p > 0 ? { alpha, p, size: 3 * G / (4 * p * p) } : null;
  }
  const b = first, h = second;
  if (!(b !== undefined && h !== undefined && b > 0 && h > 0)) return null;
  const R = Math.hypot(b, h);
  return { alpha: Math.atan2(b, h), p: Math.sqrt(3 * G / (4 * R)), size: R, b, h };
}

/** The block of the form (time histories and spectra), or null. */
export function blockParams() {
  return blockBy() === "params" ? derive("params", num("f-alpha"), num("f-p")) : derive("geometry", num("f-b"), num("f-h"));
}

/**
 * A hint describing a block: its full size when given by b and h, α and p
 * when derived, and a warning when its size is implausible.
 * @param {Block} bp
 * @param {string} by
 */
export function blockText(bp, by) {
  const parts = [];
  if (by === "geometry") {
    parts.push(`Block ${fmt(2 * (bp.b ?? NaN))} m wide × ${fmt(2 * (bp.h ?? NaN))} m tall: α = ${fmt(bp.alpha)} rad, p = ${fmt(bp.p)} rad/s.`);
  } else {
    parts.push(`Size R = 3g/(4p²) = ${fmt(bp.size)} m.`);
  }
  let warn = "";
  if (bp.size > R_MAX_M || bp.size < R_MIN_M) {
    warn = `R = ${fmt(bp.size)} m is outside ${R_MIN_M} m – ${R_MAX_M} m: ` +
      (by === "geometry" ? "b and h are HALF the width and height, in metres (not mm)." : "is p in rad/s (not Hz)?");
  }
  return { text: parts.join(" "), warn };
}

export function hints() {
  const bp = blockParams();
  const formulation = $select("f-formulation").value;
  let text = "", warn = "";
  if (bp && bp.alpha < Math.PI / 2) {
    const thr = formulation === "linear" ? bp.alpha : Math.tan(bp.alpha);
    const described = blockText(bp, blockBy());
    text = `${described.text} Rocking starts when |ü_g| > ${fmt(thr)} g (${formulation === "linear" ? "g·α" : "g·tan α"}). ${etaText(num("f-eta"), bp.alpha)}`;
    warn = described.warn;
  }
  setHint($("block-hint"), text, warn);
  let ptext = "";
  const k = kind();
  if (bp && pageOf(k)?.pulseAxes?.()) {
    const omega = omegaOf(num("f-freq"), $select("f-freq-unit").value, bp);
    if (Number.isFinite(omega)) {
      ptext = `ω_p = ${fmt(omega)} rad/s, f_p = ${fmt(omega / (2 * Math.PI))} Hz, ω_p/p = ${fmt(omega / bp.p)}.`;
    }
  }
  $("pulse-hint").textContent = ptext;
  const contact = contactText(k, bp);
  setHint($("contact-hint"), contact.text, contact.warn);
  observationHints(onCoulomb(k));
  $("fg-block-hint").textContent = fragilityBlockText();
  observationCount();
}

/**
 * What the floor chosen means for a job of kind k on the block bp (or null).
 * @param {string} k
 * @param {Block | null} bp
 */
function contactText(k, bp) {
  if (contactModel() !== "coulomb") {
    return { text: "The base never slips; the block's μ, when given, only warns where the friction rocking needs exceeds it.", warn: "" };
  }
  const mu = num("f-c-mu"), muk = num("f-c-muk");
  const parts = ["The block sticks, slides, rocks, slide-rocks (rocks on a slipping corner) or leaves the floor; nonlinear equations only."];
  // The block of the form (a record spectrum's by its α); a forensic
  // query's are its observations', each said beside its card.
  const page = pageOf(k);
  const first = firstMove(mu, page?.floorAlpha?.(bp));
  if (first) parts.push(first);
  if (page?.floorNote) parts.push(page.floorNote);
  let warn = "";
  if (mu !== undefined && !(mu > 0 && mu <= MAX_MU)) warn = `μ must be above 0 and at most ${MAX_MU}.`;
  else if (muk !== undefined && !(muk > 0 && mu !== undefined && muk <= mu)) warn = "μ_k must be above 0 and at most μ.";
  return { text: parts.join(" "), warn };
}

/**
 * How a block of slenderness α first moves on a floor of friction μ, or "".
 * @param {number | undefined} mu
 * @param {number | undefined} alpha
 */
export function firstMove(mu, alpha) {
  if (!(mu !== undefined && alpha !== undefined && mu > 0 && alpha > 0 && alpha < Math.PI / 2)) return "";
  return mu < Math.tan(alpha)
    ? `μ < tan α = ${fmt(Math.tan(alpha))}: from rest it slides first, once |ü_g| > μg.`
    : `μ ≥ tan α = ${fmt(Math.tan(alpha))}: from rest it rocks first.`;
}

/**
 * Which restitution a block gets: the one given, or the service's default
 * (Housner's 1 − 1.5 sin²α, not below 0), said in so many words.
 * @param {number | undefined} eta
 * @param {number} alpha
 */
export function etaText(eta, alpha) {
  if (eta !== undefined) return `η = ${fmt(eta)} (given).`;
  return `η = 1 − 1.5 sin²α = ${fmt(Math.max(0, 1 - 1.5 * Math.sin(alpha) ** 2))} (the default: none given).`;
}

/**
 * ω_p, rad/s, of a frequency given in `unit`.
 * @param {number | undefined} value
 * @param {string} unit
 * @param {Block | null} bp
 */
export function omegaOf(value, unit, bp) {
  if (value === undefined || !Number.isFinite(value)) return NaN;
  if (unit === "omega_p") return value;
  if (unit === "frequency_hz") return 2 * Math.PI * value;
  return bp ? value * bp.p : NaN;
}

// ---- the spec -----------------------------------------------------------

/**
 * The job spec the form describes.
 * @returns {Record<string, unknown>}
 */
export function formSpec() {
  const k = state.formKind;
  const spec = withFloor(pageOf(k)?.spec() ?? { kind: k }, k);
  // The kinds that scale their motion take a vertical ratio, sent only when given.
  const r = num("f-vr");
  if (/** @type {readonly string[]} */ (VERTICAL_RATIO_KINDS).includes(k) && r !== undefined) {
    spec.vertical = { ratio: r };
  }
  return spec;
}

/**
 * `spec` on the floor chosen: a Coulomb floor's μ (and μ_k) in `contact`,
 * the nonlinear equations, and what the kind adds on a floor.
 * @param {Record<string, unknown>} spec
 * @param {string} k
 */
function withFloor(spec, k) {
  if (!onCoulomb(k)) return spec;
  /** @type {import('topple-api').components['schemas']['ContactSpec']} */
  const contact = { model: "coulomb", mu: num("f-c-mu") };
  spec.contact = contact;
  if (num("f-c-muk") !== undefined) contact.mu_kinetic = num("f-c-muk");
  spec.formulation = "nonlinear";
  pageOf(k)?.onFloor?.(spec);
  return spec;
}

export function fillRawFromForm() {
  $textarea("f-raw").value = JSON.stringify(formSpec(), null, 2);
}

// ---- the field of a pointer -------------------------------------------------

/**
 * The form control a JSON pointer of the spec refers to.
 * @param {string | null | undefined} pointer
 * @returns {HTMLElement | null}
 */
export function fieldFor(pointer) {
  if (!pointer || kind() === "raw") return null;
  const k = kind();
  const p = pointer.replace(/^#/, "");
  // The record (or a record of the suite) is chosen in the record fieldset.
  const ofSuite = /^\/ground_motions\/(\d+)/.exec(p);
  if (ofSuite) {
    const box = /** @type {HTMLElement | null} */ ($("rec-stored").querySelector(`input[value="${suiteIds()[Number(ofSuite[1])]}"]`));
    if (box) return box;
  }
  if (/^\/ground_motion\/vertical(\/|$)/.test(p)) {
    const v = /** @type {Record<string, string>} */ ({ ratio: "f-vert-ratio", acc: "f-vert-text", unit: "f-vert-unit" })[p.split("/")[3]];
    return $(v && !$control(v).disabled ? v : $textarea("f-vert-text").value.trim() !== "" ? "f-vert-text" : "f-vert-file");
  }
  if (/^\/vertical(\/|$)/.test(p) && /** @type {readonly string[]} */ (VERTICAL_RATIO_KINDS).includes(k)) return $("f-vr");
  if (/^\/ground_motions?(\/|$)/.test(p)) return $("f-rec-file");
  // The floor, whatever the kind.
  if (/^\/contact(\/|$)/.test(p)) return $(p === "/contact/mu_kinetic" ? "f-c-muk" : "f-c-mu");
  return pageOf(k)?.fieldFor(p) ?? null;
}
