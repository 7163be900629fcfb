//! Workers: claim a task, compute it on the rayon pool (never on the async
//! runtime), keep its lease alive, store its result, and assemble the job's
//! result once all its tasks are done.

use std::sync::Arc;
use std::time::{Duration, Instant};

use serde_json::Value;
use tokio::sync::{oneshot, watch};
use tracing::{Instrument, info, info_span, warn};
use uuid::Uuid;

use super::AppState;
use crate::jobs::{JobError, SpecError};
use crate::kinds::{Job, Task};
use crate::spectrum::Control;
use crate::store::{Status, StoreError, TaskClaim, now_rfc3339};

/// Runs worker `n` until shutdown.
pub async fn run(state: AppState, n: usize, mut shutdown: watch::Receiver<bool>) {
    let owner = format!("{}#{n}", state.config.instance);
    if n == 0 {
        tokio::spawn(assemble_stranded(state.clone(), shutdown.clone()));
    }
    // Since when the service is stopping: from then on the worker takes
    // only tasks of jobs already running (a split spectrum is finished, not
    // left half done), until the grace period ends or none is left.
    let mut stopping_since: Option<Instant> = None;
    let mut whole: Whole = None;
    loop {
        if *shutdown.borrow() {
            let since = *stopping_since.get_or_insert_with(Instant::now);
            if since.elapsed() >= state.config.shutdown_grace {
                break;
            }
        }
        let stopping = stopping_since.is_some();
        let claimed = state
            .store
            .claim_in(&owner, &now_rfc3339(), state.config.lease, stopping)
            .await;
        match claimed {
            Ok(Some(task)) => {
                let span = info_span!("task", computation = %task.computation, task = task.idx, kind = %task.kind);
                execute(
                    &state,
                    &owner,
                    task,
                    &mut whole,
                    &mut shutdown,
                    &mut stopping_since,
                )
                .instrument(span)
                .await;
            }
            Ok(None) | Err(_) if stopping => break,
            Ok(None) => {
                // Idle: wait for a submission here or elsewhere, a shutdown, or
                // poll again (a lease that lapses is noticed this way).
                tokio::select! {
                    _ = state.wake.notified() => {}
                    _ = state.store.queued_elsewhere() => {}
                    _ = shutdown.changed() => {}
                    _ = tokio::time::sleep(state.idle_poll) => {}
                }
            }
            Err(e) => {
                warn!(error = %e, "claiming a task failed");
                tokio::select! {
                    _ = shutdown.changed() => {}
                    _ = tokio::time::sleep(Duration::from_millis(500)) => {}
                }
            }
        }
    }
}

/// A result document as text, with its numerics summary.
pub(super) struct Serialised {
    /// The document.
    pub body: String,
    /// Its `numerics`, as text.
    pub numerics: String,
}

/// How the computation ended, as seen by the worker.
enum Outcome {
    Done(Result<Serialised, JobError>),
    Lost,
}

