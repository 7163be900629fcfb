// @ts-check
// The error box: a problem (the service's problem+json, or the page's own),
// the field at fault named, marked and focused.

import { $, code, line, strong } from "./dom.js";
import { fieldFor, form, kind } from "./form.js";
import { observationRows } from "./observations.js";

/** @typedef {import('./api.js').PageProblem} PageProblem */

/**
 * What a field is called: its label (an observation's, with the card's
 * number and name).
 * @param {HTMLElement} el
 */
export function labelOf(el) {
  const describedBy = el.getAttribute("aria-describedby");
  const label = form.querySelector(`label[for="${el.id}"]`) || (describedBy && $(describedBy));
  const text = label ? (label.textContent ?? "").trim() : el.id;
  const row = /** @type {HTMLElement | null} */ (el.closest(".obs"));
  if (!row) return text;
  const i = observationRows().indexOf(row);
  const name = /** @type {HTMLInputElement} */ (row.querySelector(".obs-name")).value.trim();
  return `Observation ${i + 1}${name ? " (" + name + ")" : ""}: ${text}`;
}

export function clearProblem() {
  $("problem").hidden = true;
  $("problem").classList.remove("notice");
  $("problem").replaceChildren();
  for (const el of form.querySelectorAll("[aria-invalid]")) el.removeAttribute("aria-invalid");
}

/**
 * Shows a problem, `context` before its title ("Submission").
 * @param {PageProblem} pb
 * @param {string} [context]
 */
export function showProblem(pb, context) {
  const box = $("problem");
  box.replaceChildren();
  box.classList.toggle("notice", !!pb.notice);
  const head = `${context ? context + ": " : ""}${pb.title}${pb.status ? " (" + pb.status + ")" : ""}`;
  box.append(line([strong(head)]));
  let detail = pb.detail || "";
  const pointer = pb.pointer && !pb.parameter ? pb.pointer : null;
  // The detail often repeats the pointer as its prefix.
  if (pointer && detail.startsWith(pointer + ": ")) detail = detail.slice(pointer.length + 2);
  const field = fieldFor(pointer);
  if (pointer !== null) {
    /** @type {(string | Node)[]} */
    const parts = ["Field ", code(pointer || "(the whole document)")];
    if (field) parts.push(` — ${labelOf(field)}`);
    box.append(line(parts));
  }
  if (pb.file) box.append(line(["File ", code(pb.file)]));
  if (pb.parameter) box.append(line(["Parameter ", code(pb.parameter)]));
  if (pb.header) box.append(line(["Header ", code(pb.header)]));
  if (detail) box.append(line([detail]));
  if (pb.limit) {
    box.append(line([`Limit ${pb.limit}: at most ${pb.maximum}, this job ${pb.value}.`]));
  }
  if (pb.retry_after) box.append(line([`Try again in ${pb.retry_after} s.`]));
  if (pb.status === 401) {
    box.append(line(["The service needs its API token: fill in “API token” below the form."]));
    /** @type {HTMLDetailsElement} */ ($("token-box")).open = true;
  }
  box.hidden = false;
  if (field) {
    field.setAttribute("aria-invalid", "true");
    field.setAttribute("aria-errormessage", "problem");
    field.focus();
  } else if (kind() === "raw" && pointer !== null) {
    $("f-raw").setAttribute("aria-invalid", "true");
  }
}
