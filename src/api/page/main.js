// @ts-check
// The page at `/`: a form that submits jobs, follows them and shows their
// results. This module sets the page up: each part's fields and listeners,
// then the form's layout, the list of jobs, and the job the address names.

import { $, $input, $textarea, num } from "./dom.js";
import { fillRawFromForm, form, hints, layout, state } from "./form.js";
import { initJobs, letGo, openJob, refreshJobs } from "./jobs.js";
import { KIND_PAGES } from "./kinds/index.js";
import { initObservations } from "./observations.js";
import { clearProblem } from "./problems.js";
import { forgetStored, initRecords } from "./records.js";
import { initResult } from "./result.js";

/**
 * A switch of what the form describes — the kind, how a block is given,
 * what shakes it — leaves nothing of the previous choice behind: the
 * error box goes; a restitution typed for the block as it was given goes
 * (the default applies, and the hint says which); another kind's result
 * goes (it stays in "Your jobs"). What is hidden is never sent.
 * @param {Event} ev
 */
function switched(ev) {
  const t = /** @type {HTMLInputElement} */ (ev.target);
  if (t.name === "kind") {
    const next = t.value === "raw" ? state.formKind : t.value;
    if (next !== state.formKind) letGo();
    state.formKind = next;
  } else if (t.name === "block-by") {
    $input("f-eta").value = "";
  } else if (t.classList.contains("obs-by")) {
    /** @type {HTMLInputElement} */ (/** @type {HTMLElement} */ (t.closest(".obs")).querySelector(".obs-eta")).value = "";
  } else if (t.name === "contact") {
    // The block's μ, when given, is the floor's to start with.
    if (t.value === "coulomb" && num("f-mu") !== undefined) $input("f-c-mu").value = $input("f-mu").value;
  } else if (!["th-by", "fo-by", "fg-by", "fg-block-by"].includes(t.name)) {
    return;
  }
  clearProblem();
}

initObservations();
initRecords();
for (const page of Object.values(KIND_PAGES)) page.init?.();
initResult();
initJobs();
form.addEventListener("change", (ev) => { switched(ev); layout(); });
form.addEventListener("input", (ev) => {
  const t = /** @type {HTMLElement} */ (ev.target);
  if (t.hasAttribute("aria-invalid")) t.removeAttribute("aria-invalid");
  hints();
});
// Another token may see other records: list them again when next in sight.
$("f-token").addEventListener("change", () => { forgetStored(); layout(); refreshJobs(); });
$("show-json").addEventListener("click", () => {
  fillRawFromForm();
  /** @type {HTMLInputElement} */ (form.querySelector("input[name=kind][value=raw]")).checked = true;
  layout();
  $textarea("f-raw").focus();
});
$("raw-from-form").addEventListener("click", fillRawFromForm);

layout();
// A service whose reads need a token (tenants, or the single token with
// reads protected) answers the listing 401: the token box opens at once.
refreshJobs();
// A job named in the address (#job=<id>) is followed again after a reload.
const m = /^#job=([0-9a-fA-F-]{36})$/.exec(location.hash);
if (m) openJob(m[1]);
