//! A small job computed in the request that waits for it: a job of one task
//! submitted with `?wait`, expected to take at most [`SMALL_SECONDS`], and
//! new to the store, is computed on the compute pool as soon as it arrives
//! when a compute slot is free, then stored finished — job, task and result
//! in one transaction — and answered with its result. It is never queued:
//! no claim, no wake-up, no re-read.
//!
//! What holds as for any other job:
//! - a 2xx stands for a stored job: the answer is sent only once the
//!   transaction committed; a process killed before then stored nothing and
//!   answered nothing;
//! - the compute runs on the rayon pool, in a slot counted with the workers'
//!   tasks: it starts only when fewer tasks compute here than the pool has
//!   threads, so queued work (which takes slots in fair turns) is never
//!   waited behind it for longer than one small job;
//! - identical specs are computed once: a submission of a key being computed
//!   here waits for it and then takes the ordinary path (which finds it
//!   done); a key that another instance (or a queued submission) stored
//!   meanwhile is joined as any submission joins it, the result computed
//!   here being let go;
//! - the tenant's quota and the queue's limit admit it as any submission
//!   ([`super::submit::admit`]): for a job expected to take at most
//!   [`UNREAD_SECONDS`], in the statement that stores it (its admission is
//!   read there, so the job costs the database one statement); for a longer
//!   one, before it is computed (a key found known then costs no compute).
//!   A job its limits refuse is stored nowhere and refused as any other
//!   (429 or 503); one whose key turns out known takes the ordinary path;
//! - the tenant counts as served when it is stored (fair turns), written at
//!   most every [`SERVED_EVERY`] per tenant;
//! - past the wait (or the compute-time limit), during a shutdown, or when
//!   the computation fails, the job takes the ordinary path: queued, then
//!   computed, failed or canceled by the workers as any other.

use std::collections::HashMap;
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use tokio::sync::watch;
use tracing::info;

use super::AppState;
use super::submit::{Prepared, SubmitError, admit, check};
use super::worker::{Serialised, compute};
use crate::spectrum::Control;
use crate::store::{
    Admission, AdmitLimits, DoneJob, JobRecord, NewJob, StoredDone, new_job_id, now_rfc3339,
};

/// Longest expected compute time, s, of a job computed in its request.
pub const SMALL_SECONDS: f64 = 0.05;

/// Longest expected compute time, s, of a job computed before its
/// admission is read: the read then rides on the statement that stores it.
/// A submission of a key known already (computed or queued) throws away at
/// most about this much compute before it joins that work.
pub const UNREAD_SECONDS: f64 = 0.002;

/// Longest a request waits for a compute slot to free (as small jobs
/// computed in other requests end) before its job is queued instead.
pub const SLOT_WAIT: Duration = Duration::from_millis(100);

/// How often, at most, a tenant's small jobs computed here write it as
/// served (fair turns): the order of the tenants' queued work is kept to
/// this resolution, and a tenant's small jobs in quick succession do not
/// each lock its row of `tenants` until their commit (which would make them
/// commit one after another).
pub const SERVED_EVERY: Duration = Duration::from_millis(50);

/// The owner a job computed in its request is stored as done by.
const OWNER_SUFFIX: &str = "#request";

/// The keys being computed in requests in this process, each with what
/// tells identical submissions that it is done.
#[derive(Debug, Default)]
pub struct InFlight(Mutex<HashMap<String, watch::Receiver<()>>>);

/// When this process last wrote each tenant as served by a job computed in
/// its request.
#[derive(Debug, Default)]
pub struct Served(Mutex<HashMap<String, Instant>>);

impl Served {
    /// Whether `tenant` is to be written as served now (it was not in the
    /// last [`SERVED_EVERY`]); if so, it is taken as written.
    fn due(&self, tenant: &str) -> bool {
        let mut last = self.0.lock().unwrap_or_else(|e| e.into_inner());
        let now = Instant::now();
        if last
            .get(tenant)
            .is_some_and(|t| now.duration_since(*t) < SERVED_EVERY)
        {
            return false;
        }
        if last.len() >= 4096 {
            last.retain(|_, t| now.duration_since(*t) < SERVED_EVERY);
        }
        last.insert(tenant.to_string(), now);
        true
    }
}

/// A key computed in a request, until dropped.
struct Computing<'a> {
    flight: &'a InFlight,
    key: String,
    _done: watch::Sender<()>,
}

impl Drop for Computing<'_> {
    fn drop(&mut self) {
        let mut keys = self.flight.0.lock().unwrap_or_else(|e| e.into_inner());
        keys.remove(&self.key);
    }
}

impl InFlight {
    /// Marks `key` as computed here; else what says when its computation
    /// here ends.
    fn start(&self, key: &str) -> Result<Computing<'_>, watch::Receiver<()>> {
        let mut keys = self.0.lock().unwrap_or_else(|e| e.into_inner());
        if let Some(rx) = keys.get(key) {
            return Err(rx.clone());
        }
        let (tx, rx) = watch::channel(());
        keys.insert(key.to_string(), rx);
        Ok(Computing {
            flight: self,
            key: key.to_string(),
            _done: tx,
        })
    }
}

/// A compute slot taken by a request, given back (and its computation
/// stopped, if it still runs) when dropped.
struct Slot<'a> {
    state: &'a AppState,
    id: uuid::Uuid,
    control: Arc<Control>,
}

impl Drop for Slot<'_> {
    fn drop(&mut self) {
        self.control.cancel();
        self.state.unregister(self.id, 0);
    }
}

