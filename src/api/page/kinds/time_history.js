// @ts-check
// A time history: one block under a pulse or a record (and a vertical
// motion), its series; its outcome (overturned when and how, or how it
// survived) and the details of its motion.

import { headers, problemOf } from "../api.js";
import { $, $input, $select, $textarea, num } from "../dom.js";
import { fmt, plural, samplesOf, signed, towards } from "../format.js";
import { onCoulomb, thBy } from "../form.js";
import { currentRecord, groundMotionOf } from "../records.js";
import { blockCondition, blockKindFieldFor, blockKindSpec, contactCondition, pulseOfForm } from "./common.js";

/** @typedef {import('topple-api').components['schemas']} S */
/** @typedef {S['TimeHistoryResult']} TimeHistoryResult */
/** @typedef {import('./common.js').Add} Add */

/** The modes of a block on a Coulomb floor, as the summary names them. */
const MODE_NAMES = /** @type {Record<string, string>} */ ({ stick: "stick", rock: "rock", slide: "slide", slide_rock: "slide-rock", flight: "flight" });
/** How a block on a Coulomb floor first moved, in each mode. */
const FIRST_MOVES = /** @type {Record<string, string>} */ ({ rock: "rocking", slide: "sliding", slide_rock: "sliding while rocking", flight: "leaving the floor" });
// Up to this many modes are listed one by one.
const FEW_MODES = 12;

/** @type {S['RecordView'] | null} the vertical component's stored record */
let verticalRecord = null;

/**
 * The vertical ground motion the form gives, as the spec takes it (beside
 * a pulse: `vertical`; in a record: `ground_motion.vertical`), or null.
 * @returns {Record<string, unknown> | null}
 */
function verticalOf() {
  const how = $select("f-vert").value;
  if (how === "ratio" && num("f-vert-ratio") !== undefined) return { ratio: num("f-vert-ratio") };
  if (how !== "samples") return null;
  const text = $textarea("f-vert-text").value.trim();
  if (text !== "") return { acc: samplesOf(text), unit: $select("f-vert-unit").value };
  return verticalRecord ? { record: verticalRecord.id } : null;
}

/**
 * The vertical component's file: stored (POST /v1/records) in the unit
 * chosen and on the record's dt, then named by id.
 */
async function sendVerticalFile() {
  const file = $input("f-vert-file").files?.[0];
  verticalRecord = null;
  if (!file) { $("vert-status").textContent = ""; return; }
  const params = new URLSearchParams({ name: file.name });
  const unitAsked = $select("f-vert-unit").value;
  /** @type {Response | undefined} */
  let resp;
  /** @type {any} */
  let body;
  for (const withUnit of [false, true]) {
    const query = new URLSearchParams(params);
    if (withUnit) query.set("unit", unitAsked);
    const record = currentRecord();
    if (record && record.dt) query.set("dt", String(record.dt));
    $("vert-status").textContent = `Sending ${file.name} to the service…`;
    try {
      resp = await fetch("/v1/records?" + query, {
        method: "POST", body: await file.text(), headers: headers({ "Content-Type": "text/plain" })
      });
      body = resp.ok ? await resp.json() : await problemOf(resp);
    } catch (e) {
      $("vert-status").textContent = `The service did not answer: ${/** @type {Error} */ (e).message || e}`;
      return;
    }
    // The unit (or dt) the file does not state: send again with the form's.
    if (resp.ok || withUnit || !["unit", "dt"].includes(body.parameter)) break;
  }
  if (!resp || !resp.ok) {
    $("vert-status").textContent = `${file.name}: ${body.detail || body.title}`;
    return;
  }
  /** @type {S['RecordView']} */
  const stored = body;
  verticalRecord = stored;
  $("vert-status").textContent = `Vertical: ${stored.name}, ${plural(stored.samples, "sample", "samples")} every ${fmt(stored.dt)} s, peak ${fmt(stored.pga_g, 3)} g.`;
}

/**
 * What shook the block, and the block itself, from the result's own spec
 * (what was run, defaults filled in).
 * @param {TimeHistoryResult} r
 * @param {Add} add
 */
