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

    /// The result's table (`?format=csv`): its rows, written into `table`.
    fn table(result: &Self::Result, table: &mut Table) -> Result<(), TableError>;

    /// The result's figure (SVG) over `window`, a span of time; a kind
    /// whose figure has no time axis refuses a window ([`whole_figure`]).
    fn figure(result: &Self::Result, window: Option<Window>) -> Result<String, FigureError>;

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
