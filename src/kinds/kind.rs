//! What a job kind is: the [`Kind`] trait. A kind is one folder of
//! `src/kinds/` (its spec, validated job and result types, table, figure,
//! example and `impl Kind`) plus one line of the registry
//! ([`super::registry`]), from which the job enum, the kind list, every
//! dispatch (tables and figures included), the `?kind=` enum and the API
//! description's unions are generated. The compiler asks for every item of
//! the trait in the one impl. `docs/adding-a-kind.md` walks through it.

use std::fmt::Debug;

use serde::Serialize;
use serde::de::DeserializeOwned;
use serde_json::Value;
use utoipa::ToSchema;

use crate::jobs::error::{JobError, SpecError};
pub use crate::jobs::kind::NoPart;
use crate::jobs::kind::{Envelope, Size, Validate};
use crate::jobs::warning::WarningDoc;
use crate::plot::{FigureError, Window};
use crate::spectrum::Control;
use crate::table::{Table, TableError};

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

/// A task of a job of kind `K`: the job, and the part of it the task
/// computes (`None`: the whole job). A part is the service's, never a
/// field of a spec: it is stored as the task's payload (`{"part": …}`) and
/// read back against the job ([`Kind::fits`]).
pub struct Task<K: Kind + ?Sized> {
    /// The job (a job of its own for a kind that splits into jobs).
    pub job: K::Job,
    /// The part of `job` the task computes.
    pub part: Option<K::Range>,
}

impl<K: Kind + ?Sized> Task<K> {
    /// The task computing the whole of `job`.
    pub fn whole(job: K::Job) -> Task<K> {
        Task { job, part: None }
    }
}

impl<K: Kind + ?Sized> Task<K> {
    /// The tasks of `job` cut into `parts`: one per part, or the whole job
    /// when there are fewer than two.
    pub fn parts(job: &K::Job, parts: Vec<K::Range>) -> Vec<Task<K>> {
        if parts.len() <= 1 {
            return vec![Task::whole(job.clone())];
        }
        parts
            .into_iter()
            .map(|p| Task {
                job: job.clone(),
                part: Some(p),
            })
            .collect()
    }
}

impl<K: Kind + ?Sized> Clone for Task<K> {
    fn clone(&self) -> Self {
        Task {
            job: self.job.clone(),
            part: self.part,
        }
    }
}

impl<K: Kind + ?Sized> Debug for Task<K> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Task")
            .field("kind", &K::NAME)
            .field("job", &self.job)
            .field("part", &self.part)
            .finish()
    }
}

impl<K: Kind + ?Sized> PartialEq for Task<K> {
    fn eq(&self, other: &Self) -> bool {
        self.job == other.job && self.part == other.part
    }
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
    /// Which part of a job a task computes ([`NoPart`] for a kind whose
    /// tasks are whole jobs).
    type Range: Copy + Debug + PartialEq + Serialize + DeserializeOwned + 'static;

    /// Validates a spec of this kind (a JSON object whose `kind` is
    /// [`Kind::NAME`]): read as [`Kind::Spec`], then validated.
    fn parse(value: &Value) -> Result<Self::Job, SpecError> {
        super::spec::from_value::<Self::Spec>(value, "")?.validate()
    }

    /// Computes `part` of the job (`None`: the whole job) under `control`
    /// (progress, cancellation): the result before its input warnings and
    /// engine are added, or — for a part — the part.
    fn run(
        job: &Self::Job,
        part: Option<Self::Range>,
        control: &Control,
    ) -> Result<Output<Self>, JobError>;

    /// The result's table (`?format=csv`): its rows, written into `table`.
    fn table(result: &Self::Result, table: &mut Table) -> Result<(), TableError>;

    /// The result's figure (SVG) over `window`, a span of time; a kind
    /// whose figure has no time axis refuses a window ([`whole_figure`]).
    fn figure(result: &Self::Result, window: Option<Window>) -> Result<String, FigureError>;

    /// How big `part` of the job is (`None`: the whole job).
    fn size(job: &Self::Job, part: Option<Self::Range>) -> Size;

    /// The field that sets the job's grid and work, named when a limit is
    /// exceeded.
    fn grid_field(job: &Self::Job) -> &'static str;

    /// Warnings about the job's inputs (block sizes, records), added to its
    /// result.
    fn warnings(_job: &Self::Job) -> Vec<WarningDoc> {
        Vec::new()
    }

    /// The job's size measured on a sample of it (`size`: the model's,
    /// [`Kind::size`]), for a kind whose work the model cannot foresee (a
    /// scan under a record bisects as the record's chaos dictates,
    /// [`crate::spectrum::pilot`]); `None` (the default): the model's size
    /// stands. Asked off the runtime, of a new job whose model CPU time is at
    /// least [`crate::jobs::cost::SAMPLE_FROM_S`], for a sample of at most
    /// [`crate::jobs::cost::sample_budget_s`] of it.
    fn sampled_size(_job: &Self::Job, _size: &Size) -> Option<Size> {
        None
    }

    /// The tasks of the job (`size`: [`Kind::size`], or the
    /// size measured on a sample, [`Kind::sampled_size`]): parts of it, or
    /// jobs of their own; one, the whole job, by default.
    fn split(job: &Self::Job, _size: &Size) -> Vec<Task<Self>> {
        vec![Task::whole(job.clone())]
    }

    /// Whether `part`, read back from a stored task, is a part of `job`, or
    /// why not.
    fn fits(_job: &Self::Job, _part: &Self::Range) -> Result<(), JobError> {
        Ok(())
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

/// The figure `draw` draws of a result of kind `K`, which has no time axis:
/// a `window` is refused.
pub fn whole_figure<K: Kind + ?Sized>(
    window: Option<Window>,
    draw: impl FnOnce() -> Result<String, String>,
) -> Result<String, FigureError> {
    if window.is_some() {
        return Err(FigureError::Window(format!(
            "a window is a span of time: it applies to time histories, not to a {} result",
            K::NAME.replace('_', " ")
        )));
    }
    draw().map_err(FigureError::Result)
}
