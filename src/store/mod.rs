//! Persistence of jobs, computations and results: one trait, one
//! implementation over both SQL dialects ([`sql::SqlStore`]), whose
//! differences live in [`dialect`].

/// Runs `$body` (an `async` block over `conn: &mut DB::Connection`) on one
/// of the store's connections for writes, in its turn ([`writer::Writing`]),
/// settling it afterwards.
macro_rules! in_write_turn {
    ($store:expr, |$conn:ident| $body:expr) => {{
        let store = $store;
        let mut writing = store.writing().await?;
        let result = {
            let $conn: &mut DB::Connection = writing.conn();
            $body.await
        };
        store.settle(&mut writing, &result).await;
        result
    }};
}

pub mod deletions;
pub mod dialect;
pub mod finished;
pub mod migrations;
pub mod postgres;
pub mod records;
pub mod sql;
pub mod sqlite;
pub mod writer;

use std::future::Future;
use std::pin::Pin;
use std::sync::Arc;
use std::time::Duration;

use serde::Serialize;
use uuid::Uuid;

pub use deletions::{Deletion, Deletions};
pub use finished::{Announcer, Finished};

/// A boxed future, so that the trait can be used as `dyn JobStore`.
pub type BoxFuture<'a, T> = Pin<Box<dyn Future<Output = T> + Send + 'a>>;

/// Storage errors.
#[derive(Debug, thiserror::Error)]
pub enum StoreError {
    /// The database failed.
    #[error("database: {0}")]
    Database(#[from] sqlx::Error),
    /// Migrations failed.
    #[error("migration: {0}")]
    Migrate(#[from] sqlx::migrate::MigrateError),
    /// A row could not be decoded.
    #[error("corrupt row: {0}")]
    Corrupt(String),
    /// Writes failed moments ago (full disk, database unavailable).
    #[error("writes failing: {0}")]
    WritesFailing(String),
}

/// What a storage failure means for a client.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Failure {
    /// The disk (or the database's quota) is full: retry once space frees.
    NoSpace,
    /// The database is unreachable, busy, restarting or failing I/O: retry soon.
    Unavailable,
    /// Anything else (a bug, a corrupt row).
    Other,
}

impl StoreError {
    /// What this failure means for a client.
    pub fn failure(&self) -> Failure {
        match self {
            StoreError::Database(e) => match e {
                sqlx::Error::Database(db) => {
                    let code = db.code().unwrap_or_default();
                    // SQLite: the primary result code is the low byte of the
                    // extended one. PostgreSQL: SQLSTATE.
                    match code.parse::<i64>().map(|c| c & 0xff) {
                        Ok(13) => Failure::NoSpace,                       // SQLITE_FULL
                        Ok(5 | 6 | 10 | 14 | 15) => Failure::Unavailable, // BUSY, LOCKED, IOERR, CANTOPEN, PROTOCOL
                        _ => match code.as_ref() {
                            "53100" => Failure::NoSpace, // disk_full
                            c if c.starts_with("08")      // connection exception
                                || c.starts_with("53")    // insufficient resources
                                || c.starts_with("57P")   // operator intervention
                                || c == "40001"           // serialization failure
                                || c == "40P01" =>
                            // deadlock
                            {
                                Failure::Unavailable
                            }
                            _ => Failure::Other,
                        },
                    }
                }
                sqlx::Error::Io(_)
                | sqlx::Error::Tls(_)
                | sqlx::Error::Protocol(_)
                | sqlx::Error::PoolTimedOut
                | sqlx::Error::PoolClosed
                | sqlx::Error::WorkerCrashed => Failure::Unavailable,
                _ => Failure::Other,
            },
            StoreError::WritesFailing(_) => Failure::Unavailable,
            StoreError::Migrate(_) | StoreError::Corrupt(_) => Failure::Other,
        }
    }
}

/// The life of a job.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, utoipa::ToSchema)]
#[serde(rename_all = "lowercase")]
pub enum Status {
    /// Waiting for a worker.
    Queued,
    /// Being computed.
    Running,
    /// Done; the result is stored.
    Succeeded,
    /// The computation failed.
    Failed,
    /// Canceled by a user.
    Canceled,
}

impl Status {
    /// The name stored and shown.
    pub fn as_str(self) -> &'static str {
        match self {
            Status::Queued => "queued",
            Status::Running => "running",
            Status::Succeeded => "succeeded",
            Status::Failed => "failed",
            Status::Canceled => "canceled",
        }
    }

