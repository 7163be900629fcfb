//! What a job kind is: the [`Kind`] trait. A kind is one module of `jobs`
//! (its spec, validated job and result types, and its `impl Kind`) plus one
//! line of the registry ([`super::registry`]), from which the job enum, the
//! kind list, every dispatch, the `?kind=` enum and the API description's
//! unions are generated. Its table (`table`) and figure (`plot`) are chosen
//! by an exhaustive match on [`super::JobKind`], so the compiler asks for
//! both when a kind is added. `docs/adding-a-kind.md` walks through it.

use std::fmt::Debug;

use serde::Serialize;
use serde::de::DeserializeOwned;
use serde_json::Value;
use utoipa::ToSchema;

use super::error::{JobError, SpecError};
use super::warning::WarningDoc;
use crate::spectrum::Control;

/// Size of a job: its grid, its estimated simulations and their CPU
/// seconds ([`super::cost`]), what the service's limits are checked against,
/// its estimate is made of and its tasks are cut by.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Size {
    /// Series samples (time histories).
    pub series_points: usize,
    /// Grid points (spectra).
    pub grid_points: usize,
    /// Estimated simulations.
    pub work: f64,
    /// Estimated simulations × record samples (records only, else 0).
    pub record_work: f64,
    /// Estimated CPU seconds on the reference machine.
    pub cpu_s: f64,
    /// Simulations that can run at once (1: one simulation after another).
    pub lanes: f64,
}

impl Size {
    /// The size of a job of one simulation (and no series) costing `cpu_s`.
    pub fn one(cpu_s: f64) -> Size {
        Size {
            series_points: 0,
            grid_points: 1,
            work: 1.0,
            record_work: 0.0,
            cpu_s,
            lanes: 1.0,
        }
    }

    /// Expected wall seconds on `threads` compute threads at `rate` times
    /// the reference machine's CPU seconds.
    pub fn wall_s(&self, threads: usize, rate: f64) -> f64 {
        self.cpu_s * rate / self.lanes.clamp(1.0, threads.max(1) as f64)
    }
}

/// A job kind.
pub trait Kind: 'static {
    /// Its name in specs, results and `?kind=`: `"time_history"`.
    const NAME: &'static str;
    /// Its name for people: "Time history".
    const LABEL: &'static str;
    /// The spec as users write it (its schema is the API's input).
    type Spec: DeserializeOwned + ToSchema;
    /// The validated job; serialises to the canonical (normalised) spec.
    type Job: Clone + Debug + PartialEq + Serialize + ToSchema;
    /// The result document.
    type Result: Clone + Debug + PartialEq + Serialize + DeserializeOwned + ToSchema;

    /// Validates a spec of this kind (a JSON object whose `kind` is
    /// [`Kind::NAME`]).
    fn parse(value: &Value) -> Result<Self::Job, SpecError>;

    /// Computes the job under `control` (progress, cancellation): the result
    /// document before its warnings and engine are added, or — for a task
    /// of a job split into parts — the part's document.
    fn run(job: &Self::Job, control: &Control) -> Result<Value, JobError>;

    /// How big the job is.
    fn size(job: &Self::Job) -> Size;

    /// The field that sets the job's grid and work, named when a limit is
    /// exceeded.
    fn grid_field(job: &Self::Job) -> &'static str;

    /// Warnings about the job's inputs (block sizes, records), added to its
    /// result.
    fn warnings(_job: &Self::Job) -> Vec<WarningDoc> {
        Vec::new()
    }

    /// The tasks of the job (`size` is [`Kind::size`]); one by default.
    fn split(job: &Self::Job, _size: &Size) -> Vec<Self::Job> {
        vec![job.clone()]
    }

    /// A task's stored payload when it is not the task's own spec (a part
    /// of a job whose spec is stored once); `None` by default.
    fn task_payload(_job: &Self::Job) -> Option<String> {
        None
    }

    /// The task `payload` names as a part of `whole`; `None` when this kind
    /// has no parts.
    fn part_of(_whole: &Self::Job, _payload: &Value) -> Option<Result<Self::Job, JobError>> {
        None
    }

    /// Whether the job is a task's part (its result is a part, assembled by
    /// the service; it carries no warnings).
    fn is_part(_job: &Self::Job) -> bool {
        false
    }

    /// The job's result document from its tasks' documents (several, or a
    /// part's; in task order), before warnings and engine are added. Only
    /// kinds that split have several tasks.
    fn assemble(_job: &Self::Job, parts: Vec<Value>) -> Result<Value, JobError> {
        Err(JobError::Task(format!(
            "a {} job is computed in one task, not {}",
            Self::NAME,
            parts.len()
        )))
    }
}

/// `result` as a document, or the error that it cannot be one.
pub fn document<T: Serialize>(result: &T) -> Result<Value, JobError> {
    serde_json::to_value(result).map_err(JobError::Serialise)
}

/// Runs a job of one simulation under `control`: counts it, and refuses
/// when canceled before it starts.
pub fn run_one<T: Serialize>(
    control: &Control,
    run: impl FnOnce() -> Result<T, JobError>,
) -> Result<Value, JobError> {
    if control.canceled() {
        return Err(JobError::Canceled);
    }
    control.add_total(1);
    let result = run()?;
    control.add_done(1);
    document(&result)
}