function conditions(r, add) {
  /** @type {any} */
  const spec = r.spec || {};
  blockCondition(r, add);
  const peaks = r.ground_peaks || /** @type {Partial<S['GroundPeaksDoc']>} */ ({});
  const pga = `PGA ${fmt(peaks.pga_g)} g, PGV ${fmt(peaks.pgv_m_s)} m/s`;
  if (spec.ground_motion) {
    const n = Array.isArray(spec.ground_motion.acc) ? `${spec.ground_motion.acc.length} samples, ` : "";
    add("Ground motion", `a record (${n}dt = ${fmt(spec.ground_motion.dt)} s): ${pga}`);
  } else if (spec.pulse) {
    const p = spec.pulse;
    const name = /** @type {Record<string, string>} */ ({ ricker: p.symmetric === false ? "antisymmetric Ricker" : "Ricker", cn: `C${p.n ?? "n"}` })[p.type] || String(p.type).replace(/_/g, "-");
    const f = Number.isFinite(p.omega_p) ? `, f_p = ${fmt(p.omega_p / (2 * Math.PI))} Hz` : "";
    add("Ground motion", `${name} pulse${f}: ${pga}`);
  }
  contactCondition(r, add);
  // The vertical motion, when there was one: how it was given and its peak.
  const v = (spec.ground_motion && spec.ground_motion.vertical) || spec.vertical;
  if (v) {
    const how = Number.isFinite(v.ratio) ? `ü_v = ${fmt(v.ratio)} · ü_g`
      : v.type ? `a ${String(v.type).replace(/_/g, "-")} pulse of its own${Number.isFinite(v.delay_s) && v.delay_s > 0 ? `, ${fmt(v.delay_s)} s later` : ""}`
      : "a record of its own";
    add("Vertical ground motion", `${how}: PGA_v ${fmt(peaks.pga_v_g)} g${r.lift_off ? `; lifts off at t = ${fmt(r.lift_off_time)} s (no verdict after)` : ""}`);
  }
}

/**
 * How a block on a Coulomb floor moved: how far its base slid, how it
 * first moved, its modes in time order.
 * @param {TimeHistoryResult} r
 * @param {Add} add
 */
function coulombItems(r, add) {
  if (r.contact_model !== "coulomb") return;
  const peak = r.peak_slide_m, residual = r.residual_slide_m;
  if (peak != null && peak > 0) {
    const way = towards(residual);
    add("Sliding", `slid ${fmt(peak, 3)} m, residual ${signed(residual, 3)} m${way ? ` (${way})` : ""}, ${fmt(r.time_sliding_s, 3)} s sliding`);
  } else {
    add("Sliding", r.answered_by === "pure_rocking" ? "none: the friction rocking needs never exceeds μ" : "none");
  }
  add("First moved by", r.initial_mode ? FIRST_MOVES[r.initial_mode] || r.initial_mode.replace(/_/g, " ") : "never moved");
  // A slide's way (the base's, relative to the ground) beside it: "slide (−x)".
  const modes = (r.modes || []).map((m) => `${MODE_NAMES[m.mode] || m.mode.replace(/_/g, "-")}${(m.direction ?? 0) > 0 ? " (+x)" : (m.direction ?? 0) < 0 ? " (−x)" : ""}`);
  if (modes.length) {
    const shown = modes.length <= FEW_MODES ? modes : [...modes.slice(0, FEW_MODES - 2), "…", modes[modes.length - 1]];
    add("Modes", `${shown.join(" → ")}${modes.length > FEW_MODES ? ` (${modes.length} in all)` : ""}`, "wide");
  }
}