    /// Parses a stored name.
    pub fn parse(s: &str) -> Option<Status> {
        Some(match s {
            "queued" => Status::Queued,
            "running" => Status::Running,
            "succeeded" => Status::Succeeded,
            "failed" => Status::Failed,
            "canceled" => Status::Canceled,
            _ => return None,
        })
    }

    /// Whether the job will not change any more.
    pub fn is_final(self) -> bool {
        matches!(self, Status::Succeeded | Status::Failed | Status::Canceled)
    }

    /// All statuses.
    pub const ALL: [Status; 5] = [
        Status::Queued,
        Status::Running,
        Status::Succeeded,
        Status::Failed,
        Status::Canceled,
    ];
}

/// A tenant's job as stored: its own life (status, times, error) over a
/// computation that identical specs share (key, kind, spec, progress,
/// numerics).
#[derive(Clone, Debug, PartialEq)]
pub struct JobRecord {
    /// Identifier.
    pub id: Uuid,
    /// The tenant it belongs to.
    pub tenant: String,
    /// The computation it stands for.
    pub computation: Uuid,
    /// Cache key.
    pub key: String,
    /// Kind.
    pub kind: String,
    /// Normalised spec (JSON text).
    pub spec: String,
    /// Status.
    pub status: Status,
    /// 0..1: the mean progress of its computation's tasks (a finished task
    /// counts 1).
    pub progress: f64,
    /// Failure message.
    pub error: Option<String>,
    /// Numerics summary (JSON text), once done.
    pub numerics: Option<String>,
    /// RFC 3339 timestamps.
    pub created_at: String,
    /// When a worker started it.
    pub started_at: Option<String>,
    /// When it ended.
    pub finished_at: Option<String>,
}

/// A computation as a worker sees it.
#[derive(Clone, Debug, PartialEq)]
pub struct Computation {
    /// Identifier.
    pub id: Uuid,
    /// Cache key.
    pub key: String,
    /// Kind.
    pub kind: String,
    /// Normalised spec (JSON text).
    pub spec: String,
    /// Status.
    pub status: Status,
}

/// A task claimed by a worker.
#[derive(Clone, Debug, PartialEq)]
pub struct TaskClaim {
    /// The computation.
    pub computation: Uuid,
    /// The task's index within the computation.
    pub idx: i64,
    /// The computation's kind.
    pub kind: String,
    /// The task's own spec (JSON text).
    pub payload: String,
    /// How many times this task has been claimed (> 1 after a takeover).
    pub attempts: i64,
    /// How many tasks the computation has.
    pub tasks: i64,
}

/// A submission.
#[derive(Clone, Copy, Debug)]
pub struct NewJob<'a> {
    /// Whose job it is.
    pub tenant: &'a str,
    /// The id of the job, if a new one is made.
    pub id: Uuid,
    /// Cache key of its computation.
    pub key: &'a str,
    /// Kind.
    pub kind: &'a str,
    /// Normalised spec (JSON text).
    pub spec: &'a str,
    /// RFC 3339.
    pub now: &'a str,
    /// The task specs, should the computation be queued.
    pub tasks: &'a [String],
    /// The stored records the spec named (their samples are in the spec).
    pub records: &'a [String],
}

