// @ts-check
// Numbers, dates and lists as the page writes them.

/**
 * A number to `d` significant digits ("–" when not a finite number).
 * @param {number | null | undefined} x
 * @param {number} [d]
 */
export const fmt = (x, d = 4) => typeof x === "number" && Number.isFinite(x) ? Number(x.toPrecision(d)).toString() : "–";

/**
 * "1 impact", "2 impacts".
 * @param {number} n
 * @param {string} one
 * @param {string} many
 */
export const plural = (n, one, many) => `${n} ${n === 1 ? one : many}`;

/**
 * "lo – hi", or one number when both read the same.
 * @param {number | null | undefined} lo
 * @param {number | null | undefined} hi
 * @param {number} [d]
 */
export const range = (lo, hi, d = 4) => fmt(lo, d) === fmt(hi, d) ? fmt(lo, d) : `${fmt(lo, d)} – ${fmt(hi, d)}`;

/**
 * The finite numbers of a list.
 * @param {(number | null | undefined)[]} xs
 * @returns {number[]}
 */
export const finite = (xs) => xs.filter(/** @returns {x is number} */ (x) => typeof x === "number" && Number.isFinite(x));

/**
 * A signed number with a minus sign ("−0.239").
 * @param {number | null | undefined} x
 * @param {number} [d]
 */
export const signed = (x, d = 4) => fmt(x, d).replace(/^-/, "−");

/**
 * "towards +x" or "towards −x": the way a signed quantity points ("" at 0).
 * @param {number | null | undefined} x
 */
export const towards = (x) => x == null ? "" : x > 0 ? "towards +x" : x < 0 ? "towards −x" : "";

/**
 * A number rounded to 12 significant digits (not a finite number: as it is).
 * @template {number | undefined} T
 * @param {T} x
 * @returns {T}
 */
export const round12 = (x) => typeof x === "number" && Number.isFinite(x) ? /** @type {T} */ (Number(x.toPrecision(12))) : x;

/** @param {number} n */
const pad2 = (n) => String(n).padStart(2, "0");

/**
 * A time stamp as local "YYYY-MM-DD hh:mm" (":ss" with `seconds`); text
 * that is not a date, as it is.
 * @param {string | null | undefined} text
 * @param {boolean} [seconds]
 */
export function dateOf(text, seconds) {
  const d = new Date(text ?? "");
  if (!text || Number.isNaN(d.getTime())) return text || "";
  return `${d.getFullYear()}-${pad2(d.getMonth() + 1)}-${pad2(d.getDate())} ${pad2(d.getHours())}:${pad2(d.getMinutes())}`
    + (seconds ? `:${pad2(d.getSeconds())}` : "");
}

/**
 * The numbers in a text (anything else separates them).
 * @param {string} text
 */
export function samplesOf(text) {
  return text.split(/[\s,;]+/).filter((t) => t !== "").map(Number);
}
