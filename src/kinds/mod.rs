//! The job kinds, each a folder: `spec.rs` (the spec as written, the
//! validated job and the validation), `result.rs`, `run.rs`, `table.rs`,
//! `figure.rs`, `example.json` and, in `mod.rs`, its `impl Kind`
//! ([`crate::kinds::kind::Kind`]), registered in one
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

pub use registry::{Job, JobKind, JobResult, JobSpec, KINDS, NormalizedSpec, ResultError, Task};

impl Job {
    /// Parses and validates a job spec from JSON text.
    pub fn parse(text: &str) -> Result<Job, SpecError> {
        let value = spec::parse_json(text)?;
        Job::from_value(&value)
    }

    /// Validates a job spec given as a JSON value, as users submit it: a
    /// part of a job is the service's, never a spec's (a task's part is a
    /// [`Task`]).
    pub fn from_value(value: &serde_json::Value) -> Result<Job, SpecError> {
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
        if obj.contains_key("part") && kind.has_parts() {
            return Err(SpecError::at(
                "/part",
                "unknown field `part`: the service sets a task's part when it splits a job",
            ));
        }
        Job::of_kind(kind, value)
    }

    /// Runs the job under `control` (progress, cancellation) and returns its
    /// result document: the kind's document, its input warnings and the
    /// engine.
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

impl Task {
    /// A task given as a job's spec with the part it computes (`"part"`,
    /// absent for the whole job): how a task is written by hand, and how
    /// the service stored a part before it named parts by their bounds
    /// alone ([`Task::payload`]).
    pub fn from_spec(value: &Value) -> Result<Task, SpecError> {
        let mut value = value.clone();
        let part = value.as_object_mut().and_then(|o| o.remove("part"));
        let job = Job::from_value(&value)?;
        match part {
            Some(part) => {
                Task::part(&job, &part).map_err(|e| SpecError::at("/part", e.to_string()))
            }
            None => Ok(Task::whole(job)),
        }
    }
}