/// A job of one task computed already, to store finished at once.
#[derive(Clone, Copy, Debug)]
pub struct DoneJob<'a> {
    /// The submission (`now`: when it arrived; its one task, and no records).
    pub new: NewJob<'a>,
    /// Who computed it (as a worker's lease owner).
    pub owner: &'a str,
    /// When its computation started (RFC 3339).
    pub started: &'a str,
    /// When it ended (RFC 3339).
    pub finished: &'a str,
    /// Its result document (JSON text).
    pub body: &'a str,
    /// Its numerics summary (JSON text).
    pub numerics: &'a str,
    /// Whether its tenant is written as served at `started` (fair turns):
    /// a tenant's small jobs computed in quick succession need not each
    /// write, and lock, its one row of `tenants`.
    pub serve: bool,
    /// The limits it is admitted under, checked as it is stored.
    pub limits: AdmitLimits,
}

/// The limits a new job is admitted under: its tenant's live jobs below
/// `quota`, and the queue's computations below `max_queued` (`None`: no
/// limit).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct AdmitLimits {
    /// The tenant's quota of live (queued or running) jobs.
    pub quota: Option<i64>,
    /// The longest queue, in computations.
    pub max_queued: Option<i64>,
}

impl AdmitLimits {
    /// Whether `a` admits new work of a key that has no computation: the
    /// tenant is under its quota and the queue under its limit. (The
    /// PostgreSQL statement that stores a finished job says the same in
    /// SQL: `store_done_postgres.sql`.)
    pub fn admit_new(&self, a: &Admission) -> bool {
        a.computation.is_none()
            && self.quota.is_none_or(|q| a.live < q)
            && self.max_queued.is_none_or(|m| a.queued < m)
    }
}

/// What storing a finished job did.
#[derive(Clone, Debug, PartialEq)]
pub enum StoredDone {
    /// It is stored: the job as stored.
    Stored(Box<JobRecord>),
    /// Nothing is stored: its key has a computation already, or its
    /// limits did not admit it. What its admission read, to decide which.
    NotStored(Admission),
}

/// What a submission found.
#[derive(Clone, Debug, PartialEq)]
pub struct Submitted {
    /// The tenant's job (new, or its existing one for the same key).
    pub job: JobRecord,
    /// Whether existing work answers it: the tenant's own job, or another
    /// tenant's computation (queued, running or done), not new work queued.
    pub cached: bool,
}

/// What a cancellation did.
#[derive(Clone, Debug, PartialEq)]
pub struct Canceled {
    /// The job afterwards (a job already finished is returned as it is).
    pub job: JobRecord,
    /// Whether this call canceled it (it was queued or running).
    pub changed: bool,
    /// Whether its computation was stopped too: no other live job needs it.
    pub stopped: bool,
}

/// What a deletion did.
#[derive(Clone, Debug, PartialEq)]
pub enum Deleted {
    /// The job is gone (and its computation and result with it if no other
    /// job refers to them).
    Gone,
    /// The tenant has no such job.
    NotFound,
    /// The job is queued or running: cancel it first.
    NotFinished(Box<JobRecord>),
}

/// What an admission decision needs to know about a submission.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Admission {
    /// The status of the tenant's own job for this key, if any.
    pub own: Option<Status>,
    /// The status of the computation for this key, if any.
    pub computation: Option<Status>,
    /// The tenant's jobs queued or running.
    pub live: i64,
    /// Computations waiting in the queue, all tenants.
    pub queued: i64,
}

/// Filter of a listing.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ListQuery {
    /// Only this status.
    pub status: Option<Status>,
    /// Only this kind.
    pub kind: Option<String>,
    /// At most this many.
    pub limit: u32,
    /// Only jobs created before this one (ids are UUIDv7, time-ordered).
    pub before: Option<Uuid>,
}

