// @ts-check
// The kinds of job, each with its part of the page: its name in words, what
// of the form it shows, the spec it sends, the field of a pointer into that
// spec, and the outcome and summary of its result.

import forensic from "./forensic.js";
import fragility from "./fragility.js";
import friction_spectrum from "./friction_spectrum.js";
import record_spectrum from "./record_spectrum.js";
import spectrum from "./spectrum.js";
import survival from "./survival.js";
import time_history from "./time_history.js";

/** @typedef {import('topple-api').components['schemas']} S */
/** @typedef {S['JobKind']} KindName */
/** @typedef {import('../form.js').Block} Block */
/** @typedef {import('./common.js').Add} Add */

/**
 * A kind's part of the page; `R` is its result.
 * @template R
 * @typedef {object} KindPage
 * @property {string} title the kind in words ("time history")
 * @property {() => Record<string, unknown>} spec the job spec the form describes, before the floor and a vertical ratio
 * @property {(pointer: string) => HTMLElement | null} fieldFor the field of a JSON pointer into that spec
 * @property {(r: R) => [string, string]} outcome the result in a sentence, and "overturned", "stood" or "" for its colour
 * @property {(job: S['JobView'], r: R, add: Add) => void} summary the details beside the outcome
 * @property {(onRecord: boolean) => void} [layout] what of the form the kind shows of its own
 * @property {() => void} [init] sets its fields up, once
 * @property {() => "one" | "suite" | ""} [recordUse] what it needs of the records: one, a suite, or none
 * @property {() => boolean} [pulseAxes] whether the pulse's frequency (and amplitude) fields are in use
 * @property {string} [pulseLegend] the pulse fieldset's legend, when not "Pulse"
 * @property {string} [floorNote] what a Coulomb floor means for it
 * @property {(bp: Block | null) => number | undefined} [floorAlpha] the slenderness whose first move the floor's hint says
 * @property {(spec: Record<string, unknown>) => void} [onFloor] what it adds to its spec on a Coulomb floor
 */

/**
 * Every kind's page, by kind: the type check asks for one for each kind of
 * the API description.
 * @type {{ [K in KindName]: KindPage<Extract<S['JobResult'], { kind: K }>> }}
 */
export const KIND_PAGES = {
  time_history, spectrum, friction_spectrum, forensic, record_spectrum, fragility, survival
};
