//! Succeeded jobs in memory, read without a round trip to the database.
//!
//! A succeeded job never changes: its status, times, numerics and result
//! are final, and a submission of its spec finds it as it is. Only its
//! deletion ends it — by its tenant, by retention, or by another instance
//! sharing the database — and the store announces every deletion as it
//! commits ([`crate::store::Deletions`]). So:
//!
//! - a job is kept once read from the database as succeeded, and read from
//!   memory afterwards;
//! - a deletion announced forgets the job; a purge, or announcements that
//!   may have been missed, forget every job;
//! - a job read from the database is kept only if no deletion was announced
//!   since the read began, so that a read overtaken by a deletion never
//!   outlives it;
//! - while deletions are not heard (PostgreSQL: the notification connection
//!   is down) nothing is read from memory or kept;
//! - an entry is read from the database again after [`MAX_AGE`], however
//!   things went;
//! - jobs that failed or were canceled are not kept: a submission of their
//!   spec queues them again, and a canceled job's progress follows its
//!   computation while another tenant's job still needs it;
//! - the tenant is part of the entry: another tenant's read of the id is not
//!   answered from memory but by the database, as ever (no such job), in the
//!   time a job that does not exist takes;
//! - memory stays within [`MEMORY`] bytes, the jobs read longest ago let go
//!   first.

use std::sync::{Arc, Mutex, OnceLock};
use std::time::{Duration, Instant};

use tokio::sync::broadcast::{self, error::TryRecvError};
use uuid::Uuid;

use super::AppState;
use super::lru::Lru;
use crate::store::{Deletion, Deletions, JobRecord, Status, StoreError};

/// Most bytes of succeeded jobs held (their specs and status documents).
pub const MEMORY: usize = 32 << 20;

/// An entry older than this is read from the database again: the bound on
/// how long a deletion could go unseen should its announcement be lost
/// without the connection that carries it noticing.
pub const MAX_AGE: Duration = Duration::from_secs(10);

/// What a job weighs besides its spec twice (in the record and in its
/// status document): the rest of the record and of the document.
const OVERHEAD: usize = 2048;

/// A succeeded job as held in memory.
#[derive(Debug)]
pub struct SucceededJob {
    /// The job as the database gave it.
    pub record: JobRecord,
    /// When the read that gave it began.
    read_at: Instant,
    /// Its status document as served, made by the first read of it.
    pub status: OnceLock<Rendered>,
}

/// A document as served: its entity tag and its bytes.
#[derive(Clone, Debug)]
pub struct Rendered {
    /// The entity tag.
    pub etag: String,
    /// The body.
    pub body: Arc<[u8]>,
}

/// The moment a read from the database began, for [`SucceededJobs::keep`].
#[derive(Clone, Copy, Debug)]
pub struct Ticket {
    generation: u64,
    at: Instant,
}

/// Succeeded jobs by id.
#[derive(Debug)]
pub struct SucceededJobs {
    inner: Mutex<Inner>,
    deletions: Arc<Deletions>,
}

#[derive(Debug)]
struct Inner {
    jobs: Lru<Uuid, Arc<SucceededJob>>,
    /// Counts the deletions taken in: a read that began before one is not
    /// kept.
    generation: u64,
    /// The deletions announced and not yet taken in.
    news: broadcast::Receiver<Deletion>,
}

impl Inner {
    /// Forgets what the deletions announced so far delete.
    fn catch_up(&mut self) {
        loop {
            match self.news.try_recv() {
                Ok(Deletion::Job(id)) => {
                    self.generation += 1;
                    self.jobs.remove(&id);
                }
                Ok(Deletion::Any) | Err(TryRecvError::Lagged(_)) => {
                    self.generation += 1;
                    self.jobs.clear();
                }
                Err(TryRecvError::Empty | TryRecvError::Closed) => return,
            }
        }
    }
}

impl SucceededJobs {
    /// An empty set, told of deletions by `deletions`.
    pub fn new(deletions: Arc<Deletions>) -> Self {
        SucceededJobs {
            inner: Mutex::new(Inner {
                jobs: Lru::new(MEMORY),
                generation: 0,
                news: deletions.subscribe(),
            }),
            deletions,
        }
    }