/// Storage of jobs, the computations they share, their tasks and results.
///
/// Every write that a worker makes is conditional on holding the task's
/// lease, so a task that ran twice after a takeover is written once. Reads
/// and writes of jobs name their tenant: another tenant's job does not exist.
pub trait JobStore: records::RecordStore + Send + Sync {
    /// The tenant's job for `key`: its existing one (a failed or canceled job
    /// is queued again), or a new job over the computation with that key
    /// (shared with other tenants' jobs), which is created and queued with
    /// its tasks if there is none, or queued again if it failed or was
    /// canceled.
    fn submit<'a>(&'a self, job: NewJob<'a>) -> BoxFuture<'a, Result<Submitted, StoreError>>;
    /// Stores a job computed already as succeeded, in one transaction that
    /// first reads its admission ([`JobStore::admission`]): a new
    /// computation of its key with its one task done, its result and the
    /// tenant's job, returned as stored. Nothing is stored when a
    /// computation of its key exists (the submission then joins it as any
    /// other does) or its limits do not admit new work
    /// ([`AdmitLimits::admit_new`]); what the admission read is returned.
    fn store_done<'a>(&'a self, done: DoneJob<'a>)
    -> BoxFuture<'a, Result<StoredDone, StoreError>>;
    /// The tenant's job.
    fn get<'a>(
        &'a self,
        tenant: &'a str,
        id: Uuid,
    ) -> BoxFuture<'a, Result<Option<JobRecord>, StoreError>>;
    /// The result document of a succeeded computation.
    fn result(&self, computation: Uuid) -> BoxFuture<'_, Result<Option<String>, StoreError>>;
    /// The tenant's jobs, newest first.
    fn list<'a>(
        &'a self,
        tenant: &'a str,
        q: &'a ListQuery,
    ) -> BoxFuture<'a, Result<Vec<JobRecord>, StoreError>>;
    /// Cancels the tenant's queued or running job; its computation stops
    /// only if no other live job needs it.
    fn cancel<'a>(
        &'a self,
        tenant: &'a str,
        id: Uuid,
        now: &'a str,
    ) -> BoxFuture<'a, Result<Option<Canceled>, StoreError>>;
    /// Deletes the tenant's finished job; its computation, tasks and result
    /// go once no job refers to them.
    fn delete<'a>(
        &'a self,
        tenant: &'a str,
        id: Uuid,
    ) -> BoxFuture<'a, Result<Deleted, StoreError>>;
    /// Deletes every finished job that finished before `before` (RFC 3339),
    /// with the computations no job refers to any more; returns the jobs
    /// deleted.
    fn purge<'a>(&'a self, before: &'a str) -> BoxFuture<'a, Result<u64, StoreError>>;
    /// What admitting a submission of `key` by `tenant` needs to know.
    fn admission<'a>(
        &'a self,
        tenant: &'a str,
        key: &'a str,
    ) -> BoxFuture<'a, Result<Admission, StoreError>>;
    /// Claims a task for `owner` for `lease` and marks its computation and
    /// jobs running: a task whose lease lapsed first; else a queued task by
    /// round robin — the tenant served longest ago, its computation served
    /// longest ago, its first queued task.
    fn claim<'a>(
        &'a self,
        owner: &'a str,
        now: &'a str,
        lease: Duration,
    ) -> BoxFuture<'a, Result<Option<TaskClaim>, StoreError>> {
        self.claim_in(owner, now, lease, false)
    }
    /// As [`JobStore::claim`], among the computations already running only
    /// when `started_only` (a stopping instance finishes what it began,
    /// within its grace period, and starts nothing new).
    fn claim_in<'a>(
        &'a self,
        owner: &'a str,
        now: &'a str,
        lease: Duration,
        started_only: bool,
    ) -> BoxFuture<'a, Result<Option<TaskClaim>, StoreError>>;
    /// Renews the task's lease and records its progress; returns the
    /// computation's status (one canceled meanwhile reads `Canceled`), or
    /// `None` when the lease was lost.
    fn heartbeat<'a>(
        &'a self,
        computation: Uuid,
        idx: i64,
        owner: &'a str,
        progress: f64,
        lease: Duration,
    ) -> BoxFuture<'a, Result<Option<Status>, StoreError>>;
    /// Stores a task's result if `owner` still holds it.
    fn complete<'a>(
        &'a self,
        computation: Uuid,
        idx: i64,
        owner: &'a str,
        result: &'a str,
    ) -> BoxFuture<'a, Result<bool, StoreError>>;
    /// For a computation of one task: stores its result as the computation's
    /// and marks it and its live jobs succeeded, in one transaction, if
    /// `owner` still holds the task.
    fn complete_only<'a>(
        &'a self,
        computation: Uuid,
        idx: i64,
        owner: &'a str,
        body: &'a str,
        numerics: &'a str,
        now: &'a str,
    ) -> BoxFuture<'a, Result<bool, StoreError>>;
    /// The task results in order, once every task is done.
    fn parts(&self, computation: Uuid) -> BoxFuture<'_, Result<Option<Vec<String>>, StoreError>>;
    /// Stores the assembled result and marks the computation and its live
    /// jobs succeeded (once).
    fn succeed<'a>(
        &'a self,
        computation: Uuid,
        body: &'a str,
        numerics: &'a str,
        now: &'a str,
    ) -> BoxFuture<'a, Result<bool, StoreError>>;
    /// Marks the computation and its live jobs failed and cancels its other
    /// tasks.
    fn fail<'a>(
        &'a self,
        computation: Uuid,
        error: &'a str,
        now: &'a str,
    ) -> BoxFuture<'a, Result<bool, StoreError>>;
    /// Returns a task to the queue (shutdown without finishing it).
    fn requeue<'a>(
        &'a self,
        computation: Uuid,
        idx: i64,
        owner: &'a str,
    ) -> BoxFuture<'a, Result<bool, StoreError>>;
    /// At start-up: what a single-instance store left running is requeued (a
    /// shared store leaves it to the leases). Returns the tasks requeued.
    fn recover(&self) -> BoxFuture<'_, Result<u64, StoreError>>;
    /// Computations not yet final whose tasks are all done: a process
    /// stopped between storing the last task and assembling the result.
    fn stranded(&self) -> BoxFuture<'_, Result<Vec<Uuid>, StoreError>>;
    /// One computation.
    fn computation(&self, id: Uuid) -> BoxFuture<'_, Result<Option<Computation>, StoreError>>;
    /// Number of jobs per status, all tenants.
    fn counts(&self) -> BoxFuture<'_, Result<Vec<(Status, i64)>, StoreError>>;
    /// Whether the database answers.
    fn ping(&self) -> BoxFuture<'_, Result<(), StoreError>>;
    /// Whether the database takes writes: after a write failed for want of
    /// space or of the database, this tries one; `Ok` otherwise.
    fn writable(&self) -> BoxFuture<'_, Result<(), StoreError>>;
    /// Waits until another instance may have queued work (PostgreSQL
    /// LISTEN/NOTIFY); a store of one instance never resolves.
    fn queued_elsewhere(&self) -> BoxFuture<'_, ()>;
    /// Tells other instances that work was queued.
    fn announce_queued(&self) -> BoxFuture<'_, ()>;
    /// The deletions of finished jobs by [`JobStore::delete`] and
    /// [`JobStore::purge`], announced as they commit: this instance's, and
    /// (PostgreSQL) every other instance's sharing the database.
    fn deletions(&self) -> Arc<Deletions>;
    /// The computations that ended, announced as they commit: a success by
    /// the store itself (with the end its jobs took), this instance's and
    /// (PostgreSQL) every other instance's sharing the database.
    fn finished(&self) -> Announcer;
}