/// Registers computation `id` in a compute slot as soon as one is free,
/// within `limit`: whether it was.
async fn take_slot(
    state: &AppState,
    id: uuid::Uuid,
    control: &Arc<Control>,
    limit: Duration,
) -> bool {
    let deadline = tokio::time::Instant::now() + limit;
    loop {
        // Listening before looking: a slot freed in between is not missed.
        let freed = state.freed.notified();
        tokio::pin!(freed);
        freed.as_mut().enable();
        if state.try_register(id, 0, control.clone()) {
            return true;
        }
        if tokio::time::timeout_at(deadline, freed).await.is_err() {
            return false;
        }
    }
}

/// What became of a job offered to be computed in its request.
pub enum Inline {
    /// Computed and stored: the job, and its result document.
    Done(Box<JobRecord>, String),
    /// Admitted, but not computed here: it takes the ordinary path,
    /// waiting at most this long.
    Declined(Duration),
}

/// Whether the prepared job is offered to be computed in its request: one
/// task, no stored records, expected to take at most [`SMALL_SECONDS`], and
/// the service not stopping.
pub fn offered(state: &AppState, prepared: &Prepared) -> bool {
    prepared.tasks.len() == 1
        && prepared.records.is_empty()
        && !*state.stopping.borrow()
        && state
            .throughput
            .seconds(prepared.job.kind(), &prepared.size)
            <= SMALL_SECONDS
}

/// The limits of the service's configuration, as the store checks them.
fn limits(state: &AppState) -> AdmitLimits {
    let config = &state.config;
    AdmitLimits {
        quota: config
            .max_queued_per_tenant
            .and_then(|q| i64::try_from(q).ok()),
        max_queued: (config.max_queued != u64::MAX)
            .then(|| i64::try_from(config.max_queued).ok())
            .flatten(),
    }
}

/// Admits the tenant's prepared job (deciding on `read`, what its admission
/// read, if it did; else reading it), computes it in this request and
/// stores it finished when it is new and a compute slot is free (see
/// [`offered`] for which jobs are offered); `wait` is how long the client
/// waits. A job the limits refuse is an error, as from
/// [`super::submit::admit`].
pub async fn run(
    state: &AppState,
    tenant: &str,
    prepared: &Prepared,
    wait: Duration,
) -> Result<Inline, SubmitError> {
    let arrived = Instant::now();
    // Declined (after its admission): the ordinary path takes it.
    let declined = async |read: Option<Admission>| -> Result<Inline, SubmitError> {
        match read {
            Some(a) => check(state, tenant, &a)?,
            None => {
                admit(state, tenant, &prepared.key).await?;
            }
        }
        Ok(Inline::Declined(wait.saturating_sub(arrived.elapsed())))
    };
    if wait.is_zero() || !offered(state, prepared) {
        return declined(None).await;
    }
    let computing = match state.in_flight.start(&prepared.key) {
        Ok(c) => c,
        Err(mut done) => {
            // The same spec computes here: its stored job answers this one.
            let _ = tokio::time::timeout(wait, done.changed()).await;
            return declined(None).await;
        }
    };
    let kind = prepared.job.kind();
    // A longer job's admission is read before it is computed: a key known
    // already costs no compute.
    let read = if state.throughput.seconds(kind, &prepared.size) > UNREAD_SECONDS {
        let a = state.store.admission(tenant, &prepared.key).await?;
        check(state, tenant, &a)?;
        if a.computation.is_some() {
            return Ok(Inline::Declined(wait.saturating_sub(arrived.elapsed())));
        }
        Some(a)
    } else {
        None
    };
    let id = new_job_id();
    let control = Arc::new(Control::new());
    if !take_slot(state, id, &control, SLOT_WAIT.min(wait / 2)).await {
        return declined(read).await;
    }
    let slot = Slot { state, id, control };
    let created = now_rfc3339();
    let started = Instant::now();
    let rx = compute(
        state,
        crate::kinds::Task::whole(prepared.job.clone()),
        slot.control.clone(),
    );
    let limit = wait.min(state.config.job_timeout);
    let Ok(Ok(Ok(Serialised { body, numerics }))) = tokio::time::timeout(limit, rx).await else {
        // Too slow, failed or lost: the workers take it from here.
        return declined(read).await;
    };
    let seconds = started.elapsed().as_secs_f64();
    let busy = state.busy() as f64;
    drop(slot);
    state.throughput.record(kind, &prepared.size, seconds, busy);
    state.metrics.compute_seconds(kind, seconds);
    let owner = format!("{}{OWNER_SUFFIX}", state.config.instance);
    let finished = now_rfc3339();
    let stored = state
        .store
        .store_done(DoneJob {
            new: NewJob {
                tenant,
                id,
                key: &prepared.key,
                kind,
                spec: &prepared.spec,
                now: &created,
                tasks: &prepared.tasks,
                records: &prepared.records,
            },
            owner: &owner,
            started: &created,
            finished: &finished,
            body: &body,
            numerics: &numerics,
            serve: state.served.due(tenant),
            limits: limits(state),
        })
        .await?;
    drop(computing);
    let record = match stored {
        StoredDone::Stored(record) => record,
        // Its key is known (it joins that work), or the limits refuse it.
        StoredDone::NotStored(a) => return declined(Some(a)).await,
    };
    state.results.put(id, &prepared.key, &body);
    state.metrics.submitted.increment(1);
    state.announce(id);
    info!(job_id = %id, seconds, "computed in its request");
    Ok(Inline::Done(record, body))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_tenant_is_written_as_served_at_most_once_a_period() {
        let served = Served::default();
        assert!(served.due("a"));
        assert!(!served.due("a"), "again within the period");
        assert!(served.due("b"), "another tenant");
        std::thread::sleep(SERVED_EVERY + Duration::from_millis(5));
        assert!(served.due("a"), "after the period");
    }
}