/// Why the job a task computes cannot be read from what is stored.
#[derive(Debug, thiserror::Error)]
enum TaskSpecError {
    /// Its payload or spec is not JSON.
    #[error(transparent)]
    Json(#[from] serde_json::Error),
    /// It is JSON but no job (it no longer validates).
    #[error(transparent)]
    Spec(#[from] SpecError),
    /// The part it names does not fit its job.
    #[error(transparent)]
    Part(JobError),
    /// Its computation is gone from the store.
    #[error("its job is gone")]
    Gone,
    /// The store failed.
    #[error(transparent)]
    Store(#[from] StoreError),
    /// Reading it on the blocking pool stopped.
    #[error("reading the spec stopped: {0}")]
    Stopped(#[from] tokio::task::JoinError),
}

/// Why a job's result could not be made from its tasks' results.
#[derive(Debug, thiserror::Error)]
enum AssembleError {
    /// Its spec does not read.
    #[error("invalid spec: {0}")]
    Spec(TaskSpecError),
    /// Its tasks' results do not make a result.
    #[error(transparent)]
    Job(#[from] JobError),
}

fn parse(spec: &str) -> Result<Job, TaskSpecError> {
    let value = serde_json::from_str::<Value>(spec)?;
    Ok(Job::from_value(&value)?)
}

/// The computation whose spec a worker read last, parsed: the parts of a
/// fragility job name their units only, and consecutive tasks of one job
/// read its spec (which may hold a record suite) once.
type Whole = Option<(Uuid, Arc<Job>)>;

/// `f` on the blocking pool (reading specs: not work for the runtime).
async fn blocking<T: Send + 'static>(
    f: impl FnOnce() -> Result<T, TaskSpecError> + Send + 'static,
) -> Result<T, TaskSpecError> {
    tokio::task::spawn_blocking(f).await?
}

/// The job task `task` computes, read on the blocking pool: its payload, or
/// the part it names ([`Task::payload`]) of its computation's spec.
async fn task_job(
    state: &AppState,
    task: &TaskClaim,
    whole: &mut Whole,
) -> Result<Task, TaskSpecError> {
    let text = task.payload.clone();
    let payload: Value = blocking(move || Ok(serde_json::from_str(&text)?)).await?;
    if payload.get("kind").is_some() || payload.get("part").is_none() {
        return blocking(move || Ok(Task::from_spec(&payload)?)).await;
    }
    let job = match whole {
        Some((id, job)) if *id == task.computation => job.clone(),
        _ => {
            let record = state
                .store
                .computation(task.computation)
                .await?
                .ok_or(TaskSpecError::Gone)?;
            let job = Arc::new(blocking(move || parse(&record.spec)).await?);
            *whole = Some((task.computation, job.clone()));
            job
        }
    };
    let part = payload.get("part").cloned().unwrap_or(Value::Null);
    blocking(move || Task::part(&job, &part).map_err(TaskSpecError::Part)).await
}

/// A task being computed: what its worker watches while it runs and
/// reports once it ends.
struct Running<'a> {
    state: &'a AppState,
    owner: &'a str,
    task: &'a TaskClaim,
    /// The result's cache key (a job of one task is its own spec: its key
    /// names the result).
    key: String,
    control: Arc<Control>,
    started: Instant,
}

async fn execute(
    state: &AppState,
    owner: &str,
    task: TaskClaim,
    whole: &mut Whole,
    shutdown: &mut watch::Receiver<bool>,
    stopping_since: &mut Option<Instant>,
) {
    let (id, idx) = (task.computation, task.idx);
    info!(attempt = task.attempts, "task started");
    let job = match task_job(state, &task, whole).await {
        Ok(job) => job,
        Err(e) => {
            warn!(error = %e, "stored spec no longer validates");
            let _ = state
                .store
                .fail(id, &format!("invalid spec: {e}"), &now_rfc3339())
                .await;
            state.announce(id);
            return;
        }
    };
    let key = job.key();
    let size = job.size();
    let control = Arc::new(Control::new());
    state.register(id, idx, control.clone());
    let busy_at_start = state.busy();
    let started = Instant::now();
    let rx = compute(state, job, control.clone());
    let running = Running {
        state,
        owner,
        task: &task,
        key,
        control,
        started,
    };
    let (outcome, timed_out) = running.watch(rx, shutdown, stopping_since).await;
    // Tasks beside it: as it started and as it ends (itself included).
    let busy = (busy_at_start + state.busy()) as f64 / 2.0;
    state.unregister(id, idx);
    let seconds = started.elapsed().as_secs_f64();
    if matches!(outcome, Outcome::Done(Ok(_))) {
        state.throughput.record(&task.kind, &size, seconds, busy);
    }
    running
        .report(outcome, timed_out, seconds, stopping_since.is_some())
        .await;
}

/// Computes `job` on the rayon pool under `control`; its result, serialised,
/// comes through the channel returned (dropped unsent if it panicked).
pub(super) fn compute(
    state: &AppState,
    job: Task,
    control: Arc<Control>,
) -> oneshot::Receiver<Result<Serialised, JobError>> {
    let (tx, rx) = oneshot::channel();
    let engine = state.engine.clone();
    state.pool.spawn(move || {
        // A panic is reported as a failed job, never taken down with the pool.
        // The result is serialised here too: large documents stay off the runtime.
        let r = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
            engine(&job, &control).map(|result| Serialised {
                numerics: result
                    .get("numerics")
                    .map(|n| n.to_string())
                    .unwrap_or_else(|| "null".into()),
                body: result.to_string(),
            })
        }));
        if let Ok(r) = r {
            let _ = tx.send(r);
        }
    });
    rx
}