/// A new job id: a UUIDv7 (RFC 9562) whose first 48 bits are the creation
/// time in milliseconds and the next 12 (`rand_a`) its fraction of a
/// millisecond (§6.2, method 3), so that ids sort by age even for jobs made
/// within one millisecond — in this process strictly, each id after the
/// last; its other 62 bits come from the operating system's random source:
/// knowing one job's id tells nothing about another's.
pub fn new_job_id() -> Uuid {
    static LAST: std::sync::Mutex<u64> = std::sync::Mutex::new(0);
    let since = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .unwrap_or_default();
    // Milliseconds, then 4,096ths of a millisecond (about 244 ns).
    let ms = since.as_millis() as u64 & ((1 << 48) - 1);
    let sub = u64::from(since.subsec_nanos() % 1_000_000) * 4096 / 1_000_000;
    let tick = {
        let mut last = LAST.lock().unwrap_or_else(|e| e.into_inner());
        *last = (ms << 12 | sub).max(*last + 1);
        *last
    };
    let random = *Uuid::new_v4().as_bytes();
    let mut bytes = [0u8; 16];
    bytes[..6].copy_from_slice(&(tick >> 12).to_be_bytes()[2..]);
    bytes[6] = 0x70 | ((tick >> 8) & 0x0F) as u8;
    bytes[7] = (tick & 0xFF) as u8;
    bytes[8] = 0x80 | (random[8] & 0x3F);
    bytes[9..].copy_from_slice(&random[9..]);
    Uuid::from_bytes(bytes)
}

