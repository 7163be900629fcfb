// @ts-check
// What several kinds share: the pulse of the form, the block of time
// histories and spectra (and the fields of their pointers), and the
// summary's lines on the block and the floor a result ran on.

import { $, $select, num } from "../dom.js";
import { fmt } from "../format.js";
import { blockBy, onCoulomb } from "../form.js";

/** @typedef {import('topple-api').components['schemas']} S */

/**
 * Adds an item to a summary: its term, its value (text, or text and
 * links), whether it takes a whole row.
 * @typedef {(term: string, value: string | (string | Node)[], wide?: string) => void} Add
 */

/**
 * The pulse of the form: its type and the parameters of that type.
 * @returns {Record<string, unknown> & { type: string }}
 */
export function pulseOfForm() {
  const type = $select("f-type").value;
  /** @type {Record<string, unknown> & { type: string }} */
  const pulse = type === "ricker_antisymmetric" ? { type: "ricker", symmetric: false } : { type };
  if (pulse.type === "cn") pulse.n = num("f-n");
  if (pulse.type === "mavroeidis_papageorgiou") {
    pulse.gamma = num("f-gamma");
    if (num("f-nu") !== undefined) pulse.nu = num("f-nu");
  }
  return pulse;
}

/**
 * The start of the spec of a time history or a spectrum of kind `k`: its
 * block (on a Coulomb floor without its own μ, which the floor's replaces),
 * what shakes it (`{ pulse }`, or `{ ground_motion }`), the formulation.
 * @param {string} k
 * @param {Record<string, unknown>} motion
 * @returns {Record<string, unknown>}
 */
export function blockKindSpec(k, motion) {
  /** @type {Record<string, number | undefined>} */
  const block = {};
  if (blockBy() === "params") { block.alpha = num("f-alpha"); block.p = num("f-p"); }
  else { block.b = num("f-b"); block.h = num("f-h"); }
  if (num("f-eta") !== undefined) block.eta = num("f-eta");
  // On a Coulomb floor the floor's μ is sent (in `contact`), not the block's.
  const coulomb = onCoulomb(k);
  if (num("f-mu") !== undefined && !coulomb) block.mu = num("f-mu");
  /** @type {Record<string, unknown>} */
  const spec = Object.assign({ kind: k, block }, motion);
  spec.formulation = $select("f-formulation").value;
  return spec;
}

/**
 * The field of a pointer into the spec of a time history or a spectrum:
 * the block, the pulse, the formulation, the outputs, the floor.
 * @param {string} p
 * @returns {HTMLElement | null}
 */
export function blockKindFieldFor(p) {
  /** @type {Record<string, string>} */
  const direct = {
    "/block/alpha": "f-alpha", "/block/slenderness": "f-alpha",
    "/block/p": "f-p", "/block/frequency_parameter": "f-p",
    "/block/b": "f-b", "/block/h": "f-h", "/block/eta": "f-eta", "/block/mu": "f-mu",
    "/block": blockBy() === "params" ? "f-alpha" : "f-b",
    "/pulse/type": "f-type", "/pulse/n": "f-n", "/pulse/gamma": "f-gamma", "/pulse/nu": "f-nu",
    "/formulation": "f-formulation",
    "/outputs/series": "f-series", "/outputs/duration": "f-duration", "/outputs": "f-series",
    "/vertical": "f-vert", "/vertical/ratio": "f-vert-ratio",
    "/contact": "f-c-mu", "/contact/model": "f-c-mu", "/contact/mu": "f-c-mu", "/contact/mu_kinetic": "f-c-muk",
    "/a_max_alpha_g": "f-sp-amax", "/tolerance": "f-sp-tol"
  };
  if (direct[p]) return $(direct[p]);
  if (/^\/pulse\/(omega_p|frequency_hz|omega_ratio)/.test(p)) return $("f-freq");
  if (/^\/pulse\/(a_p|a_p_g|a_p_alpha_g)/.test(p)) return $("f-amp");
  if (p === "/pulse") return $("f-type");
  return null;
}

/**
 * The floor a result ran on, when it was Coulomb friction.
 * @param {{ spec?: { contact?: S['ContactNorm'] | null } | null }} r
 * @param {Add} add
 */
export function contactCondition(r, add) {
  const c = r.spec && r.spec.contact;
  if (!c || c.model !== "coulomb") return;
  const muk = c.mu_kinetic;
  const kinetic = typeof muk === "number" && Number.isFinite(muk) && muk < c.mu ? `, μ_k = ${fmt(muk)}` : "";
  add("Floor", `Coulomb friction, μ = ${fmt(c.mu)}${kinetic}`);
}

/**
 * The block as it was run (its restitution the one given or the default).
 * @param {{ spec?: { block?: Partial<S['BlockNorm']> | null } | null }} r
 * @param {Add} add
 */
export function blockCondition(r, add) {
  const b = (r.spec && r.spec.block) || {};
  if (Number.isFinite(b.alpha) && Number.isFinite(b.p)) {
    add("Block", `α = ${fmt(b.alpha)} rad, p = ${fmt(b.p)} rad/s, η = ${fmt(b.eta)}${Number.isFinite(b.mu) ? `, μ = ${fmt(b.mu)}` : ""}`);
  }
}

/**
 * Intervals [lo, hi]: how many, the lowest and highest ends, their total length.
 * @param {number[][] | null | undefined} list
 */
export function intervalStats(list) {
  const xs = (list || []).filter((iv) => Array.isArray(iv) && Number.isFinite(iv[0]) && Number.isFinite(iv[1]));
  return {
    count: xs.length,
    lo: xs.length ? Math.min(...xs.map((iv) => iv[0])) : NaN,
    hi: xs.length ? Math.max(...xs.map((iv) => iv[1])) : NaN,
    measure: xs.reduce((sum, iv) => sum + (iv[1] - iv[0]), 0)
  };
}

/** The intensity measures: their names and units. */
export const IM_NAMES = /** @type {Record<string, { name: string, unit: string }>} */ ({
  pga_g: { name: "PGA", unit: "g" }, pgv_m_s: { name: "PGV", unit: "m/s" }
});
