//! Why a spec is refused ([`SpecError`]) and why a valid job did not produce
//! a result ([`JobError`]).

use crate::spectrum::scan::ScanError;

/// A spec that cannot be run, with the field at fault.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("{pointer}: {message}")]
pub struct SpecError {
    /// JSON pointer to the offending field ("" for the document itself).
    pub pointer: String,
    /// What is wrong with it.
    pub message: String,
}

impl SpecError {
    /// An error at `pointer`.
    pub fn at(pointer: impl Into<String>, message: impl Into<String>) -> Self {
        SpecError {
            pointer: pointer.into(),
            message: message.into(),
        }
    }
}

/// Why a valid job did not produce a result.
#[derive(Debug, thiserror::Error)]
pub enum JobError {
    /// The engine refused.
    #[error(transparent)]
    Simulation(#[from] crate::dynamics::SimError),
    /// The engine refused at one point of a spectrum.
    #[error("{0}")]
    Point(String),
    /// The job was canceled.
    #[error("canceled")]
    Canceled,
}

impl From<ScanError> for JobError {
    fn from(e: ScanError) -> Self {
        match e {
            ScanError::Canceled(_) => JobError::Canceled,
            ScanError::Simulation(s) => JobError::Simulation(s),
            e @ ScanError::At { .. } => JobError::Point(e.to_string()),
        }
    }
}
