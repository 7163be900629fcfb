// @ts-check
// The observations of a forensic query: one card each (a name, whether the
// block toppled, the block by α and p or by b and h, η, and on a Coulomb
// floor how far a block seen standing slid).

import { LARGE_SLIDE_M, MAX_OBSERVATIONS } from "./constants.js";
import { $, find, num, numOf, setHint } from "./dom.js";
import { fmt } from "./format.js";
import { blockText, derive, etaText, firstMove, form, layout } from "./form.js";

/** @typedef {import('topple-api').components['schemas']['ObservationSpec']} ObservationSpec */

/**
 * An observation as the form's cards are filled in.
 * @typedef {{ name?: string, overturned?: boolean, alpha?: number, p?: number,
 *   b?: number, h?: number, eta?: number, slid?: [number, number] }} Seen
 */

let observationKey = 0;

/** The cards, in order. */
export const observationRows = () => /** @type {HTMLElement[]} */ ([...$("obs-list").querySelectorAll(".obs")]);

/**
 * The input of class `cls` in a card.
 * @param {ParentNode} row
 * @param {string} cls
 */
const part = (row, cls) => /** @type {HTMLInputElement} */ (row.querySelector("." + cls));

/**
 * A labelled field around `input`, which takes the class `cls`.
 * @param {string} labelText
 * @param {HTMLInputElement | HTMLSelectElement} input
 * @param {string} cls
 */
function field(labelText, input, cls) {
  const div = document.createElement("div");
  div.className = "field";
  const label = document.createElement("label");
  label.htmlFor = input.id;
  label.textContent = labelText;
  input.classList.add(cls);
  div.append(label, input);
  return div;
}

/**
 * A number input: required unless it has a placeholder.
 * @param {string} id
 * @param {number | undefined} value
 * @param {string} [placeholder]
 */
function numberInput(id, value, placeholder) {
  const input = document.createElement("input");
  input.type = "number";
  input.step = "any";
  input.id = id;
  if (value !== undefined) input.value = String(value);
  if (placeholder) input.placeholder = placeholder; else input.required = true;
  return input;
}

/**
 * A select of `options` ([value, text]), set to `value`.
 * @param {string} id
 * @param {[string, string][]} options
 * @param {string} value
 */
function selectInput(id, options, value) {
  const select = document.createElement("select");
  select.id = id;
  for (const [v, text] of options) {
    const o = document.createElement("option");
    o.value = v;
    o.textContent = text;
    select.append(o);
  }
  select.value = value;
  return select;
}

/**
 * Adds an observation card: name, whether it toppled, its block by α and
 * p or by half-width b and half-height h, η.
 * @param {Seen} o
 */
export function addObservation(o) {
  const k = observationKey++;
  /** @param {string} what */
  const id = (what) => `obs-${k}-${what}`;
  const row = document.createElement("div");
  row.className = "obs";
  row.id = id("row");
  const head = document.createElement("div");
  head.className = "obs-head";
  const numEl = document.createElement("span");
  numEl.className = "obs-num";
  const name = document.createElement("input");
  name.type = "text";
  name.id = id("name");
  name.value = o.name || "";
  name.placeholder = "what it is";
  const outcome = selectInput(id("outcome"), [["true", "toppled"], ["false", "stood"]], String(!!o.overturned));
  const remove = document.createElement("button");
  remove.type = "button";
  remove.className = "small obs-remove";
  remove.textContent = "✕";
  remove.addEventListener("click", () => {
    row.remove();
    renumber();
    layout();
  });
  const removeBox = document.createElement("div");
  removeBox.className = "field";
  removeBox.append(remove);
  head.append(numEl, field("Name", name, "obs-name"), field("Outcome", outcome, "obs-outcome"), removeBox);

  const body = document.createElement("div");
  body.className = "obs-block";
  const byGeometry = o.b !== undefined;
  const by = selectInput(id("by"), [["params", "α, p"], ["geometry", "b, h"]], byGeometry ? "geometry" : "params");
  const params = document.createElement("div");
  params.className = "vals by-params";
  params.append(field("α (rad)", numberInput(id("alpha"), o.alpha), "obs-alpha"),
    field("p (rad/s)", numberInput(id("p"), o.p), "obs-p"));
  const geometry = document.createElement("div");
  geometry.className = "vals by-geometry";
  geometry.append(field("b: half-width (m)", numberInput(id("b"), o.b), "obs-b"),
    field("h: half-height (m)", numberInput(id("h"), o.h), "obs-h"));
  const slid = document.createElement("div");
  slid.className = "vals obs-slid";
  slid.append(field("Slid from (m)", numberInput(id("slid-lo"), o.slid && o.slid[0], "0"), "obs-slid-lo"),
    field("to (m)", numberInput(id("slid-hi"), o.slid && o.slid[1], "not seen"), "obs-slid-hi"));
  body.append(field("Block", by, "obs-by"), params, geometry,
    field("η", numberInput(id("eta"), o.eta, "auto"), "obs-eta"), slid);
  const hint = document.createElement("p");
  hint.className = "hint";
  hint.setAttribute("aria-live", "polite");
  row.append(head, body, hint);
  $("obs-list").append(row);
  renumber();
  return row;
}

