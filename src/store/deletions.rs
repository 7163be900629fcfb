//! Deletions of finished jobs, announced to whoever holds jobs in memory.
//!
//! A finished job leaves the store in two ways: its tenant deletes it, or
//! retention purges it. The store announces each deletion once it has
//! committed: its own at once, and, on PostgreSQL, those of every instance
//! sharing the database (its own included) by LISTEN/NOTIFY, the
//! notification sent in the deleting transaction and so delivered only if it
//! commits. Where notifications may have been missed (the listening
//! connection was lost), [`Deletion::Any`] says so, and deletions are not
//! [`Deletions::heard`] until listening has resumed.

use std::sync::atomic::{AtomicBool, Ordering};

use tokio::sync::broadcast;
use uuid::Uuid;

/// Announcements held for a subscriber that has not read them yet; one that
/// falls further behind reads [`broadcast::error::TryRecvError::Lagged`],
/// which means [`Deletion::Any`].
const BACKLOG: usize = 1024;

/// What was deleted.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Deletion {
    /// This job.
    Job(Uuid),
    /// Any finished job may have been: a purge deleted some, or deletions
    /// may have gone unannounced (PostgreSQL: the notification connection was
    /// lost).
    Any,
}

impl Deletion {
    /// The payload of its PostgreSQL notification: the job id, or `*`.
    pub fn payload(self) -> String {
        match self {
            Deletion::Job(id) => id.to_string(),
            Deletion::Any => "*".into(),
        }
    }

    /// The deletion a notification's payload announces; one that does not
    /// read as a job id stands for any.
    pub fn from_payload(payload: &str) -> Deletion {
        Uuid::parse_str(payload).map_or(Deletion::Any, Deletion::Job)
    }
}

/// The deletions a store announces, and whether every deletion is heard now.
#[derive(Debug)]
pub struct Deletions {
    news: broadcast::Sender<Deletion>,
    heard: AtomicBool,
}

impl Default for Deletions {
    fn default() -> Self {
        let (news, _) = broadcast::channel(BACKLOG);
        Deletions {
            news,
            heard: AtomicBool::new(true),
        }
    }
}

impl Deletions {
    /// The deletions announced from now on.
    pub fn subscribe(&self) -> broadcast::Receiver<Deletion> {
        self.news.subscribe()
    }

    /// Whether every deletion committed from now on will be announced:
    /// always for a store of one instance; on PostgreSQL, while the
    /// notification connection listens.
    pub fn heard(&self) -> bool {
        self.heard.load(Ordering::Acquire)
    }

    /// Announces a deletion that has committed.
    pub fn announce(&self, deletion: Deletion) {
        // No subscriber: nobody holds jobs in memory.
        let _ = self.news.send(deletion);
    }

    /// Listening stopped (`false`: announcements may be missed from now on)
    /// or resumed (`true`). Either way any job may have been deleted unheard,
    /// which is announced: on stopping after the flag is lowered, on resuming
    /// before it is raised, so that what a reader kept meanwhile is dropped
    /// before it can be served.
    pub fn set_heard(&self, heard: bool) {
        if heard {
            self.announce(Deletion::Any);
            self.heard.store(true, Ordering::Release);
        } else {
            self.heard.store(false, Ordering::Release);
            self.announce(Deletion::Any);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn payloads_name_the_job_or_any() {
        let id = Uuid::now_v7();
        for d in [Deletion::Job(id), Deletion::Any] {
            assert_eq!(Deletion::from_payload(&d.payload()), d);
        }
        assert_eq!(Deletion::from_payload("not an id"), Deletion::Any);
    }

    #[test]
    fn losing_and_resuming_the_news_announce_any_deletion() {
        let deletions = Deletions::default();
        let mut news = deletions.subscribe();
        assert!(deletions.heard());
        deletions.set_heard(false);
        assert!(!deletions.heard());
        assert_eq!(news.try_recv().ok(), Some(Deletion::Any));
        deletions.set_heard(true);
        assert!(deletions.heard());
        assert_eq!(news.try_recv().ok(), Some(Deletion::Any));
        let id = Uuid::now_v7();
        deletions.announce(Deletion::Job(id));
        assert_eq!(news.try_recv().ok(), Some(Deletion::Job(id)));
        assert!(news.try_recv().is_err());
    }
}
