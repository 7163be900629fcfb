//! Workers: claim a queued job, compute it on the rayon pool (never on the
//! async runtime), keep its lease alive, store the outcome.

use std::sync::Arc;
use std::time::{Duration, Instant, SystemTime};

use tokio::sync::{oneshot, watch};
use tracing::{Instrument, info, info_span, warn};

use super::AppState;
use crate::jobs::{Job, JobError};
use crate::spectrum::Control;
use crate::store::{JobRecord, Status, now_rfc3339, rfc3339};

fn lease_until(state: &AppState) -> String {
    rfc3339(SystemTime::now() + state.config.lease)
}

/// Runs worker `n` until shutdown.
pub async fn run(state: AppState, n: usize, mut shutdown: watch::Receiver<bool>) {
    let owner = format!("{}#{n}", state.config.instance);
    loop {
        if *shutdown.borrow() {
            break;
        }
        let claimed = state
            .store
            .claim(&owner, &now_rfc3339(), &lease_until(&state))
            .await;
        match claimed {
            Ok(Some(job)) => {
                let span = info_span!("job", job_id = %job.id, kind = %job.kind);
                execute(&state, &owner, job, &mut shutdown)
                    .instrument(span)
                    .await;
            }
            Ok(None) => {
                // Idle: wait for a submission, a shutdown, or poll again (jobs
                // whose lease lapsed elsewhere, or queued by another instance).
                tokio::select! {
                    _ = state.wake.notified() => {}
                    _ = shutdown.changed() => {}
                    _ = tokio::time::sleep(state.idle_poll) => {}
                }
            }
            Err(e) => {
                warn!(error = %e, "claiming a job failed");
                tokio::select! {
                    _ = shutdown.changed() => {}
                    _ = tokio::time::sleep(Duration::from_millis(500)) => {}
                }
            }
        }
    }
}

/// How the computation ended, as seen by the worker.
enum Outcome {
    Done(Result<serde_json::Value, JobError>),
    Lost,
}

async fn execute(
    state: &AppState,
    owner: &str,
    record: JobRecord,
    shutdown: &mut watch::Receiver<bool>,
) {
    let id = record.id;
    info!("started");
    let job = match serde_json::from_str::<serde_json::Value>(&record.spec)
        .map_err(|e| e.to_string())
        .and_then(|v| Job::from_value(&v).map_err(|e| e.to_string()))
    {
        Ok(job) => job,
        Err(e) => {
            warn!(error = %e, "stored spec no longer validates");
            let _ = state
                .store
                .fail(id, owner, &format!("invalid spec: {e}"), &now_rfc3339())
                .await;
            state.announce(id);
            return;
        }
    };
    let control = Arc::new(Control::new());
    state.register(id, control.clone());
    let (tx, mut rx) = oneshot::channel();
    let started = Instant::now();
    {
        let control = control.clone();
        state.pool.spawn(move || {
            // A panic is reported as a failed job, never taken down with the pool.
            let r = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| job.run(&control)));
            if let Ok(r) = r {
                let _ = tx.send(r);
            }
        });
    }
    let mut stopping_since: Option<Instant> = None;
    let outcome = loop {
        tokio::select! {
            done = &mut rx => {
                break match done {
                    Ok(r) => Outcome::Done(r),
                    Err(_) => Outcome::Lost,
                };
            }
            _ = tokio::time::sleep(state.config.heartbeat) => {
                match state.store.heartbeat(id, owner, control.progress(), &lease_until(state)).await {
                    Ok(Some(Status::Canceled)) => control.cancel(),
                    Ok(_) => {}
                    Err(e) => warn!(error = %e, "heartbeat failed"),
                }
                if let Some(since) = stopping_since
                    && since.elapsed() >= state.config.shutdown_grace
                {
                    control.cancel();
                }
            }
            _ = shutdown.changed(), if stopping_since.is_none() => {
                if *shutdown.borrow() {
                    stopping_since = Some(Instant::now());
                }
            }
        }
    };
    state.unregister(id);
    let seconds = started.elapsed().as_secs_f64();
    let now = now_rfc3339();
    match outcome {
        Outcome::Done(Ok(result)) => {
            state.metrics.compute_seconds(&record.kind, seconds);
            let numerics = result
                .get("numerics")
                .map(|n| n.to_string())
                .unwrap_or_else(|| "null".into());
            let body = result.to_string();
            match state.store.succeed(id, owner, &body, &numerics, &now).await {
                Ok(true) => {
                    state.results.put(id, Arc::from(body.as_str()));
                    info!(seconds, "succeeded");
                }
                Ok(false) => info!("finished after it was canceled or taken over"),
                Err(e) => warn!(error = %e, "storing the result failed"),
            }
        }
        Outcome::Done(Err(JobError::Canceled)) => {
            if stopping_since.is_some() {
                // Shutdown outlasted the grace period: the job runs again later.
                let _ = state.store.requeue(id, owner).await;
                info!("requeued at shutdown");
            } else {
                info!("canceled");
            }
        }
        Outcome::Done(Err(e)) => {
            warn!(error = %e, "failed");
            let _ = state.store.fail(id, owner, &e.to_string(), &now).await;
        }
        Outcome::Lost => {
            warn!("the computation panicked");
            let _ = state
                .store
                .fail(id, owner, "internal error in the computation", &now)
                .await;
        }
    }
    state.announce(id);
}
