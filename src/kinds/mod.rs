//! The job kinds, each a folder: its spec and validation, result, run,
//! example and `impl Kind` ([`crate::kinds::kind::Kind`]), registered in one
//! line of [`registry`], from which the job enum [`Job`], the kind enum
//! [`JobKind`], every dispatch over kinds and the API description's unions
//! are generated. What kinds share (spec parts, names, warnings, costs)
//! lives below them, in [`crate::jobs`].

pub mod forensic;
pub mod fragility;
pub mod friction_spectrum;
pub mod key;
pub mod kind;
pub mod limits;
pub mod record_spectrum;
pub mod registry;
#[cfg(test)]
mod roundtrip;
pub mod spectrum;
pub mod survival;
pub mod time_history;

use serde_json::Value;

use crate::jobs::{JobError, SpecError, spec};
use crate::spectrum::Control;

pub use registry::{Job, JobKind, JobResult, JobSpec, KINDS, NormalizedSpec, ResultError};

impl Job {
    /// Parses and validates a job spec from JSON text.
    pub fn parse(text: &str) -> Result<Job, SpecError> {
        let value = spec::parse_json(text)?;
        Job::from_value(&value)
    }

    /// Validates a job spec given as a JSON value: a whole job, as users
    /// submit it (a task's `part` is refused).
    pub fn from_value(value: &serde_json::Value) -> Result<Job, SpecError> {
        let job = Job::from_task(value)?;
        if job.is_part() {
            return Err(SpecError::at(
                "/part",
                "unknown field `part`: the service sets a task's part when it splits a job",
            ));
        }
        Ok(job)
    }

    /// Validates a task's spec as the service stored it ([`Job::split`]):
    /// a job, or a part of one.
    pub fn from_task(value: &serde_json::Value) -> Result<Job, SpecError> {
        let obj = value
            .as_object()
            .ok_or_else(|| SpecError::at("", "a job spec is a JSON object"))?;
        // Serde would also read these from arrays, by position.
        for field in ["block", "pulse", "solver", "outputs", "ground_motion"] {
            if let Some(v) = obj.get(field)
                && !(v.is_object() || v.is_null())
            {
                return Err(SpecError::at(format!("/{field}"), "must be a JSON object"));
            }
        }
        let kind = obj
            .get("kind")
            .ok_or_else(|| {
                SpecError::at(
                    "/kind",
                    format!("missing field: one of {}", KINDS.join(", ")),
                )
            })?
            .as_str()
            .ok_or_else(|| SpecError::at("/kind", "must be a string"))?;
        let kind = JobKind::from_name(kind).ok_or_else(|| {
            SpecError::at(
                "/kind",
                format!(
                    "unknown kind {kind:?}: expected one of {}",
                    KINDS.join(", ")
                ),
            )
        })?;
        Job::of_kind(kind, value)
    }

    /// Runs the job under `control` (progress, cancellation) and returns its
    /// result document: the kind's document, its input warnings (a task's
    /// part carries none: the assembled result does) and the engine.
    pub fn run(&self, control: &Control) -> Result<serde_json::Value, JobError> {
        self.run_document(control)
    }

    /// The job's result from its tasks' results (in task order): one task's
    /// document is the result; several (or a part's) are assembled by the
    /// kind ([`crate::kinds::kind::Kind::assemble`]), then given the job's
    /// warnings and the engine.
    pub fn assemble(&self, mut parts: Vec<Value>) -> Result<Value, JobError> {
        if parts.len() == 1 && parts[0].get("part").is_none() {
            return Ok(parts.pop().unwrap_or(Value::Null));
        }
        self.assemble_documents(parts)
    }
}