impl Running<'_> {
    /// Waits for the computation's result on `rx`, keeping the task's lease
    /// alive at each heartbeat; cancels it once its job is canceled or its
    /// lease taken over, past the grace period of a shutdown, or past the
    /// compute-time limit (then also says so).
    async fn watch(
        &self,
        mut rx: oneshot::Receiver<Result<Serialised, JobError>>,
        shutdown: &mut watch::Receiver<bool>,
        stopping_since: &mut Option<Instant>,
    ) -> (Outcome, bool) {
        let (state, control) = (self.state, &self.control);
        let (id, idx) = (self.task.computation, self.task.idx);
        let mut timed_out = false;
        let outcome = loop {
            tokio::select! {
                done = &mut rx => {
                    break match done {
                        Ok(r) => Outcome::Done(r),
                        Err(_) => Outcome::Lost,
                    };
                }
                _ = tokio::time::sleep(state.config.heartbeat) => {
                    match state.store.heartbeat(id, idx, self.owner, control.progress(), state.config.lease).await {
                        Ok(Some(Status::Queued | Status::Running)) => {}
                        // Canceled, failed elsewhere, or the lease was taken over.
                        Ok(_) => control.cancel(),
                        Err(e) => warn!(error = %e, "heartbeat failed"),
                    }
                    if let Some(since) = stopping_since
                        && since.elapsed() >= state.config.shutdown_grace
                    {
                        control.cancel();
                    }
                    if !timed_out && self.started.elapsed() >= state.config.job_timeout {
                        timed_out = true;
                        control.cancel();
                    }
                }
                _ = shutdown.changed(), if stopping_since.is_none() => {
                    if *shutdown.borrow() {
                        *stopping_since = Some(Instant::now());
                    }
                }
            }
        };
        (outcome, timed_out)
    }

    /// Stores how the computation ended, `seconds` after it started: its
    /// result (the job's own for a job of one task), or its failure; a task
    /// canceled by a shutdown (`stopping`) is queued again.
    async fn report(&self, outcome: Outcome, timed_out: bool, seconds: f64, stopping: bool) {
        let (state, owner, task) = (self.state, self.owner, self.task);
        let (id, idx) = (task.computation, task.idx);
        match outcome {
            Outcome::Done(Ok(Serialised { body, numerics })) if task.tasks == 1 => {
                // The task is the whole job: its result is the job's, in one write.
                state.metrics.compute_seconds(&task.kind, seconds);
                // Kept before it is stored: the store announces the success,
                // and its waiters then read the result here. (The cache is
                // read only for a job stored as succeeded.)
                state.results.put(id, &self.key, &body);
                match state
                    .store
                    .complete_only(id, idx, owner, &body, &numerics, &now_rfc3339())
                    .await
                {
                    // The store announced the success, with its end.
                    Ok(true) => info!(seconds, "succeeded"),
                    Ok(false) => {
                        info!("finished after its job was canceled or its lease taken over");
                        state.announce(id);
                    }
                    Err(e) => {
                        warn!(error = %e, "storing the result failed");
                        state.announce(id);
                    }
                }
            }
            Outcome::Done(Ok(Serialised { body, .. })) => {
                state.metrics.compute_seconds(&task.kind, seconds);
                match state.store.complete(id, idx, owner, &body).await {
                    Ok(true) => {
                        info!(seconds, "task done");
                        finish_job(state, id).await;
                    }
                    Ok(false) => {
                        info!("task finished after its job was canceled or its lease taken over")
                    }
                    Err(e) => warn!(error = %e, "storing the task result failed"),
                }
            }
            Outcome::Done(Err(JobError::Canceled)) if timed_out => {
                let limit = state.config.job_timeout.as_secs_f64();
                warn!(seconds, "past the compute-time limit");
                state.metrics.timed_out.increment(1);
                let reason = format!(
                    "the computation ran past this service's limit of {limit} s (job_timeout); split the job or ask the operator to raise the limit"
                );
                self.fail(&reason).await;
            }
            Outcome::Done(Err(JobError::Canceled)) => {
                if stopping {
                    // Shutdown outlasted the grace period: the task runs again later.
                    let _ = state.store.requeue(id, idx, owner).await;
                    state.store.announce_queued().await;
                    info!("task requeued at shutdown");
                } else {
                    info!("task canceled");
                }
            }
            Outcome::Done(Err(e)) => {
                warn!(error = %e, "failed");
                self.fail(&e.to_string()).await;
            }
            Outcome::Lost => {
                warn!("the computation panicked");
                self.fail("internal error in the computation").await;
            }
        }
    }

    /// Fails the task's job for `reason`, and says so to its watchers.
    async fn fail(&self, reason: &str) {
        let id = self.task.computation;
        let _ = self.state.store.fail(id, reason, &now_rfc3339()).await;
        self.state.announce(id);
    }
}

/// The jobs this process is assembling, so that the look for stranded jobs
/// does not assemble a job a second time while its last worker does.
static ASSEMBLING: std::sync::Mutex<Vec<Uuid>> = std::sync::Mutex::new(Vec::new());

/// A job marked as being assembled here, until dropped.
struct Assembling(Uuid);

