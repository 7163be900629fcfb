//! Why a spec is refused ([`SpecError`]) and why a valid job did not produce
//! a result ([`JobError`]).

use crate::dynamics::SimError;
use crate::spectrum::scan::ScanError;

/// What is wrong with a refused spec, as far as its sender must know: the
/// HTTP layer answers each kind with its own status.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SpecErrorKind {
    /// The document is not JSON at all.
    Syntax,
    /// JSON, but not a spec that can run: a field missing, of the wrong type
    /// or out of its range, a record or a job named wrongly.
    Invalid,
}

/// A spec that cannot be run, with the field at fault.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("{pointer}: {message}")]
pub struct SpecError {
    /// What kind of fault it is.
    pub kind: SpecErrorKind,
    /// JSON pointer to the offending field ("" for the document itself).
    pub pointer: String,
    /// What is wrong with it.
    pub message: String,
}

impl SpecError {
    /// A field at `pointer` that is not valid ([`SpecErrorKind::Invalid`]).
    pub fn at(pointer: impl Into<String>, message: impl Into<String>) -> Self {
        SpecError {
            kind: SpecErrorKind::Invalid,
            pointer: pointer.into(),
            message: message.into(),
        }
    }

    /// A document that is not JSON ([`SpecErrorKind::Syntax`]).
    pub fn syntax(message: impl Into<String>) -> Self {
        SpecError {
            kind: SpecErrorKind::Syntax,
            pointer: String::new(),
            message: message.into(),
        }
    }
}

/// Why a valid job did not produce a result. Its text is the `error` a
/// failed job shows.
#[derive(Debug, thiserror::Error)]
pub enum JobError {
    /// The engine refused.
    #[error(transparent)]
    Simulation(#[from] SimError),
    /// The engine refused at one point of a spectrum: the amplitude
    /// a_p/(αg) of its ground motion.
    #[error("at a_p = {level} αg: {source}")]
    AtLevel {
        /// Amplitude, a_p/(αg).
        level: f64,
        /// What the engine said.
        source: SimError,
    },
    /// A task that does not fit its job (a part outside it, or parts that
    /// do not make it up).
    #[error("{0}")]
    Task(String),
    /// A result that could not be serialised.
    #[error("{0}")]
    Serialise(#[source] serde_json::Error),
    /// The engine refused one sample of a Monte Carlo job.
    #[error("stripe {stripe} ({level}), sample {sample}: {source}")]
    AtSample {
        /// Index of the stripe.
        stripe: usize,
        /// Its intensity, with its measure ("0.4 pga_g").
        level: String,
        /// Index of the sample in the stripe.
        sample: usize,
        /// What was refused.
        source: Box<dyn std::error::Error + Send + Sync>,
    },
    /// The job was canceled.
    #[error("canceled")]
    Canceled,
}

impl From<ScanError> for JobError {
    fn from(e: ScanError) -> Self {
        match e {
            ScanError::Canceled(_) => JobError::Canceled,
            ScanError::Simulation(s) => JobError::Simulation(s),
            ScanError::At { level, source } => JobError::AtLevel { level, source },
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A failed job shows the engine's refusal at a spectrum's point as it
    /// always has.
    #[test]
    fn a_refusal_at_a_level_reads_as_the_scan_said_it() {
        let scan = ScanError::At {
            level: 2.5,
            source: SimError::ExactNeedsLinear,
        };
        let text = scan.to_string();
        assert_eq!(JobError::from(scan).to_string(), text);
    }

    #[test]
    fn syntax_errors_are_of_the_document() {
        let e = SpecError::syntax("not valid JSON: EOF");
        assert_eq!(e.kind, SpecErrorKind::Syntax);
        assert_eq!(e.pointer, "");
        assert_eq!(SpecError::at("/a", "x").kind, SpecErrorKind::Invalid);
    }
}
