//! PostgreSQL storage: several instances share jobs, tasks and the cache.
//! Tasks are claimed with `FOR UPDATE SKIP LOCKED` under leases on the
//! database clock; LISTEN/NOTIFY wakes idle workers everywhere, and tells
//! every instance of the finished jobs any of them deleted.

use std::sync::Arc;
use std::time::Duration;

use sqlx::postgres::{PgListener, PgPoolOptions};
use sqlx::{PgPool, Postgres};
use tokio::sync::Notify;

use super::StoreError;
use super::deletions::{Deletion, Deletions};
use super::finished::{Announcer, Finished};
use super::sql::SqlStore;
use super::writer::Writer;

/// The channel that announces queued work (as in [`super::dialect`]'s
/// announcement).
const CHANNEL: &str = "topple_tasks";

/// The channel that announces deleted jobs (as in [`super::dialect`]'s
/// announcement of deletions).
const DELETED_CHANNEL: &str = "topple_deleted";

/// The channel that announces computations that ended (as in
/// [`super::dialect`]'s announcement of them).
const FINISHED_CHANNEL: &str = "topple_finished";

/// Longest wait for a connection: past it a request fails with 503.
const ACQUIRE_TIMEOUT: Duration = Duration::from_millis(1500);

/// A connection (pooled or a writer's) idle for longer is pinged before it is used.
const PING_IDLE: Duration = Duration::from_secs(1);

/// Longest pause between attempts to listen again after the connection was
/// lost (the pauses double from 100 ms up to it).
const LISTEN_BACKOFF_MAX: Duration = Duration::from_secs(3);

/// A listener on the three channels.
async fn listener(pool: &PgPool) -> Result<PgListener, sqlx::Error> {
    let mut l = PgListener::connect_with(pool).await?;
    // A lost connection is reported at once, not hidden behind a reconnection
    // that would have missed notifications meanwhile.
    l.eager_reconnect(false);
    l.listen_all([CHANNEL, DELETED_CHANNEL, FINISHED_CHANNEL])
        .await?;
    Ok(l)
}

/// What the listener passes on: deletions and computations that ended.
struct News {
    deletions: Arc<Deletions>,
    finished: Announcer,
}

/// Wakes idle workers at each notification on [`CHANNEL`], and announces
/// the deletions of [`DELETED_CHANNEL`] and the computations that ended of
/// [`FINISHED_CHANNEL`], for as long as the pool is open. A
/// lost connection (the database restarted, or the network failed) is
/// listened on again, with a backoff, for as long as it takes; the workers
/// poll meanwhile, deletions are not heard meanwhile, and once listening
/// resumes the workers are woken and any job may have been deleted (what
/// was said meanwhile is lost).
async fn listen(pool: PgPool, mut l: PgListener, wake: Arc<Notify>, news: News) {
    let News {
        deletions,
        finished,
    } = news;
    loop {
        match l.try_recv().await {
            Ok(Some(n)) if n.channel() == DELETED_CHANNEL => {
                deletions.announce(Deletion::from_payload(n.payload()));
            }
            Ok(Some(n)) if n.channel() == FINISHED_CHANNEL => {
                if let Some(f) = Finished::from_payload(n.payload()) {
                    finished.announce(f);
                }
            }
            Ok(Some(_)) => wake.notify_waiters(),
            // The connection was lost (`None`) or failed.
            lost => {
                if pool.is_closed() {
                    return;
                }
                deletions.set_heard(false);
                match lost {
                    Err(e) => {
                        tracing::warn!(error = %e, "lost the notification connection; listening again")
                    }
                    _ => tracing::warn!("lost the notification connection; listening again"),
                }
                let mut pause = Duration::from_millis(100);
                l = loop {
                    tokio::time::sleep(pause).await;
                    if pool.is_closed() {
                        return;
                    }
                    match listener(&pool).await {
                        Ok(l) => break l,
                        Err(e) => tracing::debug!(error = %e, "listening failed"),
                    }
                    pause = (pause * 2).min(LISTEN_BACKOFF_MAX);
                };
                tracing::info!("listening for queued tasks again, and for deletions");
                deletions.set_heard(true);
                wake.notify_waiters();
            }
        }
    }
}

/// Jobs in a PostgreSQL database.
pub type PgStore = SqlStore<Postgres>;

impl SqlStore<Postgres> {
    /// Connects to `url` (`postgres://…`), applies the migrations and starts
    /// listening for work queued and jobs deleted by other instances.
    pub async fn open(url: &str, connections: u32) -> Result<Self, StoreError> {
        let pool = PgPoolOptions::new()
            .max_connections(connections.max(2))
            // A connection used within the last second is taken as it is: a
            // ping before every statement would cost a round trip to the
            // database each (and the pool pings each connection given back,
            // which closes a broken one). One idle for longer (the database
            // may have restarted meanwhile) is pinged first.
            .test_before_acquire(false)
            .before_acquire(|conn, meta| {
                Box::pin(async move {
                    if meta.idle_for > PING_IDLE {
                        sqlx::Connection::ping(conn).await?;
                    }
                    Ok(true)
                })
            })
            // A database that is down fails requests fast (503), not after 10 s.
            .acquire_timeout(ACQUIRE_TIMEOUT)
            .connect(url)
            .await?;
        super::migrations::postgres().run(&pool).await?;
        let queued = Arc::new(Notify::new());
        let deletions = Arc::new(Deletions::default());
        let finished = Announcer::default();
        let l = listener(&pool).await?;
        let news = News {
            deletions: deletions.clone(),
            finished: finished.clone(),
        };
        tokio::spawn(listen(pool.clone(), l, queued.clone(), news));
        // Writes on connections of their own, half as many as the pool's
        // (which serves reads and the listener): see `super::writer`.
        let writer = Writer::new(
            pool.clone(),
            (connections / 2).max(2),
            Some(PING_IDLE),
            Some(ACQUIRE_TIMEOUT),
        );
        Ok(SqlStore::new(
            pool,
            writer,
            Some(queued),
            deletions,
            finished,
        ))
    }
}
