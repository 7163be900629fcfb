// @ts-check
// Elements of the page by id, the values of its fields, and small pieces of text.

/**
 * The element with id `id`.
 * @param {string} id
 */
export const $ = (id) => /** @type {HTMLElement} */ (document.getElementById(id));

/**
 * The input with id `id`.
 * @param {string} id
 */
export const $input = (id) => /** @type {HTMLInputElement} */ (document.getElementById(id));

/**
 * The select with id `id`.
 * @param {string} id
 */
export const $select = (id) => /** @type {HTMLSelectElement} */ (document.getElementById(id));

/**
 * The text area with id `id`.
 * @param {string} id
 */
export const $textarea = (id) => /** @type {HTMLTextAreaElement} */ (document.getElementById(id));

/** @typedef {HTMLInputElement | HTMLSelectElement | HTMLTextAreaElement} Control */

/**
 * The form control (input, select or text area) with id `id`.
 * @param {string} id
 */
export const $control = (id) => /** @type {Control} */ (document.getElementById(id));

/**
 * The element `selector` finds under `root`; one the page's own markup holds.
 * @template {Element} [E=HTMLElement]
 * @param {ParentNode} root
 * @param {string} selector
 * @returns {E}
 */
export const find = (root, selector) => /** @type {E} */ (root.querySelector(selector));

/**
 * The number a field holds, or undefined when it is empty.
 * @param {{ value: string }} el
 */
export const numOf = (el) => {
  const text = el.value.trim();
  return text === "" ? undefined : Number(text);
};

/**
 * The number the field `id` holds, or undefined when it is empty.
 * @param {string} id
 */
export const num = (id) => numOf($control(id));

/**
 * Sets a hint: its text, then a warning in red.
 * @param {HTMLElement} el
 * @param {string} text
 * @param {string} warn
 */
export function setHint(el, text, warn) {
  el.replaceChildren();
  if (text) el.append(text);
  if (warn) {
    const w = document.createElement("span");
    w.className = "warn";
    w.textContent = (text ? " " : "") + warn;
    el.append(w);
  }
}

/**
 * A paragraph of text and elements.
 * @param {(string | Node)[]} parts
 */
export function line(parts) {
  const p = document.createElement("p");
  for (const part of parts) {
    if (typeof part === "string") p.append(part);
    else p.append(part);
  }
  return p;
}

/** @param {string} t */
export const strong = (t) => { const s = document.createElement("strong"); s.textContent = t; return s; };

/** @param {string} t */
export const code = (t) => { const s = document.createElement("span"); s.className = "mono"; s.textContent = t; return s; };
