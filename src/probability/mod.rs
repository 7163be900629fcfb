//! Probabilistic forensics: the normal law, distributions of uncertain
//! inputs, hazard curves and the survival of a rock under a hazard model.
//! Pure functions, no I/O.

pub mod distribution;
pub mod fragility;
pub mod hazard;
pub mod normal;
pub mod survival;
