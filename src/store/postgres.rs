//! PostgreSQL storage: several instances share jobs, tasks and the cache.
//! Tasks are claimed with `FOR UPDATE SKIP LOCKED` under leases on the
//! database clock; LISTEN/NOTIFY wakes idle workers everywhere.

use std::sync::Arc;
use std::time::Duration;

use sqlx::postgres::{PgListener, PgPoolOptions};
use sqlx::{PgPool, Postgres};
use tokio::sync::Notify;

use super::StoreError;
use super::sql::SqlStore;

/// The channel that announces queued work (as in [`super::dialect`]'s
/// announcement).
const CHANNEL: &str = "topple_tasks";

/// Longest wait for a connection: past it a request fails with 503.
const ACQUIRE_TIMEOUT: Duration = Duration::from_millis(1500);

/// Longest pause between attempts to listen again after the connection was
/// lost (the pauses double from 100 ms up to it).
const LISTEN_BACKOFF_MAX: Duration = Duration::from_secs(3);

/// Wakes idle workers at each notification on [`CHANNEL`], for as long as the
/// pool is open. A lost connection (the database restarted, or the network
/// failed) is listened on again, with a backoff, for as long as it takes; the
/// workers poll meanwhile, and are woken once listening resumes in case work
/// was queued while it was down.
async fn listen(pool: PgPool, mut listener: PgListener, wake: Arc<Notify>) {
    loop {
        match listener.recv().await {
            Ok(_) => wake.notify_waiters(),
            Err(e) => {
                if pool.is_closed() {
                    return;
                }
                tracing::warn!(error = %e, "lost the notification connection; listening again");
                let mut pause = Duration::from_millis(100);
                listener = loop {
                    tokio::time::sleep(pause).await;
                    if pool.is_closed() {
                        return;
                    }
                    match PgListener::connect_with(&pool).await {
                        Ok(mut l) => match l.listen(CHANNEL).await {
                            Ok(()) => break l,
                            Err(e) => tracing::debug!(error = %e, "listen failed"),
                        },
                        Err(e) => tracing::debug!(error = %e, "notification connection failed"),
                    }
                    pause = (pause * 2).min(LISTEN_BACKOFF_MAX);
                };
                tracing::info!("listening for queued tasks again");
                wake.notify_waiters();
            }
        }
    }
}

/// Jobs in a PostgreSQL database.
pub type PgStore = SqlStore<Postgres>;

impl SqlStore<Postgres> {
    /// Connects to `url` (`postgres://…`), applies the migrations and starts
    /// listening for work queued by other instances.
    pub async fn open(url: &str, connections: u32) -> Result<Self, StoreError> {
        let pool = PgPoolOptions::new()
            .max_connections(connections.max(2))
            // A database that is down fails requests fast (503), not after 10 s.
            .acquire_timeout(ACQUIRE_TIMEOUT)
            .connect(url)
            .await?;
        super::migrations::postgres().run(&pool).await?;
        let queued = Arc::new(Notify::new());
        let mut listener = PgListener::connect_with(&pool).await?;
        listener.listen(CHANNEL).await?;
        tokio::spawn(listen(pool.clone(), listener, queued.clone()));
        Ok(SqlStore::new(pool, Some(queued)))
    }
}