function renumber() {
  observationRows().forEach((row, i) => {
    find(row, ".obs-num").textContent = `${i + 1}.`;
    find(row, ".obs-remove").setAttribute("aria-label", `Remove observation ${i + 1}`);
    row.setAttribute("aria-label", `Observation ${i + 1}`);
  });
}

/**
 * The block of a card, or null.
 * @param {HTMLElement} row
 */
function rowBlock(row) {
  const by = part(row, "obs-by").value;
  return by === "params"
    ? derive(by, numOf(part(row, "obs-alpha")), numOf(part(row, "obs-p")))
    : derive(by, numOf(part(row, "obs-b")), numOf(part(row, "obs-h")));
}

/**
 * The residual slide seen on an observation's block, [lo, hi] in m, or
 * null: none given, or the fields out of sight.
 * @param {HTMLElement} row
 * @returns {[number, number] | null}
 */
function rowSlid(row) {
  const lo = part(row, "obs-slid-lo"), hi = part(row, "obs-slid-hi");
  const top = numOf(hi);
  if (hi.disabled || top === undefined) return null;
  return [numOf(lo) ?? 0, top];
}

/**
 * An observation as the spec takes it.
 * @param {HTMLElement} row
 * @returns {ObservationSpec}
 */
export function observationSpec(row) {
  /** @type {Record<string, number | undefined>} */
  const block = {};
  if (part(row, "obs-by").value === "params") {
    block.alpha = numOf(part(row, "obs-alpha"));
    block.p = numOf(part(row, "obs-p"));
  } else {
    block.b = numOf(part(row, "obs-b"));
    block.h = numOf(part(row, "obs-h"));
  }
  const eta = numOf(part(row, "obs-eta"));
  if (eta !== undefined) block.eta = eta;
  /** @type {Partial<ObservationSpec>} */
  const o = {};
  const name = part(row, "obs-name").value.trim();
  if (name) o.name = name;
  o.block = /** @type {ObservationSpec['block']} */ (block);
  o.overturned = part(row, "obs-outcome").value === "true";
  // How far it slid, when seen (from 0 when only the upper end is given).
  const slid = rowSlid(row);
  if (slid) o.slid_m = slid;
  return /** @type {ObservationSpec} */ (o);
}

/**
 * Which parts of each card are in sight: the block as given, the colour of
 * its outcome, and (on a Coulomb floor, for a block that stood) its slide.
 * @param {boolean} coulomb
 */
export function observationLayout(coulomb) {
  for (const row of observationRows()) {
    const byParams = part(row, "obs-by").value === "params";
    find(row, ".by-params").hidden = !byParams;
    find(row, ".by-geometry").hidden = byParams;
    const toppled = part(row, "obs-outcome").value === "true";
    row.classList.toggle("toppled", toppled);
    // A slide is seen on a block that stood, on a floor that lets it slide.
    find(row, ".obs-slid").hidden = toppled || !coulomb;
  }
}

/**
 * Each card's hint: its block, its η, how it first moves on a Coulomb
 * floor, the slide seen.
 * @param {boolean} coulomb
 */
export function observationHints(coulomb) {
  for (const row of observationRows()) {
    const o = rowBlock(row);
    const hint = find(row, ".hint");
    if (!o) { setHint(hint, "", ""); continue; }
    const described = blockText(o, part(row, "obs-by").value);
    const slid = rowSlid(row);
    const slidWarn = slid && slid[1] > LARGE_SLIDE_M
      ? `A slide of ${fmt(slid[0])}–${fmt(slid[1])} m is rare: metres, not cm (${fmt(slid[0])}–${fmt(slid[1])} cm is ${fmt(slid[0] / 100)}–${fmt(slid[1] / 100)} m)?`
      : "";
    const floorText = coulomb ? ` ${firstMove(num("f-c-mu"), o.alpha)}` : "";
    const slidText = slid ? ` Seen standing ${fmt(slid[0])}–${fmt(slid[1])} m from where it stood: consistent only where the block stands with its residual slide in that range.` : "";
    setHint(hint, `${described.text} ${etaText(numOf(part(row, "obs-eta")), o.alpha)}${floorText}${slidText}`, [described.warn, slidWarn].filter(Boolean).join(" "));
  }
}

/** How many cards there are, of how many the service takes. */
export function observationCount() {
  const n = observationRows().length;
  $("obs-count").textContent = `${n} of ${MAX_OBSERVATIONS}`;
  /** @type {HTMLButtonElement} */ ($("obs-add")).disabled = n >= MAX_OBSERVATIONS;
  for (const b of form.querySelectorAll(".obs-remove")) /** @type {HTMLButtonElement} */ (b).disabled = n <= 1;
}

export function initObservations() {
  // The Point Reyes example: the locomotive that toppled, a transformer that stood.
  addObservation({ name: "locomotive", alpha: 0.25, p: 2.14, eta: 0.9, overturned: true });
  addObservation({ name: "transformer", b: 0.6, h: 1.2, overturned: false });
  $("obs-add").addEventListener("click", () => {
    const row = addObservation({ b: 0.5, h: 1.5, overturned: false });
    layout();
    part(row, "obs-name").focus();
  });
}
