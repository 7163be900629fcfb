//! Jobs: the spec JSON users send (to `topple run` or the service), its
//! validation into domain types, and the result documents.

pub mod distribution;
pub mod error;
pub mod forensic;
pub mod forensic_record;
pub mod fragility;
pub mod friction;
pub mod key;
pub mod limits;
pub mod names;
pub mod numerics;
pub mod plausible;
pub mod range;
pub mod record_spectrum;
#[cfg(test)]
mod roundtrip;
pub mod schema;
pub mod spec;
pub mod spectrum;
pub mod split;
pub mod survival;
pub mod time_history;

pub use error::{JobError, SpecError};

use serde::Serialize;

use crate::spectrum::Control;

/// A validated job of any kind; serialises to its canonical (normalised) spec.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(untagged)]
pub enum Job {
    /// One time history.
    TimeHistory(time_history::TimeHistoryJob),
    /// An overturning spectrum.
    Spectrum(spectrum::SpectrumJob),
    /// A friction-demand spectrum.
    FrictionSpectrum(friction::FrictionJob),
    /// The pulses consistent with blocks seen overturned or standing.
    Forensic(forensic::ForensicJob),
    /// The rocking spectrum of a recorded motion.
    RecordSpectrum(record_spectrum::RecordSpectrumJob),
    /// The survival of rocks of known age under a hazard model.
    Survival(survival::SurvivalJob),
    /// Fragility by Monte Carlo (boxed: its uncertain inputs make it the
    /// largest spec).
    Fragility(Box<fragility::FragilityJob>),
}

/// The job kinds, as named in specs.
pub const KINDS: [&str; 7] = [
    "time_history",
    "spectrum",
    "friction_spectrum",
    "forensic",
    "record_spectrum",
    "survival",
    "fragility",
];

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
        if let Job::Fragility(f) = &job
            && f.part.is_some()
        {
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
        match kind {
            "time_history" => {
                let spec: time_history::TimeHistorySpec = spec::from_value(value, "")?;
                Ok(Job::TimeHistory(spec.validate()?))
            }
            "spectrum" => {
                let spec: spectrum::SpectrumSpec = spec::from_value(value, "")?;
                Ok(Job::Spectrum(spec.validate()?))
            }
            "friction_spectrum" => {
                let spec: friction::FrictionSpec = spec::from_value(value, "")?;
                Ok(Job::FrictionSpectrum(spec.validate()?))
            }
            "forensic" => {
                if let Some(list) = obj.get("observations").and_then(|v| v.as_array()) {
                    for (i, o) in list.iter().enumerate() {
                        if let Some(b) = o.get("block")
                            && !(b.is_object() || b.is_null())
                        {
                            return Err(SpecError::at(
                                format!("/observations/{i}/block"),
                                "must be a JSON object",
                            ));
                        }
                    }
                }
                let spec: forensic::ForensicSpec = spec::from_value(value, "")?;
                Ok(Job::Forensic(spec.validate()?))
            }
            "record_spectrum" => {
                let spec: record_spectrum::RecordSpectrumSpec = spec::from_value(value, "")?;
                Ok(Job::RecordSpectrum(spec.validate()?))
            }
            "survival" => {
                let spec: survival::SurvivalSpec = spec::from_value(value, "")?;
                Ok(Job::Survival(spec.validate()?))
            }
            "fragility" => {
                let spec: fragility::FragilitySpec = spec::from_value(value, "")?;
                Ok(Job::Fragility(Box::new(spec.validate()?)))
            }
            other => Err(SpecError::at(
                "/kind",
                format!(
                    "unknown kind {other:?}: expected one of {}",
                    KINDS.join(", ")
                ),
            )),
        }
    }

    /// The kind name.
    pub fn kind(&self) -> &'static str {
        match self {
            Job::TimeHistory(_) => "time_history",
            Job::Spectrum(_) => "spectrum",
            Job::FrictionSpectrum(_) => "friction_spectrum",
            Job::Forensic(_) => "forensic",
            Job::RecordSpectrum(_) => "record_spectrum",
            Job::Survival(_) => "survival",
            Job::Fragility(_) => "fragility",
        }
    }

    /// Runs the job under `control` (progress, cancellation) and returns its
    /// result document.
    pub fn run(&self, control: &Control) -> Result<serde_json::Value, JobError> {
        let value = match self {
            Job::TimeHistory(job) => {
                if control.canceled() {
                    return Err(JobError::Canceled);
                }
                control.add_total(1);
                let result = job.run()?;
                control.add_done(1);
                serde_json::to_value(result)
            }
            Job::Spectrum(job) => serde_json::to_value(job.run(control)?),
            Job::FrictionSpectrum(job) => serde_json::to_value(job.run(control)?),
            Job::Forensic(job) => serde_json::to_value(job.run(control)?),
            Job::RecordSpectrum(job) => serde_json::to_value(job.run(control)?),
            Job::Fragility(job) if job.part.is_some() => {
                // A task's counts, assembled by the service: no warnings.
                return serde_json::to_value(job.run_part(control)?)
                    .map_err(|e| JobError::Point(e.to_string()));
            }
            Job::Fragility(job) => serde_json::to_value(job.run(control)?),
            Job::Survival(job) => {
                if control.canceled() {
                    return Err(JobError::Canceled);
                }
                control.add_total(1);
                let result = job.run();
                control.add_done(1);
                serde_json::to_value(result)
            }
        };
        let doc = plausible::with_warnings(value.unwrap_or(serde_json::Value::Null), self);
        Ok(key::with_engine(doc))
    }
}
