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
//! - the tenant's quota and the queue's limit are checked before, as for
//!   any submission; the tenant counts as served at that moment (fair turns),
//!   written at most every [`SERVED_EVERY`] per tenant;
//! - past the wait (or the compute-time limit), during a shutdown, or when
//!   the computation fails, the job takes the ordinary path: queued, then
//!   computed, failed or canceled by the workers as any other.

use std::collections::HashMap;
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use tokio::sync::watch;
use tracing::info;

use super::AppState;
use super::submit::{Prepared, SubmitError};
use super::worker::{Serialised, compute};
use crate::spectrum::Control;
use crate::store::{Admission, DoneJob, JobRecord, NewJob, new_job_id, now_rfc3339};

/// Longest expected compute time, s, of a job computed in its request.
pub const SMALL_SECONDS: f64 = 0.05;

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
    /// Not computed here: it takes the ordinary path, waiting at most this long.
    Declined(Duration),
}

/// Computes the tenant's prepared job in this request and stores it
/// finished, when it is small, new, and a compute slot is free; `wait` is
/// how long the client waits, `admission` what its admission read (if it
/// read the store).
pub async fn run(
    state: &AppState,
    tenant: &str,
    prepared: &Prepared,
    admission: Option<Admission>,
    wait: Duration,
) -> Result<Inline, SubmitError> {
    let arrived = Instant::now();
    let declined = |at: Instant| Ok(Inline::Declined(wait.saturating_sub(at.elapsed())));
    let kind = prepared.job.kind();
    if wait.is_zero()
        || prepared.tasks.len() != 1
        || !prepared.records.is_empty()
        || *state.stopping.borrow()
        || state.throughput.seconds(kind, &prepared.size) > SMALL_SECONDS
    {
        return declined(arrived);
    }
    let computing = match state.in_flight.start(&prepared.key) {
        Ok(c) => c,
        Err(mut done) => {
            // The same spec computes here: its stored job answers this one.
            let _ = tokio::time::timeout(wait, done.changed()).await;
            return declined(arrived);
        }
    };
    let known = match admission {
        Some(a) => a.computation.is_some(),
        None => state
            .store
            .admission(tenant, &prepared.key)
            .await?
            .computation
            .is_some(),
    };
    let id = new_job_id();
    let control = Arc::new(Control::new());
    if known || !take_slot(state, id, &control, SLOT_WAIT.min(wait / 2)).await {
        return declined(arrived);
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
        return declined(arrived);
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
        })
        .await?;
    drop(computing);
    let Some(record) = stored else {
        return declined(arrived);
    };
    state.results.put(id, &prepared.key, &body);
    state.metrics.submitted.increment(1);
    state.announce(id);
    info!(job_id = %id, seconds, "computed in its request");
    Ok(Inline::Done(Box::new(record), body))
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
