//! A submission made ready to store: its spec read, what it names (finished
//! fragility jobs, stored records) read into it, validated and within the
//! service's limits, with its cache key, canonical text and tasks; and
//! whether the queue and the tenant's quota admit it.

use crate::jobs::SpecError;
use crate::kinds::Job;
use crate::kinds::key::cache_key;
use crate::kinds::limits::{LimitError, Size};
use crate::store::{Admission, Status, StoreError};

use super::AppState;
use super::fragility_links::LinkError;
use super::records::ResolveError;

/// A job ready to store.
#[derive(Debug)]
pub struct Prepared {
    /// The job, validated.
    pub job: Job,
    /// Its size (the work it needs).
    pub size: Size,
    /// Its cache key.
    pub key: String,
    /// Its canonical spec, as stored.
    pub spec: String,
    /// Its tasks' payloads.
    pub tasks: Vec<String>,
    /// The stored records it names (in order, without repeats).
    pub records: Vec<String>,
    /// The field that sets its grid and work, as the spec wrote it (named
    /// when a limit is exceeded).
    pub grid_pointer: String,
    /// Whether `size` was measured on a sample of the job
    /// ([`sample`]) rather than taken from its kind's model.
    pub sampled: bool,
}

/// Why a submission is refused.
#[derive(Debug, thiserror::Error)]
pub enum SubmitError {
    /// The body is not UTF-8 text.
    #[error("the body is not UTF-8")]
    NotUtf8,
    /// The spec is not JSON, or not valid.
    #[error(transparent)]
    Spec(#[from] SpecError),
    /// The fragility jobs it names cannot stand in for their fits.
    #[error(transparent)]
    Link(#[from] LinkError),
    /// It is over a service limit (pointing at the field as written).
    #[error(transparent)]
    Limit(LimitError),
    /// The tenant has as many jobs queued or running as its quota
    /// (`max_queued_per_tenant`).
    #[error("tenant {tenant:?} has {live} jobs queued or running, its quota")]
    TenantQuota {
        /// The tenant.
        tenant: String,
        /// Its jobs queued or running.
        live: i64,
        /// Its quota.
        quota: u64,
    },
    /// The queue holds `max_queued` computations.
    #[error("{max} jobs are waiting")]
    QueueFull {
        /// The limit (`max_queued`).
        max: u64,
    },
    /// The store failed.
    #[error(transparent)]
    Store(#[from] StoreError),
    /// The job could not be serialised.
    #[error("{0}")]
    Serialise(serde_json::Error),
    /// Reading the spec on the blocking pool stopped.
    #[error("reading the spec stopped: {0}")]
    Stopped(#[from] tokio::task::JoinError),
}

impl From<ResolveError> for SubmitError {
    fn from(e: ResolveError) -> Self {
        match e {
            ResolveError::Invalid(e) => SubmitError::Spec(e),
            ResolveError::Store(e) => SubmitError::Store(e),
        }
    }
}

/// Bodies up to this many bytes are read where they arrive: a spec this
/// short parses, validates and serialises in tens of microseconds, less than
/// a hop to the blocking pool and back.
pub const SMALL_BODY: usize = 4096;

/// Runs `f` on the blocking pool (parsing and validating documents: not
/// work for the runtime, and not compute to queue behind jobs), or here for
/// a `small` document.
async fn off_runtime<T: Send + 'static>(
    small: bool,
    f: impl FnOnce() -> T + Send + 'static,
) -> Result<T, SubmitError> {
    if small {
        return Ok(f());
    }
    Ok(tokio::task::spawn_blocking(f).await?)
}

/// The tenant's submission `body` (a job spec) made ready to store.
pub async fn prepare(
    state: &AppState,
    tenant: &str,
    body: impl AsRef<[u8]> + Send + 'static,
) -> Result<Prepared, SubmitError> {
    // Reading a spec (it may hold long records) is no work for the runtime:
    // the blocking pool parses and validates it, unless it is short.
    let small = body.as_ref().len() <= SMALL_BODY;
    let value = off_runtime(small, move || {
        let text = std::str::from_utf8(body.as_ref()).map_err(|_| SubmitError::NotUtf8)?;
        Ok::<_, SubmitError>(crate::jobs::spec::parse_json(text)?)
    })
    .await??;
    // A survival spec may name finished fragility jobs: read their fits.
    let value = super::fragility_links::resolve(state, tenant, value).await?;
    // A spec may name stored records: read their samples into it.
    let (value, records) = super::records::resolve(&*state.store, tenant, value).await?;
    // Records named by the spec make it long.
    let small = small && records.is_empty();
    let (job, value) = off_runtime(small, move || (Job::from_value(&value), value)).await?;
    let job = job?;
    let size = job
        .check_limits(&state.config.limits)
        .map_err(|e| SubmitError::Limit(e.as_written(&value)))?;
    let grid_pointer = crate::kinds::limits::written_pointer(job.grid_field(), &value);
    // Its key, canonical text and tasks: serialising a long record too.
    let (job, key, spec, tasks) = off_runtime(small, move || {
        let key = cache_key(&job);
        let spec = serde_json::to_string(&job);
        let tasks: Vec<String> = job
            .split()
            .iter()
            .map(crate::kinds::Task::payload)
            .collect();
        (job, key, spec, tasks)
    })
    .await?;
    Ok(Prepared {
        job,
        size,
        key,
        spec: spec.map_err(SubmitError::Serialise)?,
        tasks,
        records,
        grid_pointer,
        sampled: false,
    })
}

/// Longest a submission waits for the sample of another to end before it is
/// estimated by its kind's model instead.
pub const SAMPLE_WAIT: std::time::Duration = std::time::Duration::from_secs(2);

/// A new job's size measured on a sample of it where its kind's model
/// cannot foresee it ([`crate::kinds::Job::sampled_size`]), checked against
/// the limits again, and its tasks cut to that size. Only a job of at least
/// [`crate::jobs::cost::SAMPLE_FROM_S`] model seconds whose work is not
/// already known under its key (`admission`: queued, running or done) is
/// sampled, on the blocking pool, one sample at a time in this instance
/// (a burst of large submissions samples in turn, and those that wait longer
/// than [`SAMPLE_WAIT`] keep the model's estimate): a sample's two threads
/// never multiply beside the compute pool.
pub async fn sample(
    state: &AppState,
    prepared: Prepared,
    admission: Option<&Admission>,
) -> Result<Prepared, SubmitError> {
    let known = admission.is_some_and(|a| {
        [a.own, a.computation].into_iter().any(|s| {
            matches!(
                s,
                Some(Status::Queued | Status::Running | Status::Succeeded)
            )
        })
    });
    if known || prepared.size.cpu_s < crate::jobs::cost::SAMPLE_FROM_S {
        return Ok(prepared);
    }
    let turn = tokio::time::timeout(SAMPLE_WAIT, state.sampling.clone().acquire_owned()).await;
    let Ok(Ok(turn)) = turn else {
        return Ok(prepared);
    };
    let (prepared, sampled) = off_runtime(false, move || {
        // Held until the sample ends, even if the request is dropped.
        let _turn = turn;
        // A sample that fails in any way, a panic included, leaves the
        // model's estimate: estimating never refuses a valid job.
        let measure = || prepared.job.sampled_size(&prepared.size);
        let measured = std::panic::catch_unwind(std::panic::AssertUnwindSafe(measure));
        let sampled = measured.ok().flatten().map(|size| {
            let tasks: Vec<String> = prepared
                .job
                .split_sized(&size)
                .iter()
                .map(crate::kinds::Task::payload)
                .collect();
            (size, tasks)
        });
        (prepared, sampled)
    })
    .await?;
    let Some((size, tasks)) = sampled else {
        return Ok(prepared);
    };
    tracing::info!(
        model_work = prepared.size.work,
        model_cpu_s = prepared.size.cpu_s,
        work = size.work,
        cpu_s = size.cpu_s,
        tasks = tasks.len(),
        "sized on a sample of its work"
    );
    prepared
        .job
        .check_size(&size, &state.config.limits)
        .map_err(|mut e| {
            e.pointer = prepared.grid_pointer.clone();
            SubmitError::Limit(e)
        })?;
    Ok(Prepared {
        size,
        tasks,
        sampled: true,
        ..prepared
    })
}

/// Refuses new work while the queue is full, and a tenant's new live job
/// beyond its quota (`max_queued_per_tenant`); work already known under
/// `key` (queued, running or done) is always admitted. Returns what it read
/// of the store (nothing without limits).
pub async fn admit(
    state: &AppState,
    tenant: &str,
    key: &str,
) -> Result<Option<Admission>, SubmitError> {
    let max = state.config.max_queued;
    let quota = state.config.max_queued_per_tenant;
    if max == u64::MAX && quota.is_none() {
        return Ok(None);
    }
    let a = state.store.admission(tenant, key).await?;
    check(state, tenant, &a)?;
    Ok(Some(a))
}

/// The decision of [`admit`] on what it read.
pub fn check(state: &AppState, tenant: &str, a: &Admission) -> Result<(), SubmitError> {
    let max = state.config.max_queued;
    let quota = state.config.max_queued_per_tenant;
    let answered = |s: Option<Status>| {
        matches!(
            s,
            Some(Status::Queued | Status::Running | Status::Succeeded)
        )
    };
    // The tenant's own job for this key, live or done: it is the answer.
    if answered(a.own) {
        return Ok(());
    }
    // A computation done: a new job over it is done at once.
    if a.computation == Some(Status::Succeeded) {
        return Ok(());
    }
    if let Some(quota) = quota
        && a.live as u64 >= quota
    {
        state.metrics.rejected_full.increment(1);
        return Err(SubmitError::TenantQuota {
            tenant: tenant.to_string(),
            live: a.live,
            quota,
        });
    }
    // Joining a computation in flight queues no new work.
    if max == u64::MAX || (a.queued as u64) < max || answered(a.computation) {
        return Ok(());
    }
    state.metrics.rejected_full.increment(1);
    Err(SubmitError::QueueFull { max })
}
