// @ts-check
// An overturning spectrum: the lowest overturning amplitude of one block at
// each pulse frequency ω_p/p.

import { $, num } from "../dom.js";
import { finite, fmt, plural, range } from "../format.js";
import { blockCondition, blockKindFieldFor, blockKindSpec, contactCondition, pulseOfForm } from "./common.js";

/** @typedef {import('topple-api').components['schemas']['SpectrumResult']} SpectrumResult */

/** @type {import('./index.js').KindPage<SpectrumResult>} */
export default {
  title: "overturning spectrum",
  floorNote: "Each amplitude is a Coulomb history (several times the work of pure rocking). The pure-rocking spectrum is computed beside it, and the figure draws both side by side.",
  floorAlpha: (bp) => bp ? bp.alpha : undefined,
  // On a floor, pure rocking's spectrum is computed beside.
  onFloor(spec) { spec.no_sliding_beside = true; },

  spec() {
    const spec = blockKindSpec("spectrum", { pulse: pulseOfForm() });
    spec.omega_ratio = { from: num("f-sp-from"), to: num("f-sp-to"), steps: num("f-sp-steps") };
    spec.a_max_alpha_g = num("f-sp-amax");
    if (num("f-sp-tol") !== undefined) spec.tolerance = num("f-sp-tol");
    return spec;
  },

  fieldFor(p) {
    if (p.startsWith("/omega_ratio")) {
      return $(p.endsWith("/to") ? "f-sp-to" : p.endsWith("/steps") ? "f-sp-steps" : "f-sp-from");
    }
    return blockKindFieldFor(p);
  },

  outcome(r) {
    if (!Array.isArray(r.spectrum)) return ["", ""];
    const mins = finite(r.spectrum.map((s) => s.min_overturn_alpha_g));
    if (!mins.length) return ["No frequency overturns the block below a_max.", "stood"];
    const lowest = /** @type {SpectrumResult['spectrum'][number]} */ (r.spectrum.reduce(
      /** @param {SpectrumResult['spectrum'][number] | null} a */
      (a, s) => (Number.isFinite(s.min_overturn_alpha_g) && (!a || /** @type {number} */ (s.min_overturn_alpha_g) < /** @type {number} */ (a.min_overturn_alpha_g)) ? s : a), null));
    const where = lowest.min_overturn_in === "mixed" ? ", inside a mixed zone" : "";
    const sure = Number.isFinite(lowest.min_certain_overturn_alpha_g) && lowest.min_overturn_in === "mixed"
      ? ` Certain from ${fmt(lowest.min_certain_overturn_alpha_g)} αg there.` : "";
    return [`Lowest overturning amplitude ${fmt(lowest.min_overturn_alpha_g)} αg (${fmt(lowest.min_overturn_g)} g), at ω_p/p = ${fmt(lowest.omega_ratio)}, mode ${lowest.min_overturn_mode ?? "–"}${where}.${sure}`, ""];
  },

  summary(_job, r, add) {
    if (!Array.isArray(r.spectrum)) return;
    const s = r.spectrum;
    const mins = finite(s.map((x) => x.min_overturn_alpha_g));
    add("Frequencies ω_p/p", `${s.length}: ${range(s[0]?.omega_ratio, s[s.length - 1]?.omega_ratio)}`);
    if (mins.length) add("Min overturning a_p, over the frequencies (αg)", range(Math.min(...mins), Math.max(...mins)));
    const mode2 = s.filter((x) => x.min_overturn_mode === 2).length;
    if (mins.length) add("Minimum by mode 2", `${mode2} of ${mins.length} frequencies`);
    add("Safe regions above min.", `${s.filter((x) => (x.safe_intervals || []).length > 0).length} frequencies`);
    const never = s.length - mins.length;
    const aMax = r.spec && r.spec.a_max_alpha_g;
    add(`Never overturn up to ${aMax ? fmt(aMax) + " αg" : "a_max"}`, plural(never, "frequency", "frequencies"));
    // Where the block leaves the floor a line stops: nothing is claimed above.
    const lifts = finite(s.map((x) => x.lift_off_above_alpha_g));
    if (lifts.length) add("Leaves the floor (the line stops there)", `at ${lifts.length} of ${plural(s.length, "frequency", "frequencies")}, from ${fmt(Math.min(...lifts))} αg`);
    blockCondition(r, add);
    contactCondition(r, add);
  }
};