    /// The tenant's job `id` if it is held (and younger than [`MAX_AGE`]).
    pub fn get(&self, tenant: &str, id: Uuid) -> Option<Arc<SucceededJob>> {
        if !self.deletions.heard() {
            return None;
        }
        let mut inner = self.inner.lock().ok()?;
        inner.catch_up();
        let job = inner.jobs.get(&id)?.clone();
        if job.read_at.elapsed() >= MAX_AGE {
            inner.jobs.remove(&id);
            return None;
        }
        (job.record.tenant == tenant).then_some(job)
    }

    /// Taken before reading a job from the database, to keep what it reads.
    pub fn ticket(&self) -> Ticket {
        let at = Instant::now();
        let generation = self.inner.lock().map_or(u64::MAX, |mut inner| {
            inner.catch_up();
            inner.generation
        });
        Ticket { generation, at }
    }

    /// Job `record`, read from the database since `ticket`, as held in
    /// memory if it succeeded, no deletion was announced since and it fits.
    pub fn keep(&self, ticket: Ticket, record: JobRecord) -> Arc<SucceededJob> {
        let weight = OVERHEAD
            + 2 * record.spec.len()
            + record.numerics.as_ref().map_or(0, String::len)
            + record.key.len();
        let id = record.id;
        let job = Arc::new(SucceededJob {
            record,
            read_at: ticket.at,
            status: OnceLock::new(),
        });
        if job.record.status != Status::Succeeded || weight > MEMORY / 16 || !self.deletions.heard()
        {
            return job;
        }
        if let Ok(mut inner) = self.inner.lock() {
            inner.catch_up();
            if inner.generation == ticket.generation {
                inner.jobs.put(id, job.clone(), weight);
            }
        }
        job
    }

    /// Jobs held.
    pub fn len(&self) -> usize {
        self.inner.lock().map_or(0, |inner| inner.jobs.len())
    }

