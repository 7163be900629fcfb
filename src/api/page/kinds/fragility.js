// @ts-check
// A fragility: the probability that blocks of uncertain size topple, at
// stripes of intensity, under pulses of uncertain frequency or a suite of
// records.

import { $, $select, num } from "../dom.js";
import { fmt, plural, range, round12 } from "../format.js";
import { derive, fgBlockBy, fgBy } from "../form.js";
import { suiteIds } from "../records.js";
import { IM_NAMES, contactCondition, pulseOfForm } from "./common.js";

/** @typedef {import('topple-api').components['schemas']['FragilityResult']} FragilityResult */
/** @typedef {{ dist: "normal", mean: number, sd: number, min: number, max: number }} Normal */

/**
 * A normal distribution truncated to ±3 sd (and to [lo, hi] when given),
 * or the mean itself when sd is 0.
 * @param {number | undefined} mean
 * @param {number | undefined} sd
 * @param {number} [lo]
 * @param {number} [hi]
 * @returns {number | undefined | Normal}
 */
function truncatedNormal(mean, sd, lo, hi) {
  if (!(sd !== undefined && sd > 0) || mean === undefined) return mean;
  let min = mean - 3 * sd, max = mean + 3 * sd;
  if (lo !== undefined) min = Math.max(min, lo);
  if (hi !== undefined) max = Math.min(max, hi);
  return { dist: "normal", mean, sd, min: round12(min), max: round12(max) };
}

/** The fragility's block as the spec takes it: α and p, or b and h. */
function fragilityBlock() {
  if (fgBlockBy() === "geometry") {
    return {
      b: truncatedNormal(num("f-fg-b"), num("f-fg-b-sd"), 1e-3),
      h: truncatedNormal(num("f-fg-h"), num("f-fg-h-sd"), 1e-3)
    };
  }
  return { alpha: truncatedNormal(num("f-fg-alpha"), num("f-fg-alpha-sd"), 1e-3, 1.5), p: num("f-fg-p") };
}

/**
 * The fragility's block in words, exactly as it is sent: each distribution
 * with its truncation, and the block at the means.
 */
export function fragilityBlockText() {
  /** @type {{ alpha?: number | Normal, p?: number | Normal, b?: number | Normal, h?: number | Normal }} */
  const block = fragilityBlock();
  /**
   * @param {string} name
   * @param {number | Normal | undefined} v
   * @param {string} unit
   */
  const of = (name, v, unit) => {
    if (v === undefined || (typeof v === "number" && !Number.isFinite(v))) return "";
    if (typeof v === "number") return `${name} = ${fmt(v)} ${unit}`;
    return `${name} normal (mean ${fmt(v.mean)}, sd ${fmt(v.sd)}) ${unit} on [${fmt(v.min)}, ${fmt(v.max)}]`;
  };
  /** @param {number | Normal | undefined} v */
  const mean = (v) => typeof v === "number" ? v : v && v.mean;
  const parts = [];
  if (fgBlockBy() === "geometry") {
    parts.push([of("b", block.b, "m"), of("h", block.h, "m")].filter(Boolean).join(", ") + ".");
    const bp = derive("geometry", mean(block.b), mean(block.h));
    if (bp) parts.push(`At the means: ${fmt(2 * (bp.b ?? NaN))} m wide × ${fmt(2 * (bp.h ?? NaN))} m tall, α = ${fmt(bp.alpha)} rad, p = ${fmt(bp.p)} rad/s.`);
  } else {
    parts.push([of("α", block.alpha, "rad"), of("p", block.p, "rad/s")].filter(Boolean).join(", ") + ".");
  }
  parts.push("η of each sample: 1 − 1.5 sin²α.");
  return parts.join(" ");
}

