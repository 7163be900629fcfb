//! The engine through the library: the paper's figures and closed forms,
//! properties, extremes, spectra, records and the forensic query. One test
//! binary (each module was one before), so the library and its dependencies are
//! linked once.

mod chaotic;
mod contact_fuzz;
mod exact_vs_numerical;
mod extremes;
mod forensic;
mod forensic_record;
mod fragility;
mod fuzz;
mod ground_motion;
mod kinds;
mod paper;
mod properties;
mod pulses;
mod record_spectrum;
mod spectra;
mod survival;
#[path = "../common/synthetic.rs"]
mod synthetic;
mod tracking;
mod vertical;
