// @ts-check
// A friction-demand spectrum: the friction pure rocking needs of one block
// at each pulse amplitude, at one frequency.

import { $, $select, num } from "../dom.js";
import { fmt, plural, range } from "../format.js";
import { blockParams, omegaOf } from "../form.js";
import { blockCondition, blockKindFieldFor, blockKindSpec, pulseOfForm } from "./common.js";

/** @typedef {import('topple-api').components['schemas']['FrictionSpectrumResult']} FrictionSpectrumResult */

/** @type {import('./index.js').KindPage<FrictionSpectrumResult>} */
export default {
  title: "friction-demand spectrum",
  pulseAxes: () => true,

  spec() {
    const spec = blockKindSpec("friction_spectrum", { pulse: pulseOfForm() });
    // The friction spectrum takes ω_p/p: other units are converted.
    const unit = $select("f-freq-unit").value;
    let ratio = num("f-freq");
    const bp = blockParams();
    if (unit !== "omega_ratio" && ratio !== undefined && bp) ratio = omegaOf(ratio, unit, bp) / bp.p;
    spec.omega_ratio = ratio;
    spec.a_alpha_g = { from: num("f-fr-from"), to: num("f-fr-to"), steps: num("f-fr-steps") };
    return spec;
  },

  fieldFor(p) {
    if (p.startsWith("/omega_ratio")) return $("f-freq");
    if (p.startsWith("/a_alpha_g")) {
      return $(p.endsWith("/to") ? "f-fr-to" : p.endsWith("/steps") ? "f-fr-steps" : "f-fr-from");
    }
    return blockKindFieldFor(p);
  },

  outcome(r) {
    if (!Array.isArray(r.points)) return ["", ""];
    const peaks = r.points.filter((q) => Number.isFinite(q.peak_friction_demand));
    if (!peaks.length) return ["No amplitude has a bounded friction demand.", ""];
    const top = peaks.reduce((a, q) => (/** @type {number} */ (q.peak_friction_demand) > /** @type {number} */ (a.peak_friction_demand) ? q : a));
    return [`Highest friction demand for pure rocking: μ = ${fmt(top.peak_friction_demand)}, at a_p = ${fmt(top.a_alpha_g)} αg (${fmt(top.a_p_g)} g).`, ""];
  },

  summary(_job, r, add) {
    if (!Array.isArray(r.points)) return;
    add("Pulse ω_p/p", fmt(r.omega_ratio));
    add("Pulse f_p (Hz)", fmt(r.frequency_hz));
    const amps = r.points.map((q) => q.a_alpha_g);
    add("Amplitudes (αg)", `${r.points.length}: ${range(amps[0], amps[amps.length - 1])}`);
    const lifts = r.points.filter((q) => q.lift_off).length;
    add(`Lift-off (μ unbounded) at ω_p/p = ${fmt(r.omega_ratio)}`, plural(lifts, "amplitude", "amplitudes"));
    add(`Overturned at ω_p/p = ${fmt(r.omega_ratio)}`, plural(r.points.filter((q) => q.overturned).length, "amplitude", "amplitudes"));
    blockCondition(r, add);
  }
};