/** @type {import('./index.js').KindPage<FragilityResult>} */
export default {
  title: "fragility",
  pulseLegend: "Ground motion",
  floorNote: "Each scale (each sample) is a Coulomb history: several times the work of pure rocking.",
  recordUse: () => fgBy() === "records" ? "suite" : "",

  layout(onRecord) {
    /** @type {HTMLElement} */ ($("f-type").closest(".field")).hidden = onRecord;
    $("fg-pulse-axes").hidden = onRecord;
    $("fg-suite-hint").hidden = !onRecord;
    $("fg-legend").textContent = onRecord ? "Uncertain block" : "Uncertain block and pulses";
  },

  spec() {
    const pulse = pulseOfForm();
    /** @type {Record<string, unknown>} */
    const spec = { kind: "fragility", block: fragilityBlock() };
    if (fgBy() === "records") {
      spec.ground_motions = suiteIds().map((id) => ({ record: id }));
    } else {
      const beta = num("f-fg-hz-beta");
      pulse.frequency_hz = beta !== undefined && beta > 0 ? { dist: "lognormal", median: num("f-fg-hz"), beta } : num("f-fg-hz");
      spec.pulse = pulse;
    }
    return Object.assign(spec, {
      formulation: $select("f-formulation").value, im: "pga_g",
      stripes: { from: num("f-fg-from"), to: num("f-fg-to"), steps: num("f-fg-steps") },
      samples: num("f-fg-samples"), seed: num("f-fg-seed")
    });
  },

  fieldFor(p) {
    /** @type {Record<string, string>} */
    const fg = {
      "/block/alpha": "f-fg-alpha", "/block": fgBlockBy() === "params" ? "f-fg-alpha" : "f-fg-b", "/block/p": "f-fg-p",
      "/block/b": "f-fg-b", "/block/h": "f-fg-h", "/block/b/sd": "f-fg-b-sd", "/block/h/sd": "f-fg-h-sd",
      "/pulse/type": "f-type", "/pulse/n": "f-n", "/pulse/gamma": "f-gamma", "/pulse/nu": "f-nu",
      "/pulse/frequency_hz": "f-fg-hz", "/pulse": "f-fg-hz", "/formulation": "f-formulation",
      "/stripes/from": "f-fg-from", "/stripes/to": "f-fg-to", "/stripes/steps": "f-fg-steps", "/stripes": "f-fg-from",
      "/samples": "f-fg-samples", "/seed": "f-fg-seed",
      "/block/alpha/sd": "f-fg-alpha-sd", "/pulse/frequency_hz/beta": "f-fg-hz-beta"
    };
    const id = fg[p] || fg[p.replace(/\/(mean|sd|min|max|median|beta|dist)$/, "")];
    return id ? $(id) : null;
  },

  outcome(r) {
    if (!Array.isArray(r.stripes)) return ["", ""];
    const im = IM_NAMES[r.im] || { name: r.im, unit: "" };
    const fit = r.lognormal ? `lognormal fit: median θ = ${fmt(r.lognormal.median)} ${im.unit} ${im.name}, β = ${fmt(r.lognormal.beta)}` : "no lognormal fit";
    return [`${plural(r.stripes.length, "stripe", "stripes")} of ${r.stripes[0].n} simulations; ${fit}${r.monotone ? "" : " (the empirical curve falls in places)"}.`, ""];
  },

  summary(_job, r, add) {
    if (Array.isArray(r.stripes) && r.stripes.length) {
      const im = IM_NAMES[r.im] || { name: r.im, unit: "" };
      /** @param {number} x */
      const at = (x) => `${im.name} ${fmt(x)} ${im.unit}`;
      const s = r.stripes;
      add(`Stripes (${im.name}, ${im.unit})`, `${s.length}: ${range(s[0].im, s[s.length - 1].im)}, ${s[0].n} simulations each`);
      // Under a vertical motion a stripe whose every sample lifted off has no P (null).
      const decided = s.filter((x) => x.p !== null && x.p !== undefined);
      const top = decided.length ? decided.reduce((a, x) => (/** @type {number} */ (x.p) > /** @type {number} */ (a.p) ? x : a)) : null;
      if (top) add("Highest P(topple)", `${fmt(top.p, 3)} [${fmt(top.interval_95[0], 2)}, ${fmt(top.interval_95[1], 2)}] at ${at(top.im)}`);
      const last = s[s.length - 1];
      if (last !== top) {
        add(`P(topple) at ${at(last.im)}`, last.p === null ? "none: every sample lifted off" : `${fmt(last.p, 3)} [${fmt(last.interval_95[0], 2)}, ${fmt(last.interval_95[1], 2)}]`);
      }
      const lifted = s.filter((x) => (x.lift_off || 0) > 0);
      if (lifted.length) {
        const total = lifted.reduce((a, x) => a + (x.lift_off ?? 0), 0);
        add("Lift-off (no verdict)", `${total} samples, from ${at(lifted[0].im)} on: the ground falls away faster than g; each P is over the samples decided`);
      }
      if (r.lognormal) {
        const f = r.lognormal;
        add(`Fitted median θ (${im.name}, ${im.unit})`, `${fmt(f.median)} [${fmt(f.median_interval_95[0], 3)}, ${fmt(f.median_interval_95[1], 3)}]`);
        add("Fitted dispersion β", `${fmt(f.beta)} [${fmt(f.beta_interval_95[0], 3)}, ${fmt(f.beta_interval_95[1], 3)}]`);
      }
      if (!r.monotone && (r.falls_at || []).length) add("Empirical P falls at", (r.falls_at || []).map((x) => at(x)).join(", "));
    }
    // The floor.
    contactCondition(r, add);
  }
};
