//! Fragility jobs named by a survival spec: `"fragility": {"job": "<id>"}`
//! (the spec's own, or a rock's of `rocks`) is replaced by that finished
//! fragility job's lognormal fit, `{"median", "beta"}`, so that the survival
//! job is the same computation — the same canonical spec and cache key — as
//! the spec giving the fit.

use serde_json::{Value, json};
use uuid::Uuid;

use super::AppState;
use super::finished::{ResultError, finished};
use crate::jobs::SpecError;
use crate::kinds::JobKind;

/// Why the fragility jobs a spec names cannot stand in for their fits.
#[derive(Debug, thiserror::Error)]
pub enum LinkError {
    /// The spec names a job wrongly: not a job id, not a fragility job, a
    /// fragility in another intensity measure than the hazard, no fit.
    #[error(transparent)]
    Invalid(#[from] SpecError),
    /// The job named cannot be read (no such job of the tenant, not
    /// succeeded, the store failing).
    #[error("{pointer}: job {id} cannot be read: {reason}")]
    Unreadable {
        /// JSON pointer to the `job` field.
        pointer: String,
        /// The job id as the spec gives it.
        id: String,
        /// Why.
        reason: ResultError,
    },
    /// A fragility job's stored result does not read as one.
    #[error("{0}")]
    Corrupt(String),
    /// Reading a result on the blocking pool stopped.
    #[error("reading the spec stopped: {0}")]
    Stopped(#[from] tokio::task::JoinError),
}

/// A survival spec whose fragilities name finished `fragility` jobs of
/// `tenant` (`{"job": "<id>"}`), rewritten with their lognormal fits
/// (`median`, `beta`); any other spec as it is (its validation says what is
/// wrong with it).
pub async fn resolve(state: &AppState, tenant: &str, mut spec: Value) -> Result<Value, LinkError> {
    if spec.get("kind").and_then(|k| k.as_str()) != Some(JobKind::Survival.name()) {
        return Ok(spec);
    }
    let hazard_im = spec
        .pointer("/hazard/im")
        .and_then(|v| v.as_str())
        .map(str::to_string);
    let mut slots = vec!["/fragility".to_string()];
    let rocks = spec
        .get("rocks")
        .and_then(|r| r.as_array())
        .map_or(0, Vec::len);
    slots.extend((0..rocks).map(|i| format!("/rocks/{i}/fragility")));
    for at in slots {
        let Some(id) = spec
            .pointer(&format!("{at}/job"))
            .and_then(|v| v.as_str())
            .map(str::to_string)
        else {
            continue;
        };
        let pointer = format!("{at}/job");
        let uuid = Uuid::parse_str(&id)
            .map_err(|_| SpecError::at(pointer.clone(), format!("{id:?} is not a job id")))?;
        let found = match finished(state, tenant, uuid).await {
            Ok(found) => found,
            Err(reason) => {
                return Err(LinkError::Unreadable {
                    pointer,
                    id,
                    reason,
                });
            }
        };
        let body = found.body.clone();
        let doc: Value = tokio::task::spawn_blocking(move || serde_json::from_str(body.as_str()))
            .await?
            .map_err(|e| LinkError::Corrupt(e.to_string()))?;
        if doc.get("kind").and_then(|k| k.as_str()) != Some("fragility") {
            return Err(SpecError::at(pointer, format!("job {id} is not a fragility job")).into());
        }
        let im = doc.get("im").and_then(|v| v.as_str()).unwrap_or("pga_g");
        if hazard_im.as_deref().is_some_and(|h| h != im) {
            return Err(SpecError::at(
                pointer,
                format!(
                    "job {id}'s fragility is in {im}, the hazard in {}",
                    hazard_im.unwrap_or_default()
                ),
            )
            .into());
        }
        let fit = doc.get("lognormal").filter(|v| !v.is_null()).ok_or_else(|| {
            SpecError::at(
                pointer.clone(),
                format!("job {id} has no lognormal fit (its counts do not bound one): give median and beta"),
            )
        })?;
        let (Some(median), Some(beta)) = (
            fit.get("median").and_then(|v| v.as_f64()),
            fit.get("beta").and_then(|v| v.as_f64()),
        ) else {
            return Err(LinkError::Corrupt(format!(
                "job {id}'s fit has no median or beta"
            )));
        };
        if let Some(slot) = spec.pointer_mut(&at) {
            *slot = json!({"median": median, "beta": beta});
        }
    }
    Ok(spec)
}
