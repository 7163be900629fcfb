// @ts-check
// A forensic query: the pulses (or the scales of a record) consistent with
// blocks seen overturned or standing (their cards: ../observations.js).

import { $, $select, num } from "../dom.js";
import { fmt, plural, range } from "../format.js";
import { foBy } from "../form.js";
import { observationRows, observationSpec } from "../observations.js";
import { groundMotionOf } from "../records.js";
import { authorisedDownload } from "../result.js";
import { contactCondition, intervalStats, pulseOfForm } from "./common.js";

/** @typedef {import('topple-api').components['schemas']} S */
/** @typedef {S['ForensicResult']} ForensicResult */
/** @typedef {S['JobView']} JobView */

// Up to this many intervals are listed in the summary.
const FEW_INTERVALS = 6;

/**
 * A pulse query's answer: each frequency's intervals, those with any, and
 * all of them together.
 * @param {ForensicResult} r
 */
function pulseAnswer(r) {
  const freqs = (r.frequencies || []).map((f) => Object.assign({ f: f.frequency_hz }, intervalStats(f.consistent_g)));
  const all = intervalStats((r.frequencies || []).flatMap((f) => f.consistent_g || []));
  return Object.assign({ freqs, withAny: freqs.filter((x) => x.count > 0) }, all);
}

/**
 * "in the figure and the CSV": links to where every interval is.
 * @param {JobView} job
 * @returns {(string | Node)[]}
 */
function whereEveryInterval(job) {
  const figure = document.createElement("a");
  figure.href = `/v1/jobs/${job.id}/plot.svg`;
  figure.target = "_blank";
  figure.rel = "noopener";
  figure.className = "to-figure";
  figure.textContent = "figure";
  const csv = document.createElement("a");
  csv.href = `/v1/jobs/${job.id}/result?format=csv`;
  csv.setAttribute("download", `topple-${job.kind}-${job.id}.csv`);
  csv.className = "to-csv";
  csv.textContent = "CSV";
  for (const a of [figure, csv]) a.addEventListener("click", authorisedDownload);
  return [" — each in the ", figure, " and the ", csv];
}

/**
 * The field of a pointer into a forensic query: an observation's inputs,
 * the ranges.
 * @param {string} p
 * @returns {HTMLElement | null}
 */
function fieldFor(p) {
  const obs = /^\/observations\/(\d+)(?:\/block)?(?:\/(\w+))?/.exec(p);
  if (obs) {
    const row = observationRows()[Number(obs[1])];
    if (!row) return null;
    const which = /** @type {Record<string, string>} */ ({ alpha: "alpha", slenderness: "alpha", p: "p", frequency_parameter: "p", b: "b", h: "h", eta: "eta", overturned: "outcome", name: "name", slid_m: "slid-hi" })[obs[2]];
    const el = which && /** @type {HTMLInputElement | null} */ (row.querySelector(".obs-" + which));
    return el && !el.disabled ? el : row.querySelector("input:not(:disabled):not(.obs-name)");
  }
  if (p === "/observations") return $("obs-add");
  if (/^\/(pga_g|scale)/.test(p)) return $(p.endsWith("/from") ? "f-fo-sfrom" : "f-fo-sto");
  if (p === "/pulse/type" || p === "/pulse") return $(foBy() === "record" ? "f-rec-file" : "f-type");
  if (p === "/pulse/n") return $("f-n");
  if (p === "/pulse/gamma") return $("f-gamma");
  if (p === "/pulse/nu") return $("f-nu");
  if (p === "/formulation") return $("f-formulation");
  if (/^\/(frequency_hz|omega_p|omega_ratio)/.test(p)) {
    return $(p.endsWith("/to") ? "f-fo-to" : p.endsWith("/steps") ? "f-fo-steps" : "f-fo-from");
  }
  if (/^\/(a_p_g|a_p)/.test(p)) return $(p.endsWith("/to") ? "f-fo-ato" : "f-fo-afrom");
  return null;
}

