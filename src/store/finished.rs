//! Computations that ended, announced to whoever waits for their jobs.
//!
//! A computation that succeeds ends every live job over it the same way:
//! status `succeeded`, progress 1, its numerics, its end time. The store
//! announces this once the transaction that wrote it has committed — its
//! own at once, and, on PostgreSQL, to every instance sharing the database
//! by LISTEN/NOTIFY (the notification sent in that transaction, so
//! delivered only if it commits) — so that a request waiting for a job has
//! the finished job without reading it again. A computation that failed or was canceled is
//! announced without its end ([`Finished::end`] `None`): its waiters read
//! their jobs again, as does a waiter that read its job while it was still
//! queued (its start, written when a worker claimed it, is not announced).

use serde::{Deserialize, Serialize};
use tokio::sync::broadcast;
use uuid::Uuid;

use super::{JobRecord, Status};

/// Announcements held for a subscriber that has not read them yet; one that
/// falls further behind reads its jobs again.
const BACKLOG: usize = 1024;

/// A computation that ended.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Finished {
    /// The computation.
    pub computation: Uuid,
    /// How it ended, if it succeeded (what every live job over it became).
    pub end: Option<End>,
}

/// What a succeeded computation wrote into each of its live jobs.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct End {
    /// Its numerics summary (JSON text).
    pub numerics: String,
    /// When it ended (RFC 3339).
    pub finished_at: String,
}

impl Finished {
    /// A computation that ended otherwise than by succeeding (or whose end
    /// is not at hand): its waiters read their jobs again.
    pub fn ended(computation: Uuid) -> Self {
        Finished {
            computation,
            end: None,
        }
    }

    /// A computation that succeeded at `finished_at` with `numerics`.
    pub fn succeeded(computation: Uuid, numerics: &str, finished_at: &str) -> Self {
        Finished {
            computation,
            end: Some(End {
                numerics: numerics.to_string(),
                finished_at: finished_at.to_string(),
            }),
        }
    }

    /// `job` (read while it was running) as the store now holds it, if
    /// this announcement says: its computation succeeded. `None` for
    /// another computation's job, a job that had finished already, a job
    /// read before it started (the store has written its start since, when
    /// a worker claimed it), or an end that is not known.
    pub fn apply(&self, job: &JobRecord) -> Option<JobRecord> {
        let end = self.end.as_ref()?;
        if job.computation != self.computation || job.status.is_final() {
            return None;
        }
        Some(JobRecord {
            status: Status::Succeeded,
            progress: 1.0,
            error: None,
            numerics: Some(end.numerics.clone()),
            started_at: Some(job.started_at.clone()?),
            finished_at: Some(end.finished_at.clone()),
            ..job.clone()
        })
    }

    /// The payload of its PostgreSQL notification: JSON, within the 8,000
    /// bytes a payload may hold (one that would not fit is sent without its
    /// end, and its waiters read their jobs again).
    pub fn payload(&self) -> String {
        let text = serde_json::to_string(self).unwrap_or_default();
        if text.len() < 7900 {
            return text;
        }
        serde_json::to_string(&Finished::ended(self.computation)).unwrap_or_default()
    }

    /// The announcement a notification's payload holds, if it reads as one.
    pub fn from_payload(payload: &str) -> Option<Finished> {
        serde_json::from_str(payload).ok()
    }
}

/// Where the computations that ended are announced.
#[derive(Debug, Clone)]
pub struct Announcer(broadcast::Sender<Finished>);

impl Default for Announcer {
    fn default() -> Self {
        Announcer(broadcast::channel(BACKLOG).0)
    }
}

impl Announcer {
    /// Announces `finished` to the subscribers of this process.
    pub fn announce(&self, finished: Finished) {
        let _ = self.0.send(finished);
    }

    /// The computations that end from now on.
    pub fn subscribe(&self) -> broadcast::Receiver<Finished> {
        self.0.subscribe()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn job(status: Status, started: Option<&str>) -> JobRecord {
        JobRecord {
            id: Uuid::now_v7(),
            tenant: "t".into(),
            computation: Uuid::nil(),
            key: "k".into(),
            kind: "time_history".into(),
            spec: "{}".into(),
            status,
            progress: 0.25,
            error: None,
            numerics: None,
            created_at: "2026-01-01T00:00:00Z".into(),
            started_at: started.map(str::to_string),
            finished_at: None,
        }
    }

    #[test]
    fn a_success_ends_a_live_job_as_the_store_writes_it() {
        let f = Finished::succeeded(Uuid::nil(), "{\"steps\":3}", "2026-01-01T00:00:02Z");
        let running = f
            .apply(&job(Status::Running, Some("2026-01-01T00:00:01Z")))
            .expect("a running job of the computation");
        assert_eq!(running.status, Status::Succeeded);
        assert_eq!(running.progress, 1.0);
        assert_eq!(running.numerics.as_deref(), Some("{\"steps\":3}"));
        assert_eq!(running.started_at.as_deref(), Some("2026-01-01T00:00:01Z"));
        assert_eq!(running.finished_at.as_deref(), Some("2026-01-01T00:00:02Z"));
        // A job read while queued started since, when a worker claimed it:
        // read again.
        assert!(f.apply(&job(Status::Queued, None)).is_none());
        // Not another computation's job, not a finished one, not without an end.
        let mut other = job(Status::Running, None);
        other.computation = Uuid::now_v7();
        assert!(f.apply(&other).is_none());
        assert!(f.apply(&job(Status::Canceled, None)).is_none());
        assert!(
            Finished::ended(Uuid::nil())
                .apply(&job(Status::Running, None))
                .is_none()
        );
    }

    #[test]
    fn a_payload_reads_back_and_fits_a_notification() {
        let f = Finished::succeeded(Uuid::now_v7(), "{\"a\":1}", "2026-01-01T00:00:02Z");
        assert_eq!(Finished::from_payload(&f.payload()), Some(f.clone()));
        let long = Finished::succeeded(f.computation, &"x".repeat(9000), "t");
        let sent = Finished::from_payload(&long.payload()).expect("reads");
        assert_eq!(sent, Finished::ended(f.computation));
        assert!(Finished::from_payload("not json").is_none());
    }
}
