//! Jobs: the spec JSON users send (to `topple run` or the service), its
//! validation into domain types, and the result documents.

pub mod numerics;
pub mod spec;
pub mod time_history;

pub use spec::SpecError;

use serde::Serialize;

/// A validated job of any kind.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(untagged)]
pub enum Job {
    /// One time history.
    TimeHistory(time_history::TimeHistoryJob),
}

/// Why a valid job failed to compute.
#[derive(Debug, thiserror::Error)]
pub enum JobError {
    /// The engine refused.
    #[error(transparent)]
    Simulation(#[from] crate::dynamics::SimError),
}

impl Job {
    /// Parses and validates a job spec from JSON text.
    pub fn parse(text: &str) -> Result<Job, SpecError> {
        let text = spec::mark_non_finite(text);
        let value: serde_json::Value = serde_json::from_str(&text)
            .map_err(|e| SpecError::at("", format!("not valid JSON: {e}")))?;
        Job::from_value(&value)
    }

    /// Validates a job spec given as a JSON value.
    pub fn from_value(value: &serde_json::Value) -> Result<Job, SpecError> {
        let obj = value
            .as_object()
            .ok_or_else(|| SpecError::at("", "a job spec is a JSON object"))?;
        let kind = obj
            .get("kind")
            .ok_or_else(|| SpecError::at("/kind", "missing field: time_history"))?
            .as_str()
            .ok_or_else(|| SpecError::at("/kind", "must be a string"))?;
        match kind {
            "time_history" => {
                let spec: time_history::TimeHistorySpec = spec::from_value(value, "")?;
                Ok(Job::TimeHistory(spec.validate()?))
            }
            other => Err(SpecError::at(
                "/kind",
                format!("unknown kind {other:?}: expected time_history"),
            )),
        }
    }

    /// The kind name.
    pub fn kind(&self) -> &'static str {
        match self {
            Job::TimeHistory(_) => "time_history",
        }
    }

    /// Runs the job and returns its result document.
    pub fn run(&self) -> Result<serde_json::Value, JobError> {
        match self {
            Job::TimeHistory(job) => {
                let result = job.run()?;
                Ok(serde_json::to_value(result).unwrap_or(serde_json::Value::Null))
            }
        }
    }
}
