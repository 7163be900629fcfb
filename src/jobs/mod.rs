//! What every job kind is made of: the [`kind::Kind`] trait, spec parts
//! (block, pulse, ground motion, contact, vertical motion, distributions),
//! typed names, warnings, errors, cost estimates and the parts a job is
//! split into. The kinds themselves live in [`crate::kinds`], above this
//! module.

pub mod contact;
pub mod cost;
pub mod distribution;
pub mod engine;
pub mod error;
pub mod kind;
pub mod mixed;
pub mod names;
pub mod numerics;
pub mod plausible;
pub mod range;
pub mod scan_parts;
pub mod schema;
pub mod spec;
pub mod split;
pub mod vertical;
pub mod vertical_record;
pub mod warning;

pub use error::{JobError, SpecError};