/** @type {import('./index.js').KindPage<TimeHistoryResult>} */
export default {
  title: "time history",
  pulseLegend: "Ground motion",
  floorNote: "The result lists the modes and the slip at each change, and its series the slip and the mode at each sample; the history runs to rest or overturning, through any flight (no end of its own).",
  floorAlpha: (bp) => bp ? bp.alpha : undefined,
  recordUse: () => thBy() === "record" ? "one" : "",
  pulseAxes: () => thBy() === "pulse",

  layout(onRecord) {
    /** @type {HTMLElement} */ ($("f-type").closest(".field")).hidden = onRecord;
    $("pulse-axes").hidden = onRecord;
    // A vertical motion of its own: samples beside a record (a pulse takes a ratio here).
    const own = /** @type {HTMLOptionElement} */ ($("f-vert-own"));
    own.hidden = own.disabled = !onRecord;
    if (!onRecord && $select("f-vert").value === "samples") $select("f-vert").value = "";
  },

  init() {
    $("f-vert-file").addEventListener("change", sendVerticalFile);
    $("f-vert-text").addEventListener("input", () => {
      if ($textarea("f-vert-text").value.trim() !== "") $("vert-status").textContent = "The pasted samples are sent (not the file).";
    });
  },

  spec() {
    const pulse = pulseOfForm();
    const spec = blockKindSpec("time_history", thBy() === "record" ? { ground_motion: groundMotionOf() } : { pulse });
    if (spec.pulse) {
      pulse[$select("f-freq-unit").value] = num("f-freq");
      pulse[$select("f-amp-unit").value] = num("f-amp");
    }
    // A series either way; a Coulomb history runs to its end (the
    // service refuses an end of its own): no duration there.
    /** @type {{ series?: number, duration?: number }} */
    const outputs = { series: num("f-series") };
    spec.outputs = outputs;
    const coulomb = onCoulomb("time_history");
    if (!coulomb && num("f-duration") !== undefined) outputs.duration = num("f-duration");
    // The vertical motion only when one is given.
    const vertical = verticalOf();
    if (vertical && spec.ground_motion) /** @type {Record<string, unknown>} */ (spec.ground_motion).vertical = vertical;
    else if (vertical) spec.vertical = vertical;
    return spec;
  },

  // A pulse at fault is its frequency and amplitude, first.
  fieldFor: (p) => p === "/pulse" ? $("f-freq") : blockKindFieldFor(p),

  outcome(r) {
    if (r.overturned) {
      const how = r.mode === 1 ? `mode 1: after ${plural(r.impact_count ?? 0, "impact", "impacts")}`
        : r.mode === 2 ? "mode 2: without impact" : "mode –";
      return [`Overturned at t = ${fmt(r.overturn_time)} s (${how}).`, "overturned"];
    }
    if (!r.rocked && r.contact_model === "coulomb") {
      if (!r.initial_mode) return ["Did not move: the ground never overcame the friction nor the rocking threshold.", "stood"];
      const how = r.initial_mode === "slide" && (r.peak_slide_m ?? 0) > 0 ? `it slid (${fmt(r.peak_slide_m, 3)} m at most)`
        : `it first moved by ${FIRST_MOVES[r.initial_mode] || r.initial_mode.replace(/_/g, " ")}`;
      const end = r.rest_time != null ? ` and came to rest at t = ${fmt(r.rest_time)} s`
        : r.lift_off ? `; it left the floor at t = ${fmt(r.lift_off_time)} s (no verdict after)`
        : `; still moving when the simulation ended at t = ${fmt(r.end_time)} s`;
      return [`Did not rock: ${how}${end}.`, "stood"];
    }
    if (!r.rocked) return ["Did not rock: the ground acceleration never exceeded the rocking threshold.", "stood"];
    const rest = r.rest_time != null ? `came to rest at t = ${fmt(r.rest_time)} s`
      : `still rocking when the simulation ended at t = ${fmt(r.end_time)} s (did not come to rest)`;
    return [`Survived: peak |θ|/α = ${fmt(r.peak_theta_over_alpha)}; ${rest}.`, "stood"];
  },

  summary(_job, r, add) {
    if (r.overturned) {
      add("Overturns at (s)", fmt(r.overturn_time));
      add("Mode", r.mode === 1 ? "1 (after impacts)" : r.mode === 2 ? "2 (without impact)" : "–");
      if (towards(r.overturn_direction)) add("Overturns", towards(r.overturn_direction));
      if (Number.isFinite(r.decided_at)) add("Bound to overturn from (s)", fmt(r.decided_at));
    } else {
      add("Overturned", "no");
      add("Peak |θ|/α", fmt(r.peak_theta_over_alpha));
      if (r.rocked) add("At rest", r.rest_time != null ? `from ${fmt(r.rest_time)} s` : `not by ${fmt(r.end_time)} s`);
    }
    add("Impacts", String(r.impact_count ?? "–"));
    if (r.rocking_start != null) add("Rocking starts at (s)", fmt(r.rocking_start));
    const until = Number.isFinite(r.friction_demand_followed_until) ? `up to t = ${fmt(r.friction_demand_followed_until)} s (the pulse end)` : "while rocking";
    if (r.peak_friction_demand != null) add(`Friction demand μ, ${until}`, `${fmt(r.peak_friction_demand)}${Number.isFinite(r.peak_friction_demand_time) ? ` at t = ${fmt(r.peak_friction_demand_time)} s` : ""}`);
    else if (r.lift_off) add("Friction demand μ", `unbounded: lifts off at ${fmt(r.lift_off_time)} s`);
    coulombItems(r, add);
    conditions(r, add);
  }
};
