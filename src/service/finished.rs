//! A finished job's result document, from memory or the store, or why there
//! is none to read.

use std::time::Duration;

use uuid::Uuid;

use super::AppState;
use super::results::{Cached, LoadError};
use super::succeeded::{Read, read};
use crate::store::{JobRecord, Status, StoreError};

/// Longest a result read waits for a turn to read the database, or for room
/// in the memory budget of large results (and a request for a rendering
/// slot); then it is refused as busy.
pub const RESULT_WAIT: Duration = Duration::from_secs(10);

/// Why a job's result cannot be read.
#[derive(Debug, thiserror::Error)]
pub enum ResultError {
    /// The tenant has no such job.
    #[error("no job {0}")]
    NotFound(Uuid),
    /// The job failed.
    #[error("job {id} failed: {error}")]
    Failed {
        /// The job.
        id: Uuid,
        /// Why.
        error: String,
    },
    /// The job was canceled.
    #[error("job {0} was canceled")]
    Canceled(Uuid),
    /// The job is queued or running.
    #[error("job {} is {}", .0.id, .0.status.as_str())]
    NotFinished(Box<JobRecord>),
    /// The job succeeded but its result is not stored.
    #[error("result of job {0} is missing")]
    Missing(Uuid),
    /// The memory for large results, or a turn to read the database, stayed
    /// taken for [`RESULT_WAIT`].
    #[error("the memory for large results or the database stayed busy")]
    Busy,
    /// The store failed.
    #[error(transparent)]
    Store(#[from] StoreError),
}

/// The result document of the tenant's job `id`, once it has succeeded
/// (the job and its document from memory when they are held there).
pub async fn finished(state: &AppState, tenant: &str, id: Uuid) -> Result<Cached, ResultError> {
    let job = match read(state, tenant, id).await? {
        Some(Read::Succeeded(job)) => {
            return match state.results.get(job.record.computation) {
                Some(found) => Ok(found),
                None => stored(state, &job.record).await,
            };
        }
        Some(Read::Other(job)) => *job,
        None => return Err(ResultError::NotFound(id)),
    };
    match job.status {
        Status::Failed => Err(ResultError::Failed {
            id,
            error: job.error.unwrap_or_default(),
        }),
        Status::Canceled => Err(ResultError::Canceled(id)),
        _ => Err(ResultError::NotFinished(Box::new(job))),
    }
}

/// The result document of succeeded job `job` (of its computation, which
/// identical jobs of other tenants share).
pub async fn stored(state: &AppState, job: &JobRecord) -> Result<Cached, ResultError> {
    let id = job.computation;
    match state
        .results
        .load(id, &job.key, RESULT_WAIT, state.store.result(id))
        .await
    {
        Ok(Some(found)) => Ok(found),
        Ok(None) => Err(ResultError::Missing(job.id)),
        Err(LoadError::Store(e)) => Err(e.into()),
        Err(LoadError::Busy) => Err(ResultError::Busy),
    }
}