/// Now, as RFC 3339 UTC with microseconds (sorts as text).
pub fn now_rfc3339() -> String {
    rfc3339(std::time::SystemTime::now())
}

/// RFC 3339 UTC text of an instant.
pub fn rfc3339(t: std::time::SystemTime) -> String {
    let d = t.duration_since(std::time::UNIX_EPOCH).unwrap_or_default();
    let secs = d.as_secs() as i64;
    let micros = d.subsec_micros();
    let days = secs.div_euclid(86_400);
    let sod = secs.rem_euclid(86_400);
    // Civil date from days since 1970-01-01 (Howard Hinnant's algorithm).
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z - era * 146_097;
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let y = yoe + era * 400;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let day = doy - (153 * mp + 2) / 5 + 1;
    let month = if mp < 10 { mp + 3 } else { mp - 9 };
    let year = if month <= 2 { y + 1 } else { y };
    format!(
        "{year:04}-{month:02}-{day:02}T{:02}:{:02}:{:02}.{micros:06}Z",
        sod / 3600,
        (sod % 3600) / 60,
        sod % 60
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn job_ids_made_in_one_millisecond_share_nothing_but_their_time() {
        let ids: Vec<u128> = (0..64).map(|_| new_job_id().as_u128()).collect();
        // rand_b, the 62 bits after the variant: random, not a counter.
        let random = |id: u128| id & ((1 << 62) - 1);
        for pair in ids.windows(2) {
            let differing = (random(pair[0]) ^ random(pair[1])).count_ones();
            // Random bits differ in 31 of 62 on average; a counter that steps
            // by one in one or two.
            assert!(differing >= 12, "{:x} {:x}", pair[0], pair[1]);
        }
        assert!(ids.iter().all(|&id| {
            let id = Uuid::from_u128(id);
            id.get_version_num() == 7 && id.get_variant() == uuid::Variant::RFC4122
        }));
        // Made one after another, they sort in that order, as text too.
        assert!(ids.windows(2).all(|p| p[0] < p[1]));
        let text: Vec<String> = ids
            .iter()
            .map(|&id| Uuid::from_u128(id).to_string())
            .collect();
        assert!(text.windows(2).all(|p| p[0] < p[1]));
        // Their time is now's, to the millisecond.
        let ms = (ids[0] >> 80) as u64;
        let now = std::time::SystemTime::now()
            .duration_since(std::time::UNIX_EPOCH)
            .expect("after 1970")
            .as_millis() as u64;
        assert!(now >= ms && now - ms < 5_000, "{ms} {now}");
    }
    use std::time::{Duration, UNIX_EPOCH};

    #[test]
    fn rfc3339_formats_known_instants() {
        assert_eq!(rfc3339(UNIX_EPOCH), "1970-01-01T00:00:00.000000Z");
        let t = UNIX_EPOCH + Duration::from_micros(1_795_000_000_123_456);
        assert_eq!(rfc3339(t), "2026-11-18T11:06:40.123456Z");
        let leap = UNIX_EPOCH + Duration::from_secs(951_782_400); // 2000-02-29
        assert_eq!(rfc3339(leap), "2000-02-29T00:00:00.000000Z");
    }
}