/** @type {import('./index.js').KindPage<ForensicResult>} */
export default {
  title: "forensic query",
  floorNote: "Each amplitude is a Coulomb history of every observed block; a block seen standing may also say how far it slid (its residual slide, in m), which pure rocking cannot use.",
  recordUse: () => foBy() === "record" ? "one" : "",

  layout(onRecord) {
    $("fo-pulse-axes").hidden = onRecord;
    $("fo-record-axes").hidden = !onRecord;
    $("fo-legend").textContent = onRecord ? "Scales examined" : "Pulses examined";
    /** @type {HTMLElement} */ ($("f-type").closest(".field")).hidden = onRecord;
  },

  spec() {
    const pulse = pulseOfForm();
    if (foBy() === "record") {
      /** @type {Record<string, unknown>} */
      const spec = { kind: "forensic", ground_motion: groundMotionOf(), observations: observationRows().map(observationSpec) };
      spec[$select("f-fo-sunit").value] = { from: num("f-fo-sfrom"), to: num("f-fo-sto") };
      spec.formulation = $select("f-formulation").value;
      return spec;
    }
    /** @type {Record<string, unknown>} */
    const spec = { kind: "forensic", pulse, observations: observationRows().map(observationSpec) };
    spec[$select("f-fo-unit").value] = { from: num("f-fo-from"), to: num("f-fo-to"), steps: num("f-fo-steps") };
    spec[$select("f-fo-aunit").value] = { from: num("f-fo-afrom"), to: num("f-fo-ato") };
    spec.formulation = $select("f-formulation").value;
    return spec;
  },

  fieldFor,

  outcome(r) {
    if (r.excitation === "ground_motion") {
      const s = intervalStats(r.consistent_scale), g = intervalStats(r.consistent_pga_g);
      const zones = r.mixed_scale || [];
      const mixedText = zones.length
        ? ` Besides, ${plural(zones.length, "mixed zone", "mixed zones")} (${fmt(zones.reduce((a, z) => a + z.to - z.from, 0))} wide in all) where the outcome alternates finer than the scan resolves.`
        : "";
      if (!s.count && zones.length) return [`No scale of the record is certainly consistent with every observation.${mixedText}`, ""];
      if (!s.count) return ["No scale of the record in the range examined is consistent with every observation.", "overturned"];
      if (s.count === 1) return [`Consistent with every observation, with certainty: one interval of the record's scale, ${range(s.lo, s.hi)} (PGA ${range(g.lo, g.hi)} g).${mixedText}`, ""];
      return [`Consistent with every observation, with certainty: ${s.count} separate intervals of the record's scale (lowest ${fmt(s.lo)}, highest ${fmt(s.hi)}; ${fmt(s.measure)} wide in all; as PGA: lowest ${fmt(g.lo)} g, highest ${fmt(g.hi)} g, ${fmt(g.measure)} g in all).${mixedText}`, ""];
    }
    if (Array.isArray(r.frequencies)) {
      const a = pulseAnswer(r);
      if (!a.count) return ["No pulse in the range examined is consistent with every observation.", "overturned"];
      if (a.count === 1) return [`Consistent with every observation: one interval of a_p, ${range(a.lo, a.hi)} g, at ${fmt(a.withAny[0].f)} Hz.`, ""];
      return [`Consistent with every observation: ${a.count} separate intervals of a_p at ${a.withAny.length} of ${a.freqs.length} frequencies (lowest ${fmt(a.lo)} g, highest ${fmt(a.hi)} g; ${fmt(a.measure)} g wide in all, summed over the frequencies).`, ""];
    }
    return ["", ""];
  },

  summary(job, r, add) {
    if (r.excitation === "ground_motion") {
      const obs = r.observations || [];
      const toppled = obs.filter((o) => o.overturned).length;
      add("Observations", `${toppled} toppled, ${obs.length - toppled} stood`);
      const rec = r.record || /** @type {Partial<S['RecordDoc']>} */ ({});
      add("Record", `${rec.samples} samples, dt = ${fmt(rec.dt_s)} s, PGA ${fmt(rec.pga_g)} g`);
      if (r.scale) add("Scales examined", `${range(r.scale.from, r.scale.to)} (PGA ${range(r.a_p_g.from, r.a_p_g.to)} g)`);
      const s = intervalStats(r.consistent_scale), g = intervalStats(r.consistent_pga_g);
      add("Consistent intervals", [String(s.count), ...(s.count ? whereEveryInterval(job) : [])]);
      const zones = r.mixed_scale || [];
      if (zones.length) {
        add("Mixed zones", `${zones.length}, ${fmt(zones.reduce((a, z) => a + z.to - z.from, 0))} wide in all: the outcome alternates finer than the scan resolves`);
      }
      if (s.count) {
        add("Lowest, highest scale", `${fmt(s.lo)} (PGA ${fmt(g.lo)} g), ${fmt(s.hi)} (PGA ${fmt(g.hi)} g)`);
        const examined = r.scale ? ` of the ${fmt(r.scale.to - r.scale.from)} examined` : "";
        add("Total width, all intervals", `${fmt(s.measure)}${examined} (PGA ${fmt(g.measure)} g)`);
        // A few intervals are read at once; many, in the figure and the CSV.
        if (s.count > 1 && s.count <= FEW_INTERVALS) {
          add("The intervals (scale)", (r.consistent_scale || []).map(([lo, hi]) => range(lo, hi)).join(", "));
        }
      }
    } else if (Array.isArray(r.frequencies)) {
      const obs = r.observations || [];
      const toppled = obs.filter((o) => o.overturned).length;
      add("Observations", `${toppled} toppled, ${obs.length - toppled} stood`);
      const f = r.frequencies.map((x) => x.frequency_hz);
      add("Frequencies (Hz)", `${f.length}: ${range(f[0], f[f.length - 1])}`);
      if (r.a_p_g) add("Amplitudes examined (g)", range(r.a_p_g.from, r.a_p_g.to));
      const a = pulseAnswer(r);
      add("Consistent intervals", [`${a.count} at ${a.withAny.length} of ${a.freqs.length} frequencies`, ...(a.count ? whereEveryInterval(job) : [])]);
      if (a.count) {
        const atLo = a.withAny.find((x) => x.lo === a.lo), atHi = a.withAny.find((x) => x.hi === a.hi);
        add("Lowest, highest a_p", `${fmt(a.lo)} g (at ${fmt(atLo?.f)} Hz), ${fmt(a.hi)} g (at ${fmt(atHi?.f)} Hz)`);
        add("Total width, all intervals", `${fmt(a.measure)} g, summed over the ${plural(a.withAny.length, "frequency", "frequencies")}`);
      }
      add("Frequencies ruled out", `${a.freqs.length - a.withAny.length} of ${f.length}`);
    }
    // The floor.
    contactCondition(r, add);
  }
};
