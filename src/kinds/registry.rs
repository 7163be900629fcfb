//! The registry of job kinds: one line per kind (the [`kinds!`] call at the
//! end), from which the job enum [`Job`], the kind enum [`JobKind`] (the
//! `?kind=` parameter), the kind list [`KINDS`], every dispatch over kinds and
//! the API description's unions of specs, normalised specs and results are
//! generated. The order of the lines is the order of the lists.

use std::borrow::Cow;

use serde::{Deserialize, Serialize};
use serde_json::Value;
use utoipa::openapi::schema::{Discriminator, OneOfBuilder, Schema};
use utoipa::openapi::{Ref, RefOr};
use utoipa::{PartialSchema, ToSchema};

use super::kind::{Kind, Output};
use crate::jobs::error::{JobError, SpecError};
use crate::jobs::kind::{Envelope, Size, document};
use crate::jobs::warning::WarningDoc;
use crate::spectrum::Control;

/// A `oneOf` of the kinds' schemas `(kind, schema name)`, discriminated by
/// `kind`.
fn union(description: &str, items: &[(&str, Cow<'static, str>)]) -> RefOr<Schema> {
    let mut one_of = OneOfBuilder::new().description(Some(description));
    for (kind, name) in items {
        let mut item = Ref::from_schema_name(name.as_ref());
        item.description = format!("`\"kind\": \"{kind}\"`.");
        one_of = one_of.item(RefOr::Ref(item));
    }
    let mapping = items
        .iter()
        .map(|(kind, name)| (kind.to_string(), format!("#/components/schemas/{name}")));
    one_of
        .discriminator(Some(Discriminator::with_mapping("kind", mapping)))
        .into()
}

/// A document that does not read as a result of its kind: a stored result
/// of another engine, or not a result at all.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("{}{}: {message}", kind.map(|k| format!("not a {} result: ", k.name())).unwrap_or_default(), if pointer.is_empty() { "the document" } else { pointer.as_str() })]
pub struct ResultError {
    /// The kind it claims, when it names one.
    pub kind: Option<JobKind>,
    /// JSON pointer to the field at fault ("" for the document).
    pub pointer: String,
    /// What is wrong with it.
    pub message: String,
}

/// The kind a result document names in its `kind`.
fn result_kind(value: &Value) -> Result<JobKind, ResultError> {
    let name = value.get("kind").and_then(Value::as_str);
    name.and_then(JobKind::from_name)
        .ok_or_else(|| ResultError {
            kind: None,
            pointer: "/kind".into(),
            message: match name {
                Some(name) => format!(
                    "no result kind {name:?}: expected one of {}",
                    KINDS.join(", ")
                ),
                None => "not a result document: it has no \"kind\"".into(),
            },
        })
}

/// `value` read as a `T`, the result type of `kind`, or the field at fault.
fn read_as<T: serde::de::DeserializeOwned>(kind: JobKind, value: Value) -> Result<T, ResultError> {
    serde_path_to_error::deserialize(value).map_err(|e| ResultError {
        kind: Some(kind),
        pointer: crate::jobs::spec::json_pointer("", e.path()),
        message: e.into_inner().to_string(),
    })
}

/// The document `part` of `job` computes (`None`: the whole job): the
/// kind's result with the job's input warnings and the engine, or the part.
fn run_document<K: Kind>(
    job: &K::Job,
    part: Option<K::Range>,
    control: &Control,
) -> Result<Value, JobError> {
    match K::run(job, part, control)? {
        Output::Whole(result) => whole::<K>(job, result),
        Output::Part(part) => document(&part),
    }
}

/// The task computing `part` (as stored) of `whole`, or why it is not one.
fn part_of<K: Kind>(whole: &K::Job, part: &Value) -> Result<super::kind::Task<K>, JobError> {
    let range = K::Range::deserialize(part)
        .map_err(|e| JobError::Task(format!("a task's part {part} does not read: {e}")))?;
    K::fits(whole, &range)?;
    Ok(super::kind::Task {
        job: whole.clone(),
        part: Some(range),
    })
}

/// The result document of `job`: `result` with the job's input warnings
/// and the engine that computed it.
fn whole<K: Kind>(job: &K::Job, mut result: K::Result) -> Result<Value, JobError> {
    result.add_warnings(K::warnings(job));
    result.set_engine(crate::jobs::engine::engine_doc());
    document(&result)
}

/// Tasks' documents read as parts of kind `K`.
fn read_parts<K: Kind>(parts: Vec<Value>) -> Result<Vec<K::Part>, JobError> {
    parts
        .into_iter()
        .map(serde_json::from_value)
        .collect::<Result<_, _>>()
        .map_err(|e| JobError::Task(format!("a task's result does not read: {e}")))
}

/// Generates, from `Variant => kind type` lines, the job enum, the kind enum
/// and list, the dispatch and the unions.
macro_rules! kinds {
    ($( $(#[doc = $doc:literal])* $variant:ident => $kind:ty ),* $(,)?) => {
        /// A validated job of any kind; serialises to its canonical
        /// (normalised) spec.
        #[derive(Clone, Debug, PartialEq, Serialize)]
        #[serde(untagged)]
        pub enum Job {
            $( $(#[doc = $doc])* $variant(Box<<$kind as Kind>::Job>), )*
        }

        /// The kind of a job.
        #[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize, ToSchema)]
        #[serde(rename_all = "snake_case")]
        pub enum JobKind {
            $( $(#[doc = $doc])* $variant, )*
        }

        impl JobKind {
            /// Every kind, in the registry's order.
            pub const ALL: &'static [JobKind] = &[$(JobKind::$variant),*];

            /// The kind's name (`"time_history"`).
            pub fn name(self) -> &'static str {
                match self {
                    $( JobKind::$variant => <$kind as Kind>::NAME, )*
                }
            }

            /// The kind's name for people ("Time history").
            pub fn label(self) -> &'static str {
                match self {
                    $( JobKind::$variant => <$kind as Kind>::LABEL, )*
                }
            }

            /// The name of the kind's result schema in the API description
            /// (`"TimeHistoryResult"`).
            pub fn result_schema(self) -> Cow<'static, str> {
                match self {
                    $( JobKind::$variant => <<$kind as Kind>::Result as ToSchema>::name(), )*
                }
            }

            /// Whether a job of this kind may be split into parts (its
            /// [`Kind::Range`] is not [`crate::jobs::kind::NoPart`]).
            pub fn has_parts(self) -> bool {
                match self {
                    $( JobKind::$variant => std::any::TypeId::of::<<$kind as Kind>::Range>()
                        != std::any::TypeId::of::<crate::jobs::kind::NoPart>(), )*
                }
            }

            /// A small spec of this kind ([`Kind::EXAMPLE`]).
            pub fn example(self) -> &'static str {
                match self {
                    $( JobKind::$variant => <$kind as Kind>::EXAMPLE, )*
                }
            }

            /// The kind named `name`.
            pub fn from_name(name: &str) -> Option<JobKind> {
                JobKind::ALL.iter().copied().find(|k| k.name() == name)
            }
        }

        /// The job kinds, as named in specs.
        pub const KINDS: &[&str] = &[$(<$kind as Kind>::NAME),*];

        impl Job {
            /// Validates a spec of kind `kind`.
            pub(crate) fn of_kind(kind: JobKind, value: &Value) -> Result<Job, SpecError> {
                Ok(match kind {
                    $( JobKind::$variant => Job::$variant(Box::new(<$kind as Kind>::parse(value)?)), )*
                })
            }

            /// A normalised spec of `kind` (what [`Job`] serialises to) read
            /// back into its job type.
            pub fn from_normalised(kind: JobKind, value: Value) -> Result<Job, serde_json::Error> {
                Ok(match kind {
                    $( JobKind::$variant => Job::$variant(Box::new(serde_json::from_value(value)?)), )*
                })
            }

            /// The job's kind.
            pub fn job_kind(&self) -> JobKind {
                match self {
                    $( Job::$variant(_) => JobKind::$variant, )*
                }
            }

            /// The kind name.
            pub fn kind(&self) -> &'static str {
                self.job_kind().name()
            }

            /// The document the job computes: the kind's result with the
            /// job's input warnings and the engine.
            pub(crate) fn run_document(&self, control: &Control) -> Result<Value, JobError> {
                match self {
                    $( Job::$variant(j) => run_document::<$kind>(j, None, control), )*
                }
            }

            /// How big the job is.
            pub fn size(&self) -> Size {
                match self {
                    $( Job::$variant(j) => <$kind as Kind>::size(j, None), )*
                }
            }

            /// The field that sets the job's grid and work.
            pub fn grid_field(&self) -> &'static str {
                match self {
                    $( Job::$variant(j) => <$kind as Kind>::grid_field(j), )*
                }
            }

            /// Warnings about the job's inputs.
            pub fn input_warnings(&self) -> Vec<WarningDoc> {
                match self {
                    $( Job::$variant(j) => <$kind as Kind>::warnings(j), )*
                }
            }

            /// The tasks of this job: parts of it, or jobs of their own.
            pub fn split(&self) -> Vec<Task> {
                self.split_sized(&self.size())
            }

            /// The job's size measured on a sample of it, for a kind that
            /// measures it ([`Kind::sampled_size`]); `None`: the model's
            /// `size` stands.
            pub fn sampled_size(&self, size: &Size) -> Option<Size> {
                match self {
                    $( Job::$variant(j) => <$kind as Kind>::sampled_size(j, size), )*
                }
            }

            /// The tasks of this job of `size` (its model's, or measured on
            /// a sample): parts of it, or jobs of their own.
            pub fn split_sized(&self, size: &Size) -> Vec<Task> {
                let size = *size;
                match self {
                    $( Job::$variant(j) => <$kind as Kind>::split(j, &size)
                        .into_iter()
                        .map(|t| Task::$variant(Box::new(t)))
                        .collect(), )*
                }
            }

            /// The typed result of the job computed whole under `control`
            /// (before its input warnings and engine are added); `None` for
            /// a task's part.
            pub fn run_typed(&self, control: &Control) -> Result<Option<JobResult>, JobError> {
                Ok(match self {
                    $( Job::$variant(j) => match <$kind as Kind>::run(j, None, control)? {
                        Output::Whole(result) => Some(JobResult::$variant(Box::new(result))),
                        Output::Part(_) => None,
                    }, )*
                })
            }

            /// The kind's assembly of several tasks' documents, read as
            /// its parts, into the job's result document.
            pub(crate) fn assemble_documents(&self, parts: Vec<Value>) -> Result<Value, JobError> {
                match self {
                    $( Job::$variant(j) => {
                        let parts = read_parts::<$kind>(parts)?;
                        whole::<$kind>(j, <$kind as Kind>::assemble(j, parts)?)
                    } )*
                }
            }
        }

        /// A task of a job: the job, or a part of it
        /// ([`crate::kinds::kind::Task`]).
        #[derive(Clone, Debug, PartialEq)]
        pub enum Task {
            $( $(#[doc = $doc])* $variant(Box<super::kind::Task<$kind>>), )*
        }

        impl Task {
            /// The task computing the whole of `job`.
            pub fn whole(job: Job) -> Task {
                match job {
                    $( Job::$variant(j) => Task::$variant(Box::new(super::kind::Task::whole(*j))), )*
                }
            }

            /// The task computing `part` (a task's stored `{"part": …}`) of
            /// `whole`, or why it is not a part of it.
            pub fn part(whole: &Job, part: &Value) -> Result<Task, JobError> {
                match whole {
                    $( Job::$variant(j) => Ok(Task::$variant(Box::new(part_of::<$kind>(j, part)?))), )*
                }
            }

            /// The task's job kind.
            pub fn job_kind(&self) -> JobKind {
                match self {
                    $( Task::$variant(_) => JobKind::$variant, )*
                }
            }

            /// Whether the task computes a part of its job (its result is
            /// a part, assembled by the service; it carries no warnings).
            pub fn is_part(&self) -> bool {
                match self {
                    $( Task::$variant(t) => t.part.is_some(), )*
                }
            }

            /// The task's job, whole.
            pub fn job(&self) -> Job {
                match self {
                    $( Task::$variant(t) => Job::$variant(Box::new(t.job.clone())), )*
                }
            }

            /// The cache key of the task's job ([`super::key::cache_key`]):
            /// its result's key when the task is the whole job.
            pub fn key(&self) -> String {
                match self {
                    $( Task::$variant(t) => super::key::cache_key(&t.job), )*
                }
            }

            /// How big the task is.
            pub fn size(&self) -> Size {
                match self {
                    $( Task::$variant(t) => <$kind as Kind>::size(&t.job, t.part), )*
                }
            }

            /// The task's stored payload: its part (`{"part": …}`; the job
            /// is stored once, with the computation), or its own job spec.
            pub fn payload(&self) -> String {
                match self {
                    $( Task::$variant(t) => match &t.part {
                        Some(part) => serde_json::json!({ "part": part }).to_string(),
                        None => serde_json::to_string(&t.job).unwrap_or_default(),
                    }, )*
                }
            }

            /// The document the task computes: its job's result with the
            /// job's input warnings and the engine, or its part.
            pub fn run(&self, control: &Control) -> Result<Value, JobError> {
                match self {
                    $( Task::$variant(t) => run_document::<$kind>(&t.job, t.part, control), )*
                }
            }
        }

        /// A job spec: exactly what `topple run` accepts.
        pub struct JobSpec;

        impl PartialSchema for JobSpec {
            fn schema() -> RefOr<Schema> {
                union(
                    "A job spec: exactly what `topple run` accepts.",
                    &[$( (<$kind as Kind>::NAME, <<$kind as Kind>::Spec as ToSchema>::name()) ),*],
                )
            }
        }

        impl ToSchema for JobSpec {
            fn schemas(schemas: &mut Vec<(String, RefOr<Schema>)>) {
                $(
                    schemas.push((
                        <<$kind as Kind>::Spec as ToSchema>::name().into(),
                        <<$kind as Kind>::Spec as PartialSchema>::schema(),
                    ));
                    <<$kind as Kind>::Spec as ToSchema>::schemas(schemas);
                )*
            }
        }

        /// A normalised spec (SI units, every default filled in), by
        /// `kind`: what a job view and a result document echo.
        pub struct NormalizedSpec;

        impl PartialSchema for NormalizedSpec {
            fn schema() -> RefOr<Schema> {
                union(
                    "A normalised spec (SI units, every default filled in), by `kind`: what a\njob view and a result document echo.",
                    &[$( (<$kind as Kind>::NAME, <<$kind as Kind>::Job as ToSchema>::name()) ),*],
                )
            }
        }

        impl ToSchema for NormalizedSpec {
            fn schemas(schemas: &mut Vec<(String, RefOr<Schema>)>) {
                $(
                    schemas.push((
                        <<$kind as Kind>::Job as ToSchema>::name().into(),
                        <<$kind as Kind>::Job as PartialSchema>::schema(),
                    ));
                    <<$kind as Kind>::Job as ToSchema>::schemas(schemas);
                )*
            }
        }

        /// A result document, read into the type of its kind: what tables
        /// and figures are drawn from. It serialises to the document it was
        /// read from, and is described in the API as a `oneOf` by `kind`.
        #[derive(Clone, Debug, PartialEq, Serialize)]
        #[serde(untagged)]
        pub enum JobResult {
            $( $(#[doc = $doc])* $variant(Box<<$kind as Kind>::Result>), )*
        }

        impl JobResult {
            /// The result's kind.
            pub fn job_kind(&self) -> JobKind {
                match self {
                    $( JobResult::$variant(_) => JobKind::$variant, )*
                }
            }

            /// The result's table (CSV text).
            pub fn table(&self) -> Result<String, crate::table::TableError> {
                let mut table = crate::table::Table::new();
                match self {
                    $( JobResult::$variant(r) => <$kind as Kind>::table(r, &mut table)?, )*
                }
                table.finish()
            }

            /// The result's figure (SVG text) over `window` (a span of time:
            /// time histories only; `None`: the whole result).
            pub fn figure(&self, window: Option<crate::plot::Window>) -> Result<String, crate::plot::FigureError> {
                match self {
                    $( JobResult::$variant(r) => <$kind as Kind>::figure(r, window), )*
                }
            }

            /// Reads a result document into the type of its `kind`; a
            /// document that is not one is an error naming the field at
            /// fault.
            pub fn from_value(value: Value) -> Result<JobResult, ResultError> {
                let kind = result_kind(&value)?;
                Ok(match kind {
                    $( JobKind::$variant => JobResult::$variant(Box::new(read_as(kind, value)?)), )*
                })
            }
        }

        impl PartialSchema for JobResult {
            fn schema() -> RefOr<Schema> {
                union(
                    "A result document, by `kind`.",
                    &[$( (<$kind as Kind>::NAME, <<$kind as Kind>::Result as ToSchema>::name()) ),*],
                )
            }
        }

        impl ToSchema for JobResult {
            fn schemas(schemas: &mut Vec<(String, RefOr<Schema>)>) {
                $(
                    schemas.push((
                        <<$kind as Kind>::Result as ToSchema>::name().into(),
                        <<$kind as Kind>::Result as PartialSchema>::schema(),
                    ));
                    <<$kind as Kind>::Result as ToSchema>::schemas(schemas);
                )*
            }
        }
    };
}

kinds! {
    /// One time history.
    TimeHistory => super::time_history::TimeHistory,
    /// An overturning spectrum.
    Spectrum => super::spectrum::Spectrum,
    /// A friction-demand spectrum.
    FrictionSpectrum => super::friction_spectrum::FrictionSpectrum,
    /// The pulses or record scales consistent with blocks seen overturned or
    /// standing.
    Forensic => super::forensic::Forensic,
    /// The rocking spectrum of a recorded motion.
    RecordSpectrum => super::record_spectrum::RecordSpectrum,
    /// The survival of rocks of known age under a hazard model.
    Survival => super::survival::Survival,
    /// Fragility by Monte Carlo.
    Fragility => super::fragility::Fragility,
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::spectrum::Control;

    /// `?kind=` (serde) and specs (`Kind::NAME`) name every kind alike.
    #[test]
    fn the_kind_enum_names_kinds_as_specs_do() {
        for kind in JobKind::ALL {
            let named = serde_json::to_value(kind).expect("a name");
            assert_eq!(named, kind.name(), "{kind:?}");
            assert_eq!(JobKind::from_name(kind.name()), Some(*kind));
        }
        assert_eq!(KINDS.len(), JobKind::ALL.len());
    }

    /// A document that does not read as a result of its kind is an error
    /// naming the field, never a guess.
    #[test]
    fn a_result_reads_into_its_kind_or_names_the_field_at_fault() {
        let job = Job::parse(
            r#"{"kind":"time_history","block":{"alpha":0.25,"p":2.14},"pulse":{"type":"one_sine","a_p_g":0.5,"frequency_hz":1}}"#,
        )
        .expect("a spec");
        let doc = job.run(&Control::default()).expect("runs");
        let typed = JobResult::from_value(doc.clone()).expect("a time history");
        assert_eq!(typed.job_kind(), JobKind::TimeHistory);
        assert_eq!(serde_json::to_value(&typed).expect("writes"), doc);

        let mut wrong = doc.clone();
        wrong["numerics"]["steps_accepted"] = serde_json::json!("many");
        let e = JobResult::from_value(wrong).expect_err("a text for a count");
        assert_eq!(e.kind, Some(JobKind::TimeHistory));
        assert_eq!(e.pointer, "/numerics/steps_accepted", "{e}");
        assert!(
            e.to_string()
                .starts_with("not a time_history result: /numerics/steps_accepted: "),
            "{e}"
        );

        let mut missing = doc;
        missing.as_object_mut().expect("object").remove("rocked");
        let e = JobResult::from_value(missing).expect_err("a field missing");
        assert!(e.message.contains("rocked"), "{e}");

        let e = JobResult::from_value(serde_json::json!({"kind": "teapot"})).expect_err("no kind");
        assert_eq!((e.kind, e.pointer.as_str()), (None, "/kind"));
        assert!(e.message.contains("teapot"), "{e}");
        assert!(JobResult::from_value(serde_json::json!({})).is_err());
    }
}
