// The types of /static/constants.js, which the service renders from its Rust
// constants (src/api/page.rs): for the type check only. A unit test of
// page.rs keeps these lines as the module is rendered.

export const G: number;
export const R_MIN_M: number;
export const R_MAX_M: number;
export const LARGE_SLIDE_M: number;
export const MAX_MU: number;
export const MAX_OBSERVATIONS: number;
export const MAX_LIST_LIMIT: number;
export const FLOOR_KINDS: readonly string[];
export const VERTICAL_RATIO_KINDS: readonly string[];
