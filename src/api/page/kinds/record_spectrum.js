// @ts-check
// A record spectrum: the lowest scale of a record that overturns blocks of
// one slenderness, at each size R.

import { $, $select, num } from "../dom.js";
import { fmt, plural, range } from "../format.js";
import { groundMotionOf } from "../records.js";
import { contactCondition } from "./common.js";

/** @typedef {import('topple-api').components['schemas']} S */
/** @typedef {S['RecordSpectrumResult']} RecordSpectrumResult */
/** @typedef {RecordSpectrumResult['spectrum'][number]} Size */

/**
 * The size whose `key` is least, of those where it is a finite number.
 * @param {Size[]} sizes
 * @param {(s: Size) => number | null | undefined} key
 */
function least(sizes, key) {
  const with_ = sizes.filter((s) => Number.isFinite(key(s)));
  return with_.length ? with_.reduce((a, s) => (/** @type {number} */ (key(s)) < /** @type {number} */ (key(a)) ? s : a)) : null;
}

/** @type {import('./index.js').KindPage<RecordSpectrumResult>} */
export default {
  title: "record spectrum",
  floorNote: "Each scale (each sample) is a Coulomb history: several times the work of pure rocking.",
  floorAlpha: () => num("f-rs-alpha"),
  recordUse: () => "one",

  spec() {
    /** @type {Record<string, number | undefined>} */
    const block = { alpha: num("f-rs-alpha") };
    if (num("f-rs-eta") !== undefined) block.eta = num("f-rs-eta");
    return {
      kind: "record_spectrum",
      ground_motion: groundMotionOf(),
      block,
      R_m: { from: num("f-rs-from"), to: num("f-rs-to"), steps: num("f-rs-steps") },
      scale: { to: num("f-rs-sto") },
      formulation: $select("f-formulation").value
    };
  },

  fieldFor(p) {
    const rs = /** @type {Record<string, string>} */ ({
      "/block/alpha": "f-rs-alpha", "/block/eta": "f-rs-eta", "/block": "f-rs-alpha",
      "/R_m/from": "f-rs-from", "/R_m/to": "f-rs-to", "/R_m/steps": "f-rs-steps", "/R_m": "f-rs-from",
      "/scale/to": "f-rs-sto", "/scale": "f-rs-sto", "/formulation": "f-formulation"
    })[p];
    if (rs) return $(rs);
    return null;
  },

  outcome(r) {
    if (!Array.isArray(r.spectrum)) return ["", ""];
    const lowest = least(r.spectrum, (s) => s.min_overturn_scale);
    if (!lowest) return [`No block size overturns up to the scale ${fmt(r.spec && r.spec.scale.to)}.`, "stood"];
    // Where it lies (a certain band, or a mixed zone with its fraction),
    // and the lowest scale from which overturning is certain.
    const zone = lowest.min_overturn_zone;
    const where = lowest.min_overturn_in === "mixed" && zone
      ? `inside a mixed zone (${range(zone.from, zone.to)}, overturns at ${fmt(100 * zone.fraction, 2)} % of the scales probed)`
      : "in a certain band";
    const sure = least(r.spectrum, (s) => s.min_certain_overturn_scale);
    const sureText = sure ? ` Lowest certain overturning: scale ${fmt(sure.min_certain_overturn_scale)} (PGA ${fmt(sure.min_certain_overturn_pga_g)} g), for R = ${fmt(sure.R_m)} m.` : " No size overturns with certainty over a principal band.";
    return [`Lowest overturning found: scale ${fmt(lowest.min_overturn_scale)} (PGA ${fmt(lowest.min_overturn_pga_g)} g), for R = ${fmt(lowest.R_m)} m, mode ${lowest.min_overturn_mode ?? "–"}, ${where}.${sureText}`, ""];
  },

  summary(_job, r, add) {
    if (Array.isArray(r.spectrum)) {
      const s = r.spectrum;
      const rec = r.record || /** @type {Partial<S['RecordDoc']>} */ ({});
      add("Record", `${rec.samples} samples, dt = ${fmt(rec.dt_s)} s`);
      add("PGA, PGV, PGD", `${fmt(rec.pga_g)} g, ${fmt(rec.pgv_m_s)} m/s, ${fmt(rec.pgd_m)} m`);
      const sizes = s.map((x) => x.R_m);
      add("Block sizes R (m)", `${s.length}: ${range(Math.min(...sizes), Math.max(...sizes))}`);
      const never = s.filter((x) => !Number.isFinite(x.min_overturn_scale)).length;
      add(`Never overturn up to scale ${fmt(r.spec && r.spec.scale.to)}`, plural(never, "size", "sizes"));
      add("Safe regions above min.", `${s.filter((x) => (x.safe_intervals || []).length > 0).length} sizes`);
      const zones = s.flatMap((x) => x.mixed || []);
      add("Mixed zones", zones.length ? `${zones.length} over ${plural(s.filter((x) => (x.mixed || []).length).length, "size", "sizes")}, ${fmt(zones.reduce((a, z) => a + z.to - z.from, 0))} wide in all` : "none");
    }
    // The floor.
    contactCondition(r, add);
  }
};
