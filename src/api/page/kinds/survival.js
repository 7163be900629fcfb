// @ts-check
// A survival job: how likely a rock of known fragility still stands after
// years under a hazard curve.

import { $, $select, $textarea, num } from "../dom.js";
import { fmt, samplesOf } from "../format.js";

/** @typedef {import('topple-api').components['schemas']['SurvivalResult']} SurvivalResult */

/** @type {import('./index.js').KindPage<SurvivalResult>} */
export default {
  title: "survival",

  // A survival job has no motion to integrate.
  layout() { $("fs-pulse").hidden = true; },

  init() {
    // The example hazard: H(x) = 1e-4 (x/0.4 g)^−2.5 at a few intensities.
    $textarea("f-su-points").value = [0.05, 0.1, 0.2, 0.4, 0.8, 1.6].map((x) => `${x} ${Number((1e-4 * Math.pow(x / 0.4, -2.5)).toPrecision(6))}`).join("\n");
  },

  spec() {
    const points = $textarea("f-su-points").value.split(/\n/).map((l) => samplesOf(l)).filter((p) => p.length);
    const im = $select("f-su-im").value;
    /** @type {Record<string, number | undefined>} */
    const fragility = { beta: num("f-su-beta") };
    fragility[im === "pga_g" ? "median_g" : "median"] = num("f-su-median");
    return { kind: "survival", hazard: { im, points }, fragility, age_years: samplesOf($textarea("f-su-ages").value) };
  },

  fieldFor(p) {
    if (p.startsWith("/hazard/points")) return $("f-su-points");
    if (p === "/hazard/im") return $("f-su-im");
    if (/^\/fragility\/(median|median_g)$/.test(p) || p === "/fragility") return $("f-su-median");
    if (p === "/fragility/beta") return $("f-su-beta");
    if (p.startsWith("/age_years")) return $("f-su-ages");
    return null;
  },

  outcome(r) {
    if (!Array.isArray(r.rocks)) return ["", ""];
    if (r.joint) return [`All ${r.rocks.length} rocks standing, each at its age: P = ${fmt(r.joint.survival_probability)}.`, ""];
    const rock = r.rocks[0];
    const ages = (rock.ages || []).map((a) => `${fmt(a.survival_probability, 3)} at ${fmt(a.age_years)} yr`);
    if (rock.age_distribution) ages.push(`${fmt(rock.age_distribution.survival_probability, 3)} over the uncertain age (median ${fmt(rock.age_distribution.median_age_years)} yr)`);
    return [`Topples ${fmt(rock.annual_toppling_rate)} times a year; still standing with P = ${ages.join(", ")}.`, ""];
  },

  summary(_job, r, add) {
    if (!Array.isArray(r.rocks)) return;
    const several = r.rocks.length > 1;
    for (const rock of r.rocks) {
      const who = several ? `${rock.name}: ` : "";
      add(`${who}λ_t (1/yr)`, `${fmt(rock.annual_toppling_rate)} (1 in ${fmt(rock.mean_years_between_topplings)} yr)`);
      for (const a of rock.ages || []) {
        if (a.rate_scale_at_5_percent != null) add(`${who}Hazard × for P = 5 % at ${fmt(a.age_years)} yr`, fmt(a.rate_scale_at_5_percent));
      }
      const d = rock.age_distribution;
      if (d && d.rate_scale_at_5_percent != null) {
        add(`${who}Hazard × for P = 5 % at the uncertain age (median ${fmt(d.median_age_years)} yr)`, fmt(d.rate_scale_at_5_percent));
      }
      if (Number.isFinite(rock.extrapolated_share)) add(`${who}Share of λ_t beyond the curve's ends`, `${fmt(100 * (rock.extrapolated_share ?? NaN), 3)} %`);
    }
    if (r.joint && r.joint.rate_scale_at_5_percent != null) {
      add("Hazard × for P = 5 % of all standing, each at its age", fmt(r.joint.rate_scale_at_5_percent));
    }
  }
};