    /// Whether none is held.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

/// A job as read for its tenant.
#[derive(Debug)]
pub enum Read {
    /// Succeeded: from memory, or from the database and now kept.
    Succeeded(Arc<SucceededJob>),
    /// Queued, running, failed or canceled: from the database.
    Other(Box<JobRecord>),
}

/// The tenant's job `id`: from memory when it succeeded and is held there,
/// else from the database (and kept when it has succeeded); `None` when the
/// tenant has no such job.
pub async fn read(state: &AppState, tenant: &str, id: Uuid) -> Result<Option<Read>, StoreError> {
    if let Some(job) = state.succeeded.get(tenant, id) {
        state.metrics.succeeded_from_memory.increment(1);
        return Ok(Some(Read::Succeeded(job)));
    }
    let ticket = state.succeeded.ticket();
    let Some(record) = state.store.get(tenant, id).await? else {
        return Ok(None);
    };
    if record.status != Status::Succeeded {
        return Ok(Some(Read::Other(Box::new(record))));
    }
    state.metrics.succeeded_from_database.increment(1);
    Ok(Some(Read::Succeeded(state.succeeded.keep(ticket, record))))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn job(tenant: &str, status: Status) -> JobRecord {
        let id = Uuid::now_v7();
        JobRecord {
            id,
            tenant: tenant.into(),
            computation: id,
            key: "k".into(),
            kind: "time_history".into(),
            spec: "{}".into(),
            status,
            progress: 1.0,
            error: None,
            numerics: None,
            created_at: "2026-01-01T00:00:00.000000Z".into(),
            started_at: None,
            finished_at: None,
        }
    }

    fn jobs() -> (Arc<Deletions>, SucceededJobs) {
        let deletions = Arc::new(Deletions::default());
        (deletions.clone(), SucceededJobs::new(deletions))
    }

    #[test]
    fn a_succeeded_job_is_kept_for_its_tenant_only() {
        let (_, held) = jobs();
        let record = job("alice", Status::Succeeded);
        let id = record.id;
        held.keep(held.ticket(), record.clone());
        let found = held.get("alice", id).expect("kept");
        assert_eq!(found.record, record);
        assert!(held.get("bob", id).is_none());
        assert!(held.get("alice", Uuid::now_v7()).is_none());
    }

    #[test]
    fn only_succeeded_jobs_are_kept() {
        let (_, held) = jobs();
        for status in [
            Status::Queued,
            Status::Running,
            Status::Failed,
            Status::Canceled,
        ] {
            let record = job("alice", status);
            let id = record.id;
            held.keep(held.ticket(), record);
            assert!(held.get("alice", id).is_none(), "{status:?}");
        }
        assert!(held.is_empty());
    }

    #[test]
    fn a_deletion_forgets_its_job_and_a_purge_every_job() {
        let (deletions, held) = jobs();
        let (one, two) = (
            job("alice", Status::Succeeded),
            job("alice", Status::Succeeded),
        );
        let (a, b) = (one.id, two.id);
        held.keep(held.ticket(), one);
        held.keep(held.ticket(), two);
        deletions.announce(Deletion::Job(a));
        assert!(held.get("alice", a).is_none());
        assert!(held.get("alice", b).is_some());
        deletions.announce(Deletion::Any);
        assert!(held.get("alice", b).is_none());
        assert!(held.is_empty());
    }

    #[test]
    fn a_read_overtaken_by_a_deletion_is_not_kept() {
        let (deletions, held) = jobs();
        let record = job("alice", Status::Succeeded);
        let id = record.id;
        let ticket = held.ticket();
        // Another job is deleted while this one is read: it could have been
        // this one's deletion, announced after the read saw the job.
        deletions.announce(Deletion::Job(Uuid::now_v7()));
        held.keep(ticket, record.clone());
        assert!(held.get("alice", id).is_none());
        held.keep(held.ticket(), record);
        assert!(held.get("alice", id).is_some());
    }

    #[test]
    fn nothing_is_read_or_kept_while_deletions_are_not_heard() {
        let (deletions, held) = jobs();
        let record = job("alice", Status::Succeeded);
        let id = record.id;
        held.keep(held.ticket(), record.clone());
        deletions.set_heard(false);
        assert!(held.get("alice", id).is_none());
        let ticket = held.ticket();
        held.keep(ticket, record.clone());
        deletions.set_heard(true);
        // What was held before is forgotten, and a read begun while deaf is
        // not kept.
        held.keep(ticket, record.clone());
        assert!(held.get("alice", id).is_none());
        held.keep(held.ticket(), record);
        assert!(held.get("alice", id).is_some());
    }

    #[test]
    fn an_entry_is_read_again_after_max_age() {
        let (_, held) = jobs();
        let record = job("alice", Status::Succeeded);
        let id = record.id;
        let Some(at) = Instant::now().checked_sub(MAX_AGE) else {
            return;
        };
        let old = Ticket {
            at,
            ..held.ticket()
        };
        held.keep(old, record);
        assert!(held.get("alice", id).is_none());
        assert!(held.is_empty());
    }

    #[test]
    fn memory_stays_within_its_budget() {
        let (_, held) = jobs();
        let mut record = job("alice", Status::Succeeded);
        // Each weighs a little over a 64th of the budget.
        record.spec = "x".repeat(MEMORY / 128);
        let ids: Vec<Uuid> = (0..100)
            .map(|_| {
                let mut r = record.clone();
                r.id = Uuid::now_v7();
                let id = r.id;
                held.keep(held.ticket(), r);
                id
            })
            .collect();
        assert!(held.len() < 64, "{}", held.len());
        assert!(held.get("alice", ids[99]).is_some());
        assert!(held.get("alice", ids[0]).is_none());
        // Larger than a sixteenth of the budget: read from the database each time.
        record.spec = "x".repeat(MEMORY / 16);
        record.id = Uuid::now_v7();
        let id = record.id;
        held.keep(held.ticket(), record);
        assert!(held.get("alice", id).is_none());
    }
}
