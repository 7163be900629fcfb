//! Overturning and friction-demand spectra: many simulations in parallel
//! (rayon), with a progress counter and a cancellation flag.

pub mod closed_form;
pub mod control;
pub mod friction;
pub mod overturning;
pub mod pilot;
pub mod record;
pub mod scan;
pub mod slide;
pub mod verify;

pub use control::{Canceled, Control};
pub use overturning::{Spectrum, SpectrumRequest, overturning_spectrum};