impl Assembling {
    /// Marks `id`; `None` if it is being assembled already.
    fn start(id: Uuid) -> Option<Assembling> {
        let mut ids = ASSEMBLING.lock().unwrap_or_else(|e| e.into_inner());
        if ids.contains(&id) {
            return None;
        }
        ids.push(id);
        Some(Assembling(id))
    }
}

impl Drop for Assembling {
    fn drop(&mut self) {
        let mut ids = ASSEMBLING.lock().unwrap_or_else(|e| e.into_inner());
        ids.retain(|x| *x != self.0);
    }
}

/// How often [`assemble_stranded`] looks for stranded jobs.
const STRANDED_LOOK: Duration = Duration::from_millis(500);

/// At start and then every [`STRANDED_LOOK`] until shutdown, assembles the
/// jobs a stopped process left with every task done but no result — whatever
/// the queue holds, so they never wait behind it.
async fn assemble_stranded(state: AppState, mut shutdown: watch::Receiver<bool>) {
    loop {
        if *shutdown.borrow() {
            break;
        }
        finish_stranded(&state).await;
        tokio::select! {
            _ = shutdown.changed() => {}
            _ = tokio::time::sleep(STRANDED_LOOK) => {}
        }
    }
}

/// Assembles the jobs whose tasks are all done but whose result is not: a
/// process that stopped between the two leaves them so.
async fn finish_stranded(state: &AppState) {
    match state.store.stranded().await {
        Ok(ids) => {
            for id in ids {
                info!(computation = %id, "assembling a computation whose tasks were all done");
                finish_job(state, id).await;
            }
        }
        Err(e) => warn!(error = %e, "looking for stranded jobs failed"),
    }
}

/// Assembles and stores the job's result once every task is done (whichever
/// worker completes the last task does it; storing it twice is harmless).
async fn finish_job(state: &AppState, id: Uuid) {
    let Some(_assembling) = Assembling::start(id) else {
        return;
    };
    let parts = match state.store.parts(id).await {
        Ok(Some(parts)) => parts,
        Ok(None) => return,
        Err(e) => {
            warn!(error = %e, "reading task results failed");
            return;
        }
    };
    let Ok(Some(record)) = state.store.computation(id).await else {
        return;
    };
    // Reading the spec and assembling a large spectrum are not trivial:
    // keep them off the runtime.
    let (tx, rx) = oneshot::channel();
    let spec = record.spec.clone();
    state.pool.spawn(move || {
        let assembled = parse(&spec)
            .map_err(AssembleError::Spec)
            .and_then(|job| {
                let values: Vec<Value> = parts
                    .iter()
                    .filter_map(|p| serde_json::from_str(p).ok())
                    .collect();
                Ok(job.assemble(values)?)
            })
            .map(|result| {
                let numerics = result
                    .get("numerics")
                    .map(|n| n.to_string())
                    .unwrap_or_else(|| "null".into());
                (result.to_string(), numerics)
            });
        let _ = tx.send(assembled);
    });
    let (body, numerics) = match rx.await {
        Ok(Ok(done)) => done,
        Ok(Err(e)) => {
            warn!(error = %e, "assembling failed");
            let _ = state.store.fail(id, &e.to_string(), &now_rfc3339()).await;
            state.announce(id);
            return;
        }
        Err(_) => return,
    };
    // Kept before it is stored, as a task's whole result is.
    state.results.put(id, &record.key, &body);
    match state
        .store
        .succeed(id, &body, &numerics, &now_rfc3339())
        .await
    {
        // The store announced the success, with its end.
        Ok(true) => info!("succeeded"),
        Ok(false) => state.announce(id),
        Err(e) => {
            warn!(error = %e, "storing the result failed");
            state.announce(id);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A failed job's `error` reads as it always has, whatever failed.
    #[test]
    fn failures_read_as_before() {
        let not_json = serde_json::from_str::<Value>("{").expect_err("not JSON");
        let text = not_json.to_string();
        assert_eq!(TaskSpecError::from(not_json).to_string(), text);
        let e = parse(r#"{"kind": "time_history"}"#).expect_err("no block");
        let spec = match &e {
            TaskSpecError::Spec(s) => s.to_string(),
            other => panic!("not a spec error: {other}"),
        };
        assert_eq!(
            AssembleError::Spec(e).to_string(),
            format!("invalid spec: {spec}")
        );
        assert_eq!(TaskSpecError::Gone.to_string(), "its job is gone");
        let part = JobError::Task("a task's part [0,9] does not fit its fragility job".into());
        assert_eq!(
            TaskSpecError::Part(part).to_string(),
            "a task's part [0,9] does not fit its fragility job"
        );
        assert_eq!(
            AssembleError::from(JobError::Canceled).to_string(),
            "canceled"
        );
    }
}
