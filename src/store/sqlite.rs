//! SQLite storage (the embedded default): WAL journal, one file, one instance.

use std::str::FromStr;
use std::time::Duration;

use sqlx::sqlite::{SqliteConnectOptions, SqliteJournalMode, SqlitePoolOptions, SqliteSynchronous};
use sqlx::{Row, Sqlite, SqlitePool};

use super::StoreError;
use super::sql::SqlStore;
use super::writer::Writer;

/// Jobs in a SQLite database.
///
/// SQLite has one writer at a time: writes queue on an in-process lock
/// rather than in SQLite's busy handler, and the WAL is checkpointed by a
/// background task rather than by whichever request crosses the checkpoint
/// size.
pub type SqliteStore = SqlStore<Sqlite>;

/// WAL frames past which a checkpoint waits for its turn among writers and
/// for readers to move on, so that the log restarts (16 MiB at 4 KiB pages).
const WAL_RESTART_FRAMES: i64 = 4096;

/// Checkpoints the WAL every half second: PASSIVE (never waits) as a rule, and
/// TRUNCATE, holding the writer lock, once the log has grown past
/// [`WAL_RESTART_FRAMES`], which a steady stream of readers would otherwise
/// let grow without bound.
async fn checkpoint_loop(pool: SqlitePool, writer: std::sync::Arc<Writer<Sqlite>>) {
    let mut tick = tokio::time::interval(Duration::from_millis(500));
    loop {
        tick.tick().await;
        if pool.is_closed() {
            break;
        }
        let frames = sqlx::query("PRAGMA wal_checkpoint(PASSIVE)")
            .fetch_optional(&pool)
            .await
            .ok()
            .flatten()
            .and_then(|row| row.try_get::<i64, _>(1).ok())
            .unwrap_or(0);
        if frames > WAL_RESTART_FRAMES {
            let _write = writer.all_turns().await;
            let _ = sqlx::query("PRAGMA wal_checkpoint(TRUNCATE)")
                .execute(&pool)
                .await;
        }
    }
}

impl SqlStore<Sqlite> {
    /// Opens (creating if missing) the database at `url` (`sqlite://path` or a
    /// plain path) and applies the migrations.
    pub async fn open(url: &str, connections: u32) -> Result<Self, StoreError> {
        let url = if url.starts_with("sqlite:") {
            url.to_string()
        } else {
            format!("sqlite://{url}")
        };
        let options = SqliteConnectOptions::from_str(&url)?
            .create_if_missing(true)
            .journal_mode(SqliteJournalMode::Wal)
            .synchronous(SqliteSynchronous::Normal)
            .busy_timeout(Duration::from_secs(10))
            .foreign_keys(true)
            .pragma("wal_autocheckpoint", "0")
            .pragma("journal_size_limit", "67108864");
        let pool = SqlitePoolOptions::new()
            .max_connections(connections.max(2))
            // A connection to a local file does not go away: it is not pinged
            // before each use (a round trip to its thread per request).
            .test_before_acquire(false)
            .connect_with(options)
            .await?;
        super::migrations::sqlite().run(&pool).await?;
        // One instance: every deletion is its own, announced as it commits.
        // One writer: a connection of its own, taken in turns; local, so
        // never pinged, and a write waits for its turn however long.
        let writer = Writer::new(pool.clone(), 1, None, None);
        let store = SqlStore::new(
            pool.clone(),
            writer,
            None,
            Default::default(),
            Default::default(),
        );
        tokio::spawn(checkpoint_loop(pool, store.writer()));
        Ok(store)
    }
}
