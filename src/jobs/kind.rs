//! What a job kind is: the [`Kind`] trait. A kind is one folder of
//! `src/kinds/` (its spec, validated job and result types, example and
//! `impl Kind`) plus one line of the registry (`crate::kinds::registry`),
//! from which the job enum, the kind list, every dispatch, the `?kind=` enum
//! and the API description's unions are generated. Its table (`api::csv`)
//! and figure (`plot`) are chosen by an exhaustive match on `JobKind`, so the
//! compiler asks for both when a kind is added. `docs/adding-a-kind.md`
//! walks through it.

use std::fmt::Debug;

use serde::Serialize;
use serde::de::DeserializeOwned;
use serde_json::Value;
use utoipa::ToSchema;

use super::error::{JobError, SpecError};
use super::names::EngineDoc;
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

/// A validated spec: what a kind's spec becomes once its every field is
/// checked and every default filled in.
pub trait Validate {
    /// The validated job.
    type Job;
    /// The job, or the first field at fault.
    fn validate(&self) -> Result<Self::Job, SpecError>;
}

/// What every result document ends with, typed: the warnings (the run's,
/// then the job's input warnings) and the engine that computed it.
pub trait Envelope {
    /// Appends the job's input warnings to the result's own.
    fn add_warnings(&mut self, found: Vec<WarningDoc>);
    /// Names the engine that computed the result.
    fn set_engine(&mut self, engine: EngineDoc);
}

/// Implements [`Envelope`] for result types whose `warnings` is a
/// `Vec<WarningDoc>` and `engine` an `Option<EngineDoc>`.
#[macro_export]
macro_rules! envelope {
    ($($result:ty),* $(,)?) => {
        $(
            impl $crate::jobs::kind::Envelope for $result {
                fn add_warnings(&mut self, found: Vec<$crate::jobs::warning::WarningDoc>) {
                    self.warnings.extend(found);
                }
                fn set_engine(&mut self, engine: $crate::jobs::names::EngineDoc) {
                    self.engine = Some(engine);
                }
            }
        )*
    };
}

/// The part of a kind that is never split: a task of it is the whole job.
#[derive(Clone, Debug, PartialEq, Serialize, serde::Deserialize)]
pub enum NoPart {}

/// What a task of a kind computes: the job's result, or (a task of a job
/// split into parts) its part, assembled by [`Kind::assemble`].
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(untagged, bound = "")]
pub enum Output<K: Kind + ?Sized> {
    /// The result of the whole job (or of a job of its own that the job was
    /// split into).
    Whole(K::Result),
    /// A part, read back and assembled once every task is done.
    Part(K::Part),
}

/// A job kind.
pub trait Kind: 'static {
    /// Its name in specs, results and `?kind=`: `"time_history"`.
    const NAME: &'static str;
    /// Its name for people: "Time history".
    const LABEL: &'static str;
    /// A spec of this kind, as the docs, tests and the page show it first.
    const EXAMPLE: &'static str;
    /// The spec as users write it (its schema is the API's input).
    type Spec: DeserializeOwned + ToSchema + Validate<Job = Self::Job>;
    /// The validated job; serialises to the canonical (normalised) spec.
    type Job: Clone + Debug + PartialEq + Serialize + DeserializeOwned + ToSchema;
    /// The result document.
    type Result: Clone + Debug + PartialEq + Serialize + DeserializeOwned + ToSchema + Envelope;
    /// What a task of a job split into parts computes ([`NoPart`] for a
    /// kind whose tasks are whole jobs).
    type Part: Debug + Serialize + DeserializeOwned;

    /// Validates a spec of this kind (a JSON object whose `kind` is
    /// [`Kind::NAME`]): read as [`Kind::Spec`], then validated.
    fn parse(value: &Value) -> Result<Self::Job, SpecError> {
        super::spec::from_value::<Self::Spec>(value, "")?.validate()
    }

    /// Computes the job under `control` (progress, cancellation): the result
    /// before its input warnings and engine are added, or — for a task of a
    /// job split into parts — the part.
    fn run(job: &Self::Job, control: &Control) -> Result<Output<Self>, JobError>;

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

    /// The job's result from its tasks' parts (several, or a part's; in
    /// task order), before warnings and engine are added. Only kinds that
    /// split have several tasks.
    fn assemble(_job: &Self::Job, parts: Vec<Self::Part>) -> Result<Self::Result, JobError> {
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
pub fn run_one<K: Kind + ?Sized>(
    control: &Control,
    run: impl FnOnce() -> Result<K::Result, JobError>,
) -> Result<Output<K>, JobError> {
    if control.canceled() {
        return Err(JobError::Canceled);
    }
    control.add_total(1);
    let result = run()?;
    control.add_done(1);
    Ok(Output::Whole(result))
}
