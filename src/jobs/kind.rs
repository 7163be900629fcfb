//! What every kind's `impl Kind` ([`crate::kinds::kind`]) is made of below
//! the kinds: a job's [`Size`], the [`Validate`] step from spec to job, the
//! [`Envelope`] every result ends with, [`NoPart`] for kinds never split.

use serde::Serialize;
use serde_json::Value;

use super::error::{JobError, SpecError};
use super::names::EngineDoc;
use super::warning::WarningDoc;

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
#[derive(Clone, Copy, Debug, PartialEq, Serialize, serde::Deserialize)]
pub enum NoPart {}

/// `result` as a document, or the error that it cannot be one.
pub fn document<T: Serialize>(result: &T) -> Result<Value, JobError> {
    serde_json::to_value(result).map_err(JobError::Serialise)
}
